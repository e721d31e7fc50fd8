//! Reader of Wavefront OBJ polygon geometry.
//!
//! Only the statements that define the surface are read:
//!
//! - `v x y z [w]` or `v x y z r g b [a]`: a vertex; `w` and colours are ignored;
//! - `f v1 v2 v3 ...` (also the obsolete `fo`): a face, each corner written `v`, `v/vt`,
//!   `v//vn` or `v/vt/vn`; indices count from 1, negative indices count back from the
//!   last vertex defined before the face (`-1` is that vertex).
//!
//! Everything else (`vt`, `vn`, `l`, `p`, groups, objects, materials, smoothing
//! groups, free-form geometry) is ignored, and all groups and objects merge into one
//! soup. Vertices keep the file's order, so vertex `k` of the file is position `k - 1`.
//!
//! The parser is written here rather than taken from `tobj`: `tobj` renumbers vertices
//! per object in order of first use, turns `l` polylines into two-vertex faces,
//! reports errors without a line, and can overflow on some relative indices.

use std::io::Read;

use super::text::{TextLines, finite_vertex, parse_f64, read_limited, strip_comment, to_u32};
use super::{MeshSoup, ParseError, Place};

/// Reads an OBJ model.
///
/// # Errors
/// A [`ParseError`] naming the line and the fix: a `v` line with a missing, extra,
/// non-numeric or non-finite value, or a face with fewer than 3 vertices, a malformed
/// corner, an index 0, or an index (absolute or relative) outside the vertices of the
/// file.
pub fn read(reader: impl Read) -> Result<MeshSoup, ParseError> {
    let bytes = read_limited(reader)?;
    parse(&bytes)
}

fn parse(bytes: &[u8]) -> Result<MeshSoup, ParseError> {
    let mut soup = MeshSoup {
        polygon_noun: "face",
        ..MeshSoup::default()
    };
    // Faces with 0-based indices. Positive indices may refer to vertices defined later
    // in the file: they are checked once every vertex is known.
    let mut faces: Vec<(usize, Vec<usize>)> = Vec::new();
    for (number, text) in TextLines::new(bytes, 1) {
        let place = Place::Line(number);
        let mut tokens = strip_comment(&text).split_whitespace();
        match tokens.next() {
            Some("v") => {
                let vertex = soup.positions.len() + 1;
                let values: Vec<&str> = tokens.collect();
                if values.len() < 3 || values.len() == 5 || values.len() > 7 {
                    return Err(ParseError::new(
                        place,
                        format!("vertex {vertex} has {} value(s); a `v` line holds x y z", values.len()),
                        "write `v x y z` (optionally followed by w, or by the colour r g b)",
                    ));
                }
                let mut p = [0.0; 3];
                for (k, token) in values.iter().enumerate() {
                    let what = match k {
                        0 => format!("the x coordinate of vertex {vertex}"),
                        1 => format!("the y coordinate of vertex {vertex}"),
                        2 => format!("the z coordinate of vertex {vertex}"),
                        _ => format!("value {} of vertex {vertex}", k + 1),
                    };
                    let value = parse_f64(token, &what, place)?;
                    if let Some(slot) = p.get_mut(k) {
                        *slot = value;
                    }
                }
                soup.positions
                    .push(finite_vertex(p, &format!("vertex {vertex}"), place)?);
            }
            Some("f" | "fo") => {
                let face = faces.len();
                let defined = soup.positions.len();
                let mut polygon = Vec::new();
                for token in tokens {
                    polygon.push(parse_corner(token, face, defined, place)?);
                }
                if polygon.len() < 3 {
                    return Err(ParseError::new(
                        place,
                        format!("face {face} has {} vertices; a face needs at least 3", polygon.len()),
                        "remove the degenerate face (use `l` for a line) or re-export the model",
                    ));
                }
                faces.push((number, polygon));
            }
            _ => {}
        }
    }

    let vertex_count = soup.positions.len();
    soup.polygons.reserve(faces.len());
    soup.polygon_lines.reserve(faces.len());
    for (face, (number, corners)) in faces.into_iter().enumerate() {
        let place = Place::Line(number);
        let mut polygon = Vec::with_capacity(corners.len());
        for index in corners {
            if index >= vertex_count {
                return Err(ParseError::new(
                    place,
                    format!(
                        "face {face} refers to vertex {} but the file has {vertex_count} vertices",
                        index.saturating_add(1)
                    ),
                    "OBJ vertex indices count from 1 up to the number of `v` lines; check the face",
                ));
            }
            polygon.push(to_u32(index, place)?);
        }
        soup.polygons.push(polygon);
        soup.polygon_lines.push(Some(number));
    }
    Ok(soup)
}

