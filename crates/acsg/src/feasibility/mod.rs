//! Geometric feasibility: is there a pose within the bounds at which a contact state
//! holds, with no penetration? Every question ends in one [`Decision`]: a verified
//! witness pose, a proof that no pose exists (with the rules that proved it), or
//! undecided with the smallest box the proof left open.
//!
//! A decision (`Problem::decide`) is a branch and prune over boxes of poses:
//! 1. local searches first: Levenberg–Marquardt within the bounds on residuals that
//!    vanish exactly when the contacts hold with their contact points inside the
//!    elements' relative interiors (with a margin) and nothing penetrates, from warm,
//!    anchored and constructive starts;
//! 2. boxes are then excluded by rotation-only conditions (`turns`: ranges of turns,
//!    wedges, faces that cannot be flush, edges that cannot be parallel) and by interval
//!    contraction of the contact links and of face–vertex separation (`prover`), split
//!    first by rotation, then by every coordinate, with a local search in the boxes that
//!    survive;
//! 3. every pose found is verified by the contact module: P(X) must equal the state
//!    asked for, read the same at a looser tolerance, with no penetration. A pose
//!    showing another state is reported as such.
//!
//! The pieces a search strategy builds on are public, so that another strategy (the
//! paper's algorithm, `graph::Strategy::Paper`) uses the same ones: one local
//! optimisation from a start ([`Problem::solve_from`]), the witness a pose gives
//! ([`Problem::settle`], [`Problem::verify`]), fixed starts spread over the bounds
//! ([`Problem::spread_starts`]) and the sound exclusion tests ([`Problem::exclusion`]).

mod below;
mod corner_run;
mod decide;
mod dip;
mod edge_pair;
mod fold;
mod hinge;
mod interval;
pub(crate) mod lp;
mod normals;
mod parallel;
mod pierce;
mod prover;
mod reflex;
mod residual;
mod slices;
mod slide;
mod solver;
mod turns;
mod two_points;

use glam::{DAffine3, DVec3};

use crate::contact::{ContactKind, ContactReport, ContactScene, PrincipalContact};
use crate::model::{ElementId, FaceId, Part};
use crate::pose::{Bounds, Pose};
use crate::tolerance::{CONTACT_REL, SEPARATION_REL, scaled};
use residual::{FaceShape, Margins, Side};

pub(crate) use below::lies_strictly_below;
pub(crate) use decide::Starts;
pub use decide::{Decided, Decision, Proof, Rule};
pub(crate) use slices::THOROUGH_EFFORT;
pub use slices::{Density, SliceFinds};

/// Every primitive principal contact (docs/concepts.md#ppc-and-klc): faces of the fixed part
/// against convex vertices of the moving part (f-v), convex edges against convex edges
/// (e-e), convex vertices of the fixed part against faces of the moving part (v-f).
#[must_use]
pub fn primitive_contacts(fixed: &Part, moving: &Part) -> Vec<PrincipalContact> {
    let faces = |p: &Part| {
        (0..p.faces().len() as u32)
            .map(|i| ElementId::Face(FaceId(i)))
            .collect::<Vec<_>>()
    };
    let vertices = |p: &Part| p.convex_vertices().map(ElementId::Vertex).collect::<Vec<_>>();
    let edges = |p: &Part| p.convex_edges().map(ElementId::Edge).collect::<Vec<_>>();
    let mut out = Vec::new();
    for f in faces(fixed) {
        out.extend(vertices(moving).into_iter().map(|v| PrincipalContact {
            fixed: f,
            moving: v,
            kind: ContactKind::FaceVertex,
        }));
    }
    for e in edges(fixed) {
        out.extend(edges(moving).into_iter().map(|x| PrincipalContact {
            fixed: e,
            moving: x,
            kind: ContactKind::EdgeEdge,
        }));
    }
    for v in vertices(fixed) {
        out.extend(faces(moving).into_iter().map(|f| PrincipalContact {
            fixed: v,
            moving: f,
            kind: ContactKind::VertexFace,
        }));
    }
    out
}

/// Every single principal contact that can be a state on its own, the PPCs first
/// ([`primitive_contacts`]), then the rest, each pair of elements once:
/// - a face on a face, a convex edge in a face (a concave edge's part fills more than a
///   half-space around it, so it cannot lie on a plane without penetrating);
/// - a pointed non-convex vertex on a face (its edges all leave to one side);
/// - a convex edge in a concave one, along it (e-e-t), a convex vertex in a concave
///   edge or corner, and the mirror cases;
/// - with `degenerate`, also the degenerate contacts of convex elements: e-v, v-e, v-v,
///   e-e-t.
#[must_use]
pub fn single_contacts(fixed: &Part, moving: &Part, degenerate: bool) -> Vec<PrincipalContact> {
    use ElementId::{Edge, Face, Vertex};
    let mut out = primitive_contacts(fixed, moving);
    let elements = |p: &Part| -> Vec<ElementId> {
        (0..p.faces().len() as u32)
            .map(|i| Face(FaceId(i)))
            .chain((0..p.edges().len() as u32).map(|i| Edge(crate::model::EdgeId(i))))
            .chain((0..p.vertices().len() as u32).map(|i| Vertex(crate::model::VertexId(i))))
            .collect()
    };
    let convex = |p: &Part, e: ElementId| match e {
        Face(_) => true,
        Edge(x) => p.edge(x).convex,
        Vertex(v) => p.vertex(v).convex,
    };
    for a in elements(fixed) {
        for b in elements(moving) {
            let (ca, cb) = (convex(fixed, a), convex(moving, b));
            let wanted = match (a, b) {
                (Face(_), Face(_)) => true,
                (Face(_), Edge(_)) => cb,
                (Edge(_), Face(_)) => ca,
                (Face(_), Vertex(v)) => !cb && pointed(moving, v),
                (Vertex(v), Face(_)) => !ca && pointed(fixed, v),
                // A crossing is a PPC; two edges along each other need one in a groove.
                (Edge(_), Edge(_)) => ca != cb || (degenerate && ca && cb),
                (Edge(_), Vertex(_)) | (Vertex(_), Edge(_)) | (Vertex(_), Vertex(_)) => {
                    ca != cb || (degenerate && ca && cb)
                }
            };
            if !wanted {
                continue;
            }
            let kind = ContactKind::of(a, b, matches!((a, b), (Edge(_), Edge(_))));
            out.push(PrincipalContact {
                fixed: a,
                moving: b,
                kind,
            });
        }
    }
    out
}

