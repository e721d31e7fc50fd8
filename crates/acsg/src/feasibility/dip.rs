//! An edge that runs over a face at a crossing and descends into it: a rotation-only
//! test, for the last proofs, that no pose shows a crossing robustly.
//!
//! Let a convex edge `e` of one part cross a convex edge `x` of the other at `O`, and let
//! `g` be a face of `x`'s part at `x`, with outward normal `n` and in-face direction `w`
//! (perpendicular to `x`, into `g`). Going from `O` along `σ e` with `σ (e · w) > 0`, the
//! edge `e` runs over `g` (its points project into `g`, past `x`); it descends into `g`'s
//! part when `σ (e · n) < 0`. Its height over `g`'s plane is then linear and falling: at
//! most the contact tolerance at `O` (the crossing holds to it), lower farther on. Follow
//! `e` over `g` to where it leaves `g` or ends. Either its far point lies deeper than the
//! tolerance below `g`, inside `g`'s part (the parts penetrate), or the whole stretch
//! lies within the tolerance of `g`'s plane: two points of `e` over `g` within the
//! contact tolerance of its plane, which every checker reads as `e` lying in `g` (e-f
//! or f-e, DOMAIN section 7), a contact the crossing does not list or imply. So no pose
//! at which `e` descends over `g` is a robust witness, however little it descends: the
//! decisions' wedge test allows a dip up to the tolerance over a lever, because it
//! counts only penetration.
//!
//! Two margins keep the argument exact. The crossing lies some distance `D` from the
//! ends of both edges, at least the separation (`1e-6 L`) at a robust witness, more
//! where the box keeps it farther ([`Dip::reach`]); so `e` runs at least that far past
//! `O`, and its points reach past `x` (which the crossing misses by up to the
//! tolerance) within `D / 2` once `|e · w|` is at least four times the tolerance over
//! `D`. And `g` must be wider than that next to `x`: a face whose corners at `x`'s ends
//! are slivers is left out. Another contact of the target that pairs `e` (or a face at
//! `e`) with `g` could list the stretch, so then the test says nothing. The same holds
//! with the parts' roles swapped: `x` over a face of `e`'s part.
//!
//! An edge that rises over `g`, but by less than the loose tolerance's margin over its
//! length (`(0.99e-6 L − 1e-9 L) / ℓ`), stays within the loose tolerance of `g`'s
//! plane as it runs over `g`, when `D` is at least eight separations: no robust
//! witness either, by the flat test's argument below (its pairs must not be implied).
//! (Until stop 59 this case leaned on the loose reading alone, which reads the edge in
//! `g` only where it lies deeper than that tolerance inside `g`'s rim.)
//!
//! **Flat**: an edge whose height over `g`'s plane changes by less than that margin
//! over its whole length, either way, needs neither the crossing's distance from the
//! ends nor a side. At `O` it is within the tolerance of `x`, so of `g`'s plane, and
//! so it stays within `0.99e-6 L` of the plane from end to end. One way along it from
//! `O` runs into `g`'s side of `x` (or it runs along `x`). Followed that way, it either
//! ends over `g`, its end then nearer `g` than the separation, or leaves `g` over
//! another of `g`'s edges or corners, passing nearer than the separation; or its end
//! stays near `x`, or `x`'s end near it. Each is a pair nearer than the separation:
//! too close, or touching, a contact the target does not hold unless one of its
//! contacts implies the pair (then the test says nothing), and an end near the other
//! edge makes the two run together when read over the overlap. So no pose of the box
//! is a robust witness. The built-in example's slab edge lying in the box's bottom
//! keeps the box's upright edge in the wall's plane this way, crossing the wall's
//! back edge 0.2 mm above the step, nearer the ends than a box can tell.

use glam::DVec3;

