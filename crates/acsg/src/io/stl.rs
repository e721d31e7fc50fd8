//! Reader of STL models, binary or ASCII.
//!
//! Every triangle corner becomes its own point (3 per triangle, no welding: the
//! topology code welds with a tolerance), so triangle `t` is polygon
//! `[3t, 3t + 1, 3t + 2]`. Facet normals are ignored; the winding is the file's.
//!
//! A file is binary when its length is exactly `84 + 50 × count` for the triangle
//! count stored at byte 80, even when its 80-byte header starts with `solid` (some
//! exporters write that). Otherwise it is ASCII when it starts with `solid` and holds
//! no NUL byte near its start, and a binary file of the wrong length otherwise.
//! Binary triangles are decoded by `stl_io`; the ASCII parser is written here so that
//! every error names its line.

use std::borrow::Cow;
use std::io::{Cursor, Read};

use glam::DVec3;

use super::text::{TextLines, finite_vertex, parse_f64, read_limited, to_u32};
use super::{MeshSoup, ParseError, Place};

/// Bytes before the first triangle of a binary STL: header and triangle count.
const BINARY_HEADER: u64 = 84;
/// Bytes per triangle of a binary STL.
const BINARY_TRIANGLE: u64 = 50;

/// Reads an STL model, binary or ASCII.
///
/// # Errors
/// A [`ParseError`]: for an empty file; for binary, a length that does not match the
/// declared triangle count (truncated or padded) or a non-finite coordinate, at the
/// byte concerned; for ASCII, a missing or misplaced keyword, a bad or non-finite
/// number, a facet without exactly 3 vertices, or a file ending inside a facet or
/// before `endsolid`, at the line concerned.
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(ParseError::new(
            Place::Whole,
            "the file is empty",
            "export the part again as STL",
        ));
    }
    let len = bytes.len() as u64;
    let declared = bytes
        .get(80..84)
        .and_then(|count| <[u8; 4]>::try_from(count).ok())
        .map(u32::from_le_bytes);
    if let Some(count) = declared
        && binary_length(count) == len
    {
        return read_binary(bytes, count);
    }
    if looks_ascii(&bytes) {
        return parse_ascii(&bytes);
    }
    Err(binary_length_error(len, declared))
}

/// The length of a binary STL holding `count` triangles.
fn binary_length(count: u32) -> u64 {
    BINARY_HEADER + BINARY_TRIANGLE * u64::from(count)
}

/// Whether the bytes start like an ASCII STL: `solid`, then either no NUL byte in the
/// first 84 bytes (a binary header that starts with `solid` is nearly always followed by
/// a count holding a NUL byte) or a second line starting with `facet` or `endsolid`.
fn looks_ascii(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = bytes.get(start..).unwrap_or_default();
    let keyword = rest.get(..5).is_some_and(|k| k.eq_ignore_ascii_case(b"solid"));
    let separated = rest.get(5).is_none_or(u8::is_ascii_whitespace);
    if !(keyword && separated) {
        return false;
    }
    let no_nul = !bytes.iter().take(BINARY_HEADER as usize).any(|&b| b == 0);
    let second = rest
        .iter()
        .position(|&b| b == b'\n')
        .and_then(|end| rest.get(end..))
        .unwrap_or_default();
    let second = second
        .iter()
        .position(|&b| !(b.is_ascii_whitespace() || b == 0))
        .and_then(|s| second.get(s..));
    let starts = |word: &[u8]| {
        second
            .and_then(|t| t.get(..word.len()))
            .is_some_and(|t| t.eq_ignore_ascii_case(word))
    };
    no_nul || starts(b"facet") || starts(b"endsolid")
}