/// Whether every edge at a vertex leaves it to one side of some plane through it (then
/// the vertex alone can touch a plane): each of its faces has a convex corner there
/// (a reflex corner spans more than a half-plane), and the mean of the unit edge
/// directions has a positive component along each of them. A sufficient test.
fn pointed(part: &Part, v: crate::model::VertexId) -> bool {
    let vertex = part.vertex(v);
    let at = vertex.position;
    let convex_corners = vertex.faces.iter().all(|&f| {
        let face = part.face(f);
        face.loops.iter().all(|l| {
            let n = l.vertices.len();
            (0..n).filter(|&i| l.vertices[i] == v).all(|i| {
                let prev = part.vertex(l.vertices[(i + n - 1) % n]).position;
                let next = part.vertex(l.vertices[(i + 1) % n]).position;
                (at - prev).cross(next - at).dot(face.normal) > 0.0
            })
        })
    });
    let directions: Vec<DVec3> = vertex
        .edges
        .iter()
        .map(|&x| {
            let [a, b] = part.edge_points(x);
            (if a == at { b - a } else { a - b }).normalize()
        })
        .collect();
    let mean = directions.iter().copied().sum::<DVec3>();
    convex_corners && directions.iter().all(|d| d.dot(mean) > 1e-9)
}

/// The outcome of a search for a pose realising a state.
#[derive(Clone, Debug, PartialEq)]
pub enum Search {
    /// A verified witness of the state asked for.
    Found(Pose),
    /// Pruned without optimisation: the elements cannot come near within the bounds.
    Unreachable,
    /// No start led to the state; poses realising other states met on the way are
    /// listed (verified, no penetration), so that they are not lost.
    NotFound {
        /// Other states seen, with their witnesses.
        others: Vec<(Vec<PrincipalContact>, Pose)>,
    },
}

/// Counts of work done.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SearchStats {
    /// Targets proved infeasible.
    pub pruned: usize,
    /// Local optimisations run.
    pub optimisations: usize,
    /// Boxes of poses examined by the branch and prune of decisions.
    pub boxes: usize,
}

/// A fixed and a moving part with misalignment bounds: the setting of every search.
pub struct Problem<'a> {
    fixed: &'a Part,
    moving: &'a Part,
    bounds: Bounds,
    assembled: DAffine3,
    scene: ContactScene<'a>,
    fixed_faces: Vec<FaceShape>,
    moving_faces: Vec<FaceShape>,
    prover: prover::Prover<'a>,
    scale: f64,
    /// The farthest vertex of the moving part from its frame's origin: how far a unit
    /// turn moves a point of it at most.
    moving_radius: f64,
    /// How many times the default budget of boxes and searches a decision may spend.
    effort: u32,
}

