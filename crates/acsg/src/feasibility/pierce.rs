//! Two crossing edges, each run on from the crossing: one that enters a convex piece of
//! the other part there sinks into it, at a depth that the piece's own faces bound.
//!
//! The wedge test ([`super::turns`]) allows a face to dip past the plane of the two
//! edges by a slack sized for the worst case, a crossing within the prover's margin of
//! an edge's end. That slack hides second-order conflicts: the box's bottom edge
//! crossing the step's back edge while the box's top edge lies on the wall is
//! infeasible only because the step's edge then runs on into the box, a sine of the
//! tilt deep per millimetre, for the tens of millimetres until the step's edge ends.
//! This test follows the ray itself: its depth inside the piece at a distance `s` from
//! the crossing is at least `min_F (g_F + s r_F)` over the piece's faces `F` (`g_F` how
//! far the crossing is from `F`'s plane at least, `r_F` the rate the ray moves into
//! `F`'s side), as long as `s` stays within the ray's edge.
//!
//! The same ray also shows an edge lying in a face: where the ray's edge turns off
//! the plane of a face at the other edge by almost nothing (the yaw pinned, a rim edge
//! along a peg's side face), it lies within a small tolerance `τ` of that plane from end
//! to end, and past the crossing it runs over the face, inside its other sides (the
//! piece's other faces) by the same `min` without that face. More than `4 τ` somewhere
//! puts the midpoint of the stretch the contact module classifies more than `2 τ`
//! inside (the depth is concave and not negative along it): a checker with tolerance
//! `τ` reads the edge in the face, which implies the crossing ([`Pierce::lies_in_a_face`]).

use glam::DVec3;

use super::interval::{Interval, IntervalMat, rotated, turned_value as value};
use crate::model::{EdgeId, Part};
use crate::pose::Bounds;

/// One edge's ray from a crossing with an edge of the other part, against one convex
/// piece of that part holding the other edge: excluded when the ray certainly sinks
/// deeper than [`DEEP_TOLERANCES`] contact tolerances into it within its reach.
#[derive(Clone, Debug)]
pub(crate) struct Pierce {
    /// Per face of the piece: the value `n · (R d)` of the rate the ray moves into its
    /// side (its inner normal against the ray's direction), the range that value is
    /// known to keep (other conditions of the target on the same value), and how far the
    /// crossing is from the face's plane at least.
    faces: Vec<PiercedFace>,
    /// How far the ray runs along its own edge at least.
    reach: Reach,
    /// The least ray length, whatever the box: the crossing is the prover's margin
    /// inside the ray's edge.
    least_reach: f64,
    /// The faces (indices into `faces`) that are faces of the part at the other edge:
    /// the ray's edge may lie in one of them ([`Pierce::lies_in_a_face`]).
    lying: Vec<usize>,
    /// The length of the ray's edge.
    length: f64,
    /// The contact tolerance.
    tolerance: f64,
}

/// How deep, in contact tolerances, a ray must certainly sink into the other part for
/// [`Pierce`] to exclude a box: the tolerance a witness may penetrate by, as much again
/// for the crossing's own tolerance, and three times more for safety.
const DEEP_TOLERANCES: f64 = 5.0;

/// The largest tolerance, in contact tolerances, of the checker [`Pierce`] reads an
/// edge lying in a face with: well inside the range every robust witness must agree
/// over (up to a thousand).
const LYING_TOLERANCES: f64 = 100.0;

#[derive(Clone, Copy, Debug)]
struct PiercedFace {
    n: DVec3,
    d: DVec3,
    known: Interval,
    gap: f64,
}

/// The distance from the crossing to the end of the ray's edge, over a box.
#[derive(Clone, Copy, Debug)]
enum Reach {
    /// A fixed edge's ray, direction `d` (G's frame), ending at `end` (its end's
    /// position along `d`), from a crossing `R q + t` with `q` on the moving edge
    /// between `points`.
    Fixed { d: DVec3, end: f64, points: [DVec3; 2] },
    /// A moving edge's ray, direction `R d`, ending at `end` (its end's position along
    /// `d` in the moving frame), from a crossing `c` on the fixed edge between `points`
    /// (G's frame): the crossing is at `R^T (c - t)` there.
    Moving { d: DVec3, end: f64, points: [DVec3; 2] },
}