/// The error for a binary STL whose length does not match its triangle count.
fn binary_length_error(len: u64, declared: Option<u32>) -> ParseError {
    let Some(count) = declared else {
        return ParseError::new(
            Place::Byte(len),
            format!(
                "the file has {len} bytes: it does not start with `solid` (ASCII STL) and is shorter than the {BINARY_HEADER}-byte header of a binary STL"
            ),
            "the file is truncated or is not an STL file: export it again",
        );
    };
    let expected = binary_length(count);
    if len < expected {
        let present = (len - BINARY_HEADER) / BINARY_TRIANGLE;
        ParseError::new(
            Place::Byte(len),
            format!(
                "the binary header declares {count} triangles ({expected} bytes) but the file ends at byte {len}, after {present} complete triangle(s)"
            ),
            "the file is truncated: export or copy it again",
        )
    } else {
        let extra = len - expected;
        let room = if (len - BINARY_HEADER) % BINARY_TRIANGLE == 0 {
            format!(
                " (the length fits {} triangles)",
                (len - BINARY_HEADER) / BINARY_TRIANGLE
            )
        } else {
            String::new()
        };
        ParseError::new(
            Place::Byte(expected),
            format!(
                "the binary header declares {count} triangles, which end at byte {expected}, but {extra} more byte(s) follow{room}"
            ),
            "the triangle count at byte 80 is wrong or data was appended: export the file again",
        )
    }
}

fn read_binary(mut bytes: Vec<u8>, count: u32) -> Result<MeshSoup, ParseError> {
    // `stl_io` reads ASCII when the first line starts with "solid ". The header holds
    // no geometry, so its first two bytes are overwritten with "\0\n": `stl_io` then
    // reads binary, and its ASCII probe stops at once.
    for (byte, value) in bytes.iter_mut().zip(b"\0\n") {
        *byte = *value;
    }
    let mut cursor = Cursor::new(bytes.as_slice());
    let triangles = stl_io::create_stl_reader(&mut cursor).map_err(|e| {
        ParseError::new(
            Place::Byte(0),
            format!("cannot read the binary STL header: {e}"),
            "export the file again",
        )
    })?;
    let count = usize::try_from(count).unwrap_or(usize::MAX);
    let mut soup = MeshSoup {
        polygon_noun: "triangle",
        ..MeshSoup::default()
    };
    soup.positions.reserve(count.saturating_mul(3));
    soup.polygons.reserve(count);
    soup.polygon_lines = vec![None; count];
    for (t, triangle) in triangles.enumerate() {
        let offset = BINARY_HEADER + BINARY_TRIANGLE * t as u64;
        let triangle = triangle.map_err(|e| {
            ParseError::new(
                Place::Byte(offset),
                format!("cannot read triangle {t}: {e}"),
                "the file is damaged: export it again",
            )
        })?;
        let first = soup.positions.len();
        for (corner, vertex) in (0u64..).zip(triangle.vertices) {
            let place = Place::Byte(offset + 12 + 12 * corner);
            let index = soup.positions.len();
            let what = format!("vertex {index} (corner {corner} of triangle {t})");
            soup.positions
                .push(finite_vertex(vertex.0.map(f64::from), &what, place)?);
        }
        let place = Place::Byte(offset);
        soup.polygons.push(vec![
            to_u32(first, place)?,
            to_u32(first + 1, place)?,
            to_u32(first + 2, place)?,
        ]);
    }
    if soup.polygons.len() != count {
        return Err(ParseError::new(
            Place::Byte(binary_length(u32::try_from(soup.polygons.len()).unwrap_or(u32::MAX))),
            format!(
                "the binary header declares {count} triangles but {} were read",
                soup.polygons.len()
            ),
            "the file is damaged: export it again",
        ));
    }
    Ok(soup)
}

/// Separates the words of an ASCII STL line (NUL padding counts as space).
fn is_separator(c: char) -> bool {
    c.is_whitespace() || c == '\0'
}

/// The words of a line.
fn words(text: &str) -> impl Iterator<Item = &str> {
    text.split(is_separator).filter(|w| !w.is_empty())
}

/// The ASCII STL lines that hold words.
struct Lines<'a> {
    lines: TextLines<'a>,
}

impl<'a> Lines<'a> {
    fn next(&mut self) -> Option<(usize, Cow<'a, str>)> {
        self.lines.by_ref().find(|(_, text)| words(text).next().is_some())
    }

