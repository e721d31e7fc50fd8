//! A vertex on a face, held on the plane of a face next to it: a target-level test, for
//! the last proofs, that no pose shows both robustly.
//!
//! Let a vertex `v` of one part lie on a face `h` of the other (f-v or v-f), and let
//! another contact of the target hold `v` on the plane of a face `g` next to `h` across
//! their common edge `y`: `v` an end of an edge lying in `g` (read from end to end, both
//! ends lie within the tolerance of `g`'s plane), or `v` on `g` itself. Then `v` lies
//! within the tolerance of both planes, so within `2 tol / sin α` of their common line,
//! `y`'s line (`α` the angle between the faces' normals). Where its foot falls on `y`,
//! `v` is that near `h`'s rim, where a checker with a looser tolerance reads it on `y`,
//! not on `h`; where its foot falls beyond `y`'s ends, `v` is off `h` altogether, `h`'s
//! corners there being convex. So no pose shows the target robustly.
//!
//! The turned square peg in the chamfered hole: a corner of the peg's bottom on one
//! chamfer while the bottom edge from it lies on the next chamfer puts the corner on the
//! chamfers' valley edge.

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::tolerance::{CONTACT_REL, SEPARATION_REL, scaled};

/// Whether `target` holds a vertex on a face and, by another contact, on the plane of
/// a face next to it ([`self`]). `scale` is the pair's length scale.
pub(super) fn on_the_fold(fixed: &Part, moving: &Part, target: &[PrincipalContact], scale: f64) -> bool {
    let tolerance = scaled(CONTACT_REL, scale);
    // Nearer the common line than this, the vertex is too near `h`'s rim for a witness.
    let near = 0.5 * scaled(SEPARATION_REL, scale);
    target.iter().any(|pc| {
        let (faces, vertex_part, h, v, h_fixed) = match (pc.kind, pc.fixed, pc.moving) {
            (ContactKind::FaceVertex, ElementId::Face(h), ElementId::Vertex(v)) => (fixed, moving, h, v, true),
            (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(h)) => (moving, fixed, h, v, false),
            _ => return false,
        };
        target.iter().filter(|other| *other != pc).any(|other| {
            let (on_faces, on_vertex) = if h_fixed {
                (other.fixed, other.moving)
            } else {
                (other.moving, other.fixed)
            };
            let ElementId::Face(g) = on_faces else {
                return false;
            };
            if g == h || !holds_on_plane(vertex_part, other.kind, on_vertex, v) {
                return false;
            }
            let Some(y) = common_edge(faces, h, g) else {
                return false;
            };
            let (nh, ng) = (faces.face(h).normal, faces.face(g).normal);
            let sine = nh.cross(ng).length();
            sine > 0.0 && 2.0 * tolerance / sine < near && convex_at_both_ends(faces, h, y)
        })
    })
}

/// Whether a contact of kind `kind` holding element `e` on a face keeps vertex `v`
/// within the tolerance of that face's plane: `v` itself on the face, or `v` an end of
/// an edge lying in it (read from end to end).
fn holds_on_plane(part: &Part, kind: ContactKind, e: ElementId, v: VertexId) -> bool {
    match (kind, e) {
        (ContactKind::FaceVertex | ContactKind::VertexFace, ElementId::Vertex(w)) => w == v,
        (ContactKind::FaceEdge | ContactKind::EdgeFace, ElementId::Edge(x)) => part.edge(x).vertices.contains(&v),
        _ => false,
    }
}

/// The edge faces `h` and `g` share, if any.
fn common_edge(part: &Part, h: FaceId, g: FaceId) -> Option<EdgeId> {
    let edges = |f: FaceId| {
        part.face(f)
            .loops
            .iter()
            .flat_map(|l| l.edges.iter().copied())
            .collect::<Vec<_>>()
    };
    let of_g = edges(g);
    edges(h).into_iter().find(|y| of_g.contains(y))
}

/// Whether face `h`'s corners at both ends of its edge `y` are convex.
fn convex_at_both_ends(part: &Part, h: FaceId, y: EdgeId) -> bool {
    part.edge(y)
        .vertices
        .iter()
        .all(|&w| super::corner_run::corners_at(part, w).iter().any(|(f, _)| *f == h))
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::contact::ContactKind as K;
    use crate::feasibility::Problem;
    use crate::testing::{contact, fixture, turned_peg_bounds, witnesses};
    use crate::tolerance::CONTACT_REL;

    #[test]
    fn a_corner_on_one_chamfer_with_its_edge_on_the_next_is_on_the_valley_edge() {
        // The turned peg's undecided {f-v f5 v0, f-e f6 e2}: the peg's bottom corner
        // v0 on the left chamfer f5, its bottom front edge e2 (from v0) on the front
        // chamfer f6. Independently: with e2 lying in f6's plane and v0 on f5's plane,
        // the contact module reads v0 on the chamfers' valley edge (or nothing on f5),
        // never the target.
        let (hole, peg) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let problem = Problem::new(&hole, &peg, turned_peg_bounds(), glam::DAffine3::IDENTITY);
        let on_chamfer = contact("f5", "v0", K::FaceVertex);
        let mut target = [on_chamfer, contact("f6", "e2", K::FaceEdge)];
        target.sort();
        assert!(on_the_fold(&hole, &peg, &target, problem.scale));
        // The poses: e2 (along x) turned into f6's plane (ry = rz), v0 placed on the
        // valley line x = y, z = 80 − x (f5 and f6 both), at heights along it.
        let mut read_on_valley = 0;
        for turn in [-0.01f64, -0.0073, -0.003] {
            let rotation = DMat3::from_rotation_z(turn) * DMat3::from_rotation_y(turn);
            for along in [0.5, 1.0, 2.0, 4.0] {
                let corner = DVec3::new(35.0 - along, 35.0 - along, 45.0 + along);
                let t = corner - rotation * DVec3::new(36.0, 36.0, 10.0);
                let pose = crate::pose::Pose::from_array([t.x, t.y, t.z, 0.0, turn, turn]);
                let placement = pose.to_affine(&glam::DAffine3::IDENTITY);
                let report = problem.scene().evaluate_within(&placement, CONTACT_REL, 1e-3);
                if report.contacts.contains(&contact("e9", "v0", K::EdgeVertex)) {
                    read_on_valley += 1;
                }
                assert!(
                    !witnesses(problem.scene(), &placement, &report, &target),
                    "{turn} {along}"
                );
                assert!(!report.contacts.contains(&on_chamfer), "{turn} {along}: {report:?}");
            }
        }
        assert!(read_on_valley >= 1, "{read_on_valley}");
        // Not the other way round: the wall f9 meets f5 at a corner only.
        let mut apart = [contact("f5", "v0", K::FaceVertex), contact("f9", "e8", K::FaceEdge)];
        apart.sort();
        assert!(!on_the_fold(&hole, &peg, &apart, problem.scale));
    }
}