use super::LOOSE_CONTACT_REL;
use super::Problem;
use super::edge_pair::{CentreMotion, EdgePair};
use super::interval::{Interval, IntervalMat, largest_length, turned_value as value};
use super::prover::implied;
use crate::contact::PrincipalContact;
use crate::geometry::{Segment, segment_segment};
use crate::model::{EdgeId, ElementId, FaceId, Part};
use crate::pose::Bounds;
use crate::tolerance::{CONTACT_REL, ROUNDOFF_REL, scaled};

/// A face's corner at an end of the crossing edge narrower than this (radians) leaves
/// the face out: the face may be too thin next to the edge for the stretch.
const LEAST_CORNER: f64 = 1e-2;

/// One edge against one face at the other edge of a crossing, as values `a · (R b)`
/// (`a` in G's frame, `b` in the moving part's): `side` tells which way along the edge
/// runs over the face, `rise` how it leaves the face's plane that way.
#[derive(Clone, Debug)]
pub(super) struct Dip {
    side: (DVec3, DVec3),
    rise: (DVec3, DVec3),
    /// The crossing edges, for how far the crossing lies from their ends over a box.
    edges: EdgePair,
    /// The separation: no robust crossing lies nearer an end of either edge.
    separation: f64,
    /// The components of `e × R x` (values `a · (R b)`): the sine of the edges' angle.
    components: [(DVec3, DVec3); 3],
    /// Per end (the fixed edge's, then the moving edge's): whether it must keep the
    /// separation from the other edge (no contact of the target implies the pair).
    apart: [[bool; 2]; 2],
    /// How far below which `|rise|` leaves the running edge, both its ends, within the
    /// loose reading's tolerance of the face's plane (the tolerances' difference over
    /// the edge's length).
    flat: f64,
    /// `e · (R x)`, the fixed edge's direction against the moving edge's: which way
    /// the running edge's foot moves along the other edge.
    along: (DVec3, DVec3),
    /// Whether the running edge is the fixed one (the face is the moving part's).
    runs_fixed: bool,
    /// The longer edge's length: no crossing lies farther from an end.
    longest: f64,
    /// The ranges the target's plain conditions keep `side` and `rise` in.
    pub known: [Interval; 2],
    /// Whether the descent test applies: the face is wide at the crossing edge's ends
    /// and no other contact pairs the running edge with it.
    descent: bool,
    /// Per end of the running edge, the pairs the flat argument needs apart running
    /// towards it ([`Dip::excludes`]) that a contact of the target implies: that end,
    /// or the edge, with an element of the face's closure off the crossing edge. The
    /// argument holds over a box that keeps each farther apart than the separation.
    held_towards: [Vec<HeldPair>; 2],
}

impl Dip {
    /// The two values, for [`super::turns::Turns`] to find what it knows of them.
    pub fn values(&self) -> [(DVec3, DVec3); 2] {
        [self.side, self.rise]
    }

    /// The crossing's least distance `D`, at every pose of `b` (rotations enclosed by
    /// `r`), from the ends the argument needs: the running edge's end on the side `σ`
    /// it runs over the face, and the other edge's end towards which its foot moves
    /// (both of that edge's ends when the edges' angle is near a right angle).
    ///
    /// At least the separation, and from each end at least what the box keeps it to.
    /// Take the nearer of the two ends: its foot on the other edge's line lies on that
    /// edge (the other end is farther), so kept apart from that edge it lies its
    /// distance times `sin θ` from it, to the tolerance, and its distance is at least
    /// `(separation − 2 tolerance) / sin θ`. So `D` is at least the lesser, over the
    /// two ends, of that bound for an end kept apart and of the box's bound for the
    /// other. With both of the other edge's ends (an angle near a right angle) the
    /// same holds of the nearest of all four.
    fn reach(&self, r: &IntervalMat, b: &Bounds, sigma: f64) -> f64 {
        let sine = largest_length(r, &self.components);
        let by_angle = (self.separation - 2.0 * self.edges.tolerance) / sine;
        let boxed = self.edges.distances_from_ends(b);
        let bound = |(edge, end): (usize, usize)| {
            let d = boxed[edge][end];
            if self.apart[edge][end] { d.max(by_angle) } else { d }
        };
        let along = value(r, self.along.0, self.along.1);
        let (running, other) = if self.runs_fixed { (0, 1) } else { (1, 0) };
        let end = |positive: bool| usize::from(positive);
        let least = if along.lo > 0.0 || along.hi < 0.0 {
            let towards = (along.lo > 0.0) == (sigma > 0.0);
            bound((running, end(sigma > 0.0))).min(bound((other, end(towards))))
        } else {
            [(0, 0), (0, 1), (1, 0), (1, 1)]
                .map(bound)
                .into_iter()
                .fold(f64::INFINITY, f64::min)
        };
        least.max(self.separation)
    }

