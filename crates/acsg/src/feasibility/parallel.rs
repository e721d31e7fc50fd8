//! A crossing of two edges where one edge stays parallel to a face at the other, for
//! every rotation in the bounds: a rotation-pinned test that rules the crossing out.
//!
//! Let edge `Y` of one part cross edge `X` of the other (e-e), and let `f` be a face
//! at `X` whose plane `Y` is exactly parallel to under every rotation the bounds allow
//! (a rim edge along y against the peg's side face whose normal stays in the xz plane
//! while the yaw is pinned at 0). Wherever the crossing holds, `Y` passes within the
//! tolerance of `X`, which lies in `f`'s plane, so all of `Y` lies within the tolerance
//! of that plane, from end to end; and `Y` crosses `X`'s line in that plane, so past the
//! crossing it runs into `f`. The contact module then reads `Y` lying in `f` (e-f or
//! f-e), whose stretch ends at the crossing: the crossing is implied, never principal,
//! and no pose in the bounds shows a state listing it. That needs `Y` to run into `f`
//! by more than the tolerance within the separation of the crossing, so the test asks
//! the angle between `Y` and `X` to stay above [`MIN_CROSSING_SINE`].
//!
//! "Parallel for every rotation" is decided exactly: `n_f · d_Y`, with one of them
//! turned by `G R(rx, ry, rz)`, is affine in the cosine and sine of each angle, so it
//! vanishes on the whole box of rotations when it vanishes at three distinct angles of
//! each component (with the others at theirs), 27 evaluations at most.

use glam::{DMat3, DVec3};

use crate::contact::{ContactKind, PrincipalContact};
use crate::model::{EdgeId, ElementId, Part};
use crate::pose::{Bounds, Pose};

/// The smallest sine of the angle between the crossing edges for which the test holds:
/// `Y` then runs into `f` by more than twice the tolerance within the separation of the
/// crossing (2e-9 L over 1e-6 L is 2e-3), with room for faces whose corners near the
/// crossing are acute.
pub(crate) const MIN_CROSSING_SINE: f64 = 0.05;

/// `n_f · d_Y` at most this (both unit vectors) at every sampled rotation is zero: the
/// round-off of turning a unit vector by three rotations.
const PARALLEL_ROUNDOFF: f64 = 1e-14;

/// Whether a crossing of `target` has one edge held parallel to a face at the other
/// edge under every rotation of `bounds` (see the module's documentation): `true`
/// proves that no pose in the bounds shows `target`. `assembled` is G's rotation.
pub(crate) fn crossing_held_in_a_face(
    fixed: &Part,
    moving: &Part,
    bounds: &Bounds,
    assembled: DMat3,
    target: &[PrincipalContact],
) -> bool {
    // Most candidates have no crossing: no rotation is sampled for them.
    if !target.iter().any(|pc| pc.kind == ContactKind::EdgeEdge) {
        return false;
    }
    let rotations = sample_rotations(bounds, assembled);
    let (centre, reach) = centre_and_reach(bounds, assembled);
    target.iter().any(|pc| {
        let (ElementId::Edge(a), ElementId::Edge(b), ContactKind::EdgeEdge) = (pc.fixed, pc.moving, pc.kind) else {
            return false;
        };
        let (da, db) = (direction(fixed, a), direction(moving, b));
        // The angle between the edges, at every rotation of the bounds.
        if da.cross(centre * db).length() - reach < MIN_CROSSING_SINE {
            return false;
        }
        // A face of the moving part at b, parallel to a; a face of the fixed part at a,
        // parallel to b.
        let moving_face = moving
            .edge(b)
            .faces
            .iter()
            .any(|&f| parallel_everywhere(&rotations, da, moving.face(f).normal));
        let fixed_face = fixed
            .edge(a)
            .faces
            .iter()
            .any(|&f| parallel_everywhere(&rotations, fixed.face(f).normal, db));
        moving_face || fixed_face
    })
}

/// Whether `u · (R v)` vanishes at every sampled rotation.
fn parallel_everywhere(rotations: &[DMat3], u: DVec3, v: DVec3) -> bool {
    rotations.iter().all(|r| u.dot(*r * v).abs() <= PARALLEL_ROUNDOFF)
}

