//! A vertex at a reflex corner of one of its own part's faces, on a face of the other
//! part: a rotation-invariant test that no pose shows it robustly.
//!
//! Let a vertex `v` of the fixed part touch a face `g` of the moving part (v-f), and let
//! `v` be a reflex corner of a face `f` of the fixed part (the hole's corner in a block's
//! top face, whose top turns 270° around it). Take either edge of `f` at `v`, direction
//! `d`. The points `v + λ d` run along that edge, the points `v − λ d` into `f`'s interior
//! (the corner is reflex, so the edge's backward continuation enters the face). Both are
//! on the fixed part's boundary with its solid behind them. Their signed distances from
//! `g`'s plane are `±λ (R n_g) · d`: one side never rises off `g`. Follow that side until
//! its point leaves `g` (passing over one of `g`'s boundary elements) or leaves the edge
//! or face it runs in (at the edge's other end, or over another edge of `f`). Before
//! that, its points lie within `g` on the moving part's side of `g`'s plane, or on it:
//! inside the moving part, or touching it along a stretch; and at that point a pair of
//! elements neither incident to `v` nor to the contact's face touches or penetrates
//! (the end vertex on `g`, an edge of `g` on `f` or on the edge). So at every pose the
//! parts penetrate, or a pair that no contact lists touches: the face on `f` (face on
//! face) when `g` lies flat, another state otherwise. The same holds with the parts'
//! roles swapped (f-v at a reflex corner of the moving part's face).
//!
//! The pairs met are the contact face's own boundary elements against the other part,
//! so another contact of the target on `g`'s closure could list or imply them; the test
//! then says nothing.

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{ElementId, FaceId, Part, VertexId};

/// Whether `target` holds a vertex at a strictly reflex corner of one of its own part's
/// faces on a face of the other part, with no other contact of the target on an element
/// that shares a vertex with that face (see the module's documentation): `true` proves
/// that no pose shows the target robustly.
pub(crate) fn corner_on_a_face(fixed: &Part, moving: &Part, target: &[PrincipalContact]) -> bool {
    target.iter().any(|pc| {
        let (corner_part, vertex, face_part, face, face_moves) = match (pc.kind, pc.fixed, pc.moving) {
            (ContactKind::VertexFace, ElementId::Vertex(v), ElementId::Face(g)) => (fixed, v, moving, g, true),
            (ContactKind::FaceVertex, ElementId::Face(f), ElementId::Vertex(v)) => (moving, v, fixed, f, false),
            _ => return false,
        };
        let alone = target.iter().filter(|other| *other != pc).all(|other| {
            let element = if face_moves { other.moving } else { other.fixed };
            !face_part.share_a_vertex(element, ElementId::Face(face))
        });
        alone && is_reflex_corner(corner_part, vertex)
    })
}

/// Whether `v` is a strictly reflex corner (interior angle above 180° by more than
/// round-off) of a loop of one of its faces.
fn is_reflex_corner(part: &Part, v: VertexId) -> bool {
    part.vertex(v).faces.iter().any(|&f| reflex_in(part, f, v))
}

fn reflex_in(part: &Part, f: FaceId, v: VertexId) -> bool {
    let normal = part.face(f).normal;
    part.face(f).loops.iter().any(|l| {
        let corners = &l.vertices;
        let n = corners.len();
        (0..n).filter(|&i| corners[i] == v).any(|i| {
            let p = |k: usize| part.vertex(corners[k % n]).position;
            let (into, out) = ((p(i) - p(i + n - 1)).normalize(), (p(i + 1) - p(i)).normalize());
            // The turn's sine: negative at a right turn (a reflex corner of a
            // counter-clockwise loop), far from zero past straight.
            into.cross(out).dot(normal) < -STRAIGHT_SINE
        })
    })
}

