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

/// Twice the signed area of a 2D polygon (positive counter-clockwise).
pub(crate) fn shoelace(points: &[DVec2]) -> f64 {
    points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(p, q)| p.perp_dot(*q))
        .sum()
}
