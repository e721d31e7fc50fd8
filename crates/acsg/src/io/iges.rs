//! Reader of IGES 5.3 files holding one planar (faceted) solid.
//!
//! Two ways CAD systems write such a solid are read:
//!
//! * the B-rep form: entity 186 (manifold solid B-rep object) over 514 (shell), 510
//!   (face), 508 (loop), 504 (edge list), 502 (vertex list), with 190 (plane surface,
//!   or 108 plane) faces and 110 (line) edges; the shell's and the faces' orientation
//!   flags and the face's outer-loop flag are honoured;
//! * the trimmed-surface form: entity 144 (trimmed surface) over a 108 or 190 plane,
//!   bounded by 142 (curve on surface) whose model-space curve is a 102 (composite
//!   curve) of 110 lines, or a single 110. A 144 has no orientation flag: its plane's
//!   normal is taken as the outward one (all faces are turned round when the normals
//!   turn out to point inward).
//!
//! Layout: 80-column records, the section letter in column 73 (S start, G global, D
//! directory, P parameters, T terminate). Each directory entry is two lines; the
//! parameter data of an entity is columns 1-64 of its P lines, with the global
//! section's parameter and record delimiters (default `,` and `;`) and Hollerith strings
//! (`nH...`). Coordinates are converted to **millimetres** with the global unit flag
//! (parameter 14; 1 inch, 2 mm, 3 named by parameter 15, 4 foot, 5 mile, 6 metre, 7
//! km, 8 mil, 9 micron, 10 cm, 11 microinch; the standard's default is inches) and the
//! model space scale (parameter 13).
//!
//! A 128 (rational B-spline surface) whose control points are coplanar is read as its
//! plane, and a 126 (rational B-spline curve) whose control points are collinear as its
//! line (within [`crate::tolerance::COPLANAR_REL`] of their size): a B-spline is an
//! affine combination of its control points, so it lies in their plane or line.
//! Curved geometry (100 circular arc, a curved 126 or 128, 120 surface of revolution,
//! ...), transformation matrices (124) and every other geometric
//! entity outside this subset are refused, naming the entity type and its directory
//! entry (DE) number. Non-geometric entities (402 groups, 406 properties, 314 colours,
//! ...) are ignored.

use std::collections::HashMap;
use std::io::Read;

use glam::DVec3;

use super::planar::{NetShape, PlanarFace, line_deviation, net_shape, soup_from_faces};
use super::text::read_limited;
use super::{MeshSoup, ParseError, Place};
use crate::tolerance::JOIN_REL;

/// What every refusal suggests.
const EXPORT_HINT: &str = "export the part as a planar (faceted) solid, e.g. IGES B-rep (entity 186) or STEP, or as a mesh (OFF, STL, OBJ, PLY)";

/// Nesting limit for composite curves inside composite curves.
const MAX_DEPTH: usize = 16;

/// Reads an IGES file holding one planar solid; coordinates come out in millimetres.
///
/// # Errors
/// A [`ParseError`] naming the line (and the entity type and DE number) and the fix:
/// a file that is not fixed-column ASCII IGES, a truncated file, an unknown or
/// contradictory unit, a curved or otherwise unsupported entity, a broken pointer, a
/// non-planar face or a loop that does not close.
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    let file = IgesFile::parse(&bytes)?;
    let faces = file.faces()?;
    soup_from_faces(faces, EXPORT_HINT)
}

/// Does this input look like fixed-column IGES (an 80-column start record with `S` in
/// column 73)?
pub(crate) fn looks_like_iges(head: &[u8]) -> bool {
    let first = head.split(|&b| b == b'\n').next().unwrap_or_default();
    let first = first.strip_suffix(b"\r").unwrap_or(first);
    (first.len() == 80 || (head.len() >= 80 && !head[..80].contains(&b'\n')))
        && first.get(72) == Some(&b'S')
        && first
            .get(73..80)
            .is_some_and(|s| s.iter().all(|b| b.is_ascii_digit() || *b == b' '))
}

/// The name of an IGES entity type, for messages.
#[must_use]
pub fn entity_name(kind: i64) -> &'static str {
    match kind {
        100 => "circular arc",
        102 => "composite curve",
        104 => "conic arc",
        106 => "copious data (polyline)",
        108 => "plane",
        110 => "line",
        112 => "parametric spline curve",
        114 => "parametric spline surface",
        116 => "point",
        118 => "ruled surface",
        120 => "surface of revolution",
        122 => "tabulated cylinder",
        123 => "direction",
        124 => "transformation matrix",
        126 => "rational B-spline curve",
        128 => "rational B-spline surface",
        130 => "offset curve",
        140 => "offset surface",
        141 => "boundary",
        142 => "curve on a parametric surface",
        143 => "bounded surface",
        144 => "trimmed surface",
        150..=184 => "constructive solid geometry entity",
        186 => "manifold solid B-rep object",
        190 => "plane surface",
        192 => "right circular cylindrical surface",
        194 => "right circular conical surface",
        196 => "spherical surface",
        198 => "toroidal surface",
        502 => "vertex list",
        504 => "edge list",
        508 => "loop",
        510 => "face",
        514 => "shell",
        _ => "entity",
    }
}

/// One directory entry.
#[derive(Clone, Debug)]
struct Entry {
    kind: i64,
    /// The sequence number of its first D line (the DE number pointers use).
    de: usize,
    /// The file line of its first D line.
    line: usize,
    param_start: usize,
    param_lines: usize,
    transform: i64,
}

/// A parameter value as written.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Text(String),
    Hollerith(String),
}

struct IgesFile {
    entries: Vec<Entry>,
    by_de: HashMap<usize, usize>,
    /// P lines' columns 1-64, in order, with their file line numbers.
    params: Vec<(usize, String)>,
    delimiters: (char, char),
    /// Multiply model coordinates by this to get millimetres.
    to_mm: f64,
}

fn err(place: Place, problem: impl Into<String>, fix: impl Into<String>) -> ParseError {
    ParseError::new(place, problem, fix)
}