/// Corners whose turn's sine is within this of zero count as straight, not reflex.
const STRAIGHT_SINE: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::contact::ContactKind as K;
    use crate::feasibility::{Problem, Rule};
    use crate::pose::{Bounds, Pose};
    use crate::testing::{contact, fixture};
    use crate::tolerance::CONTACT_REL;

    /// `f` of the square peg tilted in the plain hole (`testing::tilted_peg_bounds`):
    /// the block, the peg, their problem and its bounds.
    fn with_the_tilted_peg(f: impl FnOnce(&Part, &Part, &Problem<'_>, Bounds)) {
        let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let bounds = crate::testing::tilted_peg_bounds();
        f(
            &block,
            &peg,
            &Problem::new(&block, &peg, bounds, glam::DAffine3::IDENTITY),
            bounds,
        );
    }

    #[test]
    fn the_holes_corners_are_reflex_corners_of_the_top_and_the_blocks_outer_corners_are_not() {
        let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let at = |p: [f64; 3]| {
            (0..block.vertices().len() as u32)
                .map(VertexId)
                .find(|&v| block.vertex(v).position == DVec3::from(p))
                .expect("a vertex there")
        };
        assert!(is_reflex_corner(&block, at([35.0, 35.0, 50.0])));
        assert!(is_reflex_corner(&block, at([65.0, 65.0, 0.0])));
        assert!(!is_reflex_corner(&block, at([0.0, 0.0, 50.0])));
        assert!(!is_reflex_corner(&block, at([100.0, 100.0, 0.0])));
        // A convex peg has no reflex corner at all.
        assert!((0..peg.vertices().len() as u32).all(|v| !is_reflex_corner(&peg, VertexId(v))));
    }

    #[test]
    fn the_holes_corner_on_the_peg_bottom_holds_with_another_contact_so_the_proof_leans_on_others() {
        // The square peg tilted in the plain hole: the hole's corner v5 on the peg's
        // bottom f2 never holds alone (the test below), yet the peg's corner v0 on the
        // block's top f3 beside it makes a state, at the generator's witness. So a
        // proof by the reflex corner says nothing of the states holding the contact
        // with others, and stage 1 must still search for them.
        with_the_tilted_peg(|_, _, problem, bounds| {
            let single = [contact("v5", "f2", K::VertexFace)];
            assert_eq!(problem.last_exclusion(&single, &bounds), Some(Rule::ReflexCorner));
            let (state, pose) = crate::testing::corner_beside_the_rim();
            assert!(state.contains(&single[0]));
            assert!(bounds.contains(&pose, 0.0, 0.0));
            let placement = pose.to_affine(&glam::DAffine3::IDENTITY);
            let report = problem.scene().evaluate(&placement, CONTACT_REL);
            assert!(crate::testing::witnesses(problem.scene(), &placement, &report, &state));
            let proof = |rule: Rule| crate::feasibility::Proof {
                rules: [rule].into(),
                boxes: 1,
            };
            assert!(proof(Rule::ReflexCorner).leans_on_others_apart());
            // A rule about the contact alone (its normals) rules out every state holding it.
            assert!(!proof(Rule::NormalAngles).leans_on_others_apart());
        });
    }

    #[test]
    fn the_peg_bottom_on_the_holes_corner_is_never_a_witness_and_the_last_proofs_say_so() {
        // The hole's corner v5 (35, 35, 50) on the square peg's bottom f2 (z = 10, x
        // and y in [36, 64]), as the tilted peg's undecided candidates had it.
        with_the_tilted_peg(|block, peg, problem, bounds| {
            let target = [contact("v5", "f2", K::VertexFace)];
            assert!(corner_on_a_face(block, peg, &target));
            assert_eq!(problem.last_exclusion(&target, &bounds), Some(Rule::ReflexCorner));
            assert_ne!(problem.exclusion(&target, &bounds), Some(Rule::ReflexCorner));
            // Independently, the contact module and the witness check: the bottom's point
            // `(36 + a, 36 + b, 10)` put on the corner, tilted every way by 1e-4 to 1e-2
            // rad and not at all, the corner 2e-4 mm (just past the separation, 1.5e-4) to
            // 20 mm inside the bottom. The contact holds at many of them; no pose is a
            // robust witness of it alone.
            let corner = DVec3::new(35.0, 35.0, 50.0);
            let tilts = [-1e-2, -1e-3, -1e-4, 0.0, 1e-4, 1e-3, 1e-2];
            let insets = [2e-4, 1e-2, 1.0, 20.0];
            let mut holding = 0;
            for rx in tilts {
                for ry in tilts {
                    for a in insets {
                        for b in insets {
                            let rotation = DMat3::from_rotation_y(ry) * DMat3::from_rotation_x(rx);
                            let t = corner - rotation * DVec3::new(36.0 + a, 36.0 + b, 10.0);
                            let placement =
                                Pose::from_array([t.x, t.y, t.z, rx, ry, 0.0]).to_affine(&glam::DAffine3::IDENTITY);
                            let report = problem.scene().evaluate(&placement, CONTACT_REL);
                            if report.contacts.contains(&target[0]) {
                                holding += 1;
                            }
                            let witness = crate::testing::witnesses(problem.scene(), &placement, &report, &target);
                            assert!(!witness, "a witness at rx {rx}, ry {ry}, inset ({a}, {b})");
                        }
                    }
                }
            }
            assert!(holding >= 100, "the contact holds at {holding} poses only");
        });
    }

    #[test]
    fn another_contact_on_the_faces_closure_or_a_convex_corner_leaves_the_test_silent() {
        let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        // Two corners of the hole on the peg's bottom: the second contact may list the
        // pairs the argument meets.
        let both = [contact("v5", "f2", K::VertexFace), contact("v7", "f2", K::VertexFace)];
        assert!(!corner_on_a_face(&block, &peg, &both));
        // The block's outer corner v1 (0, 0, 50) is convex in each of its faces.
        assert!(!corner_on_a_face(&block, &peg, &[contact("v1", "f2", K::VertexFace)]));
        // The roles swapped: the block moving, its corner on the peg's face.
        assert!(corner_on_a_face(&peg, &block, &[contact("f2", "v5", K::FaceVertex)]));
    }
}