    /// Whether at every pose of `b` (rotations enclosed by `r`) the edge runs over the
    /// face one way and descends into it that way, or (with the crossing far enough from
    /// the ends for the loose reading's stretch) rises too little to leave the loose
    /// tolerance, or (flat) leaves it neither way: then no pose of the box is a robust
    /// witness.
    ///
    /// It runs over the face once `|e · w|` is at least four times the tolerance over
    /// `D` ([`Dip::reach`]): the edge is then twice the tolerance past `x` within `D /
    /// 2` of the crossing, and so at least that far from `x`'s end there.
    pub fn excludes(&self, r: &IntervalMat, b: &Bounds) -> bool {
        let side = value(r, self.side.0, self.side.1).meet(self.known[0]);
        let rise = value(r, self.rise.0, self.rise.1).meet(self.known[1]);
        if side.is_empty() || rise.is_empty() {
            // The plain conditions on these values rule every rotation of the box out
            // together.
            return true;
        }
        // Flat: the running edge stays within the loose tolerance of the face's plane
        // from end to end, whichever way it runs over the face.
        let flat_towards = |end: usize| {
            self.held_towards[end]
                .iter()
                .all(|pair| pair.apart_over(b, self.separation))
        };
        if rise.lo > -self.flat && rise.hi < self.flat && flat_towards(0) && flat_towards(1) {
            return true;
        }
        if !self.descent {
            return false;
        }
        let sigma = if side.lo > 0.0 {
            1.0
        } else if side.hi < 0.0 {
            -1.0
        } else {
            return false;
        };
        let (side, rise) = if sigma > 0.0 {
            (side, rise)
        } else {
            (side.neg(), rise.neg())
        };
        // Rising clear of any threshold, or too near the other edge's direction for any
        // reach the edges allow: nothing to work out.
        if rise.hi >= self.flat || side.lo < 4.0 * self.edges.tolerance / self.longest {
            return false;
        }
        let reach = self.reach(r, b, sigma);
        let least_side = 4.0 * self.edges.tolerance / reach;
        // Rising by less than `flat`, the edge stays within the loose tolerance of the
        // plane as it runs over the face: it ends, or leaves the face, nearer than the
        // separation, as in the flat test, whose pairs must then not be implied.
        let towards = usize::from(sigma > 0.0);
        let least_rise = if reach >= FLAT_REACH * self.separation && flat_towards(towards) {
            self.flat
        } else {
            -ROUNDOFF_REL
        };
        side.lo >= least_side && rise.hi < least_rise
    }
}

/// How far (in separations) the crossing must lie from the edges' ends for a rise
/// below [`Dip::flat`] to be read as lying in the face.
const FLAT_REACH: f64 = 8.0;

