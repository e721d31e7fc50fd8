//! An edge through a corner of the other part, running flat over a face at that
//! corner: a rotation test, for the last proofs, that no pose shows the corner on the
//! edge robustly.
//!
//! Let a vertex `v` of one part lie on an edge `x` of the other (a v-e or e-v
//! contact), and let `g` be a face at `v` whose corner there is convex. Going from `v`
//! along `x` one way, `σ x`, the edge runs into `g`'s corner (strictly between the two
//! edges of `g` at `v`, seen in `g`'s plane). At `v` the edge is within the tolerance of
//! `g`'s plane; its height changes at the rate `n · (R σ x)`. Follow it to its end `P`,
//! at most `run` away (what the box keeps the vertex's place on the edge to). If the
//! rate is below `(0.9 separation − tolerance) / run` either way, every point of that
//! stretch stays within 0.9 separations of `g`'s plane. A straight line from a convex
//! corner into it meets the corner's two edges nowhere else, so the stretch either
//! ends over `g` (then `P` is nearer `g` than the separation) or leaves `g` over another
//! of its edges or corners (then the edge passes nearer than the separation). Either
//! pair is too close for a witness, or touches: a contact the target does not hold,
//! unless one of its contacts implies the pair (then the test says nothing).
//!
//! The chamfered hole's corner at the foot of its chamfers, on the peg's upright edge
//! turned about y and z: below the corner the edge runs down the hole's wall, off its
//! plane by the product of the two small turns, to the peg's bottom corner 1 mm below.

use glam::DVec3;

use super::Problem;
use super::dip::closure_without;
use super::edge_pair::CentreMotion;
use super::interval::{IntervalMat, turned_value as value};
use super::prover::implied;
use crate::contact::PrincipalContact;
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::pose::Bounds;
use crate::tolerance::{CONTACT_REL, scaled};

/// An edge held at a corner of the other part, against one face at the corner, one
/// way along the edge. Values `a · (R b)`, `a` in G's frame and `b` in the moving
/// part's.
#[derive(Clone, Debug)]
pub(super) struct CornerRun {
    /// The edge's direction (that way) against the inward normals, in the face's
    /// plane, of the corner's two edges: both positive, the edge runs into the corner.
    into: [(DVec3, DVec3); 2],
    /// The edge's direction against the face's normal: its rate off the plane.
    rate: (DVec3, DVec3),
    /// The vertex (in the frame of the edge's part at the box's centre, moved by at
    /// most the box's motion) and the edge, to bound the run to the edge's end.
    vertex: DVec3,
    edge: [DVec3; 2],
    /// Whether the vertex is the fixed part's (the edge the moving part's).
    vertex_fixed: bool,
    /// Whether the edge runs towards its second end.
    forward: bool,
    /// How far off the plane the stretch may end: 0.9 separations less the tolerance.
    exit: f64,
}

impl CornerRun {
    /// Whether no pose of `b` (rotations enclosed by `r`) is a robust witness: the
    /// edge runs into the corner and stays within the exit of the face's plane to its
    /// end.
    pub fn excludes(&self, r: &IntervalMat, b: &Bounds) -> bool {
        if self.into.iter().any(|&(a, d)| value(r, a, d).lo <= 0.0) {
            return false;
        }
        let run = self.longest_run(b);
        if run <= 0.0 {
            return false;
        }
        let flat = self.exit / run;
        let rate = value(r, self.rate.0, self.rate.1);
        rate.lo > -flat && rate.hi < flat
    }

    /// How far the edge runs from the vertex to its end that way, at most, over `b`.
    fn longest_run(&self, b: &Bounds) -> f64 {
        let motion = CentreMotion::of(b);
        let (at, moved) = if self.vertex_fixed {
            motion.g_to_moving(self.vertex)
        } else {
            motion.moving_to_g(self.vertex)
        };
        let [e0, e1] = self.edge;
        let length = e0.distance(e1);
        let along = (at - e0).dot((e1 - e0) / length);
        let run = if self.forward {
            length - (along - moved)
        } else {
            along + moved
        };
        run.min(length)
    }
}

