//! Planar faces with holes, as CAD B-reps (STEP, IGES) state them, turned into the
//! polygon soup the other readers produce.
//!
//! A face without holes becomes one polygon; a face with holes is triangulated (ear
//! clipping, every loop point kept, so no T-junction appears). The topology then merges
//! the pieces back into the exact planar face, loops and holes included.

use glam::{DVec2, DVec3};

use super::{MeshSoup, ParseError, Place};
use crate::geometry::{Aabb, newell, shoelace};
use crate::tolerance::{AREA_REL, COPLANAR_REL, DUPLICATE_FRACTION, NEGLIGIBLE, SIZE_FLOOR};

/// One planar face of a CAD B-rep, in millimetres.
#[derive(Clone, Debug)]
pub(crate) struct PlanarFace {
    /// The outward normal, from the face's surface and its orientation flags.
    pub normal: DVec3,
    /// Its loops as point chains, the closing point not repeated; any direction.
    pub loops: Vec<Vec<DVec3>>,
    /// The outer loop when the file says which; otherwise the one of largest area.
    pub outer: Option<usize>,
    /// Names the face in messages (`face #17`, `face (entity 510) at DE 7`).
    pub name: String,
    /// Where the face is stated.
    pub place: Place,
}

/// How a B-spline (or Bézier) surface's control net lies: a rational or polynomial
/// B-spline surface is an affine combination of its control points, so when they are
/// coplanar the surface lies in their plane, whatever its degree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum NetShape {
    /// Coplanar within the tolerance: the surface's own normal `S_u × S_v` direction.
    Plane(DVec3),
    /// Curved: the largest distance of a control point from the best plane, and the
    /// tolerance it exceeds.
    Curved {
        /// Largest distance from the plane.
        deviation: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// The net spans no area (all points on a line or one point).
    Degenerate,
}

/// The shape of a control net `net[i][j]`, `i` along u and `j` along v. The normal
/// is the sum of the net's cells' `ΔP_u × ΔP_v`, which points along `S_u × S_v` for a
/// planar surface; coplanarity is checked against [`crate::tolerance::COPLANAR_REL`]
/// times the net's diagonal.
pub(crate) fn net_shape(net: &[Vec<DVec3>]) -> NetShape {
    let mut normal = DVec3::ZERO;
    for i in 0..net.len().saturating_sub(1) {
        let (row, next) = (&net[i], &net[i + 1]);
        for j in 0..row.len().min(next.len()).saturating_sub(1) {
            normal += (next[j] - row[j]).cross(row[j + 1] - row[j]);
        }
    }
    let points: Vec<DVec3> = net.iter().flatten().copied().collect();
    let bounds = Aabb::around(points.iter().copied());
    let size = (bounds.max - bounds.min).length();
    if !(size.is_finite() && size > 0.0) || normal.length() <= AREA_REL * size * size {
        return NetShape::Degenerate;
    }
    let n = normal.normalize();
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let deviation = points.iter().map(|p| (*p - centre).dot(n).abs()).fold(0.0, f64::max);
    let tolerance = crate::tolerance::COPLANAR_REL * size;
    if deviation <= tolerance {
        NetShape::Plane(n)
    } else {
        NetShape::Curved { deviation, tolerance }
    }
}

/// The largest distance of `points` from the line through the first and the farthest
/// of them, and the tolerance ([`crate::tolerance::COPLANAR_REL`] times their extent):
/// a B-spline curve is an affine combination of its control points, so collinear
/// control points make a straight curve.
pub(crate) fn line_deviation(points: &[DVec3]) -> (f64, f64) {
    let Some(&first) = points.first() else {
        return (0.0, 0.0);
    };
    let far = points
        .iter()
        .copied()
        .max_by(|a, b| a.distance(first).total_cmp(&b.distance(first)))
        .unwrap_or(first);
    let extent = far.distance(first);
    if !(extent.is_finite() && extent > 0.0) {
        return (0.0, 0.0);
    }
    let d = (far - first) / extent;
    let deviation = points
        .iter()
        .map(|p| (*p - first).reject_from_normalized(d).length())
        .fold(0.0, f64::max);
    (deviation, crate::tolerance::COPLANAR_REL * extent)
}

/// A polygon's area vector: its normal by the right-hand rule (counter-clockwise
/// order), as long as its area.
pub(crate) fn area_vector(points: &[DVec3]) -> DVec3 {
    newell(points.iter().copied()) / 2.0
}