/// The translation part of a box, per axis.
fn translation(b: &Bounds) -> [Interval; 3] {
    let (lo, hi) = (b.min.to_array(), b.max.to_array());
    std::array::from_fn(|k| Interval::new(lo[k], hi[k]))
}

impl Reach {
    /// The least distance over the box (may be negative: the box allows no crossing
    /// with that much ray).
    fn least(&self, r: &IntervalMat, b: &Bounds) -> f64 {
        let t = translation(b);
        match *self {
            Reach::Fixed { d, end, points } => {
                // (w − R q − t) · d
                let along_t = (0..3).fold(Interval::point(0.0), |acc, k| acc.add(t[k].mul(Interval::point(d[k]))));
                points
                    .iter()
                    .map(|&q| end - value(r, d, q).hi - along_t.hi)
                    .fold(f64::INFINITY, f64::min)
            }
            Reach::Moving { d, end, points } => {
                // w · d − (c − t) · (R d)
                let turned = rotated(r, d);
                points
                    .iter()
                    .map(|&c| {
                        let along = (0..3).fold(Interval::point(0.0), |acc, k| {
                            acc.add(Interval::point(c[k]).sub(t[k]).mul(turned[k]))
                        });
                        end - along.hi
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }
}

/// Ray lengths tried, as halvings of the reach: the depth is a concave function of the
/// length that is not negative at the crossing, so one of them comes within half of
/// its largest value.
const HALVINGS: i32 = 48;

impl Pierce {
    /// Whether every pose of the box with these rotations (`r`) sinks the ray deeper
    /// than the tolerance into the piece.
    pub fn certain(&self, r: &IntervalMat, b: &Bounds) -> bool {
        self.certain_beyond(r, b, 0.0)
    }

    /// [`Pierce::certain`] for the poses whose ray runs at least `least` along its edge
    /// (others being ruled out otherwise).
    pub fn certain_beyond(&self, r: &IntervalMat, b: &Bounds, least: f64) -> bool {
        let rates: Vec<(f64, f64)> = self
            .faces
            .iter()
            .map(|f| (f.gap, value(r, f.n, f.d).meet(f.known).lo))
            .collect();
        if rates.iter().any(|&(_, rate)| rate.is_nan()) {
            return false;
        }
        let reach = self.reach.least(r, b).max(self.least_reach).max(least);
        // Each face's line bounds the depth over the whole ray: below the threshold
        // there, no length tried can exceed it (the common case, answered without them).
        let deep = DEEP_TOLERANCES * self.tolerance;
        let shallow = reach > 0.0 && least_line_top(&rates, reach, None) <= deep;
        let depth = |s: f64| {
            rates
                .iter()
                .map(|&(gap, rate)| gap + s * rate)
                .fold(f64::INFINITY, f64::min)
        };
        let sinks = !shallow && (0..=HALVINGS).any(|k| depth(reach * 2f64.powi(-k)) > deep);
        sinks || self.lies_in_a_face(r, &rates, reach)
    }

    /// Whether the ray's edge lies in a face at the other edge, as a checker within the
    /// robust range reads it: the edge strays from the face's plane by at most the
    /// tolerance at the crossing plus its turn off the plane times its length (`τ`
    /// with the crossing's own tolerance), and past the crossing it runs over the face,
    /// whose other sides (the piece's other faces) it stays inside by more than `4 τ`
    /// somewhere. The depth along the ray is concave and not negative over the stretch
    /// the contact module classifies, so its midpoint lies at least half that deep:
    /// more than `2 τ`, and the checker with tolerance `τ` reads the edge in the face,
    /// which implies the crossing.
    fn lies_in_a_face(&self, r: &IntervalMat, rates: &[(f64, f64)], reach: f64) -> bool {
        self.lying.iter().any(|&i| {
            let face = &self.faces[i];
            let turn = value(r, face.n, face.d).meet(face.known);
            let stray = turn.lo.abs().max(turn.hi.abs());
            let tau = 2.0 * self.tolerance + stray * self.length;
            if tau.is_nan() || tau > LYING_TOLERANCES * self.tolerance {
                return false;
            }
            if reach > 0.0 && least_line_top(rates, reach, Some(i)) <= 4.0 * tau {
                return false;
            }
            let inside = |s: f64| {
                rates
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, &(gap, rate))| gap + s * rate)
                    .fold(f64::INFINITY, f64::min)
            };
            (0..=HALVINGS).any(|k| inside(reach * 2f64.powi(-k)) > 4.0 * tau)
        })
    }

    /// Whether this is the ray of the fixed edge (else the moving one's), and its
    /// direction (G's frame for the fixed edge, the moving part's for the moving one).
    pub fn ray(&self) -> (bool, DVec3) {
        match self.reach {
            Reach::Fixed { d, .. } => (true, d),
            Reach::Moving { d, .. } => (false, d),
        }
    }

    /// The values whose ranges the target's other conditions narrow, so that they can
    /// be recorded against them ([`Pierce::know`]).
    pub fn values(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        self.faces.iter().map(|f| (f.n, f.d))
    }

    /// Records, for the `i`-th face's value, a range it keeps at every pose that meets
    /// the target's other conditions.
    pub fn know(&mut self, i: usize, range: Interval) {
        let f = &mut self.faces[i];
        f.known = f.known.meet(range);
    }
}

/// The least, over the faces (but `skip`), of the largest value each face's line
/// `gap + s rate` takes for `s` in `[0, reach]`: an upper bound of the depth
/// `min_F (gap_F + s rate_F)` along the whole ray.
fn least_line_top(rates: &[(f64, f64)], reach: f64, skip: Option<usize>) -> f64 {
    rates
        .iter()
        .enumerate()
        .filter(|&(j, _)| Some(j) != skip)
        .map(|(_, &(gap, rate))| gap + (reach * rate).max(0.0))
        .fold(f64::INFINITY, f64::min)
}

/// What a crossing of a fixed and a moving edge needs to build its rays.
pub(crate) struct Crossing<'a> {
    pub fixed: &'a Part,
    pub moving: &'a Part,
    pub fixed_edge: EdgeId,
    pub moving_edge: EdgeId,
    /// Maps a point of the fixed part's frame into G's frame.
    pub to_g: &'a dyn Fn(DVec3) -> DVec3,
    /// Maps a direction of the fixed part's frame into G's frame.
    pub to_g_direction: &'a dyn Fn(DVec3) -> DVec3,
    /// How far inside both edges the crossing is at least (the prover's margin).
    pub margin: f64,
    /// How near a piece's boundary an edge's ends must be for the piece to hold it.
    pub near: f64,
    /// The contact tolerance.
    pub tolerance: f64,
}

impl Crossing<'_> {
    /// Each edge's ray, either way, against each convex piece of the other part that
    /// holds the other edge.
    pub fn rays(&self) -> Vec<Pierce> {
        let mut out = Vec::new();
        let [a0, a1] = self.fixed.edge_points(self.fixed_edge);
        let [b0, b1] = self.moving.edge_points(self.moving_edge);
        let (ga0, ga1) = ((self.to_g)(a0), (self.to_g)(a1));
        let inner = |p: DVec3, q: DVec3| {
            let u = (q - p).normalize();
            [p + self.margin * u, q - self.margin * u]
        };
        // The fixed edge's rays into the moving part's pieces holding the moving edge.
        let crossing_on_b = inner(b0, b1);
        let da = (ga1 - ga0).normalize();
        for piece in pieces_holding(self.moving, b0, b1, self.near) {
            for (d, end) in [(da, ga1), (-da, ga0)] {
                out.push(Pierce {
                    faces: pierced_faces(&piece, crossing_on_b, |normal| (d, -normal)),
                    reach: Reach::Fixed {
                        d,
                        end: end.dot(d),
                        points: crossing_on_b,
                    },
                    least_reach: self.margin,
                    lying: faces_at(self.moving, self.moving_edge, &piece, crossing_on_b, self.near),
                    length: ga0.distance(ga1),
                    tolerance: self.tolerance,
                });
            }
        }
        // The moving edge's rays into the fixed part's pieces holding the fixed edge.
        let crossing_on_a = inner(a0, a1);
        let crossing_on_a_g = crossing_on_a.map(|p| (self.to_g)(p));
        let db = (b1 - b0).normalize();
        for piece in pieces_holding(self.fixed, a0, a1, self.near) {
            for (d, end) in [(db, b1), (-db, b0)] {
                out.push(Pierce {
                    faces: pierced_faces(&piece, crossing_on_a, |normal| (-(self.to_g_direction)(normal), d)),
                    reach: Reach::Moving {
                        d,
                        end: end.dot(d),
                        points: crossing_on_a_g,
                    },
                    least_reach: self.margin,
                    lying: faces_at(self.fixed, self.fixed_edge, &piece, crossing_on_a, self.near),
                    length: b0.distance(b1),
                    tolerance: self.tolerance,
                });
            }
        }
        out
    }
}

