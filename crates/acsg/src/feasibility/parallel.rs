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
//!
//! The candidate's own contacts narrow the rotations too: a face flush on a face
//! leaves only the turns about their normal, two edges running together the turns
//! about the edge ([`rotation_families`]). Each such one-angle set holds every
//! rotation of the candidate and is decided the same way, at three angles of its turn.
//! On any of these sets, two crossing edges that stay parallel rule the crossing out
//! as well ([`Crossings::of_parallel_edges`]).
//!
//! An edge lying in a face holds `Y` parallel to `f` too, to the tolerance rather than
//! exactly, when it lies along `Y` and the face is normal to `f` (the box's upright
//! edge on the L-block's wall keeps the step's back edge parallel to the box's bottom
//! face, whatever the tilt): the contact holds both that edge's ends within the
//! tolerance of the face's plane, so `Y` strays from `f`'s plane by at most twice the
//! tolerance times its length over that edge's. [`pinned_pairs`] counts only edges at
//! least half as long as `Y`, so `Y` lies within five times the tolerance of `f`'s
//! plane from end to end: a checker with that tolerance, inside the range every robust
//! witness must agree over, reads `Y` lying in `f`, which it enters past the crossing
//! by five times that within the separation (the sine above [`MIN_CROSSING_SINE`]).

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

/// A candidate's crossings with the rotation sets its rotations lie in, prepared once
/// for the two tests of this module.
pub(crate) struct Crossings<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    target: &'a [PrincipalContact],
    families: Vec<Family>,
    /// The pairs `(u, v)` whose value `u · (G R v)` the candidate's own contacts hold
    /// at zero to the contact tolerance, with the length of the edge that holds them
    /// ([`pinned_pairs`]).
    pinned: Vec<(DVec3, DVec3, f64)>,
    /// `G R` at the centre of the bounds' rotations and how far any of them moves a
    /// unit vector from there ([`centre_and_reach`]).
    centre: DMat3,
    reach: f64,
}

impl<'a> Crossings<'a> {
    /// The crossings of `target` (`assembled` is G's rotation); `None` without one, as
    /// most candidates are: no rotation is sampled for them.
    pub(crate) fn of(
        fixed: &'a Part,
        moving: &'a Part,
        bounds: &Bounds,
        assembled: DMat3,
        target: &'a [PrincipalContact],
    ) -> Option<Crossings<'a>> {
        if !target.iter().any(|pc| pc.kind == ContactKind::EdgeEdge) {
            return None;
        }
        let (centre, reach) = centre_and_reach(bounds, assembled);
        Some(Crossings {
            fixed,
            moving,
            target,
            families: rotation_families(fixed, moving, bounds, assembled, target),
            pinned: pinned_pairs(fixed, moving, target),
            centre,
            reach,
        })
    }

    /// Whether a crossing has one edge held parallel to a face at the other edge under
    /// every rotation the candidate allows (see the module's documentation): `true`
    /// proves that no pose in the bounds shows the candidate.
    pub(crate) fn held_in_a_face(&self) -> bool {
        let (fixed, moving) = (self.fixed, self.moving);
        crossings(fixed, moving, self.target).any(|(a, b, da, db)| {
            // The angle between the edges, at every rotation of the bounds.
            let bounded_sine = da.cross(self.centre * db).length() - self.reach;
            // A face at one edge that another contact holds parallel to the other edge,
            // by an edge at least half as long as that one.
            let pinned = |u: DVec3, v: DVec3, along: f64| {
                self.pinned
                    .iter()
                    .any(|&(p, q, holder)| on_one_line(p, u) && on_one_line(q, v) && 2.0 * holder >= along)
            };
            let pinned_face = moving
                .edge(b)
                .faces
                .iter()
                .any(|&f| pinned(da, moving.face(f).normal, length(fixed, a)))
                || fixed
                    .edge(a)
                    .faces
                    .iter()
                    .any(|&f| pinned(fixed.face(f).normal, db, length(moving, b)));
            if pinned_face && bounded_sine >= MIN_CROSSING_SINE {
                return true;
            }
            self.families.iter().any(|family| {
                if bounded_sine.max(family.least_sine(da, db)) < MIN_CROSSING_SINE {
                    return false;
                }
                // A face of the moving part at b, parallel to a; a face of the fixed
                // part at a, parallel to b.
                let moving_face = moving
                    .edge(b)
                    .faces
                    .iter()
                    .any(|&f| parallel_everywhere(&family.samples, da, moving.face(f).normal));
                let fixed_face = fixed
                    .edge(a)
                    .faces
                    .iter()
                    .any(|&f| parallel_everywhere(&family.samples, fixed.face(f).normal, db));
                moving_face || fixed_face
            })
        })
    }

    /// Whether a crossing joins two edges that stay parallel under every rotation the
    /// candidate allows (a face flush on a face turns only about its normal; the
    /// bounds may pin the turns): `true` proves that no pose shows the candidate. Two
    /// parallel edges that meet share a stretch of line, or touch at an end: they run
    /// together (e-e-t) or meet at a corner, and never cross at one point inside both.
    pub(crate) fn of_parallel_edges(&self) -> bool {
        crossings(self.fixed, self.moving, self.target).any(|(_, _, da, db)| {
            self.families.iter().any(|family| {
                family
                    .samples
                    .iter()
                    .all(|r| da.cross(*r * db).length() <= PARALLEL_ROUNDOFF)
            })
        })
    }
}