/// Splits parameter text into tokens up to the record delimiter.
fn tokenize(text: &str, delimiters: (char, char)) -> Result<(Vec<Token>, bool), String> {
    let (pd, rd) = delimiters;
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    loop {
        while i < chars.len() && chars[i] == ' ' {
            i += 1;
        }
        // A Hollerith string: digits, `H`, then exactly that many characters.
        let digits = chars[i.min(chars.len())..]
            .iter()
            .take_while(|c| c.is_ascii_digit())
            .count();
        if digits > 0 && chars.get(i + digits).is_some_and(|c| *c == 'H' || *c == 'h') {
            let count: String = chars[i..i + digits].iter().collect();
            let n: usize = count
                .parse()
                .map_err(|_| format!("Hollerith length `{count}` is too large"))?;
            let start = i + digits + 1;
            let Some(body) = chars.get(start..start.saturating_add(n)) else {
                return Err(format!(
                    "the Hollerith string `{count}H...` runs past the end of its data"
                ));
            };
            tokens.push(Token::Hollerith(body.iter().collect()));
            i = start + n;
            while i < chars.len() && chars[i] == ' ' {
                i += 1;
            }
        } else {
            let start = i;
            while i < chars.len() && chars[i] != pd && chars[i] != rd {
                i += 1;
            }
            tokens.push(Token::Text(
                chars[start..i].iter().collect::<String>().trim().to_owned(),
            ));
        }
        match chars.get(i) {
            Some(c) if *c == pd => i += 1,
            Some(c) if *c == rd => return Ok((tokens, true)),
            Some(c) => return Err(format!("unexpected `{c}` after a value")),
            None => return Ok((tokens, false)),
        }
    }
}

fn unit_from_flag(flag: i64) -> Option<(f64, &'static str)> {
    Some(match flag {
        1 => (25.4, "inch"),
        2 => (1.0, "millimetre"),
        4 => (304.8, "foot"),
        5 => (1_609_344.0, "mile"),
        6 => (1000.0, "metre"),
        7 => (1e6, "kilometre"),
        8 => (0.0254, "mil"),
        9 => (0.001, "micron"),
        10 => (10.0, "centimetre"),
        11 => (2.54e-5, "microinch"),
        _ => return None,
    })
}

fn unit_from_name(name: &str) -> Option<i64> {
    Some(match name.trim().to_ascii_uppercase().as_str() {
        "IN" | "INCH" | "INCHES" => 1,
        "MM" | "MILLIMETRE" | "MILLIMETER" => 2,
        "FT" | "FOOT" | "FEET" => 4,
        "MI" | "MILE" => 5,
        "M" | "METRE" | "METER" => 6,
        "KM" => 7,
        "MIL" => 8,
        "UM" | "MICRON" => 9,
        "CM" => 10,
        "UIN" => 11,
        _ => return None,
    })
}

/// The file as text, refused unless it is ASCII.
fn ascii_text(bytes: &[u8]) -> Result<&str, ParseError> {
    if !bytes.is_ascii() {
        let at = bytes.iter().position(|b| !b.is_ascii()).unwrap_or(0);
        return Err(err(
            Place::Byte(at as u64),
            "the file holds non-ASCII bytes; IGES is fixed-column ASCII text",
            format!("binary and compressed IGES are not read; {EXPORT_HINT}"),
        ));
    }
    Ok(std::str::from_utf8(bytes).unwrap_or_default())
}

/// The records of the global, directory and parameter sections.
struct Sections<'a> {
    /// The global section's text (columns 1 to 72 of its records, joined).
    global: String,
    /// The directory records with their line numbers.
    directory: Vec<(usize, &'a str)>,
    /// The parameter records' data (columns 1 to 64) with their line numbers.
    params: Vec<(usize, String)>,
}