impl<'a> Problem<'a> {
    /// Prepares the searches for two parts and bounds; `assembled` is G
    /// (docs/concepts.md#poses-and-bounds).
    #[must_use]
    pub fn new(fixed: &'a Part, moving: &'a Part, bounds: Bounds, assembled: DAffine3) -> Problem<'a> {
        let scene = ContactScene::new(fixed, moving);
        let scale = scene.scale();
        Problem {
            fixed,
            moving,
            bounds,
            assembled,
            fixed_faces: FaceShape::all(fixed),
            moving_faces: FaceShape::all(moving),
            prover: prover::Prover::new(fixed, moving, &assembled, scale),
            scene,
            scale,
            moving_radius: moving
                .vertices()
                .iter()
                .map(|v| v.position.length())
                .fold(0.0, f64::max),
            effort: 1,
        }
    }

    /// Sets how many times the default budget (of boxes examined and local searches
    /// inside them) a decision may spend before it leaves a candidate undecided, and
    /// how wide a box of rotations the prover's second-order test is tried in (0.01 rad
    /// of half-widths per unit, up to 0.05); at least 1.
    pub fn set_effort(&mut self, effort: u32) {
        self.effort = effort.max(1);
        self.prover.set_effort(self.effort);
    }

    /// The misalignment bounds.
    #[must_use]
    pub fn bounds(&self) -> &Bounds {
        &self.bounds
    }

    /// The contact scene of the two parts.
    #[must_use]
    pub fn scene(&self) -> &ContactScene<'a> {
        &self.scene
    }

    /// Where the moving part's frame goes at `pose` (G composed with the pose).
    pub(crate) fn placement(&self, pose: &Pose) -> DAffine3 {
        pose.to_affine(&self.assembled)
    }

    /// The residuals of a contact state and of non-penetration at a pose, keeping
    /// contact points `margin` (a length) inside their elements.
    fn residuals(&self, target: &[PrincipalContact], pose: &Pose, margin: f64, penetration: bool, out: &mut Vec<f64>) {
        out.clear();
        let t = self.placement(pose);
        let to_b = t.inverse();
        let (a, b) = (
            Side {
                part: self.fixed,
                faces: &self.fixed_faces,
            },
            Side {
                part: self.moving,
                faces: &self.moving_faces,
            },
        );
        let m = Margins { margin };
        for pc in target {
            match (pc.fixed, pc.moving) {
                (ElementId::Face(f), ElementId::Vertex(v)) => residual::face_vertex(a, f, b, v, &t, m, out),
                (ElementId::Vertex(v), ElementId::Face(f)) => residual::face_vertex(b, f, a, v, &to_b, m, out),
                (ElementId::Face(f), ElementId::Edge(e)) => residual::face_edge(a, f, b, e, &t, m, out),
                (ElementId::Edge(e), ElementId::Face(f)) => residual::face_edge(b, f, a, e, &to_b, m, out),
                (ElementId::Face(f), ElementId::Face(g)) => residual::face_face(a, f, b, g, &t, &to_b, m, out),
                (ElementId::Edge(e), ElementId::Edge(x)) if pc.kind == ContactKind::EdgeEdgeTouch => {
                    residual::edge_along_edge(a, e, b, x, &t, m, out);
                }
                (ElementId::Edge(e), ElementId::Edge(x)) => residual::edge_crossing(a, e, b, x, &t, m, out),
                (ElementId::Edge(e), ElementId::Vertex(v)) => residual::edge_vertex(a, e, b, v, &t, m, out),
                (ElementId::Vertex(v), ElementId::Edge(e)) => residual::edge_vertex(b, e, a, v, &to_b, m, out),
                (ElementId::Vertex(v), ElementId::Vertex(w)) => residual::vertex_vertex(a, v, b, w, &t, out),
            }
        }
        if penetration {
            out.push(self.scene.penetration_excess(&t));
        }
    }

    /// Starting poses that put an anchor contact's points together (the anchors in
    /// turn), for up to `count` orientations spread over the bounds (the centre first,
    /// then the octants).
    fn starts(&self, anchors: &[PrincipalContact], count: usize, bounds: &Bounds) -> Vec<Pose> {
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let mut orientations = vec![[0.5, 0.5, 0.5]];
        for corner in 0..8 {
            orientations.push([
                0.25 + 0.5 * f64::from(corner & 1),
                0.25 + 0.5 * f64::from((corner >> 1) & 1),
                0.25 + 0.5 * f64::from((corner >> 2) & 1),
            ]);
        }
        for corner in 0..8u32 {
            orientations.push(std::array::from_fn(|k| f64::from((corner >> k) & 1)));
        }
        let angle = |w: &[f64; 3], k: usize| lo[3 + k] + (hi[3 + k] - lo[3 + k]) * w[k];
        // Each orientation with every anchor in turn.
        let n = anchors.len().max(1);
        (0..count)
            .filter_map(|i| {
                let w = orientations.get(i / n)?;
                let anchor = anchors.get(i % n)?;
                Some(self.placed(anchor, i / n, [angle(w, 0), angle(w, 1), angle(w, 2)], bounds))
            })
            .collect()
    }

    /// A pose at the given angles whose translation puts the anchor contact's `i`-th
    /// pair of points together: the elements' centres first, then other points of
    /// them, so that starts differ even when the rotation is fixed. A translation outside
    /// `bounds` is first moved along the contact's plane into them, then clamped.
    fn placed(&self, anchor: &PrincipalContact, i: usize, angles: [f64; 3], bounds: &Bounds) -> Pose {
        let goal = anchor_point(self.fixed, &self.fixed_faces, anchor.fixed, i);
        let on_b = anchor_point(self.moving, &self.moving_faces, anchor.moving, i / 3);
        let mut pose = Pose::from_array([0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]);
        let rotation = pose.rotation();
        let mut t = self.assembled.inverse().transform_point3(goal) - rotation * on_b;
        pose.x = t.x;
        pose.y = t.y;
        pose.z = t.z;
        let clamped = bounds.clamp(&pose);
        if clamped.translation() == t {
            return clamped;
        }
        // Outside the bounds, clamping would put the start on the box's side, where the
        // contact no longer holds (an edge lying on a face pushed off along it). Move
        // along the contact's plane instead, towards the point of it nearest the box's
        // centre, to halfway between where the line enters the box and that point (so
        // that different placements stay different starts, and none starts on the
        // box's side, where tight bounds press the parts together), then clamp.
        let Some(n) = self.contact_normal(anchor, rotation) else {
            return clamped;
        };
        let centre = bounds.center().translation();
        let target = centre + n * n.dot(t - centre);
        let (lo, hi) = (bounds.min.translation(), bounds.max.translation());
        let (d, mut enter) = (target - t, 0.0f64);
        for k in 0..3 {
            if d[k] != 0.0 {
                let (a, b) = ((lo[k] - t[k]) / d[k], (hi[k] - t[k]) / d[k]);
                enter = enter.max(a.min(b));
            }
        }
        let enter = enter.clamp(0.0, 1.0);
        t += d * (0.5 * (enter + 1.0));
        pose.x = t.x;
        pose.y = t.y;
        pose.z = t.z;
        bounds.clamp(&pose)
    }

    /// The start among `start` and a grid of translations on the plane through it on
    /// which the anchor contact's points stay together (at its rotation, within
    /// `bounds`) where the target's residuals, penetration included, are smallest: in
    /// tight bounds (a peg in a hole) a start placed by the contact alone often presses
    /// the parts together, and a local optimisation from there climbs out of the hole
    /// rather than finding the pose deeper down where the target holds.
    pub(crate) fn probed(
        &self,
        target: &[PrincipalContact],
        anchor: &PrincipalContact,
        start: Pose,
        bounds: &Bounds,
    ) -> Pose {
        let Some(n) = self.contact_normal(anchor, start.rotation()) else {
            return start;
        };
        let (lo, hi, t) = (bounds.min.translation(), bounds.max.translation(), start.translation());
        // The plane as a height over the two axes it is least steep along.
        let k = (0..3).fold(0, |k, j| if n[j].abs() > n[k].abs() { j } else { k });
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let mut out = Vec::new();
        let mut score = |pose: &Pose| {
            self.residuals(target, pose, SEARCH_MARGIN_REL * self.scale, true, &mut out);
            out.iter().map(|r| r * r).sum::<f64>()
        };
        let mut best = (score(&start), start);
        let at = |k: usize, step: usize| lo[k] + (hi[k] - lo[k]) * (step as f64 + 0.5) / PROBE_GRID as f64;
        for a in 0..PROBE_GRID {
            for b in 0..PROBE_GRID {
                let (u, v) = (at(i, a), at(j, b));
                let w = t[k] + (n[i] * (t[i] - u) + n[j] * (t[j] - v)) / n[k];
                if !(lo[k]..=hi[k]).contains(&w) {
                    continue;
                }
                let mut p = DVec3::ZERO;
                (p[i], p[j], p[k]) = (u, v, w);
                let pose = Pose {
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    ..start
                };
                let s = score(&pose);
                if s < best.0 {
                    best = (s, pose);
                }
            }
        }
        best.1
    }

    /// The unit normal of the plane of translations (in the assembled frame) on which a
    /// contact's points stay together at a rotation: a face's normal, or the common
    /// normal of two crossing edges; none for contacts of two points or lines along
    /// each other (or edges too near parallel).
    fn contact_normal(&self, anchor: &PrincipalContact, rotation: glam::DMat3) -> Option<DVec3> {
        let to_assembled = self.assembled.matrix3.inverse();
        let n = match (anchor.fixed, anchor.moving) {
            (ElementId::Face(f), _) => to_assembled * self.fixed.face(f).normal,
            (_, ElementId::Face(g)) => rotation * self.moving.face(g).normal,
            (ElementId::Edge(e), ElementId::Edge(x)) if anchor.kind == ContactKind::EdgeEdge => {
                let n = (to_assembled * self.fixed.edge_direction(e)).cross(rotation * self.moving.edge_direction(x));
                if n.length() <= 1e-6 {
                    return None;
                }
                n
            }
            _ => return None,
        };
        n.try_normalize()
    }

    /// Whether every two contacts of a target can hold together on a rigid body: the
    /// distance between their contact points is bounded on A by the distance range of
    /// A's elements and on B by B's; the two ranges must meet.
    fn rigidly_compatible(&self, target: &[PrincipalContact]) -> bool {
        let slack = scaled(1e3 * CONTACT_REL, self.scale);
        let range = |fixed: bool, a: ElementId, b: ElementId| {
            let part = if fixed { self.fixed } else { self.moving };
            let min = self.scene.distance_within(fixed, a, b);
            let max = part
                .closure_vertices(a)
                .iter()
                .flat_map(|&v| {
                    part.closure_vertices(b)
                        .into_iter()
                        .map(move |w| part.vertex(v).position.distance(part.vertex(w).position))
                })
                .fold(0.0, f64::max);
            (min, max)
        };
        for (i, c1) in target.iter().enumerate() {
            for c2 in &target[i + 1..] {
                let (amin, amax) = range(true, c1.fixed, c2.fixed);
                let (bmin, bmax) = range(false, c1.moving, c2.moving);
                if amin > bmax + slack || bmin > amax + slack {
                    return false;
                }
            }
        }
        true
    }

    /// The contact state at a pose if the pose is clean: inside the bounds, no
    /// penetration, every pair that does not touch at least the separation tolerance
    /// apart, and the same state read with a touching tolerance just under the
    /// separation (docs/concepts.md#tolerances: a witness is robust, every checker whose
    /// tolerance lies between the two reads it alike; a face tilted off another's plane
    /// by less than the separation is read as lying on it). Empty for a clean pose in
    /// free space.
    #[must_use]
    pub fn clean_state(&self, pose: &Pose) -> Option<Vec<PrincipalContact>> {
        self.inspect(pose)
            .filter(|report| self.is_clean(report, pose))
            .map(|report| report.contacts)
    }

    /// The contact report at a pose inside the bounds (`None` outside), with the
    /// smallest gap searched only as far as a witness check needs.
    fn inspect(&self, pose: &Pose) -> Option<ContactReport> {
        let angle_tol = 1e-12;
        self.bounds
            .contains(pose, scaled(CONTACT_REL, self.scale), angle_tol)
            .then(|| {
                self.scene
                    .evaluate_within(&self.placement(pose), CONTACT_REL, 2.0 * self.separation())
            })
    }

    /// No penetration, every pair that does not touch at least the separation
    /// tolerance apart, and the same state at the loose tolerance and read over the
    /// overlap (docs/concepts.md#tolerances): [`witness_flaw`] finds none.
    fn is_clean(&self, report: &ContactReport, pose: &Pose) -> bool {
        witness_flaw(&self.scene, &self.placement(pose), report).is_none()
    }

    fn separation(&self) -> f64 {
        scaled(SEPARATION_REL, self.scale)
    }

    /// The contact state a pose witnesses: [`Problem::clean_state`] with some contact.
    /// This is the independent check every reported witness passes (the contact
    /// module's P(X), not the optimiser's residuals).
    #[must_use]
    pub fn verify(&self, pose: &Pose) -> Option<Vec<PrincipalContact>> {
        self.clean_state(pose).filter(|contacts| !contacts.is_empty())
    }

    /// One local optimisation (counted in `stats.optimisations`) from `start` towards a
    /// pose within `bounds` where the target's contacts (sorted) hold and nothing
    /// penetrates; the pose it reaches, which need not show the target (check it with
    /// [`Problem::settle`] or [`Problem::verify`]).
    pub fn solve_from(
        &self,
        target: &[PrincipalContact],
        start: Pose,
        bounds: &Bounds,
        stats: &mut SearchStats,
    ) -> Pose {
        stats.optimisations += 1;
        self.solve(target, start, bounds)
    }

    /// One local optimisation in two phases: the contacts alone first (cheap, and for
    /// translations a convex problem, so a start pushed into the parts by the bounds
    /// does not trap it), then with the penetration depth, from there. Contact points
    /// keep [`SEARCH_MARGIN_REL`] inside their elements, which keeps the pose off
    /// neighbouring states; when that leaves a residual of about the margin (the state
    /// holds only on a sliver of the bounds), a third phase settles it with
    /// [`TIGHT_MARGIN_REL`].
    fn solve(&self, target: &[PrincipalContact], start: Pose, bounds: &Bounds) -> Pose {
        let minimise = |margin: f64, penetration: bool, from: Pose| {
            solver::minimise(
                |x, out| self.residuals(target, x, margin * self.scale, penetration, out),
                from,
                bounds,
                self.scale,
            )
        };
        let left = |margin: f64, pose: &Pose| {
            let mut left = Vec::new();
            self.residuals(target, pose, margin * self.scale, true, &mut left);
            left.iter().map(|r| r * r).sum::<f64>().sqrt()
        };
        let mut pose = minimise(SEARCH_MARGIN_REL, true, minimise(SEARCH_MARGIN_REL, false, start));
        // A state that holds only on a sliver (of the bounds, or between neighbouring
        // states) cannot keep the wide margin: settle it with smaller ones, down to a
        // few times the separation a witness needs.
        let mut margin = SEARCH_MARGIN_REL;
        while left(margin, &pose) > CONTACT_REL * self.scale && margin > TIGHT_MARGIN_REL {
            margin = (margin * 0.1).max(TIGHT_MARGIN_REL);
            pose = minimise(margin, true, pose);
        }
        pose
    }

    /// The witness of `target` that a pose reached by [`Problem::solve_from`] gives, if
    /// any: the pose itself when it verifies as the target; when the target's contacts
    /// hold there but other pairs touch as well or come too close (the optimiser stops
    /// where non-penetration becomes active, at contact rather than at clearance), the
    /// pose reached by one more optimisation (counted) that pushes those pairs apart, if
    /// it verifies. A clean pose showing another state is added to `others` (once per
    /// state), so that it is not lost.
    pub fn settle(
        &self,
        target: &[PrincipalContact],
        pose: Pose,
        bounds: &Bounds,
        others: &mut Vec<(Vec<PrincipalContact>, Pose)>,
        stats: &mut SearchStats,
    ) -> Option<Pose> {
        let report = self.inspect(&pose)?;
        if !self.is_clean(&report, &pose) {
            return self.clear(target, pose, &report, bounds, stats);
        }
        let state = report.contacts;
        if state.is_empty() {
            return None;
        }
        if state == target {
            return Some(pose);
        }
        if is_strict_superset(&state, target) {
            // The target held, with more contacts: push those apart from here. (Parts of
            // contacts are left to the descents: tried after every search, they cost
            // more than they found.)
            if let Some(Search::Found(released)) = self.push_apart(target, &state, pose, stats) {
                return Some(released);
            }
        }
        if !others.iter().any(|(known, _)| *known == state) {
            others.push((state, pose));
        }
        None
    }

    /// `count` starting poses spread over the bounds, the same for every run: for
    /// orientations at the centre of the bounds' rotations, then the centres of their
    /// eight octants, then their eight corners, the translation that puts the points of
    /// one of the target's contacts together (the contacts in turn, then other points
    /// of their elements), clamped to the bounds.
    #[must_use]
    pub fn spread_starts(&self, target: &[PrincipalContact], count: usize) -> Vec<Pose> {
        self.starts(target, count, &self.bounds)
    }

    /// One local optimisation that keeps the target's contacts and pushes the `extra`
    /// contacts' elements apart (to a small clearance), from a pose showing them all.
    fn release(
        &self,
        target: &[PrincipalContact],
        extra: &[(ElementId, ElementId)],
        start: Pose,
        bounds: &Bounds,
    ) -> Pose {
        let residuals = |margin: f64, x: &Pose, out: &mut Vec<f64>| {
            self.residuals(target, x, margin * self.scale, true, out);
            // The clearance shrinks with the margin (a tenth of it, down to twice the
            // separation): a state that holds only on a sliver has no room for more.
            let clearance = (0.1 * margin).max(2.0 * SEPARATION_REL) * self.scale;
            let t = self.placement(x);
            for &(a, b) in extra {
                let mut gap = self.scene.element_distance(&t, a, b);
                if let (ElementId::Face(f), ElementId::Face(g)) = (a, b)
                    && gap < clearance
                {
                    // Faces on each other part by sliding off as well as by lifting,
                    // and when the contacts kept hold their planes together, only by
                    // sliding: the overlap's area, which every sliding motion apart
                    // shrinks, counts against the gap (the distance alone shows the
                    // optimiser lifting as the only way out).
                    let (face, other) = (&self.fixed_faces[f.index()], &self.moving_faces[g.index()]);
                    let area = residual::overlap_area(face, other, &t);
                    if area > 0.0 {
                        gap = -area.sqrt();
                    }
                }
                out.push((clearance - gap).max(0.0));
            }
        };
        let mut pose = solver::minimise(|x, out| residuals(SEARCH_MARGIN_REL, x, out), start, bounds, self.scale);
        // As in `solve`: a state that holds only on a sliver cannot keep the wide
        // margin, so smaller ones settle it.
        let mut margin = SEARCH_MARGIN_REL;
        let mut left = Vec::new();
        loop {
            residuals(margin, &pose, &mut left);
            if left.iter().map(|r| r * r).sum::<f64>().sqrt() <= CONTACT_REL * self.scale || margin <= TIGHT_MARGIN_REL
            {
                return pose;
            }
            margin = (margin * 0.1).max(TIGHT_MARGIN_REL);
            pose = solver::minimise(|x, out| residuals(margin, x, out), pose, bounds, self.scale);
        }
    }

    /// Searches for a witness of a contact state (its contacts sorted): the decision of
    /// [`Problem::decide`] from the warm starts and `constructive` starts that place the
    /// anchor contact's points together, as a [`Search`]: proved infeasible is
    /// [`Search::Unreachable`], undecided is [`Search::NotFound`] with the other states
    /// met on the way (so that they are not lost).
    pub fn find(
        &self,
        target: &[PrincipalContact],
        warm: &[Pose],
        anchor: &PrincipalContact,
        constructive: usize,
        stats: &mut SearchStats,
    ) -> Search {
        let starts = Starts {
            warm,
            anchor,
            constructive,
            boost: 1,
        };
        self.decide(target, &starts, stats).into_search(stats)
    }

    /// Searches for a witness of `target` close to a known `pose` (of a state that
    /// holds it and more, say): decisions within small boxes around the pose, first
    /// 1e-4 then a hundred times that (translations relative to L, angles in radians),
    /// clipped to the bounds. A state whose neighbours hold only next to it, at a
    /// bound, is found this way when a search over the whole bounds misses it.
    pub fn find_near(&self, target: &[PrincipalContact], pose: Pose, stats: &mut SearchStats) -> Search {
        let mut others = Vec::new();
        let Some(anchor) = target.first() else {
            return Search::NotFound { others };
        };
        let starts = Starts {
            warm: &[pose],
            anchor,
            constructive: 2,
            boost: 1,
        };
        match self.decide_near(target, &starts, pose, &mut others, stats) {
            Some(found) => Search::Found(found),
            None => Search::NotFound { others },
        }
    }

    /// A pose where the target's contacts hold with no penetration, inside the bounds,
    /// but some other pair of elements is closer than a witness allows (the optimiser
    /// stops where non-penetration becomes active, i.e. at contact, not at clearance):
    /// one optimisation that pushes those pairs apart; the witness if it verifies.
    fn clear(
        &self,
        target: &[PrincipalContact],
        pose: Pose,
        report: &ContactReport,
        bounds: &Bounds,
        stats: &mut SearchStats,
    ) -> Option<Pose> {
        let holds = report.penetration == 0.0 && target.iter().all(|pc| report.contacts.binary_search(pc).is_ok());
        if !holds {
            return None;
        }
        let mut extra: Vec<(ElementId, ElementId)> = report
            .contacts
            .iter()
            .filter(|pc| !target.contains(pc))
            .map(|pc| (pc.fixed, pc.moving))
            .collect();
        extra.extend(
            self.scene
                .close_pairs(&self.placement(&pose), CONTACT_REL, 2.0 * self.separation()),
        );
        if extra.is_empty() {
            return None;
        }
        stats.optimisations += 1;
        let cleared = self.release(target, &extra, pose, bounds);
        (self.verify(&cleared).as_deref() == Some(target)).then_some(cleared)
    }

    /// Searches for a witness of `target`, below a known `state` (a proper subset of
    /// its contacts, or parts of them: a vertex of an edge that lies in a face), from
    /// that state's witness by pushing the other contacts' elements apart (one
    /// optimisation), else by small turns off the witness (a target that holds only
    /// in a band along the state's region). Poses that verify as other states are
    /// returned as with [`Problem::find`]; a target not below the state is not
    /// searched.
    pub fn find_below(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        stats: &mut SearchStats,
    ) -> Search {
        match self.push_apart(target, state, witness, stats) {
            None => Search::NotFound { others: Vec::new() },
            Some(Search::Found(pose)) => Search::Found(pose),
            // Bands lie along a state where a contact of the target is a part of one
            // of the state's (an edge of a face lying on a face), not where the target
            // merely drops contacts.
            Some(missed) if !below::lies_strictly_below(self.fixed, self.moving, target, state) => missed,
            Some(missed) => self.turn_off(target, witness).map_or(missed, Search::Found),
        }
    }

    /// [`Problem::find_below`]'s optimisation alone (what a search that lands on a
    /// state above its target tries); `None` when the target is not below the state.
    fn push_apart(
        &self,
        target: &[PrincipalContact],
        state: &[PrincipalContact],
        witness: Pose,
        stats: &mut SearchStats,
    ) -> Option<Search> {
        let placed = self.placement(&witness);
        let touches =
            |a: ElementId, b: ElementId| self.scene.element_distance(&placed, a, b) <= 2.0 * self.separation();
        let extra = below::parted_pairs(self.fixed, self.moving, target, state, touches)?;
        stats.optimisations += 1;
        let pose = self.release(target, &extra, witness, &self.bounds);
        Some(match self.verify(&pose) {
            Some(found) if found == target => Search::Found(pose),
            Some(found) => Search::NotFound {
                others: vec![(found, pose)],
            },
            // The target holds but not robustly (a sliver narrower than the clearance
            // pushed for): the pairs still close are pushed apart from there.
            None => match self
                .inspect(&pose)
                .and_then(|report| self.clear(target, pose, &report, &self.bounds, stats))
            {
                Some(cleared) => Search::Found(cleared),
                None => Search::NotFound { others: Vec::new() },
            },
        })
    }

    /// A witness of `target` a small turn off a state's witness: each turn about one
    /// or two axes, both ways, just large enough to part the state's other pairs by a
    /// few separations, then the translation refitted to the target's contacts. Where
    /// the target holds only in a band along the state's region (a vertical edge left
    /// on a wall by two turns whose product the contact tolerance absorbs), the
    /// optimiser's margins keep it out of the band; these turns land in it.
    fn turn_off(&self, target: &[PrincipalContact], witness: Pose) -> Option<Pose> {
        let unit = self.separation() / self.moving_radius.max(self.scale * 1e-3);
        let axes: [&[usize]; 6] = [&[3], &[4], &[5], &[3, 4], &[3, 5], &[4, 5]];
        for factor in TURN_OFF_FACTORS {
            for turn in axes {
                for signs in 0..1u32 << turn.len() {
                    let mut x = witness.to_array();
                    for (i, &k) in turn.iter().enumerate() {
                        let sign = if (signs >> i) & 1 == 0 { 1.0 } else { -1.0 };
                        x[k] += sign * factor * unit;
                    }
                    let pose = self.fit_translation(target, Pose::from_array(x));
                    if self.verify(&pose).as_deref() == Some(target) {
                        return Some(pose);
                    }
                }
            }
        }
        None
    }

    /// The pose with its translation moved, rotation kept, to make the target's
    /// contacts hold (least squares, a few Gauss–Newton steps: each contact's
    /// conditions are linear in the translation at a fixed rotation).
    fn fit_translation(&self, target: &[PrincipalContact], mut pose: Pose) -> Pose {
        let step = 1e-6 * self.scale;
        let (mut r, mut shifted) = (Vec::new(), Vec::new());
        for _ in 0..4 {
            self.residuals(target, &pose, 0.0, false, &mut r);
            if r.iter().map(|v| v * v).sum::<f64>().sqrt() <= 0.01 * CONTACT_REL * self.scale {
                break;
            }
            let columns: Vec<Vec<f64>> = (0..3)
                .map(|k| {
                    let mut x = pose.to_array();
                    x[k] += step;
                    self.residuals(target, &Pose::from_array(x), 0.0, false, &mut shifted);
                    shifted.iter().zip(&r).map(|(a, b)| (a - b) / step).collect()
                })
                .collect();
            if columns.iter().any(|c| c.len() != r.len()) {
                break;
            }
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
            let normal = glam::DMat3::from_cols_array(&std::array::from_fn(|i| {
                dot(&columns[i / 3], &columns[i % 3]) + if i / 3 == i % 3 { 1e-12 } else { 0.0 }
            }));
            let rhs = DVec3::new(-dot(&columns[0], &r), -dot(&columns[1], &r), -dot(&columns[2], &r));
            let d = normal.inverse() * rhs;
            if !d.is_finite() {
                break;
            }
            pose.x += d.x;
            pose.y += d.y;
            pose.z += d.z;
        }
        pose
    }

    /// Searches for a witness of a primitive contact (f-v, e-e or v-f, with elements
    /// of those kinds); any other contact gives [`Search::NotFound`] with no search.
    pub fn find_primitive(&self, target: &PrincipalContact, stats: &mut SearchStats) -> Search {
        if !is_primitive(target) {
            return Search::NotFound { others: Vec::new() };
        }
        self.find(&[*target], &[], target, PRIMITIVE_STARTS, stats)
    }

    /// Stage 1: every primitive contact with a verified witness.
    #[must_use]
    pub fn feasible_primitives(&self, stats: &mut SearchStats) -> Vec<(PrincipalContact, Pose)> {
        primitive_contacts(self.fixed, self.moving)
            .into_iter()
            .filter_map(|ppc| match self.find_primitive(&ppc, stats) {
                Search::Found(pose) => Some((ppc, pose)),
                _ => None,
            })
            .collect()
    }
}