impl Problem<'_> {
    /// The corner runs of a contact `pc` between vertex `v` and edge `x` of the other
    /// part (`vertex_fixed` when `v` is the fixed part's): one per face at `v` with a
    /// convex corner there, per way along `x`, unless a contact of `target` implies a
    /// pair the test counts on.
    pub(super) fn corner_runs(
        &self,
        target: &[PrincipalContact],
        (v, x): (VertexId, EdgeId),
        vertex_fixed: bool,
    ) -> Vec<CornerRun> {
        let (corner_part, edge_part) = if vertex_fixed {
            (self.fixed, self.moving)
        } else {
            (self.moving, self.fixed)
        };
        // Directions and points of the vertex's part, and of the edge's, in the
        // frames the values take them in.
        let corner_direction = |d: DVec3| {
            if vertex_fixed {
                self.prover.fixed_direction(d)
            } else {
                d
            }
        };
        let edge_direction = |d: DVec3| {
            if vertex_fixed {
                d
            } else {
                self.prover.fixed_direction(d)
            }
        };
        let edge_point = |p: DVec3| if vertex_fixed { p } else { self.prover.fixed_point(p) };
        let vertex_point = corner_part.vertex(v).position;
        let vertex = if vertex_fixed {
            self.prover.fixed_point(vertex_point)
        } else {
            vertex_point
        };
        let edge = edge_part.edge_points(x).map(edge_point);
        let dx = edge_direction(edge_part.edge_direction(x));
        let tolerance = scaled(CONTACT_REL, self.scale);
        let exit = 0.9 * self.separation() - tolerance;
        let pair = |on_corner: ElementId, on_edge: ElementId| {
            if vertex_fixed {
                (on_corner, on_edge)
            } else {
                (on_edge, on_corner)
            }
        };
        let held = |(a, b): (ElementId, ElementId)| implied(self.fixed, self.moving, target, a, b);
        let mut runs = Vec::new();
        for (f, inward) in corners_at(corner_part, v) {
            let near = closure_without(corner_part, f, &[ElementId::Vertex(v)]);
            let edge_ends = edge_part.edge(x).vertices;
            for (forward, end) in [(true, edge_ends[1]), (false, edge_ends[0])] {
                // The pairs the test counts on: the edge's end with the face's closure
                // (but the vertex), the edge with the face's other edges and corners.
                let at_v = |y: &ElementId| match *y {
                    ElementId::Edge(y) => corner_part.edge(y).vertices.contains(&v),
                    ElementId::Face(_) => true,
                    ElementId::Vertex(_) => false,
                };
                let pairs = near
                    .iter()
                    .map(|&y| pair(y, ElementId::Vertex(end)))
                    .chain(near.iter().filter(|y| !at_v(y)).map(|&y| pair(y, ElementId::Edge(x))));
                if pairs.into_iter().any(held) {
                    continue;
                }
                let sign = if forward { 1.0 } else { -1.0 };
                let d = sign * dx;
                let value_of = |a: DVec3| if vertex_fixed { (corner_direction(a), d) } else { (d, a) };
                runs.push(CornerRun {
                    into: inward.map(value_of),
                    rate: value_of(corner_part.face(f).normal),
                    vertex,
                    edge,
                    vertex_fixed,
                    forward,
                    exit,
                });
            }
        }
        runs
    }
}