/// A piece's faces against a ray from a crossing between `crossing` (in the piece's
/// frame): `rate` gives the value pair of the ray's rate into a face's side from its
/// outer normal; the gap is the crossing's least distance inside the face's plane.
fn pierced_faces(
    piece: &[(DVec3, f64)],
    crossing: [DVec3; 2],
    rate: impl Fn(DVec3) -> (DVec3, DVec3),
) -> Vec<PiercedFace> {
    piece
        .iter()
        .map(|&(normal, offset)| {
            let (n, d) = rate(normal);
            PiercedFace {
                n,
                d,
                known: Interval::new(f64::NEG_INFINITY, f64::INFINITY),
                gap: crossing
                    .iter()
                    .map(|&q| offset - normal.dot(q))
                    .fold(f64::INFINITY, f64::min)
                    .max(0.0),
            }
        })
        .collect()
}

/// The faces of a piece (indices) through the segment between `crossing` that are faces
/// of the part at edge `x` (the same outer normal), not cuts of the decomposition.
fn faces_at(part: &Part, x: EdgeId, piece: &[(DVec3, f64)], crossing: [DVec3; 2], near: f64) -> Vec<usize> {
    let normals = part.edge(x).faces.map(|f| part.face(f).normal);
    piece
        .iter()
        .enumerate()
        .filter(|(_, (normal, offset))| {
            crossing.iter().all(|q| (offset - normal.dot(*q)).abs() <= near)
                && normals.iter().any(|m| m.dot(*normal) >= 1.0 - 1e-12)
        })
        .map(|(i, _)| i)
        .collect()
}

