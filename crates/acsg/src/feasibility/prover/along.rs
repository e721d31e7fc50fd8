//! Two crossing edges where one lies along a face at the other.
//!
//! Take edges `a` and `b` of the two parts crossing at `c`, and a face `F` at `b`. When
//! `a` stays within half the separation of `F`'s plane from end to end, and runs from
//! `c` into `F` far enough to draw clearly away from `b` while still over `F`, a
//! checker at the loosest tolerance reads `a` lying on `F` there: a contact the
//! crossing does not hold, so no pose in the box is a clean witness of a target that
//! lists the crossing and no other contact at `F`'s closure.
//!
//! "Far enough" is what the rule withdrawn in 047bf89 lacked: an edge nearly parallel
//! to `b` may end before it leaves `b`'s tolerance band, and its stretch over the face
//! is then read as part of the crossing. Here the stretch must reach `REACH`
//! separations off `b`'s line within the face, which needs the crossing's position
//! along both edges: the closest points of the two lines, enclosed over the box.

use glam::DVec3;

use super::{IVec, Prover, add, cross, dot, face_untouched, mat_vec, point, sub};
use crate::contact::{ContactKind, PrincipalContact};
use crate::feasibility::interval::{Interval, IntervalMat};
use crate::geometry::{Segment, segment_segment};
use crate::model::{EdgeId, ElementId, FaceId, Part};

/// How far (in separations) the lying edge's stretch over the face must draw away from
/// the held edge: its midpoint then lies twice the separation off it, beyond the
/// loosest tolerance at which a checker reads it on that edge.
const REACH: f64 = 4.0;

/// One crossing edge that may lie along a face at the other (see the module's doc).
#[derive(Clone, Copy, Debug)]
pub(super) struct AlongFace {
    /// Whether the fixed part's edge is the lying one (the face then the moving
    /// part's, at the moving edge), or the other way round.
    fixed_lies: bool,
    /// The fixed edge in G's frame: start, unit direction, length.
    a0: DVec3,
    da: DVec3,
    la: f64,
    /// The moving edge in its part's frame: start, unit direction, length.
    b0: DVec3,
    db: DVec3,
    lb: f64,
    /// The face's outward normal and its direction across the held edge into the
    /// face, in its part's frame (G's for the fixed part).
    normal: DVec3,
    into: DVec3,
    /// The lying edge's largest sine against the face's plane: half the separation
    /// over its length.
    flat: f64,
    /// How far the face reaches from a point of the held edge: at least `corner`
    /// times its distance from the edge's nearer end, and at most `width`; whether
    /// its corner at each end of the held edge is square or obtuse (see [`face_reach`]).
    corner: f64,
    width: f64,
    square: [bool; 2],
}

/// How far the face `f` reaches from the points of its edge `b`, away from the rest
/// of its boundary: `(corner, width, square)` such that a point at distance `e` from
/// `b`'s nearer end is at least `min(corner · e, width)` from every other boundary
/// segment. A segment sharing an end with `b` at an angle below 90° to it comes no
/// closer than `e` times that angle's sine; any other, no closer than its distance
/// from `b`. `square[k]`: the face's corner at `b`'s end `k` is convex and not sharp
/// (90° to 180°, one other segment there), so a line through a point of `b` that runs
/// into the face away from that end keeps at least the point's distance from the
/// corner off that segment.
fn face_reach(part: &Part, f: FaceId, b: EdgeId) -> (f64, f64, [bool; 2]) {
    let [p, q] = part.edge_points(b);
    let ends = part.edge(b).vertices;
    let held = Segment::new(p, q);
    let into = part.edge_wedge(b)[if part.edge(b).faces[0] == f { 0 } else { 1 }];
    let (mut corner, mut width) = (1.0_f64, f64::INFINITY);
    let mut meeting = [0_usize; 2];
    let mut square = [true; 2];
    for x in part.face(f).loops.iter().flat_map(|l| l.edges.iter().copied()) {
        if x == b {
            continue;
        }
        let [x0, x1] = part.edge(x).vertices;
        let [g0, g1] = part.edge_points(x);
        let mut shared = false;
        for (k, (end, at, along)) in [(ends[0], p, q - p), (ends[1], q, p - q)].into_iter().enumerate() {
            let far = if x0 == end {
                g1
            } else if x1 == end {
                g0
            } else {
                continue;
            };
            shared = true;
            meeting[k] += 1;
            let (along, towards) = (along.normalize(), (far - at).normalize());
            let cos = along.dot(towards);
            if cos > 0.0 {
                corner = corner.min((1.0 - cos * cos).max(0.0).sqrt());
            }
            square[k] &= cos <= 0.0 && towards.dot(into) > 0.0;
        }
        if !shared {
            width = width.min(segment_segment(&held, &Segment::new(g0, g1)).0);
        }
    }
    for k in 0..2 {
        square[k] &= meeting[k] == 1;
    }
    (corner, width, square)
}