impl<'a> Sections<'a> {
    /// Sorts the records by the section letter in column 73, checking that every
    /// record is whole, the sections come in order and the file is terminated.
    fn of(lines: &[&'a str]) -> Result<Sections<'a>, ParseError> {
        let mut sections = Sections {
            global: String::new(),
            directory: Vec::new(),
            params: Vec::new(),
        };
        let mut terminated = false;
        let mut last_section = 'S';
        for (k, line) in lines.iter().enumerate() {
            let number = k + 1;
            if line.trim().is_empty() {
                continue;
            }
            if line.len() < 73 {
                let last = lines[k + 1..].iter().all(|l| l.trim().is_empty());
                return Err(err(
                    Place::Line(number),
                    if last {
                        format!(
                            "the file ends inside a record ({} of 80 columns): it looks truncated",
                            line.len()
                        )
                    } else {
                        format!("the record is {} columns long; IGES records are 80 columns", line.len())
                    },
                    "export the file again and copy it whole (IGES is fixed-column text)",
                ));
            }
            let section = line.chars().nth(72).unwrap_or(' ');
            check_section_order(section, last_section, number)?;
            last_section = section;
            let body = |end: usize| line.get(..end.min(line.len())).unwrap_or_default();
            match section {
                'G' => sections.global.push_str(body(72)),
                'D' => sections.directory.push((number, *line)),
                'P' => sections.params.push((number, format!("{:<64}", body(64)))),
                'T' => terminated = true,
                _ => {}
            }
        }
        if !terminated {
            return Err(err(
                Place::Line(lines.len().max(1)),
                "the file has no terminate (T) section: it looks truncated",
                "export the file again and copy it whole",
            ));
        }
        Ok(sections)
    }
}

/// A record of section `section` may follow one of `last_section`: a known section
/// letter, in the order S, G, D, P, T.
fn check_section_order(section: char, last_section: char, number: usize) -> Result<(), ParseError> {
    let order = |s: char| "SGDPT".find(s);
    match (order(section), order(last_section)) {
        (Some(now), Some(before)) if now < before => Err(err(
            Place::Line(number),
            format!("section `{section}` comes after section `{last_section}`"),
            "the sections must come in the order S, G, D, P, T; export the file again",
        )),
        (None, _) => {
            let fix = if section == 'C' || section == 'B' {
                format!("compressed and binary IGES are not read; {EXPORT_HINT}")
            } else {
                "every IGES record is 80 columns with the section letter (S, G, D, P, T) in column 73; the file may be damaged or not IGES".to_owned()
            };
            Err(err(
                Place::Line(number),
                format!("column 73 holds `{section}`, not a section letter"),
                fix,
            ))
        }
        _ => Ok(()),
    }
}

/// The directory entries (two records each), and the index of each by its sequence
/// number (DE).
fn directory_entries(directory: &[(usize, &str)]) -> Result<(Vec<Entry>, HashMap<usize, usize>), ParseError> {
    if directory.len() % 2 != 0 {
        let line = directory.last().map_or(1, |d| d.0);
        return Err(err(
            Place::Line(line),
            format!(
                "the directory section has {} lines; entries come in pairs",
                directory.len()
            ),
            "the file looks truncated or damaged; export it again",
        ));
    }
    let mut entries = Vec::with_capacity(directory.len() / 2);
    let mut by_de = HashMap::new();
    for pair in directory.chunks_exact(2) {
        let ((line, first), (_, second)) = (pair[0], pair[1]);
        let field = |l: &str, k: usize| {
            l.get(k * 8..(k * 8 + 8).min(l.len()))
                .unwrap_or_default()
                .trim()
                .to_owned()
        };
        let int = |l: &str, k: usize, what: &str| -> Result<i64, ParseError> {
            let f = field(l, k);
            if f.is_empty() {
                return Ok(0);
            }
            f.parse::<i64>().map_err(|_| {
                err(
                    Place::Line(line),
                    format!("directory entry field `{what}` is `{f}`, not an integer"),
                    "the directory section is damaged; export the file again",
                )
            })
        };
        let seq = first
            .get(73..80)
            .and_then(|s| s.trim().parse::<usize>().ok())
            .unwrap_or(entries.len() * 2 + 1);
        let kind = int(first, 0, "entity type")?;
        let param_start = usize::try_from(int(first, 1, "parameter data pointer")?).unwrap_or(0);
        let transform = int(first, 6, "transformation matrix")?;
        let param_lines = usize::try_from(int(second, 3, "parameter line count")?).unwrap_or(0);
        by_de.insert(seq, entries.len());
        entries.push(Entry {
            kind,
            de: seq,
            line,
            param_start,
            param_lines,
            transform,
        });
    }
    Ok((entries, by_de))
}

impl IgesFile {
    fn parse(bytes: &[u8]) -> Result<IgesFile, ParseError> {
        let text = ascii_text(bytes)?;
        // Records are lines; a file without line breaks is a run of 80-byte records.
        let lines: Vec<&str> = if !text.contains('\n') && text.len() % 80 == 0 && text.len() >= 80 {
            (0..text.len() / 80)
                .filter_map(|k| text.get(k * 80..k * 80 + 80))
                .collect()
        } else {
            text.lines().map(|l| l.strip_suffix('\r').unwrap_or(l)).collect()
        };
        let sections = Sections::of(&lines)?;
        let (delimiters, global_tokens) = parse_global(&sections.global)?;
        let to_mm = units(&global_tokens)?;
        let (entries, by_de) = directory_entries(&sections.directory)?;
        Ok(IgesFile {
            entries,
            by_de,
            params: sections.params,
            delimiters,
            to_mm,
        })
    }

    fn entry(&self, de: i64, from: &Entry, what: &str) -> Result<&Entry, ParseError> {
        usize::try_from(de)
            .ok()
            .and_then(|de| self.by_de.get(&de))
            .and_then(|&k| self.entries.get(k))
            .ok_or_else(|| {
                err(
                    Place::Line(from.line),
                    format!(
                        "entity {} ({}) at DE {}: its {what} points to DE {de}, which does not exist",
                        from.kind,
                        entity_name(from.kind),
                        from.de
                    ),
                    "the file is damaged or truncated; export it again",
                )
            })
    }

    /// The parameter tokens of an entity, without the leading type number.
    fn params(&self, e: &Entry) -> Result<Params, ParseError> {
        let place = Place::Line(e.line);
        let what = format!("entity {} ({}) at DE {}", e.kind, entity_name(e.kind), e.de);
        let start = e.param_start.checked_sub(1);
        let lines = start.and_then(|s| self.params.get(s..s.saturating_add(e.param_lines.max(1))));
        let Some(lines) = lines else {
            return Err(err(
                place,
                format!(
                    "{what}: its parameters are said to be on P lines {}..{}, but the file has {} P lines",
                    e.param_start,
                    e.param_start.saturating_add(e.param_lines),
                    self.params.len()
                ),
                "the file looks truncated; export it again",
            ));
        };
        let text: String = lines.iter().map(|(_, t)| t.as_str()).collect();
        let (tokens, closed) = tokenize(&text, self.delimiters)
            .map_err(|p| err(place, format!("{what}: {p}"), "the file is damaged; export it again"))?;
        if !closed {
            return Err(err(
                place,
                format!(
                    "{what}: its parameter data has no record delimiter `{}`",
                    self.delimiters.1
                ),
                "the file looks truncated; export it again",
            ));
        }
        let mut tokens = tokens.into_iter();
        let kind = tokens.next();
        if kind != Some(Token::Text(e.kind.to_string())) {
            let found = match &kind {
                Some(Token::Text(t)) if t.trim().is_empty() => "an empty value".to_string(),
                Some(Token::Text(t)) => format!("`{}`", t.trim()),
                Some(Token::Hollerith(t)) => format!("the string \"{t}\""),
                None => "nothing".to_string(),
            };
            return Err(err(
                place,
                format!(
                    "{what}: its parameter data starts with {found}, not its type {}",
                    e.kind
                ),
                "the directory and parameter sections disagree; export the file again",
            ));
        }
        Ok(Params {
            tokens: tokens.collect(),
            next: 0,
            place,
            what,
        })
    }

    fn refuse(&self, e: &Entry) -> ParseError {
        let kind = e.kind;
        let curved = matches!(
            kind,
            100 | 104 | 112 | 114 | 118 | 120 | 122 | 126 | 128 | 130 | 140 | 192..=198
        );
        let why = if curved {
            "is curved; acsg reads planar (polyhedral) solids only"
        } else if kind == 124 {
            "is not supported (placed instances are not read)"
        } else {
            "is outside the planar B-rep subset acsg reads"
        };
        err(
            Place::Line(e.line),
            format!("entity {kind} ({}) at DE {} {why}", entity_name(kind), e.de),
            EXPORT_HINT,
        )
    }

    /// Every used entity must be placed in the world frame.
    fn check(&self, e: &Entry, allowed: &[i64]) -> Result<(), ParseError> {
        if !allowed.contains(&e.kind) {
            return Err(self.refuse(e));
        }
        if e.transform != 0 {
            return Err(err(
                Place::Line(e.line),
                format!(
                    "entity {} ({}) at DE {} is placed by a transformation matrix (entity 124, DE {})",
                    e.kind,
                    entity_name(e.kind),
                    e.de,
                    e.transform
                ),
                format!("transformed entities are not read; {EXPORT_HINT}"),
            ));
        }
        Ok(())
    }

    fn faces(&self) -> Result<Vec<PlanarFace>, ParseError> {
        // Independent curved surfaces and solids are refused even when no solid uses them.
        for e in &self.entries {
            if matches!(e.kind, 114 | 118 | 120 | 122 | 140 | 143 | 150..=184 | 192..=198) {
                return Err(self.refuse(e));
            }
        }
        let of = |k: i64| self.entries.iter().filter(move |e| e.kind == k);
        let mut faces = Vec::new();
        if of(186).next().is_some() {
            for solid in of(186) {
                self.solid(solid, &mut faces)?;
            }
        } else if of(514).next().is_some() {
            for shell in of(514) {
                self.shell(shell, true, &mut faces)?;
            }
        } else if of(144).next().is_some() {
            for trimmed in of(144) {
                faces.push(self.trimmed(trimmed)?);
            }
        } else {
            return Err(
                match self
                    .entries
                    .iter()
                    .find(|e| (100..200).contains(&e.kind) || (500..600).contains(&e.kind))
                {
                    Some(e) if !matches!(e.kind, 102 | 108 | 110 | 116 | 123 | 190 | 502 | 504 | 508 | 510) => {
                        self.refuse(e)
                    }
                    _ => err(
                        Place::Whole,
                        "the file holds no solid: no entity 186 (manifold solid), 514 (shell) or 144 (trimmed surface)",
                        EXPORT_HINT,
                    ),
                },
            );
        }
        Ok(faces)
    }

    fn solid(&self, e: &Entry, faces: &mut Vec<PlanarFace>) -> Result<(), ParseError> {
        self.check(e, &[186])?;
        let mut p = self.params(e)?;
        let shell = p.pointer("the shell")?;
        let agrees = p.logical("the shell orientation flag")?;
        let voids = p.int_or("the void shell count", 0)?;
        if voids != 0 {
            return Err(err(
                p.place,
                format!("{}: the solid has {voids} void shell(s)", p.what),
                "acsg reads solids with one closed outer surface and no internal voids",
            ));
        }
        let shell = self.entry(shell, e, "shell pointer")?;
        self.shell(shell, agrees, faces)
    }

    fn shell(&self, e: &Entry, agrees: bool, faces: &mut Vec<PlanarFace>) -> Result<(), ParseError> {
        self.check(e, &[514])?;
        let mut p = self.params(e)?;
        let n = p.count("the face count")?;
        for _ in 0..n {
            let face = p.pointer("a face")?;
            let flag = p.logical("a face orientation flag")?;
            let face = self.entry(face, e, "face pointer")?;
            faces.push(self.face(face, flag == agrees)?);
        }
        Ok(())
    }

    fn face(&self, e: &Entry, outward: bool) -> Result<PlanarFace, ParseError> {
        self.check(e, &[510])?;
        let mut p = self.params(e)?;
        let surface = p.pointer("the surface")?;
        let n = p.count("the loop count")?;
        let outer_first = p.logical("the outer loop flag")?;
        let normal = self.plane_normal(self.entry(surface, e, "surface pointer")?)?;
        let mut loops = Vec::with_capacity(n);
        for _ in 0..n {
            let l = p.pointer("a loop")?;
            loops.push(self.loop_points(self.entry(l, e, "loop pointer")?)?);
        }
        Ok(PlanarFace {
            normal: if outward { normal } else { -normal },
            loops,
            outer: outer_first.then_some(0),
            name: format!("face (entity 510) at DE {}", e.de),
            place: Place::Line(e.line),
        })
    }

    fn plane_normal(&self, e: &Entry) -> Result<DVec3, ParseError> {
        self.check(e, &[108, 128, 190])?;
        let mut p = self.params(e)?;
        if e.kind == 128 {
            // A B-spline surface whose control points are coplanar is that plane.
            return match net_shape(&surface_net(&mut p, self.to_mm)?) {
                NetShape::Plane(normal) => Ok(normal),
                NetShape::Curved { deviation, tolerance } => Err(err(
                    Place::Line(e.line),
                    format!(
                        "entity 128 (rational B-spline surface) at DE {} is curved: its control points lie up to \
                         {deviation:.3e} mm off a plane (more than the {tolerance:.1e} mm tolerance); acsg reads \
                         planar (polyhedral) solids only",
                        e.de
                    ),
                    EXPORT_HINT,
                )),
                NetShape::Degenerate => Err(err(
                    Place::Line(e.line),
                    format!("{}: its control points span no area", p.what),
                    "the file is damaged; export it again",
                )),
            };
        }
        if e.kind == 108 {
            let n = DVec3::new(p.real("A")?, p.real("B")?, p.real("C")?);
            return Ok(n);
        }
        let _location = p.pointer("the location point")?;
        let normal = p.pointer("the normal direction")?;
        let d = self.entry(normal, e, "normal pointer")?;
        self.check(d, &[123])?;
        let mut q = self.params(d)?;
        Ok(DVec3::new(q.real("x")?, q.real("y")?, q.real("z")?))
    }

    fn vertex(
        &self,
        list: i64,
        index: i64,
        from: &Entry,
        cache: &mut HashMap<i64, Vec<DVec3>>,
    ) -> Result<DVec3, ParseError> {
        if let std::collections::hash_map::Entry::Vacant(slot) = cache.entry(list) {
            let e = self.entry(list, from, "vertex list pointer")?;
            self.check(e, &[502])?;
            let mut p = self.params(e)?;
            let n = p.count("the vertex count")?;
            let mut points = Vec::with_capacity(n.min(1 << 16));
            for _ in 0..n {
                points.push(p.point(self.to_mm)?);
            }
            slot.insert(points);
        }
        let points = cache.get(&list).map(Vec::as_slice).unwrap_or_default();
        usize::try_from(index)
            .ok()
            .and_then(|i| i.checked_sub(1))
            .and_then(|i| points.get(i))
            .copied()
            .ok_or_else(|| {
                err(
                    Place::Line(from.line),
                    format!(
                        "DE {}: vertex {index} of the vertex list at DE {list} does not exist ({} vertices)",
                        from.de,
                        points.len()
                    ),
                    "the file is damaged; export it again",
                )
            })
    }

    fn loop_points(&self, e: &Entry) -> Result<Vec<DVec3>, ParseError> {
        self.check(e, &[508])?;
        let mut p = self.params(e)?;
        let n = p.count("the edge count")?;
        let mut edge_lists: HashMap<i64, Vec<[i64; 5]>> = HashMap::new();
        let mut vertices = HashMap::new();
        let mut segments = Vec::with_capacity(n);
        for _ in 0..n {
            let kind = p.int("an edge type")?;
            let list = p.pointer("an edge list")?;
            let index = p.int("an edge index")?;
            let agrees = p.logical("an edge orientation flag")?;
            let curves = p.count("the parameter curve count")?;
            for _ in 0..curves {
                p.int("an isoparametric flag")?;
                p.int("a parameter curve")?;
            }
            if kind != 0 {
                return Err(err(
                    p.place,
                    format!("{}: an entry of the loop is a vertex, not an edge", p.what),
                    format!("degenerate loops come from curved faces; {EXPORT_HINT}"),
                ));
            }
            if let std::collections::hash_map::Entry::Vacant(slot) = edge_lists.entry(list) {
                let le = self.entry(list, e, "edge list pointer")?;
                self.check(le, &[504])?;
                let mut q = self.params(le)?;
                let m = q.count("the edge count")?;
                let mut edges = Vec::with_capacity(m.min(1 << 16));
                for _ in 0..m {
                    edges.push([
                        q.pointer("a curve")?,
                        q.pointer("a start vertex list")?,
                        q.int("a start vertex index")?,
                        q.pointer("an end vertex list")?,
                        q.int("an end vertex index")?,
                    ]);
                }
                slot.insert(edges);
            }
            let edge = edge_lists
                .get(&list)
                .and_then(|l| {
                    usize::try_from(index)
                        .ok()
                        .and_then(|i| i.checked_sub(1))
                        .and_then(|i| l.get(i))
                })
                .copied()
                .ok_or_else(|| {
                    err(
                        p.place,
                        format!("{}: edge {index} of the edge list at DE {list} does not exist", p.what),
                        "the file is damaged; export it again",
                    )
                })?;
            let curve = self.entry(edge[0], e, "edge curve pointer")?;
            self.check(curve, &[110, 126])?;
            if curve.kind == 126 {
                self.straight_spline(curve)?;
            }
            let a = self.vertex(edge[1], edge[2], e, &mut vertices)?;
            let b = self.vertex(edge[3], edge[4], e, &mut vertices)?;
            segments.push(if agrees { (a, b) } else { (b, a) });
        }
        chain(segments, &p)
    }

    fn trimmed(&self, e: &Entry) -> Result<PlanarFace, ParseError> {
        self.check(e, &[144])?;
        let mut p = self.params(e)?;
        let surface = p.pointer("the surface")?;
        let bounded = p.int("the outer boundary flag")?;
        let holes = p.count("the inner boundary count")?;
        let outer = p.pointer("the outer boundary")?;
        let normal = self.plane_normal(self.entry(surface, e, "surface pointer")?)?;
        if bounded == 0 {
            return Err(err(
                p.place,
                format!("{}: its outer boundary is the plane's own boundary (unbounded)", p.what),
                EXPORT_HINT,
            ));
        }
        let mut loops = vec![self.boundary(self.entry(outer, e, "outer boundary pointer")?)?];
        for _ in 0..holes {
            let h = p.pointer("an inner boundary")?;
            loops.push(self.boundary(self.entry(h, e, "inner boundary pointer")?)?);
        }
        Ok(PlanarFace {
            normal,
            loops,
            outer: Some(0),
            name: format!("trimmed surface (entity 144) at DE {}", e.de),
            place: Place::Line(e.line),
        })
    }

    fn boundary(&self, e: &Entry) -> Result<Vec<DVec3>, ParseError> {
        self.check(e, &[142])?;
        let mut p = self.params(e)?;
        let _how = p.int("the creation flag")?;
        let _surface = p.int("the surface")?;
        let _parameter_curve = p.int("the parameter curve")?;
        let curve = p.int("the model space curve")?;
        if curve == 0 {
            return Err(err(
                p.place,
                format!("{}: the boundary has no model-space curve", p.what),
                format!("export with model-space trimming curves; {EXPORT_HINT}"),
            ));
        }
        let mut segments = Vec::new();
        self.segments(self.entry(curve, e, "model space curve pointer")?, 0, &mut segments)?;
        chain(segments, &p)
    }

    /// A 126 curve's end points, refusing it unless its control points are collinear.
    fn straight_spline(&self, e: &Entry) -> Result<(DVec3, DVec3), ParseError> {
        let mut p = self.params(e)?;
        let curve = spline_curve(&mut p, self.to_mm)?;
        let (deviation, tolerance) = line_deviation(&curve.points);
        if deviation > tolerance {
            return Err(err(
                Place::Line(e.line),
                format!(
                    "entity 126 (rational B-spline curve) at DE {} is curved: its control points lie up to \
                     {deviation:.3e} mm off a straight line (more than the {tolerance:.1e} mm tolerance); acsg reads \
                     straight edges only",
                    e.de
                ),
                EXPORT_HINT,
            ));
        }
        let (a, b) = (curve.at(curve.range.0), curve.at(curve.range.1));
        match (a, b) {
            (Some(a), Some(b)) => Ok((a, b)),
            _ => Err(err(
                p.place,
                format!("{}: its knots or weights do not define the curve at its ends", p.what),
                "the file is damaged; export it again",
            )),
        }
    }

    fn segments(&self, e: &Entry, depth: usize, out: &mut Vec<(DVec3, DVec3)>) -> Result<(), ParseError> {
        self.check(e, &[102, 110, 126])?;
        if e.kind == 126 {
            out.push(self.straight_spline(e)?);
            return Ok(());
        }
        let mut p = self.params(e)?;
        if e.kind == 110 {
            let a = p.point(self.to_mm)?;
            let b = p.point(self.to_mm)?;
            out.push((a, b));
            return Ok(());
        }
        if depth >= MAX_DEPTH {
            return Err(err(
                p.place,
                format!("{}: composite curves nest too deep", p.what),
                EXPORT_HINT,
            ));
        }
        let n = p.count("the curve count")?;
        for _ in 0..n {
            let c = p.pointer("a curve")?;
            self.segments(self.entry(c, e, "curve pointer")?, depth + 1, out)?;
        }
        Ok(())
    }
}

/// An IGES 126 rational B-spline curve: control points (mm), weights, knots, degree
/// and parameter range.
struct SplineCurve {
    degree: usize,
    knots: Vec<f64>,
    weights: Vec<f64>,
    points: Vec<DVec3>,
    range: (f64, f64),
}

impl SplineCurve {
    /// The point at parameter `u` (de Boor's algorithm in homogeneous coordinates);
    /// `None` where the knots or weights leave it undefined.
    fn at(&self, u: f64) -> Option<DVec3> {
        let (m, n) = (self.degree, self.points.len());
        if n == 0 || self.knots.len() != n + m + 1 {
            return None;
        }
        // The span k with knots[k] <= u < knots[k + 1], within [m, n - 1].
        let mut k = m;
        while k + 1 < n && self.knots[k + 1] <= u {
            k += 1;
        }
        let mut d: Vec<(DVec3, f64)> = (0..=m)
            .map(|j| {
                let i = (k + j).checked_sub(m)?;
                let w = *self.weights.get(i)?;
                Some((*self.points.get(i)? * w, w))
            })
            .collect::<Option<_>>()?;
        for r in 1..=m {
            for j in (r..=m).rev() {
                let i = k + j - m;
                let (lo, hi) = (self.knots[i], self.knots[i + m + 1 - r]);
                let alpha = if hi > lo { (u - lo) / (hi - lo) } else { 0.0 };
                d[j] = (
                    d[j - 1].0 * (1.0 - alpha) + d[j].0 * alpha,
                    d[j - 1].1 * (1.0 - alpha) + d[j].1 * alpha,
                );
            }
        }
        let (p, w) = d[m];
        (w.abs() > 0.0 && p.is_finite()).then(|| p / w)
    }
}

/// Reads the parameters of a 126 entity (after its type).
fn spline_curve(p: &mut Params, to_mm: f64) -> Result<SplineCurve, ParseError> {
    let k = p.count("the upper index K")?;
    let degree = p.count("the degree M")?;
    for name in ["PROP1", "PROP2", "PROP3", "PROP4"] {
        p.int(name)?;
    }
    let knots = (0..k + degree + 2)
        .map(|_| p.real("a knot"))
        .collect::<Result<Vec<_>, _>>()?;
    let weights = (0..=k).map(|_| p.real("a weight")).collect::<Result<Vec<_>, _>>()?;
    let points = (0..=k).map(|_| p.point(to_mm)).collect::<Result<Vec<_>, _>>()?;
    let range = (p.real("V(0)")?, p.real("V(1)")?);
    Ok(SplineCurve {
        degree,
        knots,
        weights,
        points,
        range,
    })
}

/// Reads the control net of a 128 entity (after its type): `net[i][j]`, `i` along u.
fn surface_net(p: &mut Params, to_mm: f64) -> Result<Vec<Vec<DVec3>>, ParseError> {
    let k1 = p.count("the upper index K1")?;
    let k2 = p.count("the upper index K2")?;
    let m1 = p.count("the degree M1")?;
    let m2 = p.count("the degree M2")?;
    for name in ["PROP1", "PROP2", "PROP3", "PROP4", "PROP5"] {
        p.int(name)?;
    }
    // Each control point takes a weight and three coordinates: more than the parameters
    // hold is a damaged file (and must not size an allocation).
    let cells = (k1 + 1)
        .checked_mul(k2 + 1)
        .filter(|c| c.saturating_mul(4) <= p.tokens.len());
    let Some(cells) = cells else {
        return Err(err(
            p.place,
            format!(
                "{}: its {} x {} control points are more than its parameters hold",
                p.what,
                k1 + 1,
                k2 + 1
            ),
            "the file is damaged or truncated; export it again",
        ));
    };
    for _ in 0..(k1 + m1 + 2) + (k2 + m2 + 2) + cells {
        p.real("a knot or weight")?;
    }
    let mut net = vec![Vec::with_capacity(k2 + 1); k1 + 1];
    for _ in 0..=k2 {
        for row in &mut net {
            row.push(p.point(to_mm)?);
        }
    }
    Ok(net)
}

/// Joins line segments head to tail into a closed chain of points (a segment stated
/// the other way round is turned).
fn chain(mut segments: Vec<(DVec3, DVec3)>, p: &Params) -> Result<Vec<DVec3>, ParseError> {
    let size = segments
        .iter()
        .map(|(a, b)| a.abs().max(b.abs()).max_element())
        .fold(1.0, f64::max);
    let tol = JOIN_REL * size;
    let broken = |at: DVec3| {
        err(
            p.place,
            format!(
                "{}: its edges do not join head to tail at ({}, {}, {})",
                p.what, at.x, at.y, at.z
            ),
            "the loop is broken; export the file again",
        )
    };
    if segments.len() > 1 {
        let (a, b) = segments[0];
        let (c, d) = segments[1];
        if b.distance(c) > tol && b.distance(d) > tol && (a.distance(c) <= tol || a.distance(d) <= tol) {
            segments[0] = (b, a);
        }
    }
    let mut points = Vec::with_capacity(segments.len());
    let mut end = segments.first().map(|s| s.0);
    for (a, b) in segments {
        let Some(at) = end else { break };
        let (a, b) = if a.distance(at) <= tol {
            (a, b)
        } else if b.distance(at) <= tol {
            (b, a)
        } else {
            return Err(broken(at));
        };
        points.push(a);
        end = Some(b);
    }
    match (end, points.first()) {
        (Some(end), Some(&first)) if end.distance(first) > tol => Err(broken(end)),
        _ => Ok(points),
    }
}

/// The parameters of one entity, read in order.
struct Params {
    tokens: Vec<Token>,
    next: usize,
    place: Place,
    what: String,
}

impl Params {
    fn raw(&mut self, name: &str) -> Result<String, ParseError> {
        let token = self.tokens.get(self.next).cloned();
        self.next += 1;
        match token {
            Some(Token::Text(t)) => Ok(t),
            Some(Token::Hollerith(s)) => Err(err(
                self.place,
                format!("{}: {name} is the string `{s}`, not a number", self.what),
                "the file is damaged; export it again",
            )),
            None => Err(err(
                self.place,
                format!("{}: its parameters end before {name}", self.what),
                "the file looks truncated or damaged; export it again",
            )),
        }
    }

    fn int_or(&mut self, name: &str, default: i64) -> Result<i64, ParseError> {
        if self.next >= self.tokens.len() {
            return Ok(default);
        }
        let t = self.raw(name)?;
        if t.is_empty() {
            return Ok(default);
        }
        t.parse().map_err(|_| {
            err(
                self.place,
                format!("{}: {name} is `{t}`, not an integer", self.what),
                "the file is damaged; export it again",
            )
        })
    }

    fn int(&mut self, name: &str) -> Result<i64, ParseError> {
        let t = self.raw(name)?;
        if t.is_empty() {
            return Ok(0);
        }
        t.parse().map_err(|_| {
            err(
                self.place,
                format!("{}: {name} is `{t}`, not an integer", self.what),
                "the file is damaged; export it again",
            )
        })
    }

    fn pointer(&mut self, name: &str) -> Result<i64, ParseError> {
        // Negative pointers only mark "see also" references; the entry is the same.
        self.int(name).map(i64::abs)
    }

    fn count(&mut self, name: &str) -> Result<usize, ParseError> {
        let n = self.int(name)?;
        match usize::try_from(n) {
            Ok(n) if n <= self.tokens.len() => Ok(n),
            _ => Err(err(
                self.place,
                format!("{}: {name} is {n}, more than the parameters it has", self.what),
                "the file is damaged or truncated; export it again",
            )),
        }
    }

    fn logical(&mut self, name: &str) -> Result<bool, ParseError> {
        let t = self.raw(name)?;
        match t.to_ascii_uppercase().as_str() {
            "1" | "TRUE" | ".TRUE." => Ok(true),
            "0" | "" | "FALSE" | ".FALSE." => Ok(false),
            _ => Err(err(
                self.place,
                format!("{}: {name} is `{t}`, not 0 or 1", self.what),
                "the file is damaged; export it again",
            )),
        }
    }

    fn real(&mut self, name: &str) -> Result<f64, ParseError> {
        let t = self.raw(name)?;
        if t.is_empty() {
            return Ok(0.0);
        }
        let v: f64 = t.replace(['D', 'd'], "E").parse().map_err(|_| {
            err(
                self.place,
                format!("{}: {name} is `{t}`, not a number", self.what),
                "the file is damaged; export it again",
            )
        })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(err(
                self.place,
                format!("{}: {name} is not finite", self.what),
                "every coordinate must be a finite number; export the file again",
            ))
        }
    }

    fn point(&mut self, to_mm: f64) -> Result<DVec3, ParseError> {
        Ok(DVec3::new(self.real("x")?, self.real("y")?, self.real("z")?) * to_mm)
    }
}

/// The delimiters and the global parameters (from parameter 3 on, at index 0).
fn parse_global(global: &str) -> Result<((char, char), Vec<Token>), ParseError> {
    let place = Place::Whole;
    let bad = |what: &str| {
        err(
            place,
            format!("the global (G) section is malformed: {what}"),
            "export the file again; the global section starts with the delimiters, e.g. `1H,,1H;,`",
        )
    };
    let chars: Vec<char> = global.chars().collect();
    let mut i = 0;
    let delimiter = |i: &mut usize, default: char| -> Result<char, ParseError> {
        while chars.get(*i) == Some(&' ') {
            *i += 1;
        }
        if chars.get(*i) == Some(&'1') && matches!(chars.get(*i + 1), Some('H' | 'h')) {
            let d = *chars.get(*i + 2).ok_or_else(|| bad("a delimiter is cut off"))?;
            *i += 3;
            Ok(d)
        } else {
            Ok(default)
        }
    };
    if chars.is_empty() {
        return Err(bad("it is empty"));
    }
    let pd = delimiter(&mut i, ',')?;
    if chars.get(i) != Some(&pd) {
        return Err(bad("the parameter delimiter is not followed by itself"));
    }
    i += 1;
    let rd = delimiter(&mut i, ';')?;
    if pd == rd || pd.is_ascii_alphanumeric() || rd.is_ascii_alphanumeric() || pd == ' ' || rd == ' ' {
        return Err(bad(&format!("the delimiters `{pd}` and `{rd}` are not usable")));
    }
    let rest: String = chars.get(i..).unwrap_or_default().iter().collect();
    let tokens = if rest.starts_with(rd) {
        Vec::new()
    } else if let Some(after) = rest.strip_prefix(pd) {
        let (tokens, _) = tokenize(after, (pd, rd)).map_err(|p| bad(&p))?;
        tokens
    } else {
        return Err(bad("the record delimiter is not followed by a delimiter"));
    };
    Ok(((pd, rd), tokens))
}

/// Millimetres per model unit, from global parameters 13 (scale), 14 (unit flag) and 15
/// (unit name); `tokens[0]` is parameter 3.
fn units(tokens: &[Token]) -> Result<f64, ParseError> {
    let get = |k: usize| tokens.get(k - 3);
    let text = |k: usize| match get(k) {
        Some(Token::Text(t)) => t.trim().to_owned(),
        _ => String::new(),
    };
    let fix = "set the unit in the exporter (millimetres recommended) and export again";
    let scale_text = text(13);
    let scale = if scale_text.is_empty() {
        1.0
    } else {
        scale_text.replace(['D', 'd'], "E").parse::<f64>().unwrap_or(f64::NAN)
    };
    if !(scale.is_finite() && scale > 0.0) {
        return Err(err(
            Place::Whole,
            format!("global parameter 13 (model space scale) is `{scale_text}`, not a positive number"),
            fix,
        ));
    }
    let flag_text = text(14);
    let flag = if flag_text.is_empty() {
        1
    } else {
        flag_text.parse::<i64>().unwrap_or(-1)
    };
    let name = match get(15) {
        Some(Token::Hollerith(s)) => s.trim().to_owned(),
        Some(Token::Text(t)) => t.trim().to_owned(),
        None => String::new(),
    };
    let from_name = unit_from_name(&name);
    let flag = if flag == 3 {
        from_name.ok_or_else(|| {
            err(
                Place::Whole,
                format!("global parameter 14 (unit flag) is 3 but the unit name `{name}` is not a unit acsg knows"),
                fix,
            )
        })?
    } else {
        flag
    };
    let Some((mm, unit)) = unit_from_flag(flag) else {
        return Err(err(
            Place::Whole,
            format!("global parameter 14 (unit flag) is `{flag_text}`, not a known unit (1 to 11)"),
            fix,
        ));
    };
    if let Some(named) = from_name
        && named != flag
    {
        return Err(err(
            Place::Whole,
            format!("global parameter 14 (unit flag) says {unit} but parameter 15 names the unit `{name}`"),
            fix,
        ));
    }
    Ok(mm / scale)
}

#[cfg(test)]
mod tests {
    use super::super::text::testing::{expect_err, read_every_prefix, xorshift};
    use super::*;