/// The signed area of a polygon in a plane (positive counter-clockwise).
fn signed_area(points: &[DVec2]) -> f64 {
    shoelace(points) / 2.0
}

/// Builds the soup from planar faces. When every face's normal points inward (the
/// signed volume is negative) all faces are turned round, since some writers state the
/// surface normals of a solid consistently but inward.
///
/// # Errors
/// A [`ParseError`] at the face's place for a face with no loops, a loop of fewer than
/// 3 distinct points, a zero normal, a point off the face's plane, or a face whose holes
/// cannot be triangulated.
pub(crate) fn soup_from_faces(mut faces: Vec<PlanarFace>, export_hint: &str) -> Result<MeshSoup, ParseError> {
    let bounds = Aabb::around(faces.iter().flat_map(|f| f.loops.iter().flatten().copied()));
    let size = if bounds.min.x.is_finite() {
        (bounds.max - bounds.min).length().max(SIZE_FLOOR)
    } else {
        1.0
    };
    let tolerance = COPLANAR_REL * size;

    // Normalise loops and normals first; the orientation fix needs them all.
    for face in &mut faces {
        let bad =
            |problem: String| ParseError::new(face.place, problem, format!("the face is malformed; {export_hint}"));
        let length = face.normal.length();
        if !length.is_finite() || length < NEGLIGIBLE {
            return Err(bad(format!("{}: its plane has a zero or invalid normal", face.name)));
        }
        face.normal /= length;
        if face.loops.is_empty() {
            return Err(bad(format!("{}: it has no boundary loop", face.name)));
        }
        for l in &mut face.loops {
            l.dedup_by(|a, b| a.distance(*b) <= tolerance * DUPLICATE_FRACTION);
            while l.len() > 1
                && l.first()
                    .zip(l.last())
                    .is_some_and(|(a, b)| a.distance(*b) <= tolerance * DUPLICATE_FRACTION)
            {
                l.pop();
            }
            if l.len() < 3 {
                return Err(bad(format!(
                    "{}: a boundary loop has {} distinct point(s); a loop needs at least 3",
                    face.name,
                    l.len()
                )));
            }
        }
    }
    let flip = oriented_volume(&faces) < 0.0;

    let mut soup = MeshSoup {
        polygon_noun: "polygon",
        ..MeshSoup::default()
    };
    for face in &faces {
        let normal = if flip { -face.normal } else { face.normal };
        add_face(&mut soup, face, normal, tolerance, export_hint)?;
    }
    Ok(soup)
}

/// The signed area of a loop around `normal`, positive when counter-clockwise.
fn loop_area_about(points: &[DVec3], normal: DVec3) -> f64 {
    let (u, w) = normal.any_orthonormal_pair();
    let flat: Vec<DVec2> = points.iter().map(|p| DVec2::new(p.dot(u), p.dot(w))).collect();
    signed_area(&flat)
}

/// The solid's volume by the divergence theorem with every face taken as its outward
/// normal says: each face contributes offset x (outer area - hole areas).
fn oriented_volume(faces: &[PlanarFace]) -> f64 {
    faces
        .iter()
        .map(|f| {
            let areas: Vec<f64> = f.loops.iter().map(|l| loop_area_about(l, f.normal).abs()).collect();
            let outer = outer_index(f, &areas);
            let net = areas
                .iter()
                .enumerate()
                .map(|(k, a)| if k == outer { *a } else { -*a })
                .sum::<f64>();
            f.loops[outer][0].dot(f.normal) * net
        })
        .sum::<f64>()
        / 3.0
}

fn outer_index(face: &PlanarFace, areas: &[f64]) -> usize {
    match face.outer {
        Some(k) if k < face.loops.len() => k,
        _ => {
            areas
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |best, (k, &a)| if a > best.1 { (k, a) } else { best },
                )
                .0
        }
    }
}