impl Prover<'_> {
    /// The [`AlongFace`]s of a target's crossings: each edge against each face at the
    /// other edge, unless another contact of the target touches that face's closure.
    pub(super) fn along_faces(&self, target: &[PrincipalContact]) -> Vec<AlongFace> {
        // Half the separation: the prover's margin.
        let rise = self.margin;
        let mut out = Vec::new();
        for pc in target {
            let (ContactKind::EdgeEdge, ElementId::Edge(x), ElementId::Edge(y)) = (pc.kind, pc.fixed, pc.moving) else {
                continue;
            };
            let untouched = |fixed_side: bool, face: ElementId| {
                face_untouched((self.fixed, self.moving), target, pc, fixed_side, face)
            };
            let [a0, a1] = self.fixed.edge(x).vertices.map(|v| self.a.vertices[v.index()]);
            let [b0, b1] = self.moving.edge(y).vertices.map(|v| self.b.vertices[v.index()]);
            let (la, lb) = (a0.distance(a1), b0.distance(b1));
            let base = AlongFace {
                fixed_lies: true,
                a0,
                da: (a1 - a0) / la,
                la,
                b0,
                db: (b1 - b0) / lb,
                lb,
                normal: DVec3::ZERO,
                into: DVec3::ZERO,
                flat: 0.0,
                corner: 0.0,
                width: 0.0,
                square: [false; 2],
            };
            // The fixed edge along a face of the moving one's.
            for (g, u) in self.moving.edge(y).faces.into_iter().zip(self.moving.edge_wedge(y)) {
                if untouched(false, ElementId::Face(g)) {
                    let (corner, width, square) = face_reach(self.moving, g, y);
                    out.push(AlongFace {
                        normal: self.moving.face(g).normal,
                        into: u,
                        flat: rise / la,
                        corner,
                        width,
                        square,
                        ..base
                    });
                }
            }
            // The moving edge along a face of the fixed one's.
            for (f, u) in self.fixed.edge(x).faces.into_iter().zip(self.fixed.edge_wedge(x)) {
                if untouched(true, ElementId::Face(f)) {
                    let (corner, width, square) = face_reach(self.fixed, f, x);
                    out.push(AlongFace {
                        fixed_lies: false,
                        normal: self.fixed_direction(self.fixed.face(f).normal),
                        into: self.fixed_direction(u),
                        flat: rise / lb,
                        corner,
                        width,
                        square,
                        ..base
                    });
                }
            }
        }
        out
    }

    /// Whether every pose of the box (rotations enclosed by `r`, translations by `t`)
    /// where the crossing holds has the lying edge read on the face: flat against its
    /// plane, turned to one side of the held edge, and crossing far enough from the
    /// lying edge's end on the face's side and from the held edge's ends.
    pub(super) fn lies_along(&self, f: &AlongFace, r: &IntervalMat, t: &IVec) -> bool {
        let separation = 2.0 * self.margin;
        let (da, w) = (point(f.da), mat_vec(r, f.db));
        let (flat, into) = if f.fixed_lies {
            (dot(da, mat_vec(r, f.normal)), dot(da, mat_vec(r, f.into)))
        } else {
            (dot(point(f.normal), w), dot(point(f.into), w))
        };
        if flat.lo <= -f.flat || flat.hi >= f.flat || into.contains_zero() {
            return false;
        }
        // The lying edge's sine across the held edge within the face's plane.
        let across = into.lo.abs().min(into.hi.abs());
        let n = cross(da, w);
        let nn = n[0].square().add(n[1].square()).add(n[2].square());
        if nn.lo <= 0.0 {
            return false;
        }
        // The closest points of the two lines: `a0 + s da` and `R b0 + t + u R db`.
        let d = sub(add(mat_vec(r, f.b0), *t), point(f.a0));
        let s = dot(cross(d, w), n).div(nn);
        let u = dot(cross(d, da), n).div(nn);
        let ((lying, lying_length), (held, held_length)) = if f.fixed_lies {
            ((s, f.la), (u, f.lb))
        } else {
            ((u, f.lb), (s, f.la))
        };
        // The lying edge's length from the crossing on the face's side.
        let beyond = if into.lo > 0.0 {
            Interval::point(lying_length).sub(lying)
        } else {
            lying
        };
        let need = REACH * separation / across;
        // The lying edge's direction on the face's side along the held edge: turning
        // away from the held edge's first end when positive, from its second when
        // negative.
        let along = dot(da, w);
        let away = if into.lo > 0.0 { along } else { along.neg() };
        // Far from an end, the face stays clear of the stretch on that side. Near a
        // square or obtuse corner, a stretch turning away from it keeps the crossing's
        // distance from the corner off the corner's other segment: at least the
        // separation, which a robust crossing keeps from the held edge's ends (the
        // contact's region, [`super::Link::Region`], keeps it so).
        let clear = |from_end: f64, square: bool, turned_away: bool| {
            f.corner * from_end >= need + separation || (square && turned_away)
        };
        beyond.lo >= need
            && f.width >= need + separation
            && clear(held.lo, f.square[0], away.lo >= 0.0)
            && clear(held_length - held.hi, f.square[1], away.hi <= 0.0)
    }
}