    const PEG: &str = include_str!("../../../../fixtures/cad/peg.igs");
    const PEG_FACES: &str = include_str!("../../../../fixtures/cad/peg_faces.igs");

    #[test]
    fn hollerith_strings_may_hold_delimiters() {
        let (t, closed) = tokenize("4Ha,b;,12,;", (',', ';')).expect("tokens");
        assert!(closed);
        assert_eq!(
            t,
            vec![
                Token::Hollerith("a,b;".into()),
                Token::Text("12".into()),
                Token::Text(String::new())
            ]
        );
        assert!(tokenize("9Hab;", (',', ';')).is_err());
    }

    fn params_of(text: &str) -> Params {
        Params {
            tokens: text.split(',').map(|t| Token::Text(t.to_string())).collect(),
            next: 0,
            place: Place::Whole,
            what: "test".into(),
        }
    }

    /// De Boor's evaluation against the Bernstein form of a quadratic Bézier arc,
    /// polynomial and rational: B(½) = (w0 P0 + 2 w1 P1 + w2 P2) / (w0 + 2 w1 + w2).
    #[test]
    fn spline_curves_evaluate_at_their_ends_and_inside() {
        let (p0, p1, p2) = (
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(4.0, 0.0, 1.0),
        );
        for (w0, w1, w2) in [(1.0, 1.0, 1.0), (1.0, 2.0, 0.5)] {
            let text = format!(
                "2,2,0,0,0,0,0.,0.,0.,1.,1.,1.,{w0},{w1},{w2},{},{},{},{},{},{},{},{},{},0.,1.",
                p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z
            );
            let curve = spline_curve(&mut params_of(&text), 1.0).unwrap();
            assert!(curve.at(0.0).unwrap().abs_diff_eq(p0, 1e-12));
            assert!(curve.at(1.0).unwrap().abs_diff_eq(p2, 1e-12));
            let half = (p0 * w0 + p1 * (2.0 * w1) + p2 * w2) / (w0 + 2.0 * w1 + w2);
            assert!(curve.at(0.5).unwrap().abs_diff_eq(half, 1e-12), "{:?}", curve.at(0.5));
            // Three points not on a line: curved.
            let (deviation, tolerance) = line_deviation(&curve.points);
            assert!(deviation > tolerance);
        }
        // Knots that do not fit the count leave the curve undefined, without a panic.
        let mut curve = spline_curve(
            &mut params_of("1,1,0,0,0,0,0.,0.,1.,1.,1.,1.,0.,0.,0.,1.,0.,0.,0.,1."),
            1.0,
        )
        .unwrap();
        assert!(curve.at(0.5).unwrap().abs_diff_eq(DVec3::new(0.5, 0.0, 0.0), 1e-12));
        curve.knots.pop();
        assert_eq!(curve.at(0.5), None);
    }