/// The turns [`Problem::turn_off`] tries, in separations per unit of the moving
/// part's radius: enough to part a face from a face by a few separations, small enough
/// that two such turns move a point by less than the contact tolerance together.
const TURN_OFF_FACTORS: [f64; 3] = [3.0, 10.0, 30.0];

/// The loosest touching tolerance a checker may use, relative to L: just under the
/// separation. A witness reads the same state with it as with [`CONTACT_REL`].
pub(crate) const LOOSE_CONTACT_REL: f64 = 0.99 * SEPARATION_REL;

/// Points per side of the grid of translations [`Problem::probed`] tries.
const PROBE_GRID: usize = 7;

/// How far (relative to L) the optimiser keeps contact points inside their elements.
const SEARCH_MARGIN_REL: f64 = 1e-3;
/// The smallest margin of the settling phases, for states that hold only on a sliver:
/// a few times the separation a witness needs ([`SEPARATION_REL`]).
const TIGHT_MARGIN_REL: f64 = 3e-6;

/// Constructive starts of a search for a single contact (spread orientations).
pub(crate) const PRIMITIVE_STARTS: usize = 17;

/// Whether `big` holds every contact of `small` and more (both sorted).
fn is_strict_superset(big: &[PrincipalContact], small: &[PrincipalContact]) -> bool {
    big.len() > small.len() && small.iter().all(|pc| big.binary_search(pc).is_ok())
}