impl Problem<'_> {
    /// The dips of a crossing `pc` (fixed edge `e`, moving edge `x`) of `target`, both
    /// ways; `apart` tells, per end of either edge, whether no contact of the target
    /// implies it on the other edge.
    pub(super) fn dips(
        &self,
        target: &[PrincipalContact],
        pc: &PrincipalContact,
        (e, x): (EdgeId, EdgeId),
        apart: [[bool; 2]; 2],
    ) -> Vec<Dip> {
        let (fixed, moving) = (self.fixed, self.moving);
        let to_g = |d: DVec3| self.prover.fixed_direction(d);
        let de = to_g(fixed.edge_direction(e));
        let dx = moving.edge_direction(x);
        let loose = scaled(LOOSE_CONTACT_REL - CONTACT_REL, self.scale);
        let length = |part: &Part, edge: EdgeId| {
            let [p, q] = part.edge_points(edge);
            p.distance(q)
        };
        let dip =
            |side, rise, running: f64, runs_fixed: bool, (descent, held_towards): (bool, [Vec<HeldPair>; 2])| Dip {
                side,
                rise,
                along: (de, dx),
                runs_fixed,
                longest: length(fixed, e).max(length(moving, x)),
                flat: loose / running,
                edges: self.edge_pair(e, x),
                separation: self.separation(),
                // (d_e × R d_x)_k = (e_k × d_e) · (R d_x).
                components: DVec3::AXES.map(|axis| (axis.cross(de), dx)),
                apart,
                known: [Interval::new(f64::NEG_INFINITY, f64::INFINITY); 2],
                descent,
                held_towards,
            };
        // Whether another contact pairs an element whose closure holds `edge` (on
        // `edge`'s part) with the face `face` (on the other part).
        let listed = |edge_on_fixed: bool, edge: EdgeId, face: FaceId| {
            target.iter().filter(|other| *other != pc).any(|other| {
                let (mine, theirs, part) = if edge_on_fixed {
                    (other.fixed, other.moving, fixed)
                } else {
                    (other.moving, other.fixed, moving)
                };
                theirs == ElementId::Face(face) && part.in_closure(mine, ElementId::Edge(edge))
            })
        };
        // Per end of the running edge `edge`, the pairs the flat argument needs apart
        // running towards it that a contact of the target implies: that end with an
        // element of `face`'s closure off its crossing edge `crossed`, or the edge
        // itself with one of the face's other edges or corners (the face itself touches
        // the edge at the crossing).
        let held_towards = |edge_on_fixed: bool, edge: EdgeId, face: FaceId, crossed: EdgeId| {
            let (running_part, face_part) = if edge_on_fixed {
                (fixed, moving)
            } else {
                (moving, fixed)
            };
            // The face's closure off its crossing edge.
            let [a, b] = face_part.edge(crossed).vertices;
            let near = closure_without(
                face_part,
                face,
                &[ElementId::Edge(crossed), ElementId::Vertex(a), ElementId::Vertex(b)],
            );
            let held = |b: ElementId, a: ElementId| {
                let (f, m) = if edge_on_fixed { (b, a) } else { (a, b) };
                implied(fixed, moving, target, f, m).then(|| self.held_pair(f, m))
            };
            let by_edge: Vec<HeldPair> = near
                .iter()
                .filter(|a| **a != ElementId::Face(face))
                .filter_map(|&a| held(ElementId::Edge(edge), a))
                .collect();
            running_part.edge(edge).vertices.map(|end| {
                let mut pairs = by_edge.clone();
                pairs.extend(near.iter().filter_map(|&a| held(ElementId::Vertex(end), a)));
                pairs
            })
        };
        let mut dips = Vec::new();
        // The fixed edge over the moving edge's faces: e · R w and e · R n.
        for (&g, w) in moving.edge(x).faces.iter().zip(moving.edge_wedge(x)) {
            let tests = (
                wide_at(moving, g, x) && !listed(true, e, g),
                held_towards(true, e, g, x),
            );
            if tests.0 || tests.1.iter().any(|pairs| pairs.iter().all(HeldPair::may_clear)) {
                dips.push(dip((de, w), (de, moving.face(g).normal), length(fixed, e), true, tests));
            }
        }
        // The moving edge over the fixed edge's faces: u · R x and n · R x.
        for (&f, u) in fixed.edge(e).faces.iter().zip(fixed.edge_wedge(e)) {
            let tests = (
                wide_at(fixed, f, e) && !listed(false, x, f),
                held_towards(false, x, f, e),
            );
            if tests.0 || tests.1.iter().any(|pairs| pairs.iter().all(HeldPair::may_clear)) {
                dips.push(dip(
                    (to_g(u), dx),
                    (to_g(fixed.face(f).normal), dx),
                    length(moving, x),
                    false,
                    tests,
                ));
            }
        }
        dips
    }
}

