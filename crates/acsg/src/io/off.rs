//! Reader of the Object File Format (OFF), ASCII variant.
//!
//! Accepted layout, with `#` comments and blank lines allowed anywhere:
//!
//! ```text
//! OFF                      header keyword (also COFF, NOFF, STOFF, ...; may be omitted)
//! 8 6 12                   vertex, face and (ignored) edge counts; may follow the keyword
//! x y z [extra columns]    one line per vertex; colours, normals, texture columns ignored
//! n i1 i2 ... in [colour]  one line per face; indices count from 0; colour ignored
//! ```

use std::borrow::Cow;
use std::io::Read;

use super::text::{TextLines, finite_vertex, parse_f64, read_limited, strip_comment, to_u32};
use super::{MeshSoup, ParseError, Place};

/// Reads an OFF model.
///
/// Vertices keep the file's numbering (from 0); faces keep the file's winding. Extra
/// per-vertex columns (COFF colours, NOFF normals, ST texture coordinates) and per-face
/// colours are ignored.
///
/// # Errors
/// A [`ParseError`] naming the line and the fix: a missing or unsupported header, bad
/// counts, a non-numeric or non-finite coordinate, a face with fewer than 3 vertices or
/// an index out of range, fewer lines than the counts declare, or data after the last
/// declared face.
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    parse(&bytes)
}

/// The lines holding data: comments removed, blank lines skipped.
struct ContentLines<'a> {
    lines: TextLines<'a>,
}

impl<'a> ContentLines<'a> {
    fn next(&mut self) -> Option<(usize, Cow<'a, str>)> {
        for (number, text) in self.lines.by_ref() {
            if !strip_comment(&text).trim().is_empty() {
                return Some((number, text));
            }
        }
        None
    }
}

/// The "file ends early" error.
fn ended_early(last_line: usize, declared: usize, noun: &str, found: usize, counts_line: usize) -> ParseError {
    let plural = if noun == "vertex" { "vertices" } else { "faces" };
    ParseError::new(
        Place::Line(last_line.max(1)),
        format!("the counts on line {counts_line} declare {declared} {plural} but the file ends after {found} of them"),
        format!("the file looks truncated: export it again, or correct the {noun} count on line {counts_line}"),
    )
}

fn parse(bytes: &[u8]) -> Result<MeshSoup, ParseError> {
    let mut lines = ContentLines {
        lines: TextLines::new(bytes, 1),
    };
    let counts = read_counts(&mut lines)?;
    let mut soup = MeshSoup {
        polygon_noun: "face",
        ..MeshSoup::default()
    };
    read_vertices(&mut lines, &counts, &mut soup)?;
    read_faces(&mut lines, &counts, &mut soup)?;
    if let Some((number, _)) = lines.next() {
        let mut extra = 1;
        while lines.next().is_some() {
            extra += 1;
        }
        return Err(ParseError::new(
            Place::Line(number),
            format!(
                "{extra} data line(s) follow the {} faces declared on line {}",
                counts.faces, counts.line
            ),
            format!("correct the counts on line {}, or delete the extra lines", counts.line),
        ));
    }
    Ok(soup)
}

/// The counts an OFF file declares, and the line they are on.
struct Counts {
    vertices: usize,
    faces: usize,
    line: usize,
}

/// The header keyword (optional), then the counts, possibly on the same line.
fn read_counts(lines: &mut ContentLines<'_>) -> Result<Counts, ParseError> {
    let Some((first_number, first_text)) = lines.next() else {
        return Err(ParseError::new(
            Place::Whole,
            "the file holds no OFF header and no counts line",
            "an OFF file starts with `OFF` then a line `vertices faces edges`; export the model again",
        ));
    };
    let first_body = strip_comment(&first_text);
    let mut first_tokens = first_body.split_whitespace();
    let keyword = first_tokens.next().unwrap_or_default();
    let (counts_number, counts_tokens): (usize, Vec<String>) = if let Some(prefix) = off_prefix(keyword) {
        check_prefix(prefix, keyword, first_number)?;
        if let Some(next) = first_tokens.clone().next()
            && next.eq_ignore_ascii_case("binary")
        {
            return Err(ParseError::new(
                Place::Line(first_number),
                format!("`{keyword} BINARY` (binary OFF) is not supported"),
                "save the model as ASCII OFF, or as STL, OBJ or PLY",
            ));
        }
        let rest: Vec<String> = first_tokens.map(str::to_owned).collect();
        if rest.is_empty() {
            let Some((number, text)) = lines.next() else {
                return Err(ParseError::new(
                    Place::Line(lines.lines.last_line().max(1)),
                    format!("the file ends after the `{keyword}` header, before the counts line"),
                    "after the header comes a line `vertices faces edges`, then the vertices and faces",
                ));
            };
            (
                number,
                strip_comment(&text).split_whitespace().map(str::to_owned).collect(),
            )
        } else {
            (first_number, rest)
        }
    } else if keyword.parse::<u64>().is_ok() {
        (first_number, first_body.split_whitespace().map(str::to_owned).collect())
    } else {
        return Err(ParseError::new(
            Place::Line(first_number),
            format!("expected the `OFF` header or the counts line, found `{keyword}`"),
            "an OFF file starts with `OFF` then a line `vertices faces edges`; check that the file is OFF",
        ));
    };
    let (vertices, faces) = parse_counts(&counts_tokens, counts_number)?;
    Ok(Counts {
        vertices,
        faces,
        line: counts_number,
    })
}