#[cfg(test)]
mod tests {
    use glam::DAffine3;

    use super::*;
    use crate::contact::ContactKind as K;
    use crate::feasibility::Problem;
    use crate::pose::{Bounds, Pose};
    use crate::testing::{contact, fixture, grazing_crossing};
    use crate::tolerance::{CONTACT_REL, SEPARATION_REL, scaled};

    /// Whether some crossing of `target` has its edge read on a face over the box.
    fn lies_somewhere(problem: &Problem<'_>, target: &[PrincipalContact], b: &Bounds) -> bool {
        let prover = &problem.prover;
        let r = crate::feasibility::interval::rotation_enclosure(b);
        let t = [
            Interval::new(b.min.x, b.max.x),
            Interval::new(b.min.y, b.max.y),
            Interval::new(b.min.z, b.max.z),
        ];
        prover.along_faces(target).iter().any(|a| prover.lies_along(a, &r, &t))
    }

    /// The square peg over the plain hole, x and y within ±1, z from 0 to 45, tilted up
    /// to 1° about x and y, no yaw.
    fn tilted() -> Bounds {
        let r = 1f64.to_radians();
        Bounds::try_new([-1.0, -1.0, 0.0, -r, -r, 0.0], [1.0, 1.0, 45.0, r, r, 0.0]).unwrap()
    }

    /// The peg turned by `roll` about x and -0.01 rad about y, leaning the point of its
    /// upright corner edge (e0) at `height` (in its frame) on the hole's rim edge (e11),
    /// 1.5 mm from the rim's end.
    fn lean(roll: f64, height: f64) -> [f64; 6] {
        let turned = Pose::from_array([0.0, 0.0, 0.0, roll, -0.01, 0.0]).to_affine(&DAffine3::IDENTITY);
        let t = DVec3::new(35.0, 36.5, 50.0) - turned.transform_point3(DVec3::new(36.0, 36.0, height));
        [t.x, t.y, t.z, roll, -0.01, 0.0]
    }

    #[test]
    fn a_rim_edge_along_the_pegs_face_is_read_on_the_face_not_as_a_crossing() {
        // The peg tilted about y leans its upright corner edge (e0) on the hole's rim
        // edge (e11, along y): with no yaw or roll the rim edge lies in the plane of the
        // peg's side face (f0) through that corner edge, and runs 28 mm over it. The
        // contact module reads the rim on the face, so the crossing alone has no
        // witness in a box around the pose, and this rule alone proves it.
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let problem = Problem::new(&hole, &peg, tilted(), DAffine3::IDENTITY);
        let pose = lean(0.0, 60.0);
        let read = problem
            .scene()
            .evaluate(&Pose::from_array(pose).to_affine(&DAffine3::IDENTITY), CONTACT_REL)
            .contacts;
        assert_eq!(read, vec![contact("e11", "f0", K::EdgeFace)]);
        let crossing = [contact("e11", "e0", K::EdgeEdge)];
        let scale = problem.scale;
        for eps in [0.0, 1e-6, 1e-4] {
            let around = Bounds::try_new(
                std::array::from_fn(|k| pose[k] - if k == 5 { 0.0 } else { eps }),
                std::array::from_fn(|k| pose[k] + if k == 5 { 0.0 } else { eps }),
            )
            .unwrap();
            assert!(lies_somewhere(&problem, &crossing, &around), "± {eps}");
            assert!(problem.exclusion(&crossing, &around).is_some(), "± {eps}");
            assert_eq!(problem.exclusion(&read, &around), None, "the witness ± {eps}");
        }
        // Yawed by more than half the separation over the rim's length, the rim edge no
        // longer lies in the face's plane: the rule stands down.
        let yaw = 4.0 * scaled(SEPARATION_REL, scale) / 30.0;
        let mut yawed = pose;
        yawed[5] = yaw;
        let at = Bounds::try_new(yawed, yawed).unwrap();
        assert!(!lies_somewhere(&problem, &crossing, &at));
    }

