//! Reader of STEP (ISO 10303-21) files holding one planar solid, AP203 or AP214.
//!
//! A focused Part 21 reader for the planar B-rep subset: `MANIFOLD_SOLID_BREP` or
//! `FACETED_BREP` over a `CLOSED_SHELL` of `ADVANCED_FACE` / `FACE_SURFACE` (or
//! `ORIENTED_FACE`) on a `PLANE` (`AXIS2_PLACEMENT_3D`), bounded by
//! `FACE_OUTER_BOUND` / `FACE_BOUND` over `EDGE_LOOP`s of `ORIENTED_EDGE`s of
//! `EDGE_CURVE`s between `VERTEX_POINT`s, whose geometry is a `LINE` (also inside a
//! `SURFACE_CURVE` or `SEAM_CURVE`), or over `POLY_LOOP`s of `CARTESIAN_POINT`s. The
//! faces' `same_sense` and the oriented faces' and bounds' orientation flags are
//! honoured; the outer loop is the `FACE_OUTER_BOUND`, else the loop of largest area.
//!
//! Coordinates are converted to **millimetres** from the length unit of the
//! representation context (`GLOBAL_UNIT_ASSIGNED_CONTEXT`): an `SI_UNIT` of metres with
//! any prefix, or a `CONVERSION_BASED_UNIT` (inch, foot, ...) through its
//! `LENGTH_MEASURE_WITH_UNIT`.
//!
//! A B-spline or Bézier surface (`B_SPLINE_SURFACE_WITH_KNOTS`, rational complex
//! instances included) whose control points are coplanar is read as its plane, and a
//! B-spline curve, `TRIMMED_CURVE` of a line or `POLYLINE` whose points are collinear
//! as its line (within [`crate::tolerance::COPLANAR_REL`] of their size): OpenCASCADE
//! writes chamfers so. Curved surfaces (`CYLINDRICAL_SURFACE`, a B-spline off its
//! plane, ...), curved edges (`CIRCLE`, ...) and solids with voids are refused, naming
//! the instance (`#id` and type).
//!
//! Why not `truck-stepio` (0.3.0, the crate the survey of dependencies named): measured on this 2-core
//! machine, a clean build of it with the workspace's profile (dependencies at
//! opt-level 2) costs about 270 s of CPU (255 s user + 14 s system; 54 s of CPU at
//! opt-level 0) and about 100 crates (ruststep, truck-geometry, -modeling, -topology,
//! -polymesh, chrono, rand, cgmath, ...), and its `in` feature does not compile without
//! the default `derive` feature. Its reader also ignores length units, returns
//! `Option` from `Table::from_step` (no line or instance in the message), and prints
//! conversion errors to standard error. This reader covers the planar subset in a few
//! hundred lines, with units and the `#id` of every refused instance.

use std::collections::HashMap;
use std::io::Read;

use glam::DVec3;

use super::planar::{NetShape, PlanarFace, area_vector, line_deviation, net_shape, soup_from_faces};
use super::text::read_limited;
use super::{MeshSoup, ParseError, Place};
use crate::tolerance::{AREA_REL, COPLANAR_REL, JOIN_REL, ROUNDOFF_REL, WELD_REL, scaled};

/// What every refusal suggests.
const EXPORT_HINT: &str = "export the part as a planar (faceted) solid, e.g. STEP AP214 with planar faces, or as a mesh \
     (OFF, STL, OBJ, PLY); cylinders, cones and circles can also be read as facets with --facet MM";

/// Nesting limit for lists and typed parameters.
const MAX_DEPTH: usize = 32;

/// A parameter value of an instance.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Number(f64),
    Text(String),
    Enum(String),
    Ref(u64),
    Unset,
    List(Vec<Value>),
    Typed(String, Box<Value>),
}

/// One entity instance: a simple one has one part, a complex one `( A() B() )` several.
#[derive(Clone, Debug)]
struct Instance {
    line: usize,
    parts: Vec<(String, Vec<Value>)>,
}

impl Instance {
    fn part(&self, name: &str) -> Option<&[Value]> {
        self.parts.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
    }

    fn type_name(&self) -> String {
        match self.parts.as_slice() {
            [(name, _)] => name.clone(),
            parts => format!(
                "({})",
                parts.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(" ")
            ),
        }
    }
}

/// Reads a STEP file holding one planar solid; coordinates come out in millimetres.
///
/// # Errors
/// A [`ParseError`] naming the line (and the instance `#id` and type) and the fix: a
/// file that is not STEP Part 21, a truncated file, a missing or unknown length unit, a
/// curved surface or edge, a broken reference, a non-planar face or a loop that does
/// not close.
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    read_faceted(reader, None)
}

/// [`read`], with cylindrical and conical faces and circular edges made planar facets
/// when `facet_mm` gives a chord tolerance (millimetres): every circle becomes a
/// polygon inscribed in it whose sides stray at most that far from the arc (the same
/// number of sides, a power of two, for every circle of the file: the one the largest
/// circle needs), and a cylinder or cone between two full circles becomes the band of
/// planar quadrilaterals between their polygons.
///
/// # Errors
/// Those of [`read`]; with `facet_mm`, a curved face other than a full cylinder or cone
/// between two circles is refused by name.
pub fn read_faceted(reader: impl Read, facet_mm: Option<f64>) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    let text = String::from_utf8_lossy(&bytes);
    let instances = parse(&text)?;
    let mut model = Model {
        to_mm: length_unit(&instances)?,
        instances,
        facet: None,
    };
    if let Some(tolerance) = facet_mm {
        model.facet = Some(Facet {
            sides: model.circle_sides(tolerance)?,
        });
    }
    let faces = model.faces()?;
    soup_from_faces(faces, EXPORT_HINT)
}

/// A cursor over the text, counting lines.
struct Lexer<'a> {
    bytes: &'a [u8],
    at: usize,
    line: usize,
}