/// The 0-based vertex index of one face corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`);
/// `defined` is the number of vertices defined before the face.
fn parse_corner(token: &str, face: usize, defined: usize, place: Place) -> Result<usize, ParseError> {
    let malformed = |why: &str| {
        ParseError::new(
            place,
            format!("`{token}` is not a valid corner of face {face}: {why}"),
            "write each corner as v, v/vt, v//vn or v/vt/vn with whole-number indices",
        )
    };
    let mut parts = token.split('/');
    let vertex = parts.next().unwrap_or_default();
    let others: Vec<&str> = parts.collect();
    if others.len() > 2 {
        return Err(malformed("it has more than three parts"));
    }
    if others
        .iter()
        .any(|part| !part.is_empty() && part.parse::<i64>().is_err())
    {
        return Err(malformed("its texture or normal index is not a whole number"));
    }
    if vertex.is_empty() {
        return Err(malformed("it has no vertex index"));
    }
    let Ok(index) = vertex.parse::<i64>() else {
        return Err(malformed("its vertex index is not a whole number"));
    };
    if index == 0 {
        return Err(ParseError::new(
            place,
            format!("face {face} refers to vertex 0, which does not exist"),
            "OBJ vertex indices count from 1 (or back from -1 for the last vertex defined)",
        ));
    }
    if index > 0 {
        return Ok(usize::try_from(index - 1).unwrap_or(usize::MAX));
    }
    // Relative: -1 is the last vertex defined before this face.
    let back = usize::try_from(index.unsigned_abs()).unwrap_or(usize::MAX);
    defined.checked_sub(back).ok_or_else(|| {
        ParseError::new(
            place,
            format!(
                "face {face} refers to vertex {index}, counting back from the {defined} vertices defined before it"
            ),
            "a negative index counts back from the last `v` line above the face; check the face",
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::text::testing::{expect_err, read_every_prefix, xorshift};
    use glam::DVec3;

    const CUBE: &str = "# a unit cube
mtllib cube.mtl
o cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
vn 0 0 -1
vt 0 0
g bottom
usemtl steel
f 1 4 3 2
g top
f 5/1 6/1 7/1 8/1
s off
f 1//1 2//1 6//1 5//1
f 2/1/1 3/1/1 7/1/1 6/1/1
l 1 2
f 3 4 8 7
f 4 1 5 8
";

    fn err(text: &str) -> ParseError {
        expect_err(read(text.as_bytes()))
    }

    #[test]
    fn reads_cube() {
        let soup = read(CUBE.as_bytes()).unwrap();
        assert_eq!(soup.positions.len(), 8);
        assert_eq!(soup.polygons.len(), 6);
        assert_eq!(soup.positions[6], DVec3::new(1.0, 1.0, 1.0));
        assert_eq!(soup.polygons[0], vec![0, 3, 2, 1]);
        assert_eq!(soup.polygons[1], vec![4, 5, 6, 7]);
        assert_eq!(soup.polygons[3], vec![1, 2, 6, 5]);
        assert_eq!(soup.polygons[5], vec![3, 0, 4, 7]);
        assert_eq!(soup.polygon_lines[0], Some(16));
        assert_eq!(soup.polygon_lines[4], Some(23));
        assert_eq!(soup.polygon_noun, "face");
    }

    #[test]
    fn relative_and_forward_indices() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -1 -2 -4\nf 1 2 4\n";
        let soup = read(text.as_bytes()).unwrap();
        assert_eq!(soup.polygons, vec![vec![0, 1, 2], vec![3, 2, 0], vec![0, 1, 3]]);
        // A face may name a vertex defined further down.
        let soup = read("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n".as_bytes()).unwrap();
        assert_eq!(soup.polygons, vec![vec![0, 1, 2]]);
        // w and vertex colours are ignored.
        let soup = read("v 1 2 3 0.5\nv 1 2 3 1 0 0\nv 1 2 3 1 0 0 1\n".as_bytes()).unwrap();
        assert!(soup.positions.iter().all(|p| *p == DVec3::new(1.0, 2.0, 3.0)));
        // Nothing at all is not a parse error.
        let soup = read("# empty\n".as_bytes()).unwrap();
        assert!(soup.positions.is_empty() && soup.polygons.is_empty());
    }

    #[test]
    fn bad_vertex_lines() {
        let e = err("v 0 0 0\nv 1 x 0\n");
        assert_eq!(e.place, Place::Line(2));
        assert!(
            e.problem.contains("`x`") && e.problem.contains("y coordinate of vertex 2"),
            "{e}"
        );
        let e = err("v 0 0 0\nv 1 0\n");
        assert_eq!(e.place, Place::Line(2));
        assert!(e.problem.contains("vertex 2 has 2 value(s)"), "{e}");
        let e = err("v 0 0 0 1 2\n");
        assert!(e.problem.contains("has 5 value(s)"), "{e}");
    }

    #[test]
    fn non_finite_coordinate() {
        for bad in ["NaN", "inf", "-1e999"] {
            let e = err(&format!("v 0 0 0\n\nv 0 {bad} 0\n"));
            assert_eq!(e.place, Place::Line(3));
            assert!(
                e.problem.starts_with("vertex 2:") && e.problem.contains("not finite"),
                "{e}"
            );
        }
    }

    #[test]
    fn bad_faces() {
        let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let e = err(&format!("{base}f 1 2 4\n"));
        assert_eq!(e.place, Place::Line(4));
        assert!(
            e.problem
                .contains("face 0 refers to vertex 4 but the file has 3 vertices"),
            "{e}"
        );
        let e = err(&format!("{base}f 1 2 3\nf 1 2 -4\n"));
        assert_eq!(e.place, Place::Line(5));
        assert!(e.problem.contains("face 1 refers to vertex -4"), "{e}");
        let e = err(&format!("{base}f 0 1 2\n"));
        assert!(e.problem.contains("vertex 0"), "{e}");
        let e = err(&format!("{base}f 1 2\n"));
        assert!(e.problem.contains("face 0 has 2 vertices"), "{e}");
        let e = err(&format!("{base}f 1 2 three\n"));
        assert!(e.problem.contains("`three`"), "{e}");
        let e = err(&format!("{base}f 1 2 3/x\n"));
        assert!(e.problem.contains("`3/x`"), "{e}");
        let e = err(&format!("{base}f 1 2 /3\n"));
        assert!(e.problem.contains("no vertex index"), "{e}");
        let e = err(&format!("{base}f 1 2 3/1/1/1\n"));
        assert!(e.problem.contains("more than three parts"), "{e}");
        let e = err(&format!("{base}f 1 2 -9223372036854775808\n"));
        assert!(e.problem.contains("refers to vertex -9223372036854775808"), "{e}");
        let e = err(&format!("{base}f 1 2 9223372036854775807\n"));
        assert!(e.problem.contains("refers to vertex 9223372036854775807"), "{e}");
    }

    #[test]
    fn never_panics_on_prefixes_and_garbage() {
        let bytes = CUBE.as_bytes();
        read_every_prefix(|b| read(b), bytes);
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let alphabet = b"0123456789 -./\nvf#enai";
        for round in 0..500 {
            let mut garbage = Vec::new();
            for _ in 0..(round % 113) {
                xorshift(&mut state);
                garbage.push(alphabet[(state % alphabet.len() as u64) as usize]);
                if round % 3 == 0 {
                    garbage.push(state as u8);
                }
            }
            let _ = read(garbage.as_slice());
        }
    }
}