    #[test]
    fn both_forms_of_the_peg_read() {
        for text in [PEG, PEG_FACES] {
            let soup = read(text.as_bytes()).expect("reads");
            assert_eq!(soup.polygons.len(), 6);
        }
    }

    #[test]
    fn the_global_section_gives_delimiters_and_units() {
        let ((pd, rd), tokens) =
            parse_global(&format!("1H//1H#/4HNAME/8Hfile.igs{}0.5/6/1HM#", "/".repeat(9))).expect("global");
        assert_eq!((pd, rd), ('/', '#'));
        assert!((units(&tokens).expect("units") - 2000.0).abs() < 1e-9);
        let (_, tokens) = parse_global(",,4HNAME,,,,,,,,,,1.,3,5HFURLG;").expect("global");
        let e = units(&tokens).expect_err("unknown unit");
        assert!(e.problem.contains("FURLG"), "{e}");
    }

    #[test]
    fn no_prefix_or_mutation_panics() {
        read_every_prefix(|b| read(b), &PEG.as_bytes()[..PEG.len().min(3000)]);
        let mut state = 0x1234_5678_u64;
        for _ in 0..300 {
            let mut bytes = PEG_FACES.as_bytes().to_vec();
            for _ in 0..4 {
                let at = (xorshift(&mut state) as usize) % bytes.len();
                bytes[at] = b" 0123456789,;H.-DPG"[(xorshift(&mut state) % 19) as usize];
            }
            let _ = read(bytes.as_slice());
        }
        let e = expect_err(read(&PEG.as_bytes()[..PEG.len() / 2]));
        assert!(e.problem.contains("truncated"), "{e}");
    }
}