impl Lexer<'_> {
    fn error(&self, problem: impl Into<String>) -> ParseError {
        ParseError::new(
            Place::Line(self.line),
            problem,
            "the file is damaged or truncated; export it again",
        )
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.at).copied()
    }

    /// Skips white space and `/* ... */` comments.
    fn skip(&mut self) -> Result<(), ParseError> {
        loop {
            match self.peek() {
                Some(b'\n') => {
                    self.line += 1;
                    self.at += 1;
                }
                Some(b) if b.is_ascii_whitespace() => self.at += 1,
                Some(b'/') if self.bytes.get(self.at + 1) == Some(&b'*') => {
                    self.at += 2;
                    loop {
                        match self.peek() {
                            None => return Err(self.error("a comment `/*` is never closed")),
                            Some(b'*') if self.bytes.get(self.at + 1) == Some(&b'/') => {
                                self.at += 2;
                                break;
                            }
                            Some(b) => {
                                if b == b'\n' {
                                    self.line += 1;
                                }
                                self.at += 1;
                            }
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn expect(&mut self, byte: u8) -> Result<(), ParseError> {
        self.skip()?;
        if self.peek() == Some(byte) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.found(&format!("`{}`", byte as char)))
        }
    }

    fn found(&self, expected: &str) -> ParseError {
        match self.peek() {
            None => self.error(format!("the file ends where {expected} was expected")),
            Some(b) => self.error(format!("expected {expected}, found `{}`", b as char)),
        }
    }

    fn keyword(&mut self) -> String {
        let start = self.at;
        while self
            .peek()
            .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        {
            self.at += 1;
        }
        String::from_utf8_lossy(&self.bytes[start..self.at]).to_ascii_uppercase()
    }

    fn number(&mut self) -> u64 {
        let start = self.at;
        while self.peek().is_some_and(|b| b.is_ascii_digit()) {
            self.at += 1;
        }
        std::str::from_utf8(&self.bytes[start..self.at])
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(u64::MAX)
    }

    /// A parenthesised parameter list.
    fn list(&mut self, depth: usize) -> Result<Vec<Value>, ParseError> {
        if depth > MAX_DEPTH {
            return Err(self.error("lists nest too deep"));
        }
        self.expect(b'(')?;
        let mut values = Vec::new();
        self.skip()?;
        if self.peek() == Some(b')') {
            self.at += 1;
            return Ok(values);
        }
        loop {
            values.push(self.value(depth)?);
            self.skip()?;
            match self.peek() {
                Some(b',') => self.at += 1,
                Some(b')') => {
                    self.at += 1;
                    return Ok(values);
                }
                _ => return Err(self.found("`,` or `)`")),
            }
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, ParseError> {
        self.skip()?;
        match self.peek() {
            Some(b'$' | b'*') => {
                self.at += 1;
                Ok(Value::Unset)
            }
            Some(b'#') => {
                self.at += 1;
                Ok(Value::Ref(self.number()))
            }
            Some(b'(') => Ok(Value::List(self.list(depth + 1)?)),
            Some(b'\'') => {
                self.at += 1;
                let mut s = Vec::new();
                loop {
                    match self.peek() {
                        None => return Err(self.error("a string is never closed")),
                        Some(b'\'') if self.bytes.get(self.at + 1) == Some(&b'\'') => {
                            s.push(b'\'');
                            self.at += 2;
                        }
                        Some(b'\'') => {
                            self.at += 1;
                            return Ok(Value::Text(String::from_utf8_lossy(&s).into_owned()));
                        }
                        Some(b) => {
                            if b == b'\n' {
                                self.line += 1;
                            }
                            s.push(b);
                            self.at += 1;
                        }
                    }
                }
            }
            Some(b'.') if self.bytes.get(self.at + 1).is_some_and(u8::is_ascii_alphabetic) => {
                self.at += 1;
                let name = self.keyword();
                self.expect(b'.')?;
                Ok(Value::Enum(name))
            }
            Some(b'"') => {
                self.at += 1;
                while self.peek().is_some_and(|b| b != b'"') {
                    self.at += 1;
                }
                self.expect(b'"')?;
                Ok(Value::Text(String::new()))
            }
            Some(b) if b.is_ascii_alphabetic() => {
                let name = self.keyword();
                let mut inner = self.list(depth + 1)?;
                let value = if inner.len() == 1 {
                    inner.remove(0)
                } else {
                    Value::List(inner)
                };
                Ok(Value::Typed(name, Box::new(value)))
            }
            Some(b) if b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.') => {
                let start = self.at;
                while self
                    .peek()
                    .is_some_and(|b| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'E' | b'e'))
                {
                    self.at += 1;
                }
                let token = String::from_utf8_lossy(&self.bytes[start..self.at]).into_owned();
                match token.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(Value::Number(v)),
                    _ => Err(self.error(format!("`{token}` is not a finite number"))),
                }
            }
            _ => Err(self.found("a value")),
        }
    }
}

/// The instances of the DATA section, by id.
fn parse(text: &str) -> Result<HashMap<u64, Instance>, ParseError> {
    let start = text.trim_start_matches('\u{feff}').trim_start();
    if !start.starts_with("ISO-10303-21") {
        return Err(ParseError::new(
            Place::Line(1),
            "the file does not start with `ISO-10303-21;`: it is not a STEP (Part 21) file",
            "export the part as STEP AP203/AP214, or give a mesh file (OFF, STL, OBJ, PLY)",
        ));
    }
    let Some(data) = text.find("DATA;") else {
        return Err(ParseError::new(
            Place::Whole,
            "the file has no DATA section: it looks truncated",
            "export the file again and copy it whole",
        ));
    };
    let mut lexer = Lexer {
        bytes: text.as_bytes(),
        at: data + "DATA;".len(),
        line: 1 + text[..data].matches('\n').count(),
    };
    let mut instances = HashMap::new();
    loop {
        lexer.skip()?;
        match lexer.peek() {
            Some(b'#') => {
                lexer.at += 1;
                let line = lexer.line;
                let id = lexer.number();
                lexer.expect(b'=')?;
                lexer.skip()?;
                let parts = if lexer.peek() == Some(b'(') {
                    lexer.at += 1;
                    let mut parts = Vec::new();
                    loop {
                        lexer.skip()?;
                        if lexer.peek() == Some(b')') {
                            lexer.at += 1;
                            break;
                        }
                        let name = lexer.keyword();
                        if name.is_empty() {
                            return Err(lexer.found("an entity name"));
                        }
                        parts.push((name, lexer.list(0)?));
                    }
                    parts
                } else {
                    let name = lexer.keyword();
                    if name.is_empty() {
                        return Err(lexer.found("an entity name"));
                    }
                    vec![(name, lexer.list(0)?)]
                };
                lexer.expect(b';')?;
                if instances.insert(id, Instance { line, parts }).is_some() {
                    return Err(lexer.error(format!("instance #{id} is defined twice")));
                }
            }
            Some(b'E') => {
                if lexer.keyword() == "ENDSEC" {
                    lexer.expect(b';')?;
                    return Ok(instances);
                }
                return Err(lexer.error("expected an instance `#id = ...;` or `ENDSEC;`"));
            }
            None => {
                return Err(ParseError::new(
                    Place::Line(lexer.line),
                    "the file ends inside the DATA section (no `ENDSEC;`): it looks truncated",
                    "export the file again and copy it whole",
                ));
            }
            _ => return Err(lexer.found("an instance `#id = ...;` or `ENDSEC;`")),
        }
    }
}

/// Millimetres per unit of a length unit instance.
fn unit_mm(instances: &HashMap<u64, Instance>, id: u64, depth: usize) -> Result<f64, ParseError> {
    let fix = "export with a length unit of millimetres, metres or inches";
    let Some(unit) = instances.get(&id) else {
        return Err(ParseError::new(
            Place::Whole,
            format!("the length unit #{id} does not exist"),
            fix,
        ));
    };
    let place = Place::Line(unit.line);
    let name = unit.type_name();
    if depth > 4 {
        return Err(ParseError::new(
            place,
            format!("#{id} {name}: units refer to each other in a cycle"),
            fix,
        ));
    }
    if let Some(si) = unit.part("SI_UNIT") {
        let prefix = match si.first() {
            Some(Value::Enum(p)) => Some(p.as_str()),
            _ => None,
        };
        let base = match si.get(1) {
            Some(Value::Enum(b)) => b.as_str(),
            _ => "",
        };
        if base != "METRE" {
            return Err(ParseError::new(
                place,
                format!("#{id} {name}: the length unit is SI `{base}`, not a length (METRE)"),
                fix,
            ));
        }
        let factor = match prefix {
            None => 1000.0,
            Some("MILLI") => 1.0,
            Some("CENTI") => 10.0,
            Some("DECI") => 100.0,
            Some("MICRO") => 1e-3,
            Some("NANO") => 1e-6,
            Some("KILO") => 1e6,
            Some(other) => {
                return Err(ParseError::new(
                    place,
                    format!("#{id} {name}: the SI prefix `{other}` is not one acsg knows for lengths"),
                    fix,
                ));
            }
        };
        return Ok(factor);
    }
    if let Some(conversion) = unit.part("CONVERSION_BASED_UNIT") {
        let label = match conversion.first() {
            Some(Value::Text(t)) => t.clone(),
            _ => String::new(),
        };
        let Some(Value::Ref(measure)) = conversion.get(1) else {
            return Err(ParseError::new(
                place,
                format!("#{id} {name} ('{label}') has no conversion factor"),
                fix,
            ));
        };
        let Some(m) = instances.get(measure) else {
            return Err(ParseError::new(
                place,
                format!("#{id} {name} ('{label}'): #{measure} does not exist"),
                fix,
            ));
        };
        let args = m.parts.first().map(|(_, v)| v.as_slice()).unwrap_or_default();
        let value = match args.first() {
            Some(Value::Number(v)) => Some(*v),
            Some(Value::Typed(_, v)) => match v.as_ref() {
                Value::Number(v) => Some(*v),
                _ => None,
            },
            _ => None,
        };
        let (Some(value), Some(Value::Ref(base))) = (value, args.get(1)) else {
            return Err(ParseError::new(
                Place::Line(m.line),
                format!(
                    "#{measure} {}: the conversion of '{label}' is not a measure with a unit",
                    m.type_name()
                ),
                fix,
            ));
        };
        let mm = value * unit_mm(instances, *base, depth + 1)?;
        if !(mm.is_finite() && mm > 0.0) {
            return Err(ParseError::new(
                place,
                format!("#{id} {name}: '{label}' converts to {mm} mm"),
                fix,
            ));
        }
        return Ok(mm);
    }
    Err(ParseError::new(
        place,
        format!("#{id} {name} is not a length unit acsg knows (SI_UNIT or CONVERSION_BASED_UNIT)"),
        fix,
    ))
}

/// Millimetres per file unit, from the length unit of the global unit contexts.
fn length_unit(instances: &HashMap<u64, Instance>) -> Result<f64, ParseError> {
    let mut ids: Vec<(u64, usize)> = Vec::new();
    for instance in instances.values() {
        let Some(args) = instance.part("GLOBAL_UNIT_ASSIGNED_CONTEXT") else {
            continue;
        };
        let Some(Value::List(units)) = args.first() else {
            continue;
        };
        for unit in units {
            if let Value::Ref(r) = unit
                && instances.get(r).is_some_and(|u| u.part("LENGTH_UNIT").is_some())
            {
                ids.push((*r, instance.line));
            }
        }
    }
    ids.sort_unstable();
    ids.dedup_by_key(|(r, _)| *r);
    let Some(&(first, _)) = ids.first() else {
        return Err(ParseError::new(
            Place::Whole,
            "the file declares no length unit (no LENGTH_UNIT in a GLOBAL_UNIT_ASSIGNED_CONTEXT)",
            "export with a length unit (millimetres recommended)",
        ));
    };
    let mm = unit_mm(instances, first, 0)?;
    for &(other, line) in &ids[1..] {
        let other_mm = unit_mm(instances, other, 0)?;
        if (other_mm - mm).abs() > ROUNDOFF_REL * mm {
            return Err(ParseError::new(
                Place::Line(line),
                format!("the file declares two different length units (#{first} and #{other})"),
                "export the part alone, with one length unit",
            ));
        }
    }
    Ok(mm)
}

struct Model {
    instances: HashMap<u64, Instance>,
    to_mm: f64,
    /// How circles are faceted, when they are.
    facet: Option<Facet>,
}

/// Faceting of circles: `sides` per full circle (from the chord tolerance).
#[derive(Clone, Copy, Debug)]
struct Facet {
    sides: usize,
}

/// The most sides a faceted circle may have.
const MAX_SIDES: usize = 1 << 16;

/// A circle in millimetres: centre, in-plane axes (`x` the placement's reference
/// direction), normal `axis`, radius.
#[derive(Clone, Copy, Debug)]
struct Circle {
    centre: DVec3,
    x: DVec3,
    y: DVec3,
    axis: DVec3,
    radius: f64,
}

impl Circle {
    fn at(&self, angle: f64) -> DVec3 {
        self.centre + self.radius * (angle.cos() * self.x + angle.sin() * self.y)
    }

    /// The angle of `p` about the axis, in [0, 2π).
    fn angle(&self, p: DVec3) -> f64 {
        let d = p - self.centre;
        d.dot(self.y).atan2(d.dot(self.x)).rem_euclid(std::f64::consts::TAU)
    }
}

/// Entities that make a face or an edge curved.
const CURVED: &[&str] = &[
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
    "B_SPLINE_SURFACE",
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "BEZIER_SURFACE",
    "RATIONAL_B_SPLINE_SURFACE",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "SURFACE_OF_REVOLUTION",
    "OFFSET_SURFACE",
    "CIRCLE",
    "ELLIPSE",
    "HYPERBOLA",
    "PARABOLA",
    "B_SPLINE_CURVE",
    "B_SPLINE_CURVE_WITH_KNOTS",
    "BEZIER_CURVE",
    "RATIONAL_B_SPLINE_CURVE",
    "TRIMMED_CURVE",
    "OFFSET_CURVE_3D",
];

/// Surfaces read as planes when their control points are coplanar.
const SPLINE_SURFACES: &[&str] = &[
    "B_SPLINE_SURFACE_WITH_KNOTS",
    "B_SPLINE_SURFACE",
    "BEZIER_SURFACE",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
];

/// Curves read as straight edges when their control points are collinear.
const SPLINE_CURVES: &[&str] = &[
    "B_SPLINE_CURVE_WITH_KNOTS",
    "B_SPLINE_CURVE",
    "BEZIER_CURVE",
    "UNIFORM_CURVE",
    "QUASI_UNIFORM_CURVE",
];

impl Model {
    fn get(&self, id: u64, from: (u64, &Instance), what: &str) -> Result<&Instance, ParseError> {
        self.instances.get(&id).ok_or_else(|| {
            ParseError::new(
                Place::Line(from.1.line),
                format!("#{} {}: its {what} #{id} does not exist", from.0, from.1.type_name()),
                "the file is damaged or truncated; export it again",
            )
        })
    }

    /// The arguments of `instance` as one of `allowed`; anything else is refused.
    fn args<'a>(
        &self,
        id: u64,
        instance: &'a Instance,
        allowed: &[&str],
    ) -> Result<(&'a str, &'a [Value]), ParseError> {
        for (name, args) in &instance.parts {
            if allowed.contains(&name.as_str()) {
                return Ok((name.as_str(), args.as_slice()));
            }
        }
        let name = instance.type_name();
        let curved = instance.parts.iter().any(|(n, _)| CURVED.contains(&n.as_str()));
        let problem = if curved {
            format!("#{id} {name} is curved; acsg reads planar (polyhedral) solids only")
        } else {
            format!("#{id} {name} is not supported here (expected {})", allowed.join(" or "))
        };
        Err(ParseError::new(Place::Line(instance.line), problem, EXPORT_HINT))
    }

    fn bad(&self, id: u64, instance: &Instance, problem: &str) -> ParseError {
        ParseError::new(
            Place::Line(instance.line),
            format!("#{id} {}: {problem}", instance.type_name()),
            "the file is damaged; export it again",
        )
    }

    fn reference(&self, id: u64, instance: &Instance, value: Option<&Value>, what: &str) -> Result<u64, ParseError> {
        match value {
            Some(Value::Ref(r)) => Ok(*r),
            _ => Err(self.bad(id, instance, &format!("its {what} is not a reference"))),
        }
    }

    fn logical(&self, id: u64, instance: &Instance, value: Option<&Value>, what: &str) -> Result<bool, ParseError> {
        match value {
            Some(Value::Enum(e)) if e == "T" => Ok(true),
            Some(Value::Enum(e)) if e == "F" => Ok(false),
            _ => Err(self.bad(id, instance, &format!("its {what} is not .T. or .F."))),
        }
    }

    fn triple(&self, id: u64, instance: &Instance, value: Option<&Value>) -> Result<DVec3, ParseError> {
        if let Some(Value::List(c)) = value
            && let [Value::Number(x), Value::Number(y), Value::Number(z)] = c.as_slice()
        {
            return Ok(DVec3::new(*x, *y, *z));
        }
        Err(self.bad(id, instance, "it does not hold three numbers"))
    }

    fn point(&self, id: u64, from: (u64, &Instance)) -> Result<DVec3, ParseError> {
        let p = self.get(id, from, "point")?;
        let (_, args) = self.args(id, p, &["CARTESIAN_POINT"])?;
        Ok(self.triple(id, p, args.get(1))? * self.to_mm)
    }

    fn faces(&self) -> Result<Vec<PlanarFace>, ParseError> {
        let mut ids: Vec<&u64> = self.instances.keys().collect();
        ids.sort_unstable();
        let find = |name: &str| {
            ids.iter()
                .copied()
                .filter(|id| self.instances.get(id).is_some_and(|i| i.part(name).is_some()))
                .copied()
                .collect::<Vec<u64>>()
        };
        if let Some(&id) = find("BREP_WITH_VOIDS").first() {
            let i = &self.instances[&id];
            return Err(ParseError::new(
                Place::Line(i.line),
                format!("#{id} BREP_WITH_VOIDS: the solid has internal voids"),
                "acsg reads solids with one closed outer surface and no voids",
            ));
        }
        let mut shells = Vec::new();
        for id in find("MANIFOLD_SOLID_BREP").into_iter().chain(find("FACETED_BREP")) {
            let i = &self.instances[&id];
            let (_, args) = self.args(id, i, &["MANIFOLD_SOLID_BREP", "FACETED_BREP"])?;
            shells.push(self.reference(id, i, args.get(1), "outer shell")?);
        }
        if shells.is_empty() {
            shells = find("CLOSED_SHELL");
        }
        if shells.is_empty() {
            // Name what is there instead: a curved or surface model.
            let curved = ids.iter().find(|id| {
                self.instances
                    .get(id)
                    .is_some_and(|i| i.parts.iter().any(|(n, _)| CURVED.contains(&n.as_str())))
            });
            return Err(match curved {
                Some(&&id) => {
                    let i = &self.instances[&id];
                    ParseError::new(
                        Place::Line(i.line),
                        format!("the file holds no planar solid; #{id} {} is curved", i.type_name()),
                        EXPORT_HINT,
                    )
                }
                None => ParseError::new(
                    Place::Whole,
                    "the file holds no solid (no MANIFOLD_SOLID_BREP, FACETED_BREP or CLOSED_SHELL)",
                    EXPORT_HINT,
                ),
            });
        }
        let mut faces = Vec::new();
        for shell in shells {
            let Some(s) = self.instances.get(&shell) else {
                return Err(ParseError::new(
                    Place::Whole,
                    format!("the solid's shell #{shell} does not exist"),
                    "the file is damaged or truncated; export it again",
                ));
            };
            let (_, args) = self.args(shell, s, &["CLOSED_SHELL"])?;
            let Some(Value::List(list)) = args.get(1) else {
                return Err(self.bad(shell, s, "its faces are not a list"));
            };
            for f in list {
                let f = self.reference(shell, s, Some(f), "face")?;
                faces.extend(self.face(f, (shell, s), true, 0)?);
            }
        }
        Ok(faces)
    }

    fn face(
        &self,
        id: u64,
        from: (u64, &Instance),
        outward: bool,
        depth: usize,
    ) -> Result<Vec<PlanarFace>, ParseError> {
        let f = self.get(id, from, "face")?;
        let (kind, args) = self.args(id, f, &["ADVANCED_FACE", "FACE_SURFACE", "ORIENTED_FACE"])?;
        if kind == "ORIENTED_FACE" {
            let inner = self.reference(id, f, args.get(2), "face element")?;
            let same = self.logical(id, f, args.get(3), "orientation")?;
            if depth > 4 {
                return Err(self.bad(id, f, "oriented faces refer to each other in a cycle"));
            }
            return self.face(inner, (id, f), outward == same, depth + 1);
        }
        let surface = self.reference(id, f, args.get(2), "surface")?;
        let same_sense = self.logical(id, f, args.get(3), "same_sense flag")?;
        let Some(Value::List(bounds)) = args.get(1) else {
            return Err(self.bad(id, f, "its bounds are not a list"));
        };
        if let Some(facet) = self.facet {
            let s = self.get(surface, (id, f), "surface")?;
            if s.part("CYLINDRICAL_SURFACE").is_some() || s.part("CONICAL_SURFACE").is_some() {
                return self.round_face((id, f), (surface, s), bounds, outward == same_sense, facet);
            }
        }
        let normal = self.plane_normal(surface, (id, f))?;
        let mut loops = Vec::with_capacity(bounds.len());
        let mut outer = None;
        for b in bounds {
            let b = self.reference(id, f, Some(b), "bound")?;
            let bi = self.get(b, (id, f), "bound")?;
            let (bkind, bargs) = self.args(b, bi, &["FACE_OUTER_BOUND", "FACE_BOUND"])?;
            if bkind == "FACE_OUTER_BOUND" {
                outer = Some(loops.len());
            }
            let l = self.reference(b, bi, bargs.get(1), "loop")?;
            loops.push(self.loop_points(l, (b, bi))?);
        }
        Ok(vec![PlanarFace {
            normal: if outward == same_sense { normal } else { -normal },
            loops,
            outer,
            name: format!("face #{id}"),
            place: Place::Line(f.line),
        }])
    }

    /// The sides of every faceted circle: the fewest (a power of two, at least 8) for
    /// which the largest circle of the file strays at most `tolerance` mm from its
    /// polygon (`r (1 - cos(π / n)) <= tolerance`).
    fn circle_sides(&self, tolerance: f64) -> Result<usize, ParseError> {
        let mut largest = 0.0_f64;
        for (&id, instance) in &self.instances {
            if instance.part("CIRCLE").is_some() {
                largest = largest.max(self.circle(id, (id, instance))?.radius);
            }
        }
        let mut sides = 8;
        while largest * (1.0 - (std::f64::consts::PI / sides as f64).cos()) > tolerance {
            sides *= 2;
            if sides > MAX_SIDES {
                return Err(ParseError::new(
                    Place::Whole,
                    format!(
                        "a chord tolerance of {tolerance:e} mm needs more than {MAX_SIDES} sides for the circle of radius \
                         {largest} mm"
                    ),
                    "give a larger --facet tolerance",
                ));
            }
        }
        Ok(sides)
    }

    /// A CIRCLE instance in millimetres.
    fn circle(&self, id: u64, from: (u64, &Instance)) -> Result<Circle, ParseError> {
        let c = self.get(id, from, "circle")?;
        let (_, args) = self.args(id, c, &["CIRCLE"])?;
        let placement = self.reference(id, c, args.get(1), "placement")?;
        let radius = match args.get(2) {
            Some(Value::Number(r)) if r.is_finite() && *r > 0.0 => r * self.to_mm,
            _ => return Err(self.bad(id, c, "its radius is not a positive number")),
        };
        let (centre, axis, x) = self.placement(placement, (id, c))?;
        Ok(Circle {
            centre,
            x,
            y: axis.cross(x),
            axis,
            radius,
        })
    }

    /// An AXIS2_PLACEMENT_3D: origin (mm), unit axis, unit reference direction
    /// perpendicular to it.
    fn placement(&self, id: u64, from: (u64, &Instance)) -> Result<(DVec3, DVec3, DVec3), ParseError> {
        let p = self.get(id, from, "placement")?;
        let (_, args) = self.args(id, p, &["AXIS2_PLACEMENT_3D"])?;
        let origin = self.point(self.reference(id, p, args.get(1), "location")?, (id, p))?;
        let axis = match args.get(2) {
            Some(Value::Ref(r)) => self.direction(*r, (id, p))?,
            _ => DVec3::Z,
        };
        let reference = match args.get(3) {
            Some(Value::Ref(r)) => self.direction(*r, (id, p))?,
            _ => DVec3::X,
        };
        let axis = axis
            .try_normalize()
            .ok_or_else(|| self.bad(id, p, "its axis is zero"))?;
        let x = reference
            .reject_from_normalized(axis)
            .try_normalize()
            .or_else(|| axis.any_orthonormal_vector().try_normalize())
            .ok_or_else(|| self.bad(id, p, "its reference direction is zero"))?;
        Ok((origin, axis, x))
    }

    /// The circle an edge curve is, through surface, seam and trimmed curves; `None`
    /// for any other curve.
    fn circle_of(&self, id: u64, from: (u64, &Instance), depth: usize) -> Result<Option<Circle>, ParseError> {
        let c = self.get(id, from, "curve")?;
        if c.part("CIRCLE").is_some() {
            return self.circle(id, from).map(Some);
        }
        for wrapper in ["SURFACE_CURVE", "SEAM_CURVE", "TRIMMED_CURVE"] {
            if let Some(args) = c.part(wrapper)
                && depth < 4
            {
                let inner = self.reference(id, c, args.get(1), "curve")?;
                return self.circle_of(inner, (id, c), depth + 1);
            }
        }
        Ok(None)
    }

    /// The points of a faceted circular edge from `start` to `end` (both included):
    /// a full circle (`start` = `end`) is the polygon of `sides` corners from `start`,
    /// counter-clockwise about the axis; an arc takes the corners of the circle's own
    /// polygon (from its reference direction) that lie on it. `ccw` is the edge's
    /// direction about the axis (the circle's, unless the edge's sense flag is false).
    fn arc_points(circle: &Circle, start: DVec3, end: DVec3, ccw: bool, sides: usize, full: bool) -> Vec<DVec3> {
        use std::f64::consts::TAU;
        let step = TAU / sides as f64;
        if full {
            let a0 = circle.angle(start);
            let mut points: Vec<DVec3> = (0..sides).map(|k| circle.at(a0 + step * k as f64)).collect();
            points[0] = start;
            points.push(start);
            if !ccw {
                points.reverse();
            }
            return points;
        }
        // Walk counter-clockwise from the arc's first point to its last.
        let (from, to) = if ccw { (start, end) } else { (end, start) };
        let (a, mut b) = (circle.angle(from), circle.angle(to));
        if b <= a {
            b += TAU;
        }
        let mut points = vec![from];
        let first = (a / step).floor() as i64 + 1;
        let mut k = first;
        loop {
            let angle = step * k as f64;
            if angle >= b - ROUNDOFF_REL || points.len() > sides + 1 {
                break;
            }
            points.push(circle.at(angle));
            k += 1;
        }
        points.push(to);
        if !ccw {
            points.reverse();
        }
        points
    }

    /// A cylindrical or conical face made planar facets: the band of quadrilaterals
    /// between the polygons of the two full circles that bound it (its seam edges are
    /// dropped). `outward` says whether the face's normal is the surface's (away from
    /// the axis).
    fn round_face(
        &self,
        (id, f): (u64, &Instance),
        (surface_id, surface): (u64, &Instance),
        bounds: &[Value],
        outward: bool,
        facet: Facet,
    ) -> Result<Vec<PlanarFace>, ParseError> {
        let kind = surface.type_name();
        let refuse = |why: &str| {
            ParseError::new(
                Place::Line(f.line),
                format!("face #{id} on #{surface_id} {kind}: {why}"),
                format!(
                    "--facet makes planar facets of a whole cylinder or cone between two circles only; {EXPORT_HINT}"
                ),
            )
        };
        let args = surface
            .part("CYLINDRICAL_SURFACE")
            .or_else(|| surface.part("CONICAL_SURFACE"))
            .unwrap_or_default();
        let placement = self.reference(surface_id, surface, args.get(1), "placement")?;
        let (origin, axis, _) = self.placement(placement, (surface_id, surface))?;
        // The full circles among the face's edges.
        let mut circles: Vec<(Circle, DVec3)> = Vec::new();
        for b in bounds {
            let b = self.reference(id, f, Some(b), "bound")?;
            let bi = self.get(b, (id, f), "bound")?;
            let (_, bargs) = self.args(b, bi, &["FACE_OUTER_BOUND", "FACE_BOUND"])?;
            let l = self.reference(b, bi, bargs.get(1), "loop")?;
            let li = self.get(l, (b, bi), "loop")?;
            let (_, largs) = self.args(l, li, &["EDGE_LOOP"])?;
            let Some(Value::List(items)) = largs.get(1) else {
                return Err(self.bad(l, li, "its edges are not a list"));
            };
            for item in items {
                let oe = self.reference(l, li, Some(item), "oriented edge")?;
                let o = self.get(oe, (l, li), "oriented edge")?;
                let (_, oargs) = self.args(oe, o, &["ORIENTED_EDGE"])?;
                let edge = self.reference(oe, o, oargs.get(3), "edge element")?;
                let e = self.get(edge, (oe, o), "edge")?;
                let (_, eargs) = self.args(edge, e, &["EDGE_CURVE"])?;
                let start = self.vertex(self.reference(edge, e, eargs.get(1), "start vertex")?, (edge, e))?;
                let end = self.vertex(self.reference(edge, e, eargs.get(2), "end vertex")?, (edge, e))?;
                let curve = self.reference(edge, e, eargs.get(3), "curve")?;
                match self.circle_of(curve, (edge, e), 0)? {
                    Some(circle) if start.distance(end) <= scaled(WELD_REL, circle.radius.max(1.0)) => {
                        circles.push((circle, start));
                    }
                    Some(_) => return Err(refuse("it is bounded by an arc, not a whole circle")),
                    None => {
                        // A seam: a straight edge along the surface (dropped).
                        self.check_line(curve, (edge, e), 0)?;
                    }
                }
            }
        }
        let [(a, a_start), (b, b_start)] = circles.as_slice() else {
            return Err(refuse(&format!(
                "it is bounded by {} whole circles, not two",
                circles.len()
            )));
        };
        let sides = facet.sides;
        let ring = |c: &Circle, start: DVec3| Self::arc_points(c, start, start, true, sides, true);
        let mut ring_a = ring(a, *a_start);
        let mut ring_b = ring(b, *b_start);
        ring_a.pop();
        ring_b.pop();
        // Both rings counter-clockwise about the surface's axis.
        if a.axis.dot(axis) < 0.0 {
            ring_a[1..].reverse();
        }
        if b.axis.dot(axis) < 0.0 {
            ring_b[1..].reverse();
        }
        // Corner k of each ring must lie on the same line through the axis.
        let about = |p: DVec3| {
            let d = (p - origin).reject_from_normalized(axis);
            d.try_normalize().unwrap_or(DVec3::ZERO)
        };
        for (p, q) in ring_a.iter().zip(&ring_b) {
            if about(*p).distance(about(*q)) > COPLANAR_REL {
                return Err(refuse(
                    "its two circles do not start at the same angle about the axis (their seam is not straight)",
                ));
            }
        }
        let mut facets = Vec::with_capacity(sides);
        for k in 0..sides {
            let n = (k + 1) % sides;
            let quad = vec![ring_a[k], ring_a[n], ring_b[n], ring_b[k]];
            let mut normal = area_vector(&quad);
            let centre = quad.iter().copied().sum::<DVec3>() / 4.0;
            if normal.dot((centre - origin).reject_from_normalized(axis)) < 0.0 {
                normal = -normal;
            }
            // A cone's apex ring has no area: no facet there.
            let scale = a.radius.max(b.radius);
            if normal.length() <= AREA_REL * scale * scale {
                continue;
            }
            facets.push(PlanarFace {
                normal: if outward { normal } else { -normal },
                loops: vec![quad],
                outer: Some(0),
                name: format!("facet {k} of face #{id}"),
                place: Place::Line(f.line),
            });
        }
        Ok(facets)
    }

    fn plane_normal(&self, id: u64, from: (u64, &Instance)) -> Result<DVec3, ParseError> {
        let s = self.get(id, from, "surface")?;
        if s.part("PLANE").is_none()
            && let Some(net) = self.spline_net(id, s, SPLINE_SURFACES)?
        {
            // A B-spline surface whose control points are coplanar is that plane
            // (OpenCASCADE writes chamfers so).
            return match net_shape(&net) {
                NetShape::Plane(normal) => Ok(normal),
                NetShape::Curved { deviation, tolerance } => Err(ParseError::new(
                    Place::Line(s.line),
                    format!(
                        "#{id} {} is curved: its control points lie up to {deviation:.3e} mm off a plane (more \
                         than the {tolerance:.1e} mm tolerance); acsg reads planar (polyhedral) solids only",
                        s.type_name()
                    ),
                    EXPORT_HINT,
                )),
                NetShape::Degenerate => Err(self.bad(id, s, "its control points span no area")),
            };
        }
        let (_, args) = self.args(id, s, &["PLANE"])?;
        let placement = self.reference(id, s, args.get(1), "placement")?;
        let p = self.get(placement, (id, s), "placement")?;
        let (_, pargs) = self.args(placement, p, &["AXIS2_PLACEMENT_3D"])?;
        match pargs.get(2) {
            Some(Value::Ref(axis)) => self.direction(*axis, (placement, p)),
            _ => Ok(DVec3::Z),
        }
    }

    /// The control points of a B-spline or Bézier surface (rows along u) or curve (one
    /// row), in millimetres: the first list of references (of lists of references, for
    /// a surface) in one of the instance's `kinds` parts. A simple instance has its
    /// name first; a complex (rational) one keeps the points in its `B_SPLINE_*` part.
    /// `None` when the instance is none of `kinds`.
    fn spline_net(&self, id: u64, instance: &Instance, kinds: &[&str]) -> Result<Option<Vec<Vec<DVec3>>>, ParseError> {
        let refs = |list: &[Value]| -> Option<Vec<u64>> {
            list.iter()
                .map(|v| match v {
                    Value::Ref(r) => Some(*r),
                    _ => None,
                })
                .collect()
        };
        let mut found = false;
        for (name, args) in &instance.parts {
            if !kinds.contains(&name.as_str()) {
                continue;
            }
            found = true;
            for arg in args {
                let Value::List(items) = arg else { continue };
                let rows: Option<Vec<Vec<u64>>> = if kinds == SPLINE_SURFACES {
                    items
                        .iter()
                        .map(|row| match row {
                            Value::List(row) => refs(row),
                            _ => None,
                        })
                        .collect()
                } else {
                    refs(items).map(|row| vec![row])
                };
                let Some(rows) = rows.filter(|r| !r.is_empty() && r.iter().all(|row| !row.is_empty())) else {
                    continue;
                };
                let mut net = Vec::with_capacity(rows.len());
                for row in rows {
                    net.push(
                        row.into_iter()
                            .map(|r| self.point(r, (id, instance)))
                            .collect::<Result<Vec<_>, _>>()?,
                    );
                }
                return Ok(Some(net));
            }
        }
        if found {
            Err(self.bad(id, instance, "its control points are not a list of points"))
        } else {
            Ok(None)
        }
    }

    fn direction(&self, id: u64, from: (u64, &Instance)) -> Result<DVec3, ParseError> {
        let d = self.get(id, from, "direction")?;
        let (_, args) = self.args(id, d, &["DIRECTION"])?;
        self.triple(id, d, args.get(1))
    }

    fn loop_points(&self, id: u64, from: (u64, &Instance)) -> Result<Vec<DVec3>, ParseError> {
        let l = self.get(id, from, "loop")?;
        let (kind, args) = self.args(id, l, &["EDGE_LOOP", "POLY_LOOP"])?;
        let Some(Value::List(items)) = args.get(1) else {
            return Err(self.bad(id, l, "its edges are not a list"));
        };
        if kind == "POLY_LOOP" {
            return items
                .iter()
                .map(|p| self.point(self.reference(id, l, Some(p), "point")?, (id, l)))
                .collect();
        }
        let mut points = Vec::with_capacity(items.len());
        let mut ends = Vec::with_capacity(items.len());
        // Where each edge's points begin in `points`.
        let mut starts = Vec::with_capacity(items.len());
        for item in items {
            starts.push(points.len());
            let oe = self.reference(id, l, Some(item), "oriented edge")?;
            let o = self.get(oe, (id, l), "oriented edge")?;
            let (_, oargs) = self.args(oe, o, &["ORIENTED_EDGE"])?;
            let edge = self.reference(oe, o, oargs.get(3), "edge element")?;
            let forward = self.logical(oe, o, oargs.get(4), "orientation")?;
            let e = self.get(edge, (oe, o), "edge")?;
            let (_, eargs) = self.args(edge, e, &["EDGE_CURVE"])?;
            let start = self.vertex(self.reference(edge, e, eargs.get(1), "start vertex")?, (edge, e))?;
            let end = self.vertex(self.reference(edge, e, eargs.get(2), "end vertex")?, (edge, e))?;
            let curve = self.reference(edge, e, eargs.get(3), "curve")?;
            let circle = match self.facet {
                Some(_) => self.circle_of(curve, (edge, e), 0)?,
                None => None,
            };
            let mut chain = match (circle, self.facet) {
                (Some(circle), Some(facet)) => {
                    let sense = !matches!(eargs.get(4), Some(Value::Enum(v)) if v == "F");
                    let full = start.distance(end) <= scaled(WELD_REL, circle.radius.max(1.0));
                    Self::arc_points(&circle, start, end, sense, facet.sides, full)
                }
                _ => {
                    self.check_line(curve, (edge, e), 0)?;
                    vec![start, end]
                }
            };
            if !forward {
                chain.reverse();
            }
            let b = chain.pop().unwrap_or(end);
            points.extend(chain);
            ends.push((oe, o, b));
        }
        // The oriented edges must join head to tail.
        let size = points.iter().map(|p| p.abs().max_element()).fold(1.0, f64::max);
        for (k, (oe, o, end)) in ends.iter().enumerate() {
            let next = starts.get(k + 1).or(starts.first()).map_or(*end, |&i| points[i]);
            if end.distance(next) > JOIN_REL * size {
                return Err(ParseError::new(
                    Place::Line(o.line),
                    format!("#{oe} ORIENTED_EDGE of loop #{id}: it ends where the next edge does not start"),
                    "the loop is broken; export the file again",
                ));
            }
        }
        Ok(points)
    }

    fn vertex(&self, id: u64, from: (u64, &Instance)) -> Result<DVec3, ParseError> {
        let v = self.get(id, from, "vertex")?;
        let (_, args) = self.args(id, v, &["VERTEX_POINT"])?;
        self.point(self.reference(id, v, args.get(1), "point")?, (id, v))
    }

    /// An edge's geometry must be straight: a LINE (also as a surface curve's 3D curve
    /// or a trimmed curve's basis), a POLYLINE or a B-spline or Bézier curve whose
    /// points are collinear (within [`crate::tolerance::COPLANAR_REL`] of their extent).
    fn check_line(&self, id: u64, from: (u64, &Instance), depth: usize) -> Result<(), ParseError> {
        let c = self.get(id, from, "curve")?;
        if let Some(net) = self.spline_net(id, c, SPLINE_CURVES)? {
            return self.straight(id, c, &net.concat());
        }
        let (kind, args) = self.args(
            id,
            c,
            &["LINE", "POLYLINE", "SURFACE_CURVE", "SEAM_CURVE", "TRIMMED_CURVE"],
        )?;
        match kind {
            "POLYLINE" => match args.get(1) {
                Some(Value::List(points)) if points.len() >= 2 => {
                    let points = points
                        .iter()
                        .map(|p| self.point(self.reference(id, c, Some(p), "point")?, (id, c)))
                        .collect::<Result<Vec<_>, _>>()?;
                    self.straight(id, c, &points)
                }
                _ => Err(self.bad(id, c, "its points are not a list of two or more")),
            },
            "SURFACE_CURVE" | "SEAM_CURVE" | "TRIMMED_CURVE" if depth < 4 => {
                let what = if kind == "TRIMMED_CURVE" {
                    "basis curve"
                } else {
                    "3D curve"
                };
                let inner = self.reference(id, c, args.get(1), what)?;
                self.check_line(inner, (id, c), depth + 1)
            }
            "LINE" => Ok(()),
            _ => Err(self.bad(id, c, "curves nest too deep")),
        }
    }

    /// Refuses a curve whose points are not collinear, naming it.
    fn straight(&self, id: u64, c: &Instance, points: &[DVec3]) -> Result<(), ParseError> {
        let (deviation, tolerance) = line_deviation(points);
        if deviation <= tolerance {
            return Ok(());
        }
        Err(ParseError::new(
            Place::Line(c.line),
            format!(
                "#{id} {} is curved: its points lie up to {deviation:.3e} mm off a straight line (more than the \
                 {tolerance:.1e} mm tolerance); acsg reads straight edges only",
                c.type_name()
            ),
            EXPORT_HINT,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::super::text::testing::{read_every_prefix, xorshift};
    use super::*;

    const PEG: &str = include_str!("../../../../fixtures/cad/peg.step");

    #[test]
    fn the_peg_reads_with_six_faces() {
        let soup = read(PEG.as_bytes()).expect("reads");
        assert_eq!(soup.polygons.len(), 6);
    }

    #[test]
    fn values_parse() {
        let text =
            "ISO-10303-21;\nDATA;\n#1 = A('it''s', (1., -2.5E1, #3), .T., $, *, B(4.));\n#2 = ( C() D(1) );\nENDSEC;\n";
        let instances = parse(text).expect("parses");
        let a = &instances[&1];
        assert_eq!(a.line, 3);
        assert_eq!(
            a.parts[0].1,
            vec![
                Value::Text("it's".into()),
                Value::List(vec![Value::Number(1.0), Value::Number(-25.0), Value::Ref(3)]),
                Value::Enum("T".into()),
                Value::Unset,
                Value::Unset,
                Value::Typed("B".into(), Box::new(Value::Number(4.0))),
            ]
        );
        assert_eq!(instances[&2].type_name(), "(C D)");
    }

    #[test]
    fn no_prefix_or_mutation_panics() {
        read_every_prefix(|b| read(b), &PEG.as_bytes()[..PEG.len().min(4000)]);
        let mut state = 0x9e37_79b9_u64;
        for _ in 0..300 {
            let mut bytes = PEG.as_bytes().to_vec();
            for _ in 0..4 {
                let at = (xorshift(&mut state) as usize) % bytes.len();
                bytes[at] = b" 0123456789,;#().'$*TFE"[(xorshift(&mut state) % 23) as usize];
            }
            let _ = read(bytes.as_slice());
        }
        let deep = format!("ISO-10303-21;\nDATA;\n#1 = A({});\nENDSEC;\n", "(".repeat(10_000));
        assert!(read(deep.as_bytes()).is_err());
    }
}