/// The unit direction of an edge.
fn direction(part: &Part, x: EdgeId) -> DVec3 {
    let [p, q] = part.edge_points(x);
    (q - p).normalize()
}

/// `G R` at three distinct angles of each rotation component that the bounds leave
/// free (a quarter, a half and three quarters of its range), at its one value when
/// pinned.
fn sample_rotations(bounds: &Bounds, assembled: DMat3) -> Vec<DMat3> {
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    let values = |k: usize| -> Vec<f64> {
        if hi[k] > lo[k] {
            [0.25, 0.5, 0.75].iter().map(|t| lo[k] + t * (hi[k] - lo[k])).collect()
        } else {
            vec![lo[k]]
        }
    };
    let mut out = Vec::new();
    for &rx in &values(3) {
        for &ry in &values(4) {
            for &rz in &values(5) {
                out.push(assembled * Pose::from_array([0.0, 0.0, 0.0, rx, ry, rz]).rotation());
            }
        }
    }
    out
}

/// `G R` at the centre of the bounds' rotations, and how far any rotation of the bounds
/// moves a unit vector from where that one puts it, at most (the sum of the half-ranges:
/// a turn by `a` moves a unit vector by at most `a`).
fn centre_and_reach(bounds: &Bounds, assembled: DMat3) -> (DMat3, f64) {
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    let centre: [f64; 6] = std::array::from_fn(|k| if k < 3 { 0.0 } else { 0.5 * (lo[k] + hi[k]) });
    let reach = (3..6).map(|k| 0.5 * (hi[k] - lo[k])).sum();
    (assembled * Pose::from_array(centre).rotation(), reach)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{contact, fixture};

    /// The plain hole's rim edge along y (x = 35) and the peg's corner edges: with the
    /// yaw pinned, the peg's side faces facing ±x keep their normals in the xz plane.
    #[test]
    fn a_rim_edge_crossing_a_pegs_corner_edge_lies_in_its_side_face_when_the_yaw_is_pinned() {
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let d = 1f64.to_radians();
        let pinned = Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, 0.0], [1.0, 1.0, 45.0, d, d, 0.0]).unwrap();
        let crossing = [contact("e11", "e0", ContactKind::EdgeEdge)];
        assert!(crossing_held_in_a_face(
            &hole,
            &peg,
            &pinned,
            DMat3::IDENTITY,
            &crossing
        ));
        // With the yaw free the face turns off the rim edge's direction.
        let free = Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, -d], [1.0, 1.0, 45.0, d, d, d]).unwrap();
        assert!(!crossing_held_in_a_face(&hole, &peg, &free, DMat3::IDENTITY, &crossing));
    }

    /// Independently of the rule: at poses where the peg's corner edge e0 crosses the
    /// rim edge e11 (found by the local solver from spread starts), the contact module
    /// reads the rim edge in the peg's face, never the crossing alone.
    #[test]
    fn where_the_pinned_crossing_holds_the_contact_module_reads_the_edge_in_the_face() {
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let d = 1f64.to_radians();
        let pinned = Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, 0.0], [1.0, 1.0, 45.0, d, d, 0.0]).unwrap();
        let problem = super::super::Problem::new(&hole, &peg, pinned, glam::DAffine3::IDENTITY);
        let crossing = [contact("e11", "e0", ContactKind::EdgeEdge)];
        let mut stats = super::super::SearchStats::default();
        let mut held = 0;
        for start in problem.spread_starts(&crossing, 24) {
            let pose = problem.solve_from(&crossing, start, &pinned, &mut stats);
            let report = problem
                .scene()
                .state(&problem.placement(&pose), crate::tolerance::CONTACT_REL);
            let lying = report
                .contacts
                .iter()
                .any(|pc| pc.fixed == crossing[0].fixed && pc.kind == ContactKind::EdgeFace);
            if report.penetration == 0.0 && lying {
                held += 1;
            }
            assert_ne!(report.contacts, crossing, "at {:?}", pose.to_array());
        }
        assert!(held > 0, "no start reached the rim edge on the peg's face");
    }
}