/// Why a pose is no robust witness of the state read there, bounds aside
/// (docs/concepts.md#tolerances): the first of the witness check's tests that fails.
#[derive(Clone, Debug, PartialEq)]
pub enum WitnessFlaw {
    /// The parts penetrate by this much (more than the contact tolerance).
    Penetration(f64),
    /// Two elements that do not touch are this far apart, closer than the separation
    /// tolerance.
    TooClose(f64),
    /// Two contacts hold two points of one edge on a face's plane, and no contact lists
    /// the edge on that face: in exact geometry the edge lies on the face.
    EdgeOnTwoPoints,
    /// The chord between two contacts' points lies on one part's boundary and inside
    /// the other, or inside both, on none of their shared faces or edges (whatever the
    /// pose): in exact geometry the parts penetrate there.
    ChordOffTheBoundary,
    /// Read with a touching tolerance just under the separation, the state is this one.
    LooseReading(Vec<PrincipalContact>),
    /// Read over the overlap (an edge or face lying on a face where they overlap, two
    /// edges with two points on one line running together), the state is this one.
    OverlapReading(Vec<PrincipalContact>),
}

/// The first reason the pose `moving_to_fixed` is no robust witness of the state
/// `report` reads there (read at [`CONTACT_REL`], with the smallest gap searched at
/// least twice the separation tolerance far), or `None` when every checker whose
/// touching tolerance lies between 1e-9 L and 1e-6 L reads that state. The bounds are
/// not checked. The same test as every reported witness passes.
///
/// ```
/// use acsg::contact::ContactScene;
/// use acsg::feasibility::witness_flaw;
/// use acsg::pose::Pose;
/// use glam::DAffine3;
///
/// let (slab, cube) = acsg::examples::cube_and_slab();
/// let scene = ContactScene::new(&slab, &cube);
/// // The cube flat on the slab: face on face, robust.
/// let flat = Pose::from_array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).to_affine(&DAffine3::IDENTITY);
/// let report = scene.evaluate(&flat, acsg::tolerance::CONTACT_REL);
/// assert_eq!(witness_flaw(&scene, &flat, &report), None);
/// // Pressed 1e-3 into the slab: no witness.
/// let pressed = Pose::from_array([0.0, 0.0, -1e-3, 0.0, 0.0, 0.0]).to_affine(&DAffine3::IDENTITY);
/// let report = scene.evaluate(&pressed, acsg::tolerance::CONTACT_REL);
/// assert!(matches!(witness_flaw(&scene, &pressed, &report), Some(acsg::feasibility::WitnessFlaw::Penetration(_))));
/// ```
#[must_use]
pub fn witness_flaw(
    scene: &ContactScene<'_>,
    moving_to_fixed: &DAffine3,
    report: &ContactReport,
) -> Option<WitnessFlaw> {
    let (fixed, moving) = scene.parts();
    let separation = scaled(SEPARATION_REL, scene.scale());
    if report.penetration > 0.0 {
        return Some(WitnessFlaw::Penetration(report.penetration));
    }
    if let Some(gap) = report.min_gap.filter(|&g| g < separation) {
        return Some(WitnessFlaw::TooClose(gap));
    }
    if two_points::edge_on_two_points(fixed, moving, &report.contacts) {
        return Some(WitnessFlaw::EdgeOnTwoPoints);
    }
    if two_points::chord_off_the_boundary(fixed, moving, &report.contacts) {
        return Some(WitnessFlaw::ChordOffTheBoundary);
    }
    let loose = scene.state(moving_to_fixed, LOOSE_CONTACT_REL).contacts;
    if loose != report.contacts {
        return Some(WitnessFlaw::LooseReading(loose));
    }
    let overlap = scene.state_over_overlap(moving_to_fixed, CONTACT_REL);
    (overlap != report.contacts).then_some(WitnessFlaw::OverlapReading(overlap))
}