/// The faces (outer normal, offset) of each convex piece of a part whose boundary holds
/// the segment `p`–`q` (both ends within `near` of it).
fn pieces_holding(part: &Part, p: DVec3, q: DVec3, near: f64) -> Vec<Vec<(DVec3, f64)>> {
    part.convex_pieces()
        .iter()
        .filter(|piece| piece.outside_distance(p) <= near && piece.outside_distance(q) <= near)
        .map(|piece| piece.faces().iter().map(|f| (f.normal, f.offset)).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::contact::{ContactKind as K, PrincipalContact};
    use crate::feasibility::Problem;
    use crate::pose::{Bounds, Pose};
    use crate::tolerance::{CONTACT_REL, scaled};
    use glam::DVec3;

    /// The L-block's step back edge e7 crossed by the box's bottom edge e1 at
    /// `y_b` along it, the box turned by `rx` and `ry` (and the `rz` that keeps its
    /// bottom edges e1 and e9 parallel to the wall), `gap` short of the wall.
    fn crossing_pose(rx: f64, ry: f64, y_b: f64, gap: f64) -> Pose {
        // The rz where R y_B has no x component (it is small).
        let x_of_e1 = |rz: f64| (Pose::from_array([0.0, 0.0, 0.0, rx, ry, rz]).rotation() * DVec3::Y).x;
        let rz = crate::testing::bisect(x_of_e1, -0.5, 0.5);
        let turned = Pose::from_array([0.0, 0.0, 0.0, rx, ry, rz]).rotation();
        let side = turned * DVec3::new(150.0, 10.0, 50.0);
        let on_e1 = turned * DVec3::new(50.0, y_b, 50.0);
        Pose::from_array([150.0 - gap - side.x, 100.0 - on_e1.y, 50.0 - on_e1.z, rx, ry, rz])
    }

    #[test]
    fn the_steps_edge_runs_on_into_the_box_tilted_past_the_plane_of_the_crossing() {
        // The box tilted back about x by 0.2 rad, its bottom edge e1 crossing the
        // step's back edge e7, and tilted 1e-3 rad about y: the box's bottom face dips
        // past the plane through the two edges, within the wedge test's slack (8e-3),
        // and the step's edge runs on into the box under it for 100 mm.
        let (a, b) = crate::examples::l_block_and_box();
        let problem = Problem::new(&a, &b, crate::examples::paper_bounds(), glam::DAffine3::IDENTITY);
        let target = [crate::testing::contact("e7", "e1", K::EdgeEdge)];
        let turns = problem.turns(&target);
        for (ry, deeper_than) in [(1e-3, 1e-2), (1e-7, scaled(5.0 * CONTACT_REL, problem.scale))] {
            let pose = crossing_pose(-0.2, ry, 88.0, 1.0);
            let placed = problem.placement(&pose);
            // The contact module reads the crossing there, and the parts penetrate.
            assert_eq!(problem.scene().state(&placed, CONTACT_REL).contacts, target);
            let depth = problem.scene().penetration_depth(&placed);
            assert!(depth > deeper_than, "tilted {ry}: depth {depth}");
            let at = Bounds::try_new(pose.to_array(), pose.to_array()).unwrap();
            // The rays exclude it, and the other conditions as they stood before the
            // crossing's reach ([`super::turns`]' wedge) and its exits do not; the
            // reach does too.
            let older = turns.without_reach();
            assert!(!older.may_hold(&at), "tilted {ry}");
            assert!(
                older.without_pierce().without_exits().may_hold(&at),
                "the rays exclude it, not the rest"
            );
            assert!(!turns.may_hold(&at), "tilted {ry}");
        }
    }

    #[test]
    fn a_crossing_the_rays_leave_outside_stays_open() {
        // The same crossing tilted the other way about y: the step's edge runs on under
        // the box's bottom face, and the pose is a witness of the crossing (checked by
        // the contact module). Neither the decisions' nor the last proofs' conditions
        // exclude it.
        let (a, b) = crate::examples::l_block_and_box();
        let problem = Problem::new(&a, &b, crate::examples::paper_bounds(), glam::DAffine3::IDENTITY);
        let pose = crossing_pose(-0.2, -0.01, 88.0, 1.0);
        let state = problem.clean_state(&pose).expect("a witness");
        let crossing: PrincipalContact = crate::testing::contact("e7", "e1", K::EdgeEdge);
        assert_eq!(state, [crossing]);
        let at = Bounds::try_new(pose.to_array(), pose.to_array()).unwrap();
        assert!(problem.turns(&state).may_hold(&at));
        assert!(problem.strict_turns(&state).may_hold(&at));
    }

    #[test]
    fn a_rim_edge_crossing_the_pegs_bottom_edge_with_the_yaw_pinned_lies_in_its_side_face() {
        // The plain hole's rim edge e11 (along y) and the square peg's bottom edge e1,
        // turned 0.04 rad apart about x, the yaw pinned at 0: the peg's side face f0
        // keeps its normal in the xz plane, so e11 lies in f0's plane once it crosses
        // e1, and past the crossing it runs over f0. Over the bounds the two edges may
        // be parallel, so the whole-bounds rule (a sine above 0.05 throughout) says
        // nothing; the ray sees the stretch over the face at this tilt, even with the
        // crossing as near an end of e1 as the margin allows.
        let (hole, peg) = (
            crate::testing::fixture("block_with_hole.off"),
            crate::testing::fixture("peg.off"),
        );
        let d = 3f64.to_radians();
        let pinned = Bounds::try_new([-1.0, -1.0, 0.0, -d, -d, 0.0], [1.0, 1.0, 45.0, d, d, 0.0]).unwrap();
        let problem = Problem::new(&hole, &peg, pinned, glam::DAffine3::IDENTITY);
        let (rx, ry) = (0.04, -0.003);
        let turned = Pose::from_array([0.0, 0.0, 0.0, rx, ry, 0.0]).rotation();
        let on_e1 = turned * DVec3::new(36.0, 50.0, 10.0);
        let pose = Pose::from_array([35.0 - on_e1.x, 50.0 - on_e1.y, 50.0 - on_e1.z, rx, ry, 0.0]);
        // Independently of the rule: the contact module reads e11 lying in f0 there.
        let report = problem.scene().state(&problem.placement(&pose), CONTACT_REL);
        let crossing = crate::testing::contact("e11", "e1", K::EdgeEdge);
        let lying = crate::testing::contact("e11", "f0", K::EdgeFace);
        assert!(report.contacts.contains(&lying), "{:?}", report.contacts);
        assert!(!report.contacts.contains(&crossing));
        let at = Bounds::try_new(pose.to_array(), pose.to_array()).unwrap();
        let turns = problem.turns(&[crossing]);
        assert!(!turns.may_hold(&at));
        assert!(
            turns.without_pierce().without_exits().may_hold(&at),
            "the rays exclude it, not the rest"
        );
    }
}