/// A pair of elements, the fixed one's points in G's frame and the moving one's in its
/// part's, as a point or a segment each; `None` for a face (never cleared).
#[derive(Clone, Debug)]
pub(super) struct HeldPair {
    fixed: Option<Segment>,
    moving: Option<Segment>,
}

impl HeldPair {
    /// Whether some box could keep the pair apart (neither is a face).
    fn may_clear(&self) -> bool {
        self.fixed.is_some() && self.moving.is_some()
    }

    /// Whether every pose of `b` keeps the two farther apart than `separation`: their
    /// distance at the box's centre, less how far the box moves the moving one.
    fn apart_over(&self, b: &Bounds, separation: f64) -> bool {
        let (Some(fixed), Some(moving)) = (self.fixed, self.moving) else {
            return false;
        };
        let motion = CentreMotion::of(b);
        let (a, moved_a) = motion.moving_to_g(moving.a);
        let (c, moved_c) = motion.moving_to_g(moving.b);
        let distance = segment_segment(&fixed, &Segment::new(a, c)).0;
        distance - moved_a.max(moved_c) > separation
    }
}

impl Problem<'_> {
    /// A fixed and a moving element as a [`HeldPair`].
    fn held_pair(&self, fixed: ElementId, moving: ElementId) -> HeldPair {
        let shape = |part: &Part, e: ElementId, to_g: &dyn Fn(DVec3) -> DVec3| match e {
            ElementId::Vertex(v) => {
                let p = to_g(part.vertex(v).position);
                Some(Segment::new(p, p))
            }
            ElementId::Edge(x) => {
                let [p, q] = part.edge_points(x);
                Some(Segment::new(to_g(p), to_g(q)))
            }
            ElementId::Face(_) => None,
        };
        HeldPair {
            fixed: shape(self.fixed, fixed, &|p| self.prover.fixed_point(p)),
            moving: shape(self.moving, moving, &|p| p),
        }
    }
}

/// The elements of face `f`'s closure (the face, its edges, its vertices) but those in
/// `skip`.
pub(super) fn closure_without(part: &Part, f: FaceId, skip: &[ElementId]) -> Vec<ElementId> {
    let face = part.face(f);
    let edges = face
        .loops
        .iter()
        .flat_map(|l| l.edges.iter())
        .map(|&y| ElementId::Edge(y));
    let vertices = face
        .loops
        .iter()
        .flat_map(|l| l.vertices.iter())
        .map(|&v| ElementId::Vertex(v));
    std::iter::once(ElementId::Face(f))
        .chain(edges)
        .chain(vertices)
        .filter(|e| !skip.contains(e))
        .collect()
}