/// Adds one face to the soup: one polygon, or triangles over all its points when it
/// has holes.
fn add_face(
    soup: &mut MeshSoup,
    face: &PlanarFace,
    normal: DVec3,
    tolerance: f64,
    export_hint: &str,
) -> Result<(), ParseError> {
    let (u, w) = normal.any_orthonormal_pair();
    let flat: Vec<Vec<DVec2>> = face
        .loops
        .iter()
        .map(|l| l.iter().map(|p| DVec2::new(p.dot(u), p.dot(w))).collect())
        .collect();
    let areas: Vec<f64> = flat.iter().map(|l| signed_area(l)).collect();
    let outer = outer_index(face, &areas.iter().map(|a| a.abs()).collect::<Vec<_>>());
    check_on_plane(face, outer, normal, tolerance, export_hint)?;
    let loops = oriented_loops(face, outer, &areas);
    let line = match face.place {
        Place::Line(line) => Some(line),
        _ => None,
    };
    let base = soup.positions.len();
    let index = |k: usize| u32::try_from(base + k);
    let too_many = || {
        ParseError::new(
            face.place,
            "the model has more than 2^32 points",
            "split the model into smaller parts",
        )
    };
    soup.positions.extend(loops.iter().flatten().copied());
    if loops.len() == 1 {
        let polygon = (0..loops[0].len())
            .map(index)
            .collect::<Result<Vec<u32>, _>>()
            .map_err(|_| too_many())?;
        soup.polygons.push(polygon);
        soup.polygon_lines.push(line);
        return Ok(());
    }
    for t in triangulate_with_holes(face, &loops, (u, w), tolerance, export_hint)? {
        let polygon = t
            .iter()
            .map(|&k| index(k))
            .collect::<Result<Vec<u32>, _>>()
            .map_err(|_| too_many())?;
        soup.polygons.push(polygon);
        soup.polygon_lines.push(line);
    }
    Ok(())
}

/// Every point of the face must lie on one plane with this normal (through the outer
/// loop's mean point), within `tolerance`.
fn check_on_plane(
    face: &PlanarFace,
    outer: usize,
    normal: DVec3,
    tolerance: f64,
    export_hint: &str,
) -> Result<(), ParseError> {
    let offset = face.loops[outer].iter().map(|p| p.dot(normal)).sum::<f64>() / face.loops[outer].len() as f64;
    for p in face.loops.iter().flatten() {
        let off = (p.dot(normal) - offset).abs();
        if off > tolerance {
            return Err(ParseError::new(
                face.place,
                format!(
                    "{}: the point ({}, {}, {}) is {off:.3e} mm off the face's plane",
                    face.name, p.x, p.y, p.z
                ),
                format!("the face's edges do not lie on its plane; {export_hint}"),
            ));
        }
    }
    Ok(())
}

/// The face's loops, the outer first and counter-clockwise around the normal, then the
/// holes clockwise (`areas` are the loops' signed areas around the normal).
fn oriented_loops(face: &PlanarFace, outer: usize, areas: &[f64]) -> Vec<Vec<DVec3>> {
    let mut loops: Vec<Vec<DVec3>> = Vec::with_capacity(face.loops.len());
    let mut order = vec![outer];
    order.extend((0..face.loops.len()).filter(|&k| k != outer));
    for &k in &order {
        let mut l = face.loops[k].clone();
        let ccw = areas[k] > 0.0;
        if ccw != (k == outer) {
            l.reverse();
        }
        loops.push(l);
    }
    loops
}

/// Triangles over all the points of a face with holes (indices into its loops' points
/// in order), counter-clockwise around the normal: ear clipping in the plane basis
/// `(u, w)`, then the points it dropped put back.
fn triangulate_with_holes(
    face: &PlanarFace,
    loops: &[Vec<DVec3>],
    (u, w): (DVec3, DVec3),
    tolerance: f64,
    export_hint: &str,
) -> Result<Vec<[usize; 3]>, ParseError> {
    let mut coords = Vec::new();
    let mut holes = Vec::new();
    for (k, l) in loops.iter().enumerate() {
        if k > 0 {
            holes.push(coords.len() / 2);
        }
        for p in l {
            coords.extend([p.dot(u), p.dot(w)]);
        }
    }
    let points: Vec<DVec2> = coords.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect();
    let failed = || {
        ParseError::new(
            face.place,
            format!(
                "{}: its loops cannot be triangulated (do holes cross the outer loop?)",
                face.name
            ),
            format!("check the face's holes; {export_hint}"),
        )
    };
    let indices = earcutr::earcut(&coords, &holes, 2).map_err(|_| failed())?;
    let mut triangles: Vec<[usize; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            let (a, b, c) = (points[t[0]], points[t[1]], points[t[2]]);
            if (b - a).perp_dot(c - a) < 0.0 {
                [t[0], t[2], t[1]]
            } else {
                [t[0], t[1], t[2]]
            }
        })
        .collect();
    if triangles.is_empty() {
        return Err(failed());
    }
    insert_dropped_points(&mut triangles, &points, tolerance);
    Ok(triangles)
}

