//! Planar polygons: normals, areas and coordinates in their plane.

use glam::{DVec2, DVec3};

/// Newell's normal (length = twice the area) of a closed polygon.
pub(crate) fn newell(points: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let next = points.clone().cycle().skip(1);
    points.zip(next).fold(DVec3::ZERO, |acc, (p, q)| acc + p.cross(q))
}

/// Orthonormal basis (u, v) of the plane with normal `n`.
pub(crate) fn plane_basis(n: DVec3) -> (DVec3, DVec3) {
    let u = n.any_orthonormal_vector();
    (u, n.cross(u))
}

/// The convex hull of points lying on a plane of normal `n`, counter-clockwise about
/// `n`, with points within `tol` merged.
pub(crate) fn hull_in_plane(points: &[DVec3], n: DVec3, tol: f64) -> Vec<DVec3> {
    let (u, w) = plane_basis(n);
    let mut pts: Vec<(f64, f64, DVec3)> = points.iter().map(|&p| (p.dot(u), p.dot(w), p)).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup_by(|a, b| (a.0 - b.0).abs() <= tol && (a.1 - b.1).abs() <= tol);
    if pts.len() < 3 {
        return pts.into_iter().map(|p| p.2).collect();
    }
    let turn = |o: &(f64, f64, DVec3), a: &(f64, f64, DVec3), b: &(f64, f64, DVec3)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64, DVec3)> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64, DVec3)>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2 && turn(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= tol * tol {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull.into_iter().map(|p| p.2).collect()
}

/// Twice the signed area of a 2D polygon (positive counter-clockwise).
pub(crate) fn shoelace(points: &[DVec2]) -> f64 {
    points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(p, q)| p.perp_dot(*q))
        .sum()
}