/// Whether both of face `f`'s corners at the ends of its edge `x` open by at least
/// [`LEAST_CORNER`] (reflex corners do).
fn wide_at(part: &Part, f: FaceId, x: EdgeId) -> bool {
    let normal = part.face(f).normal;
    part.face(f).loops.iter().all(|l| {
        let n = l.vertices.len();
        (0..n).filter(|&i| l.edges[i] == x).all(|i| {
            let p = |k: usize| part.vertex(l.vertices[k % n]).position;
            // The loop runs p(i) → p(i+1) along x; the corners there are at p(i) (from
            // p(i−1)) and at p(i+1) (towards p(i+2)).
            let opening = |a: DVec3, corner: DVec3, b: DVec3| {
                let (u, v) = ((a - corner).normalize(), (b - corner).normalize());
                // The interior angle, measured counter-clockwise about the normal from
                // the loop's outgoing edge to its incoming one.
                let angle = v.cross(u).dot(normal).atan2(u.dot(v));
                if angle < 0.0 {
                    angle + std::f64::consts::TAU
                } else {
                    angle
                }
            };
            let first = opening(p(i + n - 1), p(i), p(i + 1));
            let second = opening(p(i), p(i + 1), p(i + 2));
            first >= LEAST_CORNER && second >= LEAST_CORNER
        })
    })
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::contact::ContactKind as K;
    use crate::examples::{l_block_and_box, paper_bounds};
    use crate::feasibility::Problem;
    use crate::pose::Pose;
    use crate::testing::contact;
    use crate::tolerance::CONTACT_REL;

    /// The built-in example's box turned by `(rx, ry, rz)`, its corner v6 (150, 90, 50)
    /// on the wall (x = 150) at height `y6`, its bottom back edge e6 (towards v2 (50,
    /// 90, 50)) crossing the slab's top back edge e7 (y = 100, z = 50): `None` when
    /// the crossing is not inside e6.
    fn corner_on_the_wall_and_edges_crossing(rx: f64, ry: f64, rz: f64, y6: f64) -> Option<Pose> {
        let rotation = DMat3::from_rotation_z(rz) * DMat3::from_rotation_y(ry) * DMat3::from_rotation_x(rx);
        let (v6, v2) = (
            rotation * DVec3::new(150.0, 90.0, 50.0),
            rotation * DVec3::new(50.0, 90.0, 50.0),
        );
        let mut t = DVec3::new(150.0 - v6.x, y6 - v6.y, 0.0);
        let d = v2 - v6;
        let s = (100.0 - (v6.y + t.y)) / d.y;
        if !(0.01..=0.99).contains(&s) {
            return None;
        }
        t.z = 50.0 - (v6.z + s * d.z);
        Some(Pose::from_array([t.x, t.y, t.z, rx, ry, rz]))
    }

    #[test]
    fn the_slabs_edge_descending_under_the_boxs_bottom_is_never_a_witness_and_the_last_proofs_say_so() {
        // The built-in example's undecided {f-v f5 v6, e-e e7 e6}: the box tilted back
        // about x, its bottom back edge crossing the slab's top back edge at a grazing
        // angle, its corner on the wall. Its edge up the wall, e11, rises off the wall
        // only when the slab's edge, running under the box's bottom, descends into it
        // (both are the sign of `(R z)_x`): the limit of a larger state, which the
        // halving could not separate.
        let (block, boxed) = l_block_and_box();
        let bounds = paper_bounds();
        let problem = Problem::new(&block, &boxed, bounds, glam::DAffine3::IDENTITY);
        let mut target = [contact("f5", "v6", K::FaceVertex), contact("e7", "e6", K::EdgeEdge)];
        target.sort();
        // Independently, the contact module and the witness check over the family,
        // on both sides of the limit `rz / ry = cot(−rx)`.
        let mut holding = 0;
        let mut descending = 0;
        for rx in [-0.3f64, -0.25, -0.2, -0.15, -0.1] {
            for ry in [-0.008, -0.004, -0.002, -0.001] {
                for share in [0.5, 0.9, 0.99, 0.999, 1.001, 1.01, 1.1, 2.0] {
                    let rz = ry * share / (-rx).tan();
                    for y6 in [99.9, 99.5, 99.0, 98.0] {
                        let Some(pose) = corner_on_the_wall_and_edges_crossing(rx, ry, rz, y6) else {
                            continue;
                        };
                        let placement = pose.to_affine(&glam::DAffine3::IDENTITY);
                        let report = problem.scene().evaluate(&placement, CONTACT_REL);
                        if report.contacts == target {
                            holding += 1;
                        }
                        let rotation = pose.rotation();
                        // The slab's edge e7 (x) against the box's bottom f2: which way
                        // it runs over it, and how it leaves its plane.
                        let side = DVec3::X.dot(rotation * DVec3::NEG_Y);
                        let rise = DVec3::X.dot(rotation * DVec3::NEG_Z);
                        if side * rise < 0.0 {
                            descending += 1;
                        }
                        let witness = crate::testing::witnesses(problem.scene(), &placement, &report, &target);
                        assert!(!witness, "a witness at {pose:?}");
                    }
                }
            }
        }
        assert!(
            holding >= 50 && descending >= 50,
            "{holding} poses read the target, {descending} descend"
        );
        // A small box across the limit (its turns 1e-3 wide either way): where the
        // corner's edge rises off the wall, the slab's edge descends under the bottom;
        // where it does not, the edge dips into the wall. Only with the dips do the
        // conditions see both.
        let pose = corner_on_the_wall_and_edges_crossing(-0.3, -0.004, -0.004 * 0.9 / 0.3f64.tan(), 99.5)
            .expect("a crossing inside the edge")
            .to_array();
        let widths = [1e-2, 1e-2, 1e-2, 1e-3, 1e-3, 1e-3];
        let small = Bounds::try_new(
            std::array::from_fn(|k| pose[k] - widths[k]),
            std::array::from_fn(|k| pose[k] + widths[k]),
        )
        .expect("a box");
        assert!(!problem.strict_turns(&target).may_hold(&small));
        assert!(
            problem
                .strict_turns(&target)
                .without_dips()
                .without_joint()
                .may_hold(&small)
        );
        // The decisions' conditions leave it open: the dips are for the last proofs.
        assert!(problem.turns(&target).may_hold(&small));
    }

    /// The built-in example's box turned by `rx` and `ry` about x and y and about z so
    /// that `(R z)_x = 0`: its bottom's plane through the slab's top back edge e7 (y =
    /// 100, z = 50), its back right edge e11 crossing the wall's back edge e12 (x =
    /// 150, y = 100) `height` above that edge's foot. e11 then runs in the wall's plane.
    fn upright_edge_crossing_the_walls_back_edge(rx: f64, ry: f64, height: f64) -> Pose {
        let rz = rotation_z(rx, ry);
        let rotation = DMat3::from_rotation_z(rz) * DMat3::from_rotation_y(ry) * DMat3::from_rotation_x(rx);
        let crossing = DVec3::new(150.0, 100.0, 50.0 + height);
        // The bottom (local z = 50) through e7: z0 = 50 − n_z height, n = R(−z).
        let z0 = 50.0 + (rotation * DVec3::Z).z * height;
        let t = crossing - rotation * DVec3::new(150.0, 90.0, z0);
        Pose::from_array([t.x, t.y, t.z, rx, ry, rz])
    }

    /// The turn about z that keeps `(R z)_x = 0` for turns `rx`, `ry` (the smaller one).
    fn rotation_z(rx: f64, ry: f64) -> f64 {
        (-rx.cos() * ry.sin() / rx.sin()).atan()
    }

    #[test]
    fn an_edge_running_flat_over_the_wall_from_a_crossing_is_never_a_witness() {
        // The built-in example's undecided {e-f e7 f2, e-e e12 e11}: the slab's edge in
        // the box's bottom keeps `(R z)_x` at zero, so the box's back right edge e11,
        // crossing the wall's back edge e12, runs in the wall's plane. Below the crossing
        // it lies over the wall, within the tolerance of its plane down to its end, the
        // box's corner v6: that corner touches the wall or lies nearer than the
        // separation, whatever the angle. The crossing lies 0.2 mm from both edges'
        // ends, nearer than any box of the halving can tell apart, which left it open.
        let (block, boxed) = l_block_and_box();
        let problem = Problem::new(&block, &boxed, paper_bounds(), glam::DAffine3::IDENTITY);
        let (slab_edge, crossing) = (contact("e7", "f2", K::EdgeFace), contact("e12", "e11", K::EdgeEdge));
        let mut target = [slab_edge, crossing];
        target.sort();
        let near_the_wall = |pc: &crate::contact::PrincipalContact| {
            let on_box = [
                contact("f5", "v6", K::FaceVertex).moving,
                contact("f5", "e11", K::FaceEdge).moving,
            ];
            on_box.contains(&pc.moving) && !target.contains(pc)
        };
        // Independently, the contact module and the witness check over the family.
        let mut holding = 0;
        for rx in [-0.3, -0.2, -0.1284, -0.05] {
            // Turned about y the same way as about x: the box's right face leans off the
            // wall towards its front.
            for ry in [-3e-3, -1e-3, -5.7e-4, -1e-4] {
                for height in [0.01, 0.05, 0.2, 1.0, 5.0] {
                    let placement =
                        upright_edge_crossing_the_walls_back_edge(rx, ry, height).to_affine(&glam::DAffine3::IDENTITY);
                    let report = problem.scene().evaluate_within(&placement, CONTACT_REL, 1e-3);
                    assert_eq!(report.penetration, 0.0, "{rx} {ry} {height}");
                    // The slab's edge in the bottom, as built; the crossing, or the
                    // edge lying in the wall (which holds the crossing).
                    let crossed = report.contacts.contains(&crossing)
                        || report.contacts.contains(&contact("f5", "e11", K::FaceEdge));
                    if report.contacts.contains(&slab_edge) && crossed {
                        holding += 1;
                    }
                    // The box's corner or edge on the wall, or too near it.
                    let too_near = report.min_gap.is_some_and(|g| g < problem.separation());
                    assert!(
                        report.contacts.iter().any(near_the_wall) || too_near,
                        "{rx} {ry} {height}: {:?}",
                        report.contacts
                    );
                    let witness = crate::testing::witnesses(problem.scene(), &placement, &report, &target);
                    assert!(!witness, "a witness at {rx} {ry} {height}");
                }
            }
        }
        assert!(holding >= 60, "{holding} poses hold the slab's edge and the crossing");
        // The box the last proofs left open before the flat test: the dips now rule
        // it out, the decisions' conditions do not.
        let open = Bounds::try_new(
            [
                -0.40458136273766643,
                4.943493096194722,
                11.85060332119112,
                -0.12850933054627955,
                -0.0005727854040769586,
                -0.004432556044157393,
            ],
            [
                -0.39303359070997307,
                5.0,
                11.867733871516894,
                -0.12840038006056267,
                -0.0005621420665911642,
                -0.004354087380219749,
            ],
        )
        .expect("a box");
        assert!(!problem.strict_turns(&target).may_hold(&open));
        assert!(
            problem
                .strict_turns(&target)
                .without_dips()
                .without_joint()
                .may_hold(&open)
        );
        assert!(problem.turns(&target).may_hold(&open));
    }

    #[test]
    fn a_held_pair_is_cleared_only_by_boxes_that_keep_it_apart() {
        // The wall's front foot v4 (150, 0, 50) and the box's back bottom corner v6
        // (150, 90, 50): 90 apart at rest.
        let (block, boxed) = l_block_and_box();
        let problem = Problem::new(&block, &boxed, paper_bounds(), glam::DAffine3::IDENTITY);
        let pair = problem.held_pair("v4".parse().expect("v4"), "v6".parse().expect("v6"));
        let around = |pose: [f64; 6], half: [f64; 6]| {
            Bounds::try_new(
                std::array::from_fn(|k| pose[k] - half[k]),
                std::array::from_fn(|k| pose[k] + half[k]),
            )
            .expect("a box")
        };
        let separation = problem.separation();
        assert!(pair.apart_over(&around([0.0; 6], [1e-3; 6]), separation));
        // Moved 90 forward, the corners meet.
        assert!(!pair.apart_over(&around([0.0, -90.0, 0.0, 0.0, 0.0, 0.0], [1e-3; 6]), separation));
        // Turns wide enough to sweep the corner 90 away are not ruled out either.
        assert!(!pair.apart_over(&around([0.0; 6], [1e-3, 1e-3, 1e-3, 0.6, 0.6, 0.6]), separation));
        // A face is never cleared.
        let face = problem.held_pair("f5".parse().expect("f5"), "v6".parse().expect("v6"));
        assert!(!face.may_clear() && !face.apart_over(&around([0.0; 6], [1e-3; 6]), separation));
    }
}