/// The declared number of vertex lines, `x y z [extra columns]`.
fn read_vertices(lines: &mut ContentLines<'_>, counts: &Counts, soup: &mut MeshSoup) -> Result<(), ParseError> {
    let (vertex_count, counts_number) = (counts.vertices, counts.line);
    soup.positions.reserve(vertex_count.min(1 << 16));
    for vertex in 0..vertex_count {
        let Some((number, text)) = lines.next() else {
            return Err(ended_early(
                lines.lines.last_line(),
                vertex_count,
                "vertex",
                vertex,
                counts_number,
            ));
        };
        let place = Place::Line(number);
        let tokens: Vec<&str> = strip_comment(&text).split_whitespace().take(3).collect();
        let &[x, y, z] = tokens.as_slice() else {
            return Err(ParseError::new(
                place,
                format!(
                    "vertex {vertex} has {} value(s); it needs 3 coordinates x y z",
                    tokens.len()
                ),
                format!(
                    "write `x y z` on each vertex line; the counts on line {counts_number} declare {vertex_count} vertices, check them"
                ),
            ));
        };
        let p = [
            parse_f64(x, &format!("the x coordinate of vertex {vertex}"), place)?,
            parse_f64(y, &format!("the y coordinate of vertex {vertex}"), place)?,
            parse_f64(z, &format!("the z coordinate of vertex {vertex}"), place)?,
        ];
        soup.positions
            .push(finite_vertex(p, &format!("vertex {vertex}"), place)?);
    }
    Ok(())
}

/// The declared number of face lines, `n i1 ... in [colour]`.
fn read_faces(lines: &mut ContentLines<'_>, counts: &Counts, soup: &mut MeshSoup) -> Result<(), ParseError> {
    soup.polygons.reserve(counts.faces.min(1 << 16));
    for face in 0..counts.faces {
        let Some((number, text)) = lines.next() else {
            return Err(ended_early(
                lines.lines.last_line(),
                counts.faces,
                "face",
                face,
                counts.line,
            ));
        };
        soup.polygons
            .push(parse_face(&text, face, Place::Line(number), counts)?);
        soup.polygon_lines.push(Some(number));
    }
    Ok(())
}

/// One face line: its vertex count, then that many indices (any further values are a
/// face colour, ignored).
fn parse_face(text: &str, face: usize, place: Place, counts: &Counts) -> Result<Vec<u32>, ParseError> {
    let (vertex_count, counts_number) = (counts.vertices, counts.line);
    let mut tokens = strip_comment(text).split_whitespace();
    let count_token = tokens.next().unwrap_or_default();
    let Ok(corners) = count_token.parse::<usize>() else {
        return Err(ParseError::new(
            place,
            format!("`{count_token}` is not a vertex count (expected the first value of face {face})"),
            "a face line is `n i1 ... in`: the number of vertices, then their indices",
        ));
    };
    if corners < 3 {
        return Err(ParseError::new(
            place,
            format!("face {face} has {corners} vertices; a face needs at least 3"),
            "remove the degenerate face or re-export the model",
        ));
    }
    let mut polygon = Vec::with_capacity(corners.min(64));
    for position in 0..corners {
        let Some(token) = tokens.next() else {
            return Err(ParseError::new(
                place,
                format!("face {face} declares {corners} vertices but lists only {position} indices"),
                "a face line is `n i1 ... in`: give exactly n vertex indices",
            ));
        };
        let Ok(index) = token.parse::<i64>() else {
            return Err(ParseError::new(
                place,
                format!("`{token}` is not a vertex index (vertex {position} of face {face})"),
                "vertex indices are whole numbers counting from 0",
            ));
        };
        if index < 0 {
            return Err(ParseError::new(
                place,
                format!("face {face} refers to vertex {index}; OFF indices cannot be negative"),
                "vertex indices of an OFF file count from 0",
            ));
        }
        let index = usize::try_from(index).unwrap_or(usize::MAX);
        if index >= vertex_count {
            return Err(ParseError::new(
                place,
                format!("face {face} refers to vertex {index} but the file has {vertex_count} vertices"),
                format!(
                    "vertex indices of an OFF file count from 0; check the face and the vertex count on line {counts_number}"
                ),
            ));
        }
        polygon.push(to_u32(index, place)?);
    }
    Ok(polygon)
}