/// Whether a contact is of a primitive kind (f-v, v-f or e-e) between elements of the
/// matching dimensions.
#[must_use]
pub fn is_primitive(pc: &PrincipalContact) -> bool {
    matches!(
        (pc.kind, pc.fixed, pc.moving),
        (ContactKind::FaceVertex, ElementId::Face(_), ElementId::Vertex(_))
            | (ContactKind::VertexFace, ElementId::Vertex(_), ElementId::Face(_))
            | (ContactKind::EdgeEdge, ElementId::Edge(_), ElementId::Edge(_))
    )
}

/// The `k`-th representative point of an element: a face's inner point then its
/// interior samples; an edge's midpoint, then its quarter points; a vertex.
fn anchor_point(part: &Part, faces: &[FaceShape], e: ElementId, k: usize) -> DVec3 {
    match e {
        ElementId::Face(f) => {
            let face = &faces[f.index()];
            match k {
                0 => face.inner,
                _ if face.samples.is_empty() => face.inner,
                _ => face.samples[(k * 7) % face.samples.len()],
            }
        }
        ElementId::Edge(x) => {
            let [a, b] = part.edge_points(x);
            a.lerp(b, [0.5, 0.25, 0.75][k % 3])
        }
        ElementId::Vertex(v) => part.vertex(v).position,
    }
}