/// The crossings (e-e contacts) of `target`: the edges and their unit directions.
fn crossings<'t>(
    fixed: &'t Part,
    moving: &'t Part,
    target: &'t [PrincipalContact],
) -> impl Iterator<Item = (EdgeId, EdgeId, DVec3, DVec3)> + 't {
    target.iter().filter_map(|pc| match (pc.fixed, pc.moving, pc.kind) {
        (ElementId::Edge(a), ElementId::Edge(b), ContactKind::EdgeEdge) => {
            Some((a, b, direction(fixed, a), direction(moving, b)))
        }
        _ => None,
    })
}

/// A set of rotations `G R` holding every rotation a candidate allows, given by
/// samples from which a function affine in the cosine and sine of each of its angles
/// is known everywhere on it (it vanishes on the set when it vanishes at the samples).
struct Family {
    samples: Vec<DMat3>,
    /// For a one-angle family `M₀ · Rot(axis, φ)`, φ over the whole turn: `M₀` and
    /// the axis (in the moving part's frame).
    turn: Option<(DMat3, DVec3)>,
}

/// Samples of φ a one-angle family's least crossing sine is taken over; between them
/// a unit vector moves by at most π / this.
const TURN_SAMPLES: usize = 64;

impl Family {
    /// `M₀ · Rot(axis, φ)` for φ over the whole turn: sampled at three angles (a
    /// turned vector is affine in cos φ and sin φ, Rodrigues' formula).
    fn turning(m0: DMat3, axis: DVec3) -> Family {
        let samples = (0..3)
            .map(|k| m0 * DMat3::from_axis_angle(axis, f64::from(k) * std::f64::consts::TAU / 3.0))
            .collect();
        Family {
            samples,
            turn: Some((m0, axis)),
        }
    }

    /// A lower bound of `|da × M db|` over the family (−∞ when unknown): for a
    /// one-angle family its least value at [`TURN_SAMPLES`] angles, less the most a
    /// unit vector moves between two of them.
    fn least_sine(&self, da: DVec3, db: DVec3) -> f64 {
        let Some((m0, axis)) = self.turn else {
            return f64::NEG_INFINITY;
        };
        let step = std::f64::consts::TAU / TURN_SAMPLES as f64;
        (0..TURN_SAMPLES)
            .map(|k| {
                da.cross(m0 * (DMat3::from_axis_angle(axis, k as f64 * step) * db))
                    .length()
            })
            .fold(f64::INFINITY, f64::min)
            - 0.5 * step
    }
}

