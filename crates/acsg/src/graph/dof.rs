//! Degrees of freedom of a contact state at its witness: 6 minus the rank of the
//! contact constraints (one unit wrench per contact point and normal direction). For a
//! single contact this gives the table of docs/concepts.md#degrees-of-freedom (5 for point
//! contacts, 4 for an edge in a face or a vertex in a groove, 3 for face on face or a
//! vertex in a corner, 2 for an edge in a groove); for several contacts it counts what they
//! leave together.

use glam::{DAffine3, DVec3};

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{ElementId, Part};
use crate::tolerance::RANK_REL;

/// Contact points (A's frame) with the directions they block.
fn constraints(fixed: &Part, moving: &Part, pc: &PrincipalContact, t: &DAffine3) -> Vec<(DVec3, DVec3)> {
    let points_of = |part: &Part, e: ElementId, map: &DAffine3| -> Vec<DVec3> {
        part.outline_points(e)
            .into_iter()
            .map(|p| map.transform_point3(p))
            .collect()
    };
    let normals_at = |part: &Part, e: ElementId, map: &DAffine3| -> Vec<DVec3> {
        part.faces_around(e)
            .into_iter()
            .map(|f| map.transform_vector3(part.face(f).normal))
            .collect()
    };
    let id = DAffine3::IDENTITY;
    let all = |points: Vec<DVec3>, normals: Vec<DVec3>| -> Vec<(DVec3, DVec3)> {
        points
            .iter()
            .flat_map(|&p| normals.iter().map(move |&n| (p, n)))
            .collect()
    };
    match pc.kind {
        ContactKind::FaceVertex | ContactKind::FaceEdge | ContactKind::FaceFace => {
            all(points_of(moving, pc.moving, t), normals_at(fixed, pc.fixed, &id))
        }
        ContactKind::VertexFace | ContactKind::EdgeFace => {
            all(points_of(fixed, pc.fixed, &id), normals_at(moving, pc.moving, t))
        }
        ContactKind::EdgeEdge => {
            let [a0, a1] = points_of(fixed, pc.fixed, &id)[..] else {
                return vec![];
            };
            let [b0, b1] = points_of(moving, pc.moving, t)[..] else {
                return vec![];
            };
            vec![(a0.lerp(a1, 0.5).lerp(b0.lerp(b1, 0.5), 0.5), (a1 - a0).cross(b1 - b0))]
        }
        // A vertex held in an edge: it stays on the edge's line (the faces' normals
        // span the two blocked directions, for a concave edge and a convex one alike).
        ContactKind::EdgeVertex => all(points_of(moving, pc.moving, t), normals_at(fixed, pc.fixed, &id)),
        ContactKind::VertexEdge => all(points_of(fixed, pc.fixed, &id), normals_at(moving, pc.moving, t)),
        ContactKind::EdgeEdgeTouch => all(points_of(moving, pc.moving, t), normals_at(fixed, pc.fixed, &id)),
        ContactKind::VertexVertex => all(points_of(fixed, pc.fixed, &id), vec![DVec3::X, DVec3::Y, DVec3::Z]),
    }
}

/// The degrees of freedom a state leaves at the pose `t` (B's frame to A's); `scale` is
/// the length scale L.
#[must_use]
pub(crate) fn state_dof(fixed: &Part, moving: &Part, contacts: &[PrincipalContact], t: &DAffine3, scale: f64) -> u8 {
    let pairs: Vec<(DVec3, DVec3)> = contacts
        .iter()
        .flat_map(|pc| constraints(fixed, moving, pc, t))
        .filter(|(_, n)| n.length() > 0.0)
        .collect();
    if pairs.is_empty() {
        return 6;
    }
    let centre = pairs.iter().map(|(p, _)| *p).sum::<DVec3>() / pairs.len() as f64;
    let mut rows: Vec<[f64; 6]> = pairs
        .iter()
        .map(|(p, n)| {
            let n = n.normalize();
            let m = (*p - centre).cross(n) / scale;
            [n.x, n.y, n.z, m.x, m.y, m.z]
        })
        .collect();
    6 - rank(&mut rows, RANK_REL) as u8
}

/// Rank by Gaussian elimination with full row pivoting; entries below `tol` count as 0.
fn rank(rows: &mut [[f64; 6]], tol: f64) -> usize {
    let mut rank = 0;
    for col in 0..6 {
        let Some(pivot) = (rank..rows.len()).max_by(|&i, &j| rows[i][col].abs().total_cmp(&rows[j][col].abs())) else {
            break;
        };
        if rows[pivot][col].abs() <= tol {
            continue;
        }
        rows.swap(rank, pivot);
        let top = rows[rank];
        for row in rows.iter_mut().skip(rank + 1) {
            let f = row[col] / top[col];
            for k in col..6 {
                row[k] -= f * top[k];
            }
        }
        rank += 1;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rank_counts_independent_rows() {
        let mut rows = vec![
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        ];
        assert_eq!(rank(&mut rows, 1e-9), 2);
        let mut full: Vec<[f64; 6]> = (0..6)
            .map(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }))
            .collect();
        assert_eq!(rank(&mut full, 1e-9), 6);
    }
}