/// Ear clipping drops loop points that lie on a straight run of their loop; the
/// neighbouring face keeps them, so each is put back by splitting the triangle whose
/// edge it lies on (the two halves keep the triangle's winding).
fn insert_dropped_points(triangles: &mut Vec<[usize; 3]>, points: &[DVec2], tolerance: f64) {
    let mut used = vec![false; points.len()];
    for t in triangles.iter() {
        for &k in t {
            used[k] = true;
        }
    }
    for (b, _) in used.clone().iter().enumerate().filter(|(_, u)| !**u) {
        let p = points[b];
        let found = triangles.iter().enumerate().find_map(|(ti, t)| {
            (0..3).find_map(|e| {
                let (a, c) = (points[t[e]], points[t[(e + 1) % 3]]);
                let ac = c - a;
                let len2 = ac.length_squared();
                if len2 <= 0.0 {
                    return None;
                }
                let s = (p - a).dot(ac) / len2;
                let off = (p - a).perp_dot(ac).abs() / len2.sqrt();
                (s > 0.0 && s < 1.0 && off <= tolerance).then_some((ti, e))
            })
        });
        if let Some((ti, e)) = found {
            let t = triangles[ti];
            let (a, c, d) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            triangles[ti] = [a, b, d];
            triangles.push([b, c, d]);
            used[b] = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_nets_and_polygons_are_told_flat_or_curved() {
        // A chamfer: the bilinear patch of four coplanar points, normal u × v.
        let net = vec![
            vec![DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)],
            vec![DVec3::new(1.0, 0.0, 1.0), DVec3::new(1.0, 1.0, 1.0)],
        ];
        let NetShape::Plane(n) = net_shape(&net) else {
            panic!("{:?}", net_shape(&net))
        };
        let expected = DVec3::new(1.0, 0.0, 1.0).cross(DVec3::Y).normalize();
        assert!(n.abs_diff_eq(expected, 1e-12), "{n}");
        // A twisted patch (hyperbolic paraboloid) is curved.
        let twisted = vec![
            vec![DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)],
            vec![DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.5)],
        ];
        assert!(matches!(net_shape(&twisted), NetShape::Curved { deviation, .. } if deviation > 0.1));
        let line = vec![vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0]];
        assert_eq!(net_shape(&line), NetShape::Degenerate);
        let (dev, tol) = line_deviation(&[DVec3::ZERO, DVec3::X * 5.0, DVec3::X * 10.0]);
        assert!(dev <= tol);
        let (dev, tol) = line_deviation(&[DVec3::ZERO, DVec3::new(5.0, 1.0, 0.0), DVec3::X * 10.0]);
        assert!((dev - 1.0).abs() < 1e-12 && dev > tol);
    }

    fn square(x0: f64, x1: f64, z: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(x0, x0, z),
            DVec3::new(x1, x0, z),
            DVec3::new(x1, x1, z),
            DVec3::new(x0, x1, z),
        ]
    }

    #[test]
    fn a_collinear_point_on_an_outer_loop_is_kept() {
        let mut outer = square(0.0, 10.0, 0.0);
        outer.insert(1, DVec3::new(5.0, 0.0, 0.0));
        let face = PlanarFace {
            normal: DVec3::Z,
            loops: vec![outer, square(3.0, 4.0, 0.0)],
            outer: Some(0),
            name: "face".into(),
            place: Place::Whole,
        };
        let soup = soup_from_faces(vec![face], "hint").expect("reads");
        let mut used = vec![false; soup.positions.len()];
        for p in &soup.polygons {
            for &k in p {
                used[k as usize] = true;
            }
        }
        assert!(used.iter().all(|u| *u), "every point used: {soup:?}");
        let area: f64 = soup
            .polygons
            .iter()
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| soup.positions[t[k] as usize]);
                (b - a).cross(c - a).z / 2.0
            })
            .sum();
        assert!((area - 99.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn a_point_off_the_plane_is_refused() {
        let mut l = square(0.0, 10.0, 0.0);
        l[2].z = 1.0;
        let face = PlanarFace {
            normal: DVec3::Z,
            loops: vec![l],
            outer: None,
            name: "face #3".into(),
            place: Place::Line(4),
        };
        let e = soup_from_faces(vec![face], "hint").expect_err("off plane");
        assert!(
            e.problem.contains("face #3") && e.problem.contains("off the face's plane"),
            "{e}"
        );
    }
}