/// The rotation sets a candidate's rotations lie in: the bounds' (sampled per angle
/// component), and for each face flush on a face (f-f) the turns about the normals
/// that keep them opposed, for each pair of edges running together (e-e-t) the turns
/// about the edge that keep them parallel, either way round. Each set holds every
/// rotation of the candidate, so what holds on all of one set holds on the candidate.
fn rotation_families(
    fixed: &Part,
    moving: &Part,
    bounds: &Bounds,
    assembled: DMat3,
    target: &[PrincipalContact],
) -> Vec<Family> {
    let mut families = vec![Family {
        samples: sample_rotations(bounds, assembled),
        turn: None,
    }];
    for pc in target {
        match (pc.kind, pc.fixed, pc.moving) {
            (ContactKind::FaceFace, ElementId::Face(f), ElementId::Face(g)) => {
                let (na, nb) = (fixed.face(f).normal, moving.face(g).normal);
                families.push(Family::turning(
                    DMat3::from_quat(glam::DQuat::from_rotation_arc(nb, -na)),
                    nb,
                ));
            }
            (ContactKind::EdgeEdgeTouch, ElementId::Edge(a), ElementId::Edge(b)) => {
                let (da, db) = (direction(fixed, a), direction(moving, b));
                for sign in [1.0, -1.0] {
                    families.push(Family::turning(
                        DMat3::from_quat(glam::DQuat::from_rotation_arc(db, sign * da)),
                        db,
                    ));
                }
            }
            _ => {}
        }
    }
    families
}

/// The pairs `(u, v)` whose value `u · (G R v)` a contact of `target` holds at zero,
/// each with the length of the edge that holds it: an edge lying in a face (f-e: the
/// face's normal and the edge; e-f: the edge and the face's normal). The contact holds
/// both ends of the edge within the tolerance of the plane, so the value is at most
/// twice the tolerance over the edge's length.
fn pinned_pairs(fixed: &Part, moving: &Part, target: &[PrincipalContact]) -> Vec<(DVec3, DVec3, f64)> {
    target
        .iter()
        .filter_map(|pc| match (pc.kind, pc.fixed, pc.moving) {
            (ContactKind::FaceEdge, ElementId::Face(f), ElementId::Edge(x)) => {
                Some((fixed.face(f).normal, direction(moving, x), length(moving, x)))
            }
            (ContactKind::EdgeFace, ElementId::Edge(e), ElementId::Face(g)) => {
                Some((direction(fixed, e), moving.face(g).normal, length(fixed, e)))
            }
            _ => None,
        })
        .collect()
}

/// The length of an edge.
fn length(part: &Part, x: EdgeId) -> f64 {
    let [p, q] = part.edge_points(x);
    p.distance(q)
}