    /// The next line, which must exist because a facet is open.
    fn inside_facet(&mut self, facet_line: usize) -> Result<(usize, Cow<'a, str>), ParseError> {
        self.next().ok_or_else(|| {
            let last = self.lines.last_line().max(1);
            ParseError::new(
                Place::Line(last),
                format!("the file ends at line {last}, inside the facet that starts on line {facet_line}"),
                "the file looks truncated: export it again",
            )
        })
    }

    /// Reads a line that must hold exactly `expected` (case-insensitive).
    fn expect(&mut self, expected: &[&str], facet_line: usize) -> Result<usize, ParseError> {
        let (number, text) = self.inside_facet(facet_line)?;
        let found: Vec<&str> = words(&text).collect();
        let matches =
            found.len() == expected.len() && found.iter().zip(expected).all(|(f, e)| f.eq_ignore_ascii_case(e));
        if matches {
            Ok(number)
        } else {
            Err(ParseError::new(
                Place::Line(number),
                format!(
                    "expected `{}` in the facet that starts on line {facet_line}, found `{}`",
                    expected.join(" "),
                    found.join(" ")
                ),
                "each facet reads `facet normal ...`, `outer loop`, three `vertex x y z` lines, `endloop`, `endfacet`",
            ))
        }
    }
}

fn parse_ascii(bytes: &[u8]) -> Result<MeshSoup, ParseError> {
    let mut lines = Lines {
        lines: TextLines::new(bytes, 1),
    };
    let mut soup = MeshSoup {
        polygon_noun: "triangle",
        ..MeshSoup::default()
    };
    // The line of the `solid` keyword of the solid being read, if one is open.
    let mut open_solid: Option<usize> = None;
    let mut seen_solid = false;
    loop {
        let Some((number, text)) = lines.next() else {
            if let Some(solid_line) = open_solid {
                let last = lines.lines.last_line().max(1);
                return Err(ParseError::new(
                    Place::Line(last),
                    format!(
                        "the file ends at line {last} without the `endsolid` of the solid that starts on line {solid_line}"
                    ),
                    "the file looks truncated: export it again (if it is complete, add a line `endsolid`)",
                ));
            }
            break;
        };
        let keyword = words(&text).next().unwrap_or_default();
        let place = Place::Line(number);
        match open_solid {
            None if keyword.eq_ignore_ascii_case("solid") => {
                open_solid = Some(number);
                seen_solid = true;
            }
            None if seen_solid => {
                return Err(ParseError::new(
                    place,
                    format!("expected `solid` or the end of the file after `endsolid`, found `{keyword}`"),
                    "delete the text after `endsolid`, or export the file again",
                ));
            }
            None => {
                return Err(ParseError::new(
                    place,
                    format!("an ASCII STL starts with `solid`, found `{keyword}`"),
                    "check that the file is STL; export it again",
                ));
            }
            Some(_) if keyword.eq_ignore_ascii_case("endsolid") => open_solid = None,
            Some(_) if keyword.eq_ignore_ascii_case("facet") => parse_facet(&mut lines, number, &mut soup)?,
            Some(solid_line) => {
                return Err(ParseError::new(
                    place,
                    format!(
                        "expected `facet` or `endsolid` in the solid that starts on line {solid_line}, found `{keyword}`"
                    ),
                    "each facet reads `facet normal ...`, `outer loop`, three `vertex x y z` lines, `endloop`, `endfacet`",
                ));
            }
        }
    }
    Ok(soup)
}