/// The faces at vertex `v` whose corner there is convex, each with the inward normals
/// (in the face's plane) of its two edges at `v`. A loop runs counter-clockwise about
/// its face's outward normal with the face on its left, so the face lies left of the
/// outgoing edge `a` (`n × a`) and right of the incoming one, taken from `v` (`a' × n`).
pub(super) fn corners_at(part: &Part, v: VertexId) -> Vec<(FaceId, [DVec3; 2])> {
    let mut corners = Vec::new();
    for (index, face) in part.faces().iter().enumerate() {
        let n = face.normal;
        for l in &face.loops {
            let count = l.vertices.len();
            for i in 0..count {
                if l.vertices[i] != v {
                    continue;
                }
                let at = part.vertex(v).position;
                let next = part.vertex(l.vertices[(i + 1) % count]).position;
                let prev = part.vertex(l.vertices[(i + count - 1) % count]).position;
                let (out, back) = ((next - at).normalize(), (prev - at).normalize());
                // Convex corner: turning from the outgoing edge to the incoming one
                // counter-clockwise about n takes less than half a turn.
                if out.cross(back).dot(n) <= 1e-9 {
                    continue;
                }
                corners.push((
                    FaceId(u32::try_from(index).expect("face index")),
                    [n.cross(out), back.cross(n)],
                ));
            }
        }
    }
    corners
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use crate::contact::ContactKind as K;
    use crate::feasibility::Problem;
    use crate::pose::{Bounds, Pose};
    use crate::testing::{contact, fixture, turned_peg_bounds};
    use crate::tolerance::CONTACT_REL;

    /// The square peg turned by `ry` and `rz` in the chamfered hole, the hole's corner
    /// v7 (35, 35, 45), at the foot of its chamfers, on the peg's upright edge e0 (x =
    /// y = 36), `up` above the edge's lower end.
    fn corner_on_the_upright_edge(ry: f64, rz: f64, up: f64) -> Pose {
        let rotation = DMat3::from_rotation_z(rz) * DMat3::from_rotation_y(ry);
        let t = DVec3::new(35.0, 35.0, 45.0) - rotation * DVec3::new(36.0, 36.0, 10.0 + up);
        Pose::from_array([t.x, t.y, t.z, 0.0, ry, rz])
    }

    #[test]
    fn an_edge_running_flat_down_the_wall_from_the_holes_corner_is_never_a_witness() {
        // The turned peg's undecided {v-e v7 e0}: below the corner, the peg's upright
        // edge runs down the hole's wall f9 (y = 35), off its plane by the product of
        // the two turns, to the peg's bottom corner v0 about 1 mm below: nearer the
        // wall than the separation (1.8e-4 mm), or on it.
        let (hole, peg) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let problem = Problem::new(&hole, &peg, turned_peg_bounds(), glam::DAffine3::IDENTITY);
        let target = [contact("v7", "e0", K::VertexEdge)];
        let separation = problem.separation();
        let mut holding = 0;
        // Turned about z by more than the tolerance over the peg's width, one of the
        // peg's faces at e0 dips into a wall just under the corner: only the turns
        // about y are left.
        for ry in [-0.03, -0.0235, -0.01] {
            for rz in [-3e-9, 0.0, 3e-9] {
                for up in [0.3, 0.9, 1.5] {
                    let placement = corner_on_the_upright_edge(ry, rz, up).to_affine(&glam::DAffine3::IDENTITY);
                    let report = problem.scene().evaluate_within(&placement, CONTACT_REL, 1e-3);
                    assert_eq!(report.penetration, 0.0, "{ry} {rz} {up}");
                    // The corner on the edge, or held by larger contacts (the peg's
                    // face on the wall).
                    let corner = &target[0];
                    if report
                        .contacts
                        .iter()
                        .any(|pc| hole.in_closure(pc.fixed, corner.fixed) && peg.in_closure(pc.moving, corner.moving))
                    {
                        holding += 1;
                    }
                    // The bottom corner on the wall (alone, or with an edge or face of
                    // the peg holding it), or too near it.
                    let wall = contact("f9", "v0", K::FaceVertex);
                    let on_wall = report
                        .contacts
                        .iter()
                        .any(|pc| pc.fixed == wall.fixed && peg.in_closure(pc.moving, wall.moving));
                    let too_near = report.min_gap.is_some_and(|g| g < separation);
                    assert!(
                        on_wall || too_near,
                        "{ry} {rz} {up}: {:?} {:?}",
                        report.contacts,
                        report.min_gap
                    );
                    let witness = crate::testing::witnesses(problem.scene(), &placement, &report, &target);
                    assert!(!witness, "a witness at {ry} {rz} {up}");
                }
            }
        }
        assert!(holding >= 20, "{holding} poses hold the corner on the edge");
        // The box the last proofs left open before the corner runs: now ruled out by
        // them, and left open without them and by the decisions' conditions.
        let open = Bounds::try_new(
            [
                -0.7683342122251668,
                -0.9917483968079884,
                34.109808902550995,
                0.0,
                -0.023589215671485864,
                -0.00035401389956814987,
            ],
            [
                -0.7613852314783095,
                -0.9873381310100613,
                34.15840804002989,
                0.0,
                -0.023452861823673808,
                -0.0002308213280475071,
            ],
        )
        .expect("a box");
        assert!(!problem.strict_turns(&target).may_hold(&open));
        assert!(problem.strict_turns(&target).without_corner_runs().may_hold(&open));
        assert!(problem.turns(&target).may_hold(&open));
    }
}