/// Whether two unit vectors lie on one line (either way).
fn on_one_line(u: DVec3, v: DVec3) -> bool {
    u.cross(v).length() <= PARALLEL_ROUNDOFF
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

    fn held(fixed: &Part, moving: &Part, bounds: &Bounds, at: DMat3, target: &[PrincipalContact]) -> bool {
        Crossings::of(fixed, moving, bounds, at, target).is_some_and(|c| c.held_in_a_face())
    }

    fn parallel(fixed: &Part, moving: &Part, bounds: &Bounds, at: DMat3, target: &[PrincipalContact]) -> bool {
        Crossings::of(fixed, moving, bounds, at, target).is_some_and(|c| c.of_parallel_edges())
    }

    /// The plain hole's rim edge along y (x = 35) and the peg's corner edges: with the
    /// yaw pinned, the peg's side faces facing ±x keep their normals in the xz plane.
    #[test]
    fn a_rim_edge_crossing_a_pegs_corner_edge_lies_in_its_side_face_when_the_yaw_is_pinned() {
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let pinned = crate::testing::tilted_peg_bounds();
        let crossing = [contact("e11", "e0", ContactKind::EdgeEdge)];
        assert!(held(&hole, &peg, &pinned, DMat3::IDENTITY, &crossing));
        // With the yaw free the face turns off the rim edge's direction.
        let d = 1f64.to_radians();
        let free = Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, -d], [1.0, 1.0, 45.0, d, d, d]).unwrap();
        assert!(!held(&hole, &peg, &free, DMat3::IDENTITY, &crossing));
    }

    /// The built-in example's box with its +x face flush on the wall (f-f f5/f5) turns
    /// only about x: its bottom edge e6 (along x) stays parallel to the step's back edge
    /// e7, and its bottom face f2 holds the x direction, so e7 crossing the bottom edge
    /// e1 lies in f2. Without the flush face neither holds over the bounds.
    #[test]
    fn a_flush_face_pins_the_turns_that_hold_edges_parallel() {
        let (fixed, moving) = crate::examples::l_block_and_box();
        let bounds = crate::examples::paper_bounds();
        let flush = contact("f5", "f5", ContactKind::FaceFace);
        let mut along = vec![flush, contact("e7", "e6", ContactKind::EdgeEdge)];
        along.sort();
        let mut across = vec![flush, contact("e7", "e1", ContactKind::EdgeEdge)];
        across.sort();
        let at = DMat3::IDENTITY;
        assert!(parallel(&fixed, &moving, &bounds, at, &along));
        assert!(!held(&fixed, &moving, &bounds, at, &along));
        assert!(held(&fixed, &moving, &bounds, at, &across));
        assert!(!parallel(&fixed, &moving, &bounds, at, &across));
        for alone in [&along[1..], &across[1..]] {
            assert!(!parallel(&fixed, &moving, &bounds, at, alone));
            assert!(!held(&fixed, &moving, &bounds, at, alone));
        }
        // An assembled pose turns the family with the parts: a quarter turn about the
        // wall's normal keeps the face flush and e6 still runs along x.
        let quarter = DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2);
        assert!(parallel(&fixed, &moving, &bounds, quarter, &along));
    }

    /// Independently of the rule: poses built by hand with the box's +x face on the
    /// wall (turned about x only, at x = 0) and its bottom edge e1 through a point of the
    /// step's back edge e7. The contact module reads e7 lying on the box's bottom face
    /// there, never the flush face and the crossing alone.
    #[test]
    fn where_a_flush_box_crosses_the_steps_edge_the_contact_module_reads_the_edge_on_its_bottom() {
        let (fixed, moving) = crate::examples::l_block_and_box();
        let scene = crate::contact::ContactScene::new(&fixed, &moving);
        let mut crossing = vec![
            contact("f5", "f5", ContactKind::FaceFace),
            contact("e7", "e1", ContactKind::EdgeEdge),
        ];
        crossing.sort();
        let lying = contact("e7", "f2", ContactKind::EdgeFace);
        for (rx, along) in [(-0.05, 50.0), (-0.2, 30.0), (-0.3, 70.0), (-0.01, 20.0)] {
            // The point (50, along, 50) of e1 at (50, 100, 50), on e7.
            let (c, s) = (f64::cos(rx), f64::sin(rx));
            let pose = Pose::from_array([
                0.0,
                100.0 - (along * c - 50.0 * s),
                50.0 - (along * s + 50.0 * c),
                rx,
                0.0,
                0.0,
            ]);
            let report = scene.state(
                &pose.to_affine(&glam::DAffine3::IDENTITY),
                crate::tolerance::CONTACT_REL,
            );
            assert_eq!(report.penetration, 0.0, "at rx = {rx}");
            assert!(report.contacts.contains(&lying), "at rx = {rx}: {:?}", report.contacts);
            assert_ne!(report.contacts, crossing);
        }
    }

    /// Independently of the rule: at poses where the peg's corner edge e0 crosses the
    /// rim edge e11 (found by the local solver from spread starts), the contact module
    /// reads the rim edge in the peg's face, never the crossing alone.
    #[test]
    fn where_the_pinned_crossing_holds_the_contact_module_reads_the_edge_in_the_face() {
        let (hole, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let pinned = crate::testing::tilted_peg_bounds();
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

    /// The box's upright edge e8 lying on the wall (f-e f5/e8) holds its bottom face f2
    /// parallel to x, so the step's back edge e7 crossing the bottom edge e1 lies in
    /// f2; the L-block's edge e7 lying on the box's bottom (e-f e7/f2) holds e8 parallel
    /// to the wall, so e8 crossing the wall's top edge e10 lies in the wall. Neither
    /// crossing alone is held, nor one whose edges cross at a grazing angle.
    #[test]
    fn an_edge_lying_in_a_face_holds_a_crossing_edge_in_a_face() {
        let (fixed, moving) = crate::examples::l_block_and_box();
        let bounds = crate::examples::paper_bounds();
        let at = DMat3::IDENTITY;
        let sorted = |mut v: Vec<PrincipalContact>| {
            v.sort();
            v
        };
        let upright = sorted(vec![
            contact("f5", "e8", ContactKind::FaceEdge),
            contact("e7", "e1", ContactKind::EdgeEdge),
        ]);
        assert!(held(&fixed, &moving, &bounds, at, &upright));
        let on_bottom = sorted(vec![
            contact("e7", "f2", ContactKind::EdgeFace),
            contact("e10", "e8", ContactKind::EdgeEdge),
        ]);
        assert!(held(&fixed, &moving, &bounds, at, &on_bottom));
        assert!(!held(&fixed, &moving, &bounds, at, &upright[..1]));
        assert!(!held(&fixed, &moving, &bounds, at, &on_bottom[..1]));
        // e6 runs along x as e7 does: within the bounds they may cross at any small
        // angle, and the test then says nothing.
        let grazing = sorted(vec![
            contact("f5", "e8", ContactKind::FaceEdge),
            contact("e7", "e6", ContactKind::EdgeEdge),
        ]);
        assert!(!held(&fixed, &moving, &bounds, at, &grazing));
    }

    /// Independently of the rule: poses built by hand with the box's upright edge e8
    /// on the wall's plane (ry solved so that the box's z axis has no x component, x so
    /// that e8 is at x = 150) and its bottom edge e1 through a point of the step's back
    /// edge e7. The contact module reads e7 lying on the box's bottom face there, never
    /// the upright edge on the wall with the crossing alone.
    #[test]
    fn where_an_upright_edge_lies_on_the_wall_the_step_edge_lies_on_the_boxs_bottom() {
        let (fixed, moving) = crate::examples::l_block_and_box();
        let scene = crate::contact::ContactScene::new(&fixed, &moving);
        let mut target = vec![
            contact("f5", "e8", ContactKind::FaceEdge),
            contact("e7", "e1", ContactKind::EdgeEdge),
        ];
        target.sort();
        let lying = contact("e7", "f2", ContactKind::EdgeFace);
        for (rx, rz, along) in [(-0.2, 0.02, 60.0), (-0.1, 0.05, 40.0), (-0.3, 0.01, 75.0)] {
            let turned = |ry: f64| Pose::from_array([0.0, 0.0, 0.0, rx, ry, rz]).rotation();
            let ry = crate::testing::bisect(|ry| (turned(ry) * DVec3::Z).x, -0.5, 0.5);
            let r = turned(ry);
            let (corner, on_e1) = (r * DVec3::new(150.0, 10.0, 50.0), r * DVec3::new(50.0, along, 50.0));
            let pose = Pose::from_array([150.0 - corner.x, 100.0 - on_e1.y, 50.0 - on_e1.z, rx, ry, rz]);
            let report = scene.state(
                &pose.to_affine(&glam::DAffine3::IDENTITY),
                crate::tolerance::CONTACT_REL,
            );
            assert_eq!(report.penetration, 0.0, "at {:?}", pose.to_array());
            assert!(
                report.contacts.contains(&lying),
                "at {:?}: {:?}",
                pose.to_array(),
                report.contacts
            );
            assert_ne!(report.contacts, target);
        }
    }
}