/// The letters before `OFF` in a header keyword (`""`, `"C"`, `"ST"`, ...), if the
/// token is one.
fn off_prefix(keyword: &str) -> Option<&str> {
    let split = keyword.len().checked_sub(3)?;
    let (prefix, suffix) = (keyword.get(..split)?, keyword.get(split..)?);
    (suffix.eq_ignore_ascii_case("off") && prefix.chars().all(|c| "STCNn4".contains(c))).then_some(prefix)
}

/// Refuses the header variants whose vertex lines are not `x y z ...`.
fn check_prefix(prefix: &str, keyword: &str, line: usize) -> Result<(), ParseError> {
    if prefix.contains('4') || prefix.contains('n') {
        return Err(ParseError::new(
            Place::Line(line),
            format!("`{keyword}` (4-dimensional or n-dimensional OFF) is not supported"),
            "save the model as 3-dimensional OFF, or as STL, OBJ or PLY",
        ));
    }
    Ok(())
}

/// The vertex and face counts of the counts line (the edge count is ignored).
fn parse_counts(tokens: &[String], line: usize) -> Result<(usize, usize), ParseError> {
    let place = Place::Line(line);
    if !(2..=3).contains(&tokens.len()) {
        return Err(ParseError::new(
            place,
            format!(
                "the counts line has {} value(s); it needs the vertex, face and edge counts",
                tokens.len()
            ),
            "write a line `vertices faces edges` after the header, e.g. `8 6 12` for a cube",
        ));
    }
    let mut counts = [0usize; 2];
    for (slot, (token, noun)) in counts.iter_mut().zip(tokens.iter().zip(["vertex", "face"])) {
        *slot = token.parse::<usize>().map_err(|_| {
            ParseError::new(
                place,
                format!("`{token}` is not a {noun} count"),
                "the counts line holds whole numbers `vertices faces edges`",
            )
        })?;
    }
    if let Some(edges) = tokens.get(2)
        && edges.parse::<u64>().is_err()
    {
        return Err(ParseError::new(
            place,
            format!("`{edges}` is not an edge count"),
            "the counts line holds whole numbers `vertices faces edges` (the edge count may be 0)",
        ));
    }
    Ok((counts[0], counts[1]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::text::testing::{expect_err, read_every_prefix, xorshift};
    use glam::DVec3;

    const CUBE: &str = "OFF
# a unit cube
8 6 12
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 1 2 6 5
4 2 3 7 6
4 3 0 4 7
";

    fn parse_str(text: &str) -> Result<MeshSoup, ParseError> {
        read(text.as_bytes())
    }

    fn err(text: &str) -> ParseError {
        expect_err(parse_str(text))
    }

    #[test]
    fn reads_cube() {
        let soup = parse_str(CUBE).unwrap();
        assert_eq!(soup.positions.len(), 8);
        assert_eq!(soup.polygons.len(), 6);
        assert_eq!(soup.positions[6], DVec3::new(1.0, 1.0, 1.0));
        assert_eq!(soup.polygons[0], vec![0, 3, 2, 1]);
        assert_eq!(soup.polygons[5], vec![3, 0, 4, 7]);
        assert_eq!(soup.polygon_lines[0], Some(12));
        assert_eq!(soup.polygon_lines[5], Some(17));
        assert_eq!(soup.polygon_noun, "face");
    }

    #[test]
    fn reads_variants() {
        // Counts on the header line, CRLF endings, trailing comments, COFF colours,
        // face colours.
        let text = "COFF 4 1 0\r\n0 0 0 255 0 0 255\r\n1 0 0 1 1 1 1 # c\r\n0 1 0 1 1 1 1\r\n0 0 1 1 1 1 1\r\n3 0 2 1 0.5 0.5 0.5\r\n";
        let soup = parse_str(text).unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.polygons, vec![vec![0, 2, 1]]);
        assert_eq!(soup.polygon_lines, vec![Some(6)]);
        // No header keyword at all.
        let soup = parse_str("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
        assert_eq!(soup.polygons, vec![vec![0, 1, 2]]);
        // Empty model: not a parse error.
        let soup = parse_str("OFF\n0 0 0\n").unwrap();
        assert!(soup.positions.is_empty() && soup.polygons.is_empty());
    }

    #[test]
    fn non_numeric_coordinate() {
        let e = err("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n");
        assert_eq!(e.place, Place::Line(4));
        assert!(e.problem.contains("`zero`") && e.problem.contains("vertex 1"), "{e}");
    }

    #[test]
    fn wrong_value_count() {
        let e = err("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n");
        assert_eq!(e.place, Place::Line(4));
        assert!(e.problem.contains("vertex 1 has 2 value"), "{e}");
        let e = err("OFF\n3\n");
        assert_eq!(e.place, Place::Line(2));
        assert!(e.problem.contains("counts line has 1 value"), "{e}");
        let e = err("OFF\n3 x 0\n");
        assert!(e.problem.contains("`x` is not a face count"), "{e}");
        let e = err("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n");
        assert_eq!(e.place, Place::Line(6));
        assert!(e.problem.contains("declares 4 vertices but lists only 3"), "{e}");
    }

    #[test]
    fn missing_lines() {
        let e = err("OFF\n8 6 12\n0 0 0\n1 0 0\n");
        assert_eq!(e.place, Place::Line(4));
        assert!(e.problem.contains("declare 8 vertices"), "{e}");
        assert!(e.problem.contains("after 2 of them"), "{e}");
        let e = err("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
        assert!(e.problem.contains("declare 2 faces but the file ends after 1"), "{e}");
        let e = err("OFF\n");
        assert!(e.problem.contains("before the counts line"), "{e}");
        let e = err("# only a comment\n");
        assert_eq!(e.place, Place::Whole);
    }

    #[test]
    fn extra_lines_after_faces() {
        let e = err("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n");
        assert_eq!(e.place, Place::Line(7));
        assert!(e.problem.contains("1 data line(s) follow the 1 faces"), "{e}");
    }

    #[test]
    fn non_finite_coordinate() {
        for bad in ["nan", "inf", "-infinity", "1e400"] {
            let e = err(&format!("OFF\n3 1 0\n0 0 0\n1 0 0\n0 {bad} 0\n3 0 1 2\n"));
            assert_eq!(e.place, Place::Line(5), "{bad}");
            assert!(
                e.problem.starts_with("vertex 2:") && e.problem.contains("not finite"),
                "{e}"
            );
        }
    }

    #[test]
    fn bad_faces() {
        let base = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
        let e = err(&format!("{base}3 0 1 3\n"));
        assert_eq!(e.place, Place::Line(6));
        assert!(
            e.problem
                .contains("face 0 refers to vertex 3 but the file has 3 vertices"),
            "{e}"
        );
        let e = err(&format!("{base}3 0 -1 2\n"));
        assert!(e.problem.contains("vertex -1") && e.problem.contains("negative"), "{e}");
        let e = err(&format!("{base}2 0 1\n"));
        assert!(e.problem.contains("face 0 has 2 vertices"), "{e}");
        let e = err(&format!("{base}3 0 one 2\n"));
        assert!(e.problem.contains("`one` is not a vertex index"), "{e}");
        let e = err(&format!("{base}three 0 1 2\n"));
        assert!(e.problem.contains("`three` is not a vertex count"), "{e}");
    }

    #[test]
    fn bad_headers() {
        let e = err("OFF BINARY\n");
        assert!(e.problem.contains("binary OFF"), "{e}");
        let e = err("4OFF\n1 0 0\n0 0 0 1\n");
        assert!(e.problem.contains("not supported"), "{e}");
        let e = err("solid cube\n");
        assert_eq!(e.place, Place::Line(1));
        assert!(e.problem.contains("`solid`"), "{e}");
    }

    #[test]
    fn huge_declared_counts_do_not_allocate() {
        let e = err("OFF\n18446744073709551615 18446744073709551615 0\n0 0 0\n");
        assert!(e.problem.contains("ends after 1 of them"), "{e}");
    }

    #[test]
    fn never_panics_on_prefixes_and_garbage() {
        let bytes = CUBE.as_bytes();
        read_every_prefix(|b| read(b), bytes);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for round in 0..500 {
            let len = round % 97;
            let mut garbage: Vec<u8> = if round % 2 == 0 {
                b"OFF\n3 1 0\n".to_vec()
            } else {
                Vec::new()
            };
            let alphabet = b"0123456789 -.\n#eOFnai";
            for _ in 0..len {
                xorshift(&mut state);
                garbage.push(alphabet[(state % alphabet.len() as u64) as usize]);
                garbage.push(state as u8);
            }
            let _ = read(garbage.as_slice());
        }
    }
}