/// Reads one facet, from the line after `facet normal ...` (normals are ignored).
fn parse_facet(lines: &mut Lines<'_>, facet_line: usize, soup: &mut MeshSoup) -> Result<(), ParseError> {
    let triangle = soup.polygons.len();
    lines.expect(&["outer", "loop"], facet_line)?;
    let mut corners: Vec<DVec3> = Vec::with_capacity(3);
    let endloop_line = loop {
        let (number, text) = lines.inside_facet(facet_line)?;
        let place = Place::Line(number);
        let mut tokens = words(&text);
        let keyword = tokens.next().unwrap_or_default();
        if keyword.eq_ignore_ascii_case("endloop") {
            break number;
        }
        if !keyword.eq_ignore_ascii_case("vertex") {
            return Err(ParseError::new(
                place,
                format!(
                    "expected `vertex` or `endloop` in the facet that starts on line {facet_line}, found `{keyword}`"
                ),
                "each facet reads `facet normal ...`, `outer loop`, three `vertex x y z` lines, `endloop`, `endfacet`",
            ));
        }
        let corner = corners.len();
        if corner == 3 {
            return Err(ParseError::new(
                place,
                format!("triangle {triangle} (the facet on line {facet_line}) has more than 3 vertices"),
                "STL facets are triangles: triangulate the model when exporting",
            ));
        }
        let index = soup.positions.len() + corner;
        let vertex = format!("vertex {index} (corner {corner} of triangle {triangle})");
        let values: Vec<&str> = tokens.collect();
        let &[x, y, z] = values.as_slice() else {
            return Err(ParseError::new(
                place,
                format!("{vertex} has {} value(s); it needs 3 coordinates x y z", values.len()),
                "write each vertex as `vertex x y z`",
            ));
        };
        let p = [
            parse_f64(x, &format!("the x coordinate of {vertex}"), place)?,
            parse_f64(y, &format!("the y coordinate of {vertex}"), place)?,
            parse_f64(z, &format!("the z coordinate of {vertex}"), place)?,
        ];
        corners.push(finite_vertex(p, &vertex, place)?);
    };
    if corners.len() != 3 {
        return Err(ParseError::new(
            Place::Line(endloop_line),
            format!(
                "triangle {triangle} (the facet on line {facet_line}) has {} vertices; an STL facet has exactly 3",
                corners.len()
            ),
            "remove the degenerate facet or export the model again",
        ));
    }
    lines.expect(&["endfacet"], facet_line)?;
    let first = soup.positions.len();
    let place = Place::Line(facet_line);
    soup.positions.extend(corners);
    soup.polygons.push(vec![
        to_u32(first, place)?,
        to_u32(first + 1, place)?,
        to_u32(first + 2, place)?,
    ]);
    soup.polygon_lines.push(Some(facet_line));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::text::testing::{expect_err, read_every_prefix, xorshift};
    use std::fmt::Write as _;

    /// The 12 triangles of a unit cube, counter-clockwise seen from outside.
    fn cube_triangles() -> Vec<[[f32; 3]; 3]> {
        let p = |i: usize| -> [f32; 3] { [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32] };
        // Corner i has x = bit 0, y = bit 1, z = bit 2.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [1, 3, 7, 5],
            [3, 2, 6, 7],
            [2, 0, 4, 6],
        ];
        quads
            .iter()
            .flat_map(|q| [[p(q[0]), p(q[1]), p(q[2])], [p(q[0]), p(q[2]), p(q[3])]])
            .collect()
    }

    fn cube_ascii() -> String {
        let mut text = String::from("solid cube\n");
        for t in cube_triangles() {
            text.push_str("  facet normal 0 0 0\n    outer loop\n");
            for v in t {
                writeln!(text, "      vertex {} {} {}", v[0], v[1], v[2]).unwrap();
            }
            text.push_str("    endloop\n  endfacet\n");
        }
        text.push_str("endsolid cube\n");
        text
    }

    fn cube_binary(header: &[u8]) -> Vec<u8> {
        let triangles: Vec<stl_io::Triangle> = cube_triangles()
            .into_iter()
            .map(|t| stl_io::Triangle {
                normal: stl_io::Normal::new([0.0; 3]),
                vertices: t.map(stl_io::Vertex::new),
            })
            .collect();
        let mut bytes = Vec::new();
        stl_io::write_stl(&mut bytes, triangles.iter()).unwrap();
        for (b, h) in bytes.iter_mut().zip(header) {
            *b = *h;
        }
        bytes
    }

    fn check_cube(soup: &MeshSoup) {
        let expected = cube_triangles();
        assert_eq!(soup.positions.len(), 36);
        assert_eq!(soup.polygons.len(), 12);
        assert_eq!(soup.polygon_noun, "triangle");
        for (t, triangle) in expected.iter().enumerate() {
            let base = 3 * t as u32;
            assert_eq!(soup.polygons[t], vec![base, base + 1, base + 2]);
            for (c, v) in triangle.iter().enumerate() {
                assert_eq!(soup.positions[3 * t + c], DVec3::from_array(v.map(f64::from)));
            }
        }
    }

    fn err(bytes: &[u8]) -> ParseError {
        expect_err(read(bytes))
    }

    #[test]
    fn reads_ascii_cube() {
        let soup = read(cube_ascii().as_bytes()).unwrap();
        check_cube(&soup);
        assert_eq!(soup.polygon_lines[0], Some(2));
        assert_eq!(soup.polygon_lines[1], Some(9));
    }

    #[test]
    fn reads_binary_cube() {
        let soup = read(cube_binary(b"").as_slice()).unwrap();
        check_cube(&soup);
        assert!(soup.polygon_lines.iter().all(Option::is_none));
        assert_eq!(soup.polygon_lines.len(), 12);
        // A binary file whose header starts with "solid" and even "facet".
        let soup = read(cube_binary(b"solid cube facet normal").as_slice()).unwrap();
        check_cube(&soup);
    }

    #[test]
    fn ascii_variants() {
        // Upper case, CRLF, several solids, no name, trailing NUL padding.
        let text = "SOLID\r\nFACET NORMAL 0 0 1\r\nOUTER LOOP\r\nVERTEX 0 0 0\r\nVERTEX 1 0 0\r\nVERTEX 0 1 0\r\nENDLOOP\r\nENDFACET\r\nENDSOLID\r\nsolid b\nfacet normal -nan(ind) 0 0\nouter loop\nvertex 0 0 1\nvertex 1 0 1\nvertex 0 1 1\nendloop\nendfacet\nendsolid b\n\0\0";
        let soup = read(text.as_bytes()).unwrap();
        assert_eq!(soup.polygons, vec![vec![0, 1, 2], vec![3, 4, 5]]);
        assert_eq!(soup.polygon_lines, vec![Some(2), Some(11)]);
        assert_eq!(soup.positions[5], DVec3::new(0.0, 1.0, 1.0));
        // No facets: not a parse error.
        let soup = read("solid empty\nendsolid empty\n".as_bytes()).unwrap();
        assert!(soup.polygons.is_empty());
    }

    #[test]
    fn empty_input() {
        let e = err(b"");
        assert_eq!(e.place, Place::Whole);
        assert!(e.problem.contains("empty"), "{e}");
        let e = err(b"  \n ");
        assert!(e.problem.contains("empty"), "{e}");
    }

    #[test]
    fn truncated_binary() {
        let bytes = cube_binary(b"");
        let e = err(&bytes[..bytes.len() - 30]);
        assert_eq!(e.place, Place::Byte(bytes.len() as u64 - 30));
        assert!(
            e.problem.contains("declares 12 triangles") && e.problem.contains("after 11 complete"),
            "{e}"
        );
        // Header starting with "solid": still reported as binary.
        let bytes = cube_binary(b"solid cube");
        let e = err(&bytes[..200]);
        assert_eq!(e.place, Place::Byte(200));
        assert!(
            e.problem.contains("declares 12 triangles") && e.problem.contains("after 2 complete"),
            "{e}"
        );
        let e = err(&bytes[..50]);
        assert!(
            e.problem.contains("shorter than the 84-byte header") || e.place == Place::Line(1),
            "{e}"
        );
        let e = err(&[1u8; 50]);
        assert_eq!(e.place, Place::Byte(50));
        assert!(e.problem.contains("shorter than the 84-byte header"), "{e}");
    }

    #[test]
    fn padded_binary() {
        let mut bytes = cube_binary(b"");
        bytes.extend_from_slice(&[0; 50]);
        let e = err(&bytes);
        assert_eq!(e.place, Place::Byte(84 + 600));
        assert!(
            e.problem.contains("50 more byte(s)") && e.problem.contains("fits 13 triangles"),
            "{e}"
        );
    }

    #[test]
    fn huge_declared_count_is_checked_before_reading() {
        let mut bytes = vec![0u8; 84 + 50];
        bytes[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = err(&bytes);
        assert_eq!(e.place, Place::Byte(134));
        assert!(e.problem.contains(&format!("declares {} triangles", u32::MAX)), "{e}");
    }

    #[test]
    fn binary_non_finite() {
        let mut bytes = cube_binary(b"");
        // Triangle 1, corner 2, y coordinate.
        let at = 84 + 50 + 12 + 24 + 4;
        bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = err(&bytes);
        assert_eq!(e.place, Place::Byte(84 + 50 + 12 + 24));
        assert!(
            e.problem.starts_with("vertex 5 (corner 2 of triangle 1)") && e.problem.contains("not finite"),
            "{e}"
        );
    }

    #[test]
    fn ascii_errors() {
        let good = cube_ascii();
        let lines: Vec<&str> = good.lines().collect();
        let with = |n: usize, replacement: &str| {
            let mut l = lines.clone();
            l[n - 1] = replacement;
            l.join("\n")
        };
        // Line 4 is the first vertex of triangle 0.
        let e = err(with(4, "vertex 0 zero 0").as_bytes());
        assert_eq!(e.place, Place::Line(4));
        assert!(
            e.problem.contains("`zero`") && e.problem.contains("vertex 0 (corner 0 of triangle 0)"),
            "{e}"
        );
        let e = err(with(12, "vertex 1 NaN 0").as_bytes());
        assert_eq!(e.place, Place::Line(12));
        assert!(
            e.problem.starts_with("vertex 4 (corner 1 of triangle 1)") && e.problem.contains("not finite"),
            "{e}"
        );
        let e = err(with(5, "vertex 1 0").as_bytes());
        assert_eq!(e.place, Place::Line(5));
        assert!(e.problem.contains("has 2 value(s)"), "{e}");
        let e = err(with(6, "endloop").as_bytes());
        assert_eq!(e.place, Place::Line(6));
        assert!(e.problem.contains("has 2 vertices"), "{e}");
        let e = err(with(7, "vertex 1 1 1").as_bytes());
        assert!(e.problem.contains("more than 3 vertices"), "{e}");
        let e = err(with(3, "outer").as_bytes());
        assert!(e.problem.contains("expected `outer loop`"), "{e}");
        let e = err(with(2, "facets normal 0 0 0").as_bytes());
        assert_eq!(e.place, Place::Line(2));
        assert!(e.problem.contains("found `facets`"), "{e}");
        let e = err(with(lines.len(), "the end").as_bytes());
        assert!(e.problem.contains("found `the`"), "{e}");
        let e = err(format!("{good}garbage\n").as_bytes());
        assert!(e.problem.contains("after `endsolid`"), "{e}");
    }

    #[test]
    fn truncated_ascii() {
        let good = cube_ascii();
        let cut: String = good.lines().take(5).collect::<Vec<_>>().join("\n");
        let e = err(cut.as_bytes());
        assert_eq!(e.place, Place::Line(5));
        assert!(e.problem.contains("inside the facet that starts on line 2"), "{e}");
        let cut: String = good.lines().take(8).collect::<Vec<_>>().join("\n");
        let e = err(cut.as_bytes());
        assert_eq!(e.place, Place::Line(8));
        assert!(e.problem.contains("without the `endsolid`"), "{e}");
    }

    #[test]
    fn never_panics_on_prefixes_and_garbage() {
        let ascii = cube_ascii();
        read_every_prefix(|b| read(b), ascii.as_bytes());
        for header in [&b""[..], b"solid x"] {
            let binary = cube_binary(header);
            read_every_prefix(|b| read(b), &binary);
        }
        let mut state = 0x853c_49e6_748f_ea9b_u64;
        for round in 0..300 {
            let mut garbage: Vec<u8> = match round % 3 {
                0 => b"solid g\n".to_vec(),
                1 => vec![0; 84],
                _ => Vec::new(),
            };
            for _ in 0..(round % 211) {
                xorshift(&mut state);
                garbage.push(state as u8);
            }
            let len = garbage.len();
            if round % 3 == 1 && len >= 84 {
                // Sometimes make the count match the length.
                let count = ((len - 84) / 50) as u32;
                garbage.truncate(84 + 50 * count as usize);
                garbage[80..84].copy_from_slice(&count.to_le_bytes());
            }
            let _ = read(garbage.as_slice());
        }
    }
}