    #[test]
    fn near_a_square_corner_the_rim_turning_away_from_it_is_still_read_on_the_face() {
        // The same lean, the crossing now twice the separation above the peg's bottom
        // corner: too near the corner for the face's reach alone, but the rim edge,
        // turned away from the corner's other edge (the peg's bottom edge) by a roll of
        // the peg, keeps that distance off it all along the face.
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let problem = Problem::new(&hole, &peg, tilted(), DAffine3::IDENTITY);
        let above = 2.0 * scaled(SEPARATION_REL, problem.scale);
        let crossing = [contact("e11", "e0", K::EdgeEdge)];
        let at = |roll: f64| lean(roll, 10.0 + above);
        // Rolled one way, the rim edge runs from the crossing up the face, away from the
        // bottom edge: the rule holds, and no checker reads the crossing alone there.
        let away = at(-0.005);
        assert!(lies_somewhere(
            &problem,
            &crossing,
            &Bounds::try_new(away, away).unwrap()
        ));
        assert_ne!(problem.clean_state(&Pose::from_array(away)), Some(crossing.to_vec()));
        // Rolled the other way it runs down towards the bottom edge, which this rule
        // does not follow.
        let towards = at(0.005);
        assert!(!lies_somewhere(
            &problem,
            &crossing,
            &Bounds::try_new(towards, towards).unwrap()
        ));
    }

    #[test]
    fn a_grazing_crossing_whose_edge_ends_within_the_band_is_left_to_the_two_points_rule() {
        // The box's top edge, turned 7.7e-5 rad, crosses the wall's top edge 2.8e-3 mm
        // from its end: the wall edge lies along the box's face, but its stretch beyond
        // the crossing stays within the tolerance of the box's edge. This rule does not
        // fire there, for the state or for the crossing on its own; the state is no
        // witness all the same (the box's edge has its end and the crossing on the
        // wall's plane), which the last proofs' own rule says.
        let (a, b) = crate::examples::l_block_and_box();
        let problem = Problem::new(&a, &b, crate::examples::paper_bounds(), DAffine3::IDENTITY);
        let (state, x) = grazing_crossing();
        assert_eq!(problem.clean_state(&Pose::from_array(x)), None);
        let at = Bounds::try_new(x, x).unwrap();
        assert!(!lies_somewhere(&problem, &state, &at));
        assert!(!lies_somewhere(&problem, &[contact("e10", "e10", K::EdgeEdge)], &at));
        assert_eq!(
            problem.last_exclusion(&state, &at),
            Some(crate::feasibility::Rule::EdgeOnTwoPoints)
        );
    }

    #[test]
    fn a_face_reaches_from_its_edge_as_its_corners_allow() {
        // The L-block's front face (an L-shaped hexagon): from its bottom edge (200 long),
        // both corners are right angles and the nearest other edge not at its ends is
        // the step's top, 50 above.
        let (a, _) = crate::examples::l_block_and_box();
        let ElementId::Edge(bottom) = crate::testing::edge_between(&a, DVec3::ZERO, DVec3::new(200.0, 0.0, 0.0)) else {
            panic!("the bottom front edge is an edge");
        };
        let front = a
            .edge(bottom)
            .faces
            .into_iter()
            .find(|&f| a.face(f).normal.y < -0.5)
            .unwrap();
        let (corner, width, square) = face_reach(&a, front, bottom);
        assert!((corner - 1.0).abs() < 1e-12, "{corner}");
        assert!((width - 50.0).abs() < 1e-9, "{width}");
        assert_eq!(square, [true, true]);
    }
}
