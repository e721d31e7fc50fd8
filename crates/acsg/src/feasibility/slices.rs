//! Rotation slices: the states that show at a fixed rotation of the moving part, found
//! without any optimisation.
//!
//! At a fixed rotation `R`, in the frame where a point of the moving part lies at
//! `R p + t`, the moving part's convex piece `Q_j` touches the fixed part's piece `P_i`
//! exactly when `t` lies on the boundary of their Minkowski difference
//! `M_ij = P_i ⊕ (−R Q_j)`, and the parts touch without penetrating exactly when `t`
//! lies on the boundary of the union of all the `M_ij`. A point in the relative
//! interior of a facet of one `M_ij`, outside every other, shows one contact; a point
//! on the segment where facets of two of them meet shows two; a point where a third
//! one's facet crosses that segment, three. So every state that holds at `R` with
//! point contacts between different pieces shows at such a point, and states with a
//! face on a face or an edge in a face show at the rotations that align them, which
//! the slices include.
//!
//! The sweep takes many rotations (the bounds' centre and corners, the centres of
//! their faces and edges, pseudo-random ones, ones close to the centre, and ones that
//! turn a face of one part flat to a face of the other or an edge parallel to a face),
//! samples every such region once, and reads the state at each sample with the
//! witness check ([`Problem::clean_state`]). The local searches miss states whose
//! poses fill only a sliver of the bounds (a part jammed in a hole at the largest turn
//! allowed); a slice through the sliver shows them at once.

use glam::{DAffine3, DMat3, DVec3};
use rayon::prelude::*;

use super::Problem;
use crate::contact::{ContactKind, PrincipalContact};
use crate::geometry::{Aabb, ConvexPolytope, Segment, clip_convex, hull_in_plane, newell, plane_basis, point_segment};
use crate::model::{EdgeId, ElementId, FaceId, Part, VertexId};
use crate::pose::{Bounds, Pose, euler_zyx};
use crate::tolerance::SEPARATION_REL;

/// How many rotations a sweep takes: always the centre of the rotation bounds, the
/// identity (when inside) and the corners, then the counts here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Density {
    /// Also the centres of the faces and edges of the box of rotation bounds.
    pub grid: bool,
    /// Pseudo-random rotations anywhere in the bounds.
    pub random: usize,
    /// Pseudo-random rotations on each face of the box of rotation bounds (one angle at
    /// a bound) and on each of its edges (two): the largest turns allowed.
    pub on_faces: usize,
    /// See `on_faces`.
    pub on_edges: usize,
    /// Pseudo-random rotations in the bounds shrunk about their centre by each of the
    /// factors 0.1, 0.01 and 0.001: a part in a tight hole turns only a little before it
    /// jams.
    pub shrunk: usize,
    /// Random base rotations, besides the centre and the identity, from which faces
    /// are turned flat on faces and edges parallel to faces.
    pub align_bases: usize,
}

impl Density {
    /// Over the whole bounds: a few hundred rotations.
    pub const WIDE: Density = Density {
        grid: true,
        random: 400,
        on_faces: 20,
        on_edges: 10,
        shrunk: 40,
        align_bases: 4,
    };
    /// In a small box of poses a decision left open: a dozen.
    pub const LOCAL: Density = Density {
        grid: false,
        random: 4,
        on_faces: 0,
        on_edges: 0,
        shrunk: 0,
        align_bases: 0,
    };
}

/// How far inside each end of a stretch where two facets meet the sweep also reads the
/// state, in separations.
const INSET_SEPARATIONS: f64 = 4.0;
/// The turns off an open box's centre that [`Problem::states_in_open_box`] also
/// takes, in parts of each free angle's bounds.
const OPEN_BOX_STEPS: [f64; 4] = [0.01, 0.03, 0.1, 0.3];
/// The factors of [`Density::shrunk`].
const SHRUNK: [f64; 3] = [0.1, 0.01, 0.001];
/// Turns about an aligned face's normal tried per alignment.
const TWISTS: usize = 9;
/// Small turns about an aligned face's normal (parts of the bounds' turn, both ways).
const SMALL_TWISTS: [f64; 4] = [1e-4, 1e-3, 1e-2, 0.05];
/// Where, in parts of an angle's bounds, the turns about one or two axes go.
const AXIS_TURNS: [f64; 12] = [0.0, 0.02, 0.1, 0.2, 0.3, 0.4, 0.45, 0.499, 0.501, 0.55, 0.7, 0.95];
/// Seed of the pseudo-random rotations: the same slices on every run.
const SEED: u64 = 0x51ce_5eed_ac59_0001;

/// A state with its witness.
type Found = (Vec<PrincipalContact>, Pose);

/// What a sweep found: the states with their witnesses (each state once, at the first
/// sample that showed it), and the work done.
#[derive(Clone, Debug, Default)]
pub struct SliceFinds {
    /// The states found, in the order of the slices and samples.
    pub states: Vec<Found>,
    /// Rotations swept.
    pub slices: usize,
    /// Translations whose state was read.
    pub samples: usize,
}

impl Problem<'_> {
    /// The states that show at the sweep's rotations within `within` (a box of the
    /// bounds), at translations within it (see the module's documentation), each with a
    /// verified witness; degenerate states only when `degenerate`.
    #[must_use]
    pub fn states_in_slices(&self, within: &Bounds, density: Density, degenerate: bool) -> SliceFinds {
        let sweep = self.sweep(within);
        let slices = sweep.rotations(self.fixed, self.moving, density);
        self.states_at(&sweep, &slices, degenerate)
    }

    /// The states that show in `open`, a box of poses that the decision of `target`
    /// (its contacts) left open: at the box's rotations as [`Density::LOCAL`] takes
    /// them, and at each of those carried onto the alignments that `target`'s contacts
    /// need (an edge lying in a face, a face on a face, collinear edges), at
    /// translations within the box. Those contacts hold only where the rotation keeps
    /// their alignments exactly, a set of measure zero that the box's own rotations
    /// miss; a box the prover cannot close around such a state (a face balanced on a
    /// rim edge, at the largest offset the bounds allow) holds the state there. When
    /// the target needs an alignment, also at the box's centre turned along each free
    /// angle (by [`OPEN_BOX_STEPS`] of its width) and carried so, at translations
    /// anywhere in the bounds: the box may lie next to the part of the region wide
    /// enough for a witness.
    #[must_use]
    pub fn states_in_open_box(&self, open: &Bounds, target: &[PrincipalContact], degenerate: bool) -> SliceFinds {
        self.open_box_finds(&self.sweep(self.bounds()), open, target, degenerate)
    }

    /// [`Problem::states_in_open_box`] of each (target, open box), in parallel, the
    /// convex pieces prepared once for the turns that read the whole bounds.
    #[must_use]
    pub fn states_in_open_boxes(&self, boxes: &[(Vec<PrincipalContact>, Bounds)], degenerate: bool) -> Vec<SliceFinds> {
        let wide = self.sweep(self.bounds());
        boxes
            .par_iter()
            .map(|(target, open)| self.open_box_finds(&wide, open, target, degenerate))
            .collect()
    }

    /// The states that show at the rotations where each target, left open by the last
    /// proofs, may hold only on a sliver of the bounds ([`Problem::sliver_rotations`]),
    /// at translations anywhere in the bounds; in parallel, one entry per target.
    #[must_use]
    pub fn states_in_slivers(&self, targets: &[Vec<PrincipalContact>], degenerate: bool) -> Vec<SliceFinds> {
        let wide = self.sweep(self.bounds());
        targets
            .par_iter()
            .map(|target| self.states_at(&wide, &self.sliver_rotations(target), degenerate))
            .collect()
    }

    /// [`Problem::states_in_open_box`], with `wide` the sweep over the whole bounds.
    fn open_box_finds(&self, wide: &Sweep, open: &Bounds, target: &[PrincipalContact], degenerate: bool) -> SliceFinds {
        let sweep = self.sweep(open);
        let mut slices = sweep.rotations(self.fixed, self.moving, Density::LOCAL);
        let alignments = sweep.alignments_of(self.fixed, self.moving, target);
        let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
        let free: [bool; 3] = std::array::from_fn(|k| hi[k + 3] > lo[k + 3]);
        let inside = |a: &[f64; 3]| (0..3).all(|k| a[k] >= lo[k + 3] && a[k] <= hi[k + 3]);
        // Every alignment alone, and every two at once (carried_onto keeps at most two).
        let mut sets: Vec<Vec<Perpendicular>> = alignments.iter().map(|a| vec![*a]).collect();
        for (i, a) in alignments.iter().enumerate() {
            sets.extend(alignments[i + 1..].iter().map(|b| vec![*a, *b]));
        }
        let carry = |bases: &[[f64; 3]], out: &mut Vec<[f64; 3]>| {
            for base in bases {
                for set in &sets {
                    if let Some(on) = carried_onto(*base, free, set)
                        && inside(&on)
                        && !out.iter().any(|b| (0..3).all(|k| (on[k] - b[k]).abs() < 1e-15))
                    {
                        out.push(on);
                    }
                }
            }
        };
        let bases = slices.clone();
        carry(&bases, &mut slices);
        let mut finds = self.states_at(&sweep, &slices, degenerate);
        if sets.is_empty() {
            return finds;
        }
        // The box may lie where the target's region along its alignments is too narrow
        // for a witness, next to where it is wide enough: turns off the box's centre
        // along each free angle, carried onto the alignments, at translations anywhere
        // in the bounds.
        let c = open.center().to_array();
        let mut stepped = Vec::new();
        for k in (0..3).filter(|&k| free[k]) {
            for step in OPEN_BOX_STEPS {
                for sign in [-1.0, 1.0] {
                    let mut a = [c[3], c[4], c[5]];
                    a[k] = (a[k] + sign * step * (hi[k + 3] - lo[k + 3])).clamp(lo[k + 3], hi[k + 3]);
                    stepped.push(a);
                }
            }
        }
        let mut turned = Vec::new();
        carry(&stepped, &mut turned);
        let along = self.states_at(wide, &turned, degenerate);
        finds.slices += along.slices;
        finds.samples += along.samples;
        for (state, pose) in along.states {
            if !finds.states.iter().any(|(s, _)| *s == state) {
                finds.states.push((state, pose));
            }
        }
        finds
    }

    /// The states that show at rotations close to each of `seeds` (witnesses of states
    /// already known), at translations anywhere in the bounds: each seed's angles
    /// moved a little (1e-4 to a tenth of each free angle's width), and each such turn
    /// carried onto the rotations that keep an edge parallel to a face, or two such
    /// alignments at once (a face flat on a face), among those nearly kept at the seed.
    /// States that hold only on a sliver next to a known one, with a face or an edge
    /// lying in a face, show there.
    #[must_use]
    pub fn states_near(&self, seeds: &[Pose], degenerate: bool) -> SliceFinds {
        let bounds = self.bounds();
        let sweep = self.sweep(bounds);
        let slices = sweep.rotations_near(self.fixed, self.moving, seeds);
        self.states_at(&sweep, &slices, degenerate)
    }

    /// Whether no exclusion rule of the decisions rules `state` out at `pose` itself. A
    /// sample at a nearly aligned rotation can read as a state that another reading of
    /// the same pose would not give (a corner on a wall whose edge runs within the
    /// tolerance of the wall all along its part over it, up to the wall's rim); the
    /// rotation conditions know those readings, and every state reported must survive
    /// them at its witness.
    fn survives_exclusions(&self, state: &[PrincipalContact], pose: &Pose) -> bool {
        let x = pose.to_array();
        Bounds::try_new(x, x).is_ok_and(|at| self.exclusion(state, &at).is_none())
    }

    /// The sweep's setting over `within`.
    fn sweep(&self, within: &Bounds) -> Sweep {
        let thorough = self.effort >= THOROUGH_EFFORT;
        Sweep::new(self.fixed, self.moving, &self.assembled, within, self.scale, thorough)
    }

    fn states_at(&self, sweep: &Sweep, slices: &[[f64; 3]], degenerate: bool) -> SliceFinds {
        let per_slice: Vec<(usize, Vec<Found>)> = slices
            .par_iter()
            .map(|&angles| {
                let samples = sweep.samples(angles);
                let mut found: Vec<Found> = Vec::new();
                for t in &samples {
                    let pose = Pose::from_array([t.x, t.y, t.z, angles[0], angles[1], angles[2]]);
                    if let Some(state) = self.verify(&pose)
                        && (degenerate || !state.iter().any(|pc| pc.degenerate(self.fixed, self.moving)))
                        && !found.iter().any(|(s, _)| *s == state)
                    {
                        found.push((state, pose));
                    }
                }
                (samples.len(), found)
            })
            .collect();
        let mut finds = SliceFinds {
            slices: slices.len(),
            ..SliceFinds::default()
        };
        for (samples, found) in per_slice {
            finds.samples += samples;
            for (state, pose) in found {
                if !finds.states.iter().any(|(s, _)| *s == state)
                    && (!sweep.thorough || self.survives_exclusions(&state, &pose))
                {
                    finds.states.push((state, pose));
                }
            }
        }
        finds
    }
}

/// A convex piece as the sweep needs it.
struct Piece {
    vertices: Vec<DVec3>,
    /// For each vertex, the elements of its part whose closure holds it (empty inside
    /// the solid): what a facet's contact is named by.
    holders: std::sync::Arc<[Vec<ElementId>]>,
    normals: Vec<DVec3>,
    /// Each edge once, as the normals of its two faces (its arc on the Gauss map).
    arcs: Vec<(DVec3, DVec3)>,
    bounds: Aabb,
}

impl Piece {
    /// A piece of `part` mapped by `m` (a rigid motion, or a rotation and negation).
    fn new(part: &Part, polytope: &ConvexPolytope, m: &DAffine3, eps: f64) -> Piece {
        let vertices: Vec<DVec3> = polytope.vertices().iter().map(|&v| m.transform_point3(v)).collect();
        let holders = polytope.vertices().iter().map(|&v| holders_of(part, v, eps)).collect();
        let normals: Vec<DVec3> = polytope
            .faces()
            .iter()
            .map(|f| m.transform_vector3(f.normal).normalize())
            .collect();
        let id = |p: DVec3| {
            polytope
                .vertices()
                .iter()
                .position(|v| v.distance(p) <= eps)
                .unwrap_or(usize::MAX)
        };
        let mut faces_of: std::collections::BTreeMap<(usize, usize), Vec<usize>> = Default::default();
        for (f, face) in polytope.faces().iter().enumerate() {
            let ids: Vec<usize> = face.points.iter().map(|&p| id(p)).collect();
            for k in 0..ids.len() {
                let (a, b) = (ids[k], ids[(k + 1) % ids.len()]);
                if a != b && a != usize::MAX && b != usize::MAX {
                    faces_of.entry((a.min(b), a.max(b))).or_default().push(f);
                }
            }
        }
        let arcs = faces_of
            .values()
            .filter(|faces| faces.len() == 2)
            .map(|faces| (normals[faces[0]], normals[faces[1]]))
            .collect();
        Piece {
            bounds: Aabb::around(vertices.iter().copied()),
            vertices,
            holders,
            normals,
            arcs,
        }
    }

    /// The piece turned by `r` and reflected through the origin: `−R Q`.
    fn turned_back(&self, r: &DMat3) -> Piece {
        let minus = |v: &DVec3| -(*r * *v);
        let vertices: Vec<DVec3> = self.vertices.iter().map(minus).collect();
        Piece {
            bounds: Aabb::around(vertices.iter().copied()),
            vertices,
            holders: self.holders.clone(),
            normals: self.normals.iter().map(minus).collect(),
            arcs: self.arcs.iter().map(|(a, b)| (minus(a), minus(b))).collect(),
        }
    }

    fn support(&self, n: DVec3) -> f64 {
        self.vertices
            .iter()
            .map(|v| n.dot(*v))
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The box around the Minkowski difference of two pieces' boxes (`q` already `−R Q`).
fn sum_bounds(p: &Piece, q: &Piece) -> Aabb {
    Aabb {
        min: p.bounds.min + q.bounds.min,
        max: p.bounds.max + q.bounds.max,
    }
}

/// A facet of a Minkowski difference: its plane and its polygon (counter-clockwise
/// about the outward normal).
#[derive(Clone, Debug)]
struct Facet {
    normal: DVec3,
    offset: f64,
    polygon: Vec<DVec3>,
    /// The contact its points show, as the elements of the fixed and the moving part
    /// touching there; `None` when a support lies off the parts' boundaries or on no
    /// one element.
    contact: Option<(ElementId, ElementId)>,
}

/// A Minkowski difference `P ⊕ (−R Q)` of two convex pieces.
struct Difference {
    facets: Vec<Facet>,
    bounds: Aabb,
}

impl Difference {
    /// The difference of `p` and `q` (already `−R Q`); `tol` is the length below which
    /// points count as on a plane.
    fn new(p: &Piece, q: &Piece, tol: f64) -> Difference {
        let mut normals: Vec<DVec3> = p.normals.iter().chain(&q.normals).copied().collect();
        for &(a1, a2) in &p.arcs {
            for &(b1, b2) in &q.arcs {
                if let Some(n) = arcs_cross(a1, a2, b1, b2) {
                    normals.push(n);
                }
            }
        }
        let mut facets: Vec<Facet> = Vec::new();
        for n in normals {
            if facets.iter().any(|f| f.normal.dot(n) > 1.0 - 1e-12) {
                continue;
            }
            let (hp, hq) = (p.support(n), q.support(n));
            let near = |part: &Piece, h: f64| -> Vec<usize> {
                (0..part.vertices.len())
                    .filter(|&i| n.dot(part.vertices[i]) >= h - tol)
                    .collect()
            };
            let (sp, sq) = (near(p, hp), near(q, hq));
            let sums: Vec<DVec3> = sp
                .iter()
                .flat_map(|&a| sq.iter().map(move |&b| p.vertices[a] + q.vertices[b]))
                .collect();
            let polygon = hull_in_plane(&sums, n, tol);
            if polygon.len() >= 3 && area(&polygon, n) > tol * tol {
                facets.push(Facet {
                    normal: n,
                    offset: hp + hq,
                    polygon,
                    contact: common_element(&p.holders, &sp).zip(common_element(&q.holders, &sq)),
                });
            }
        }
        Difference {
            facets,
            bounds: sum_bounds(p, q),
        }
    }

    /// The open interval of `s` where `x0 + s d` is more than `margin` inside (a
    /// negative `margin`: closer than `-margin` to the difference or in it), if any.
    fn inside_along(&self, x0: DVec3, d: DVec3, margin: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for f in &self.facets {
            // f.normal · (x0 + s d) < f.offset − margin
            let (a, b) = (f.normal.dot(d), f.offset - margin - f.normal.dot(x0));
            if a.abs() < 1e-15 {
                if b <= 0.0 {
                    return None;
                }
            } else if a > 0.0 {
                hi = hi.min(b / a);
            } else {
                lo = lo.max(b / a);
            }
            if lo >= hi {
                return None;
            }
        }
        Some((lo, hi))
    }

    fn meets(&self, other: &Aabb, pad: f64) -> bool {
        self.bounds.inflated(pad).overlaps(other)
    }
}

/// The sweep's setting: the pieces, the translation box, the rotation bounds.
struct Sweep {
    fixed: Vec<Piece>,
    moving: Vec<Piece>,
    bounds: Bounds,
    /// The translation bounds.
    translations: Aabb,
    scale: f64,
    /// `G⁻¹` as a rotation: takes the fixed part's directions into the frame of `t`.
    to_frame: DMat3,
    /// At an effort of [`THOROUGH_EFFORT`] or more: turns about one or two axes, small
    /// twists of the face-on-face alignments, both ends of every stretch, and every
    /// state read checked against the exclusion rules at its pose.
    thorough: bool,
}

impl Sweep {
    fn new(fixed: &Part, moving: &Part, assembled: &DAffine3, bounds: &Bounds, scale: f64, thorough: bool) -> Sweep {
        let eps = 1e-9 * scale;
        // p_A = G (R p_B + t): the fixed part in the frame of R p_B + t is G⁻¹ P.
        let to_frame = assembled.inverse();
        let identity = DAffine3::IDENTITY;
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        Sweep {
            fixed: fixed
                .convex_pieces()
                .iter()
                .map(|p| Piece::new(fixed, p, &to_frame, eps))
                .collect(),
            moving: moving
                .convex_pieces()
                .iter()
                .map(|p| Piece::new(moving, p, &identity, eps))
                .collect(),
            bounds: *bounds,
            translations: Aabb {
                min: DVec3::new(lo[0], lo[1], lo[2]),
                max: DVec3::new(hi[0], hi[1], hi[2]),
            },
            scale,
            to_frame: to_frame.matrix3,
            thorough,
        }
    }

    fn tol(&self) -> f64 {
        1e-9 * self.scale
    }

    /// The translations to read at rotation `angles`: one in each region of a facet of
    /// the union's boundary, the middle of each stretch where two facets meet, and the
    /// points where a third crosses such a stretch; all inside the translation bounds
    /// (the facets are clipped to them padded by round-off, the samples clamped back).
    fn samples(&self, angles: [f64; 3]) -> Vec<DVec3> {
        let r = rotation_of(angles);
        let tol = self.tol();
        let turned: Vec<Piece> = self.moving.iter().map(|q| q.turned_back(&r)).collect();
        let mut differences = Vec::new();
        for p in &self.fixed {
            for q in &turned {
                if sum_bounds(p, q).inflated(tol).overlaps(&self.translations) {
                    differences.push(Difference::new(p, q, tol));
                }
            }
        }
        // The facets inside the translation box, clipped to it.
        let mut facets: Vec<(usize, Facet)> = Vec::new();
        for (m, d) in differences.iter().enumerate() {
            for f in &d.facets {
                let polygon = self.clip_to_box(&f.polygon);
                if polygon.len() >= 3 && area(&polygon, f.normal) > tol * tol {
                    facets.push((m, Facet { polygon, ..f.clone() }));
                }
            }
        }
        let mut out = Vec::new();
        for (m, f) in &facets {
            for region in outside_others(f, *m, &differences, tol) {
                out.push(centroid(&region));
            }
        }
        let ends = Ends {
            every: self.thorough,
            inset: INSET_SEPARATIONS * SEPARATION_REL * self.scale,
        };
        for (i, (m1, f1)) in facets.iter().enumerate() {
            for (m2, f2) in &facets[i + 1..] {
                if m1 != m2 {
                    meeting_points(f1, f2, [*m1, *m2], &differences, tol, ends, &mut out);
                }
            }
        }
        for t in &mut out {
            *t = t.clamp(self.translations.min, self.translations.max);
        }
        out
    }

    /// The part of a polygon inside the translation bounds, padded by round-off: a
    /// state may hold only at a bound (a face flat on the floor at the lowest height).
    fn clip_to_box(&self, polygon: &[DVec3]) -> Vec<DVec3> {
        let pad = 1e-12 * self.scale;
        let mut poly = polygon.to_vec();
        for k in 0..3 {
            let axis = DVec3::AXES[k];
            poly = clip_convex(&poly, axis, self.translations.max[k] + pad);
            poly = clip_convex(&poly, -axis, -self.translations.min[k] + pad);
            if poly.len() < 3 {
                return Vec::new();
            }
        }
        poly
    }

    /// The rotations swept, as pose angles, each inside the bounds, without repeats.
    fn rotations(&self, fixed: &Part, moving: &Part, density: Density) -> Vec<[f64; 3]> {
        let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
        let (lo, hi): ([f64; 3], [f64; 3]) = ([lo[3], lo[4], lo[5]], [hi[3], hi[4], hi[5]]);
        let at = |w: [f64; 3]| -> [f64; 3] { std::array::from_fn(|k| lo[k] + (hi[k] - lo[k]) * w[k]) };
        let mut out: Vec<[f64; 3]> = Vec::new();
        let push = |a: [f64; 3], out: &mut Vec<[f64; 3]>| {
            let inside = (0..3).all(|k| a[k] >= lo[k] - 1e-12 && a[k] <= hi[k] + 1e-12);
            let a: [f64; 3] = std::array::from_fn(|k| a[k].clamp(lo[k], hi[k]));
            if inside && !out.iter().any(|b| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)) {
                out.push(a);
            }
        };
        // The centre, the identity, then the corners, the faces' and edges' centres.
        push(at([0.5; 3]), &mut out);
        push([0.0; 3], &mut out);
        for code in 0..27u32 {
            let w = [code % 3, (code / 3) % 3, code / 9].map(|c| 0.5 * f64::from(c));
            if density.grid || w.iter().all(|&x| x != 0.5) {
                push(at(w), &mut out);
            }
        }
        let mut random = SplitMix(SEED);
        for _ in 0..density.random {
            push(at([random.unit(), random.unit(), random.unit()]), &mut out);
        }
        // On the faces and edges of the box of rotation bounds.
        for k in 0..3 {
            for end in [0.0, 1.0] {
                for _ in 0..density.on_faces {
                    let mut w = [random.unit(), random.unit(), random.unit()];
                    w[k] = end;
                    push(at(w), &mut out);
                }
                for j in (k + 1)..3 {
                    for other in [0.0, 1.0] {
                        for _ in 0..density.on_edges {
                            let mut w = [random.unit(), random.unit(), random.unit()];
                            w[k] = end;
                            w[j] = other;
                            push(at(w), &mut out);
                        }
                    }
                }
            }
        }
        // Turns about one axis alone, and about two (the third angle at the centre's or
        // zero): they keep many edges parallel to faces at once.
        let bases = if density.grid && self.thorough {
            vec![at([0.5; 3]), [0.0; 3]]
        } else {
            Vec::new()
        };
        for base in bases {
            for k in 0..3 {
                for j in 0..3 {
                    for &w in &AXIS_TURNS {
                        let mut a = base;
                        a[k] = lo[k] + (hi[k] - lo[k]) * w;
                        if j != k {
                            a[j] = lo[j] + (hi[j] - lo[j]) * (1.0 - w);
                        }
                        push(a, &mut out);
                    }
                }
            }
        }
        for factor in SHRUNK {
            for _ in 0..density.shrunk {
                push(at([0, 1, 2].map(|_| 0.5 + factor * (random.unit() - 0.5))), &mut out);
            }
        }
        // Alignments, from the centre, the identity and a few random bases.
        let mut bases = vec![rotation_of(at([0.5; 3])), DMat3::IDENTITY];
        for _ in 0..density.align_bases {
            bases.push(rotation_of(at([random.unit(), random.unit(), random.unit()])));
        }
        for r in self.aligned(fixed, moving, &bases) {
            let (rx, ry, rz) = euler_zyx(&r);
            push([rx, ry, rz], &mut out);
        }
        out
    }

    /// The alignments of the two parts, each once (parallel directions give the same).
    fn perpendiculars(&self, fixed: &Part, moving: &Part) -> Vec<Perpendicular> {
        let directions = |part: &Part, frame: DMat3| -> (Vec<DVec3>, Vec<DVec3>) {
            let normals = part.faces().iter().map(|f| frame * f.normal).collect();
            let edges = (0..part.edges().len() as u32)
                .map(|e| frame * part.edge_direction(EdgeId(e)))
                .collect();
            (distinct(normals), distinct(edges))
        };
        let (fixed_normals, fixed_edges) = directions(fixed, self.to_frame);
        let (moving_normals, moving_edges) = directions(moving, DMat3::IDENTITY);
        let mut out: Vec<Perpendicular> = Vec::new();
        let pairs = moving_edges
            .iter()
            .flat_map(|&m| fixed_normals.iter().map(move |&f| (m, f)))
            .chain(
                moving_normals
                    .iter()
                    .flat_map(|&m| fixed_edges.iter().map(move |&f| (m, f))),
            );
        for (m, f) in pairs {
            // An edge along a normal of the other part's face gives the same condition
            // as that face's normal across the edge: keep one.
            let p = Perpendicular { moving: m, fixed: f };
            if !out.iter().any(|q| q.same_as(&p)) {
                out.push(p);
            }
        }
        out
    }

    /// The alignments `target`'s contacts need, each once: an edge lying in a face
    /// (one), a face on a face and collinear edges (two each).
    fn alignments_of(&self, fixed: &Part, moving: &Part, target: &[PrincipalContact]) -> Vec<Perpendicular> {
        // A face's normal, an edge's direction.
        let axis = |part: &Part, e: ElementId| match e {
            ElementId::Face(f) => Some(part.face(f).normal),
            ElementId::Edge(id) => Some(part.edge_direction(id)),
            ElementId::Vertex(_) => None,
        };
        let mut out: Vec<Perpendicular> = Vec::new();
        for pc in target {
            let (Some(f), Some(m)) = (axis(fixed, pc.fixed), axis(moving, pc.moving)) else {
                continue;
            };
            let f = self.to_frame * f;
            let found = match pc.kind {
                // An edge in a face: the edge across the face's normal.
                ContactKind::EdgeFace | ContactKind::FaceEdge => vec![Perpendicular { moving: m, fixed: f }],
                // A face on a face, collinear edges: the moving part's axis across two
                // directions perpendicular to the fixed part's.
                ContactKind::FaceFace | ContactKind::EdgeEdgeTouch => {
                    let (u, v) = plane_basis(f);
                    vec![
                        Perpendicular { moving: m, fixed: u },
                        Perpendicular { moving: m, fixed: v },
                    ]
                }
                _ => Vec::new(),
            };
            for p in found {
                if !out.iter().any(|q| q.same_as(&p)) {
                    out.push(p);
                }
            }
        }
        out
    }

    /// The rotations of [`Problem::states_near`], as pose angles inside the bounds.
    fn rotations_near(&self, fixed: &Part, moving: &Part, seeds: &[Pose]) -> Vec<[f64; 3]> {
        let perpendiculars = self.perpendiculars(fixed, moving);
        let (lo, hi) = (self.bounds.min.to_array(), self.bounds.max.to_array());
        let width: [f64; 3] = std::array::from_fn(|k| hi[k + 3] - lo[k + 3]);
        let free = width.map(|w| w > 0.0);
        let mut random = SplitMix(SEED ^ 0x6e65_6172);
        let mut seen = std::collections::BTreeSet::new();
        let mut out = Vec::new();
        let mut push = |a: [f64; 3], out: &mut Vec<[f64; 3]>| {
            if (0..3).all(|k| a[k] >= lo[k + 3] && a[k] <= hi[k + 3]) && seen.insert(a.map(f64::to_bits)) {
                out.push(a);
            }
        };
        for seed in seeds {
            let r_seed = seed.rotation();
            let angles = [seed.rx, seed.ry, seed.rz];
            // The alignments nearly kept, closest first, at most NEAR_ALIGNMENTS of them
            // (a round peg keeps dozens nearly: their pairs would swamp the sweep).
            let mut near: Vec<(f64, usize)> = perpendiculars
                .iter()
                .enumerate()
                .map(|(i, p)| (p.residual(&r_seed).abs(), i))
                .filter(|&(g, _)| g < NEARLY_KEPT.sin())
                .collect();
            near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let near: Vec<Perpendicular> = near
                .iter()
                .take(NEAR_ALIGNMENTS)
                .map(|&(_, i)| perpendiculars[i])
                .collect();
            for scale in NEAR_TURNS {
                for _ in 0..NEAR_PER_TURN {
                    let towards: [f64; 3] = std::array::from_fn(|k| (2.0 * random.unit() - 1.0) * width[k]);
                    // Both ways: an alignment reached from either side of it shows the
                    // contacts on that side (an edge of the cube down, or the other).
                    for sign in [scale, -scale] {
                        let turned: [f64; 3] = std::array::from_fn(|k| angles[k] + sign * towards[k]);
                        push(turned, &mut out);
                        for (i, a) in near.iter().enumerate() {
                            if let Some(on) = carried_onto(turned, free, &[*a]) {
                                push(on, &mut out);
                            }
                            for b in &near[i + 1..] {
                                if let Some(on) = carried_onto(turned, free, &[*a, *b]) {
                                    push(on, &mut out);
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// Rotations that turn a face of the moving part flat against a face of the fixed
    /// part (with several turns about the face's normal), or an edge of one part
    /// parallel to a face of the other, each the smallest turn from a base.
    fn aligned(&self, fixed: &Part, moving: &Part, bases: &[DMat3]) -> Vec<DMat3> {
        let widths = self.bounds.width();
        let reach: f64 = (3..6).map(|k| widths[k]).sum::<f64>();
        let fixed_normals: Vec<DVec3> = fixed.faces().iter().map(|f| self.to_frame * f.normal).collect();
        let moving_normals: Vec<DVec3> = moving.faces().iter().map(|f| f.normal).collect();
        let edge_directions = |part: &Part| -> Vec<DVec3> {
            (0..part.edges().len() as u32)
                .map(|e| part.edge_direction(EdgeId(e)))
                .collect()
        };
        let fixed_edges: Vec<DVec3> = edge_directions(fixed).into_iter().map(|d| self.to_frame * d).collect();
        let moving_edges = edge_directions(moving);
        let mut out = Vec::new();
        for base in bases {
            for &nf in &fixed_normals {
                for &ng in &moving_normals {
                    // R n_g = −n_f.
                    let turned = *base * ng;
                    if turned.angle_between(-nf) > reach {
                        continue;
                    }
                    let r0 = rotation_between(turned, -nf) * *base;
                    for k in 0..TWISTS {
                        let phi = reach * (k as f64 / (TWISTS - 1) as f64 - 0.5);
                        out.push(DMat3::from_axis_angle(nf, phi) * r0);
                    }
                    for small in SMALL_TWISTS.iter().filter(|_| self.thorough) {
                        for phi in [-small * reach, small * reach] {
                            out.push(DMat3::from_axis_angle(nf, phi) * r0);
                        }
                    }
                }
                // An edge of the moving part parallel to the fixed face: R d ⟂ n_f.
                for &d in &moving_edges {
                    let v = *base * d;
                    if let Some(turn) = perpendicular_turn(v, nf, reach) {
                        out.push(turn * *base);
                    }
                }
            }
            // An edge of the fixed part parallel to a moving face: R n_g ⟂ d.
            for &d in &fixed_edges {
                for &ng in &moving_normals {
                    let v = *base * ng;
                    if let Some(turn) = perpendicular_turn(v, d, reach) {
                        out.push(turn * *base);
                    }
                }
            }
        }
        out
    }
}

/// An alignment: a direction of the moving part kept perpendicular to one of the fixed
/// part (in the frame of the translations), `R m ⟂ f`. An edge parallel to a face is
/// one; a face flat on a face is two (its normal perpendicular to two edges of the
/// other face).
#[derive(Clone, Copy, Debug)]
struct Perpendicular {
    moving: DVec3,
    fixed: DVec3,
}

impl Perpendicular {
    fn residual(&self, r: &DMat3) -> f64 {
        (*r * self.moving).dot(self.fixed)
    }

    /// Whether both directions are the other's, up to sign: the same condition.
    fn same_as(&self, other: &Perpendicular) -> bool {
        self.moving.dot(other.moving).abs() > 1.0 - 1e-12 && self.fixed.dot(other.fixed).abs() > 1.0 - 1e-12
    }
}

/// The pose angles nearest `a` (least change of the angles `free` to move, by
/// Gauss-Newton steps) at which every alignment of `set` is kept, if the steps
/// converge. Angles pinned by the bounds stay where they are.
fn carried_onto(a: [f64; 3], free: [bool; 3], set: &[Perpendicular]) -> Option<[f64; 3]> {
    let mut a = a;
    for _ in 0..MAX_STEPS {
        let r = rotation_of(a);
        let g: Vec<f64> = set.iter().map(|p| p.residual(&r)).collect();
        if g.iter().all(|v| v.abs() < 1e-15) {
            return Some(a);
        }
        let partials = angle_partials(a);
        let rows: Vec<DVec3> = set
            .iter()
            .map(|p| {
                DVec3::from_array(std::array::from_fn(|k| {
                    if free[k] {
                        (partials[k] * p.moving).dot(p.fixed)
                    } else {
                        0.0
                    }
                }))
            })
            .collect();
        // δ = −Jᵀ (J Jᵀ)⁻¹ g, the least change that zeroes the linearised residuals.
        let step = match rows.as_slice() {
            [u] => {
                let n = u.length_squared();
                if n < 1e-24 {
                    return None;
                }
                -*u * (g[0] / n)
            }
            [u, v] => {
                let (uu, uv, vv) = (u.dot(*u), u.dot(*v), v.dot(*v));
                let det = uu * vv - uv * uv;
                if det.abs() < 1e-18 {
                    return None;
                }
                let y0 = (vv * g[0] - uv * g[1]) / det;
                let y1 = (uu * g[1] - uv * g[0]) / det;
                -(*u * y0 + *v * y1)
            }
            _ => return None,
        };
        if step == DVec3::ZERO || !step.is_finite() {
            return None;
        }
        a = std::array::from_fn(|k| a[k] + step[k]);
    }
    None
}

/// `∂R/∂rx`, `∂R/∂ry`, `∂R/∂rz` of `R = Rz Ry Rx` at the pose angles `a`.
fn angle_partials(a: [f64; 3]) -> [DMat3; 3] {
    let (rx, ry, rz) = (
        DMat3::from_rotation_x(a[0]),
        DMat3::from_rotation_y(a[1]),
        DMat3::from_rotation_z(a[2]),
    );
    let skew = |v: DVec3| DMat3::from_cols(v.cross(DVec3::X), v.cross(DVec3::Y), v.cross(DVec3::Z));
    [
        rz * ry * rx * skew(DVec3::X),
        rz * ry * skew(DVec3::Y) * rx,
        rz * skew(DVec3::Z) * ry * rx,
    ]
}

/// Gauss-Newton steps at most in [`carried_onto`].
const MAX_STEPS: usize = 30;
/// How far from the seed's rotation the sweep near it turns, in parts of each angle's
/// width in the bounds.
const NEAR_TURNS: [f64; 4] = [1e-4, 1e-3, 1e-2, 1e-1];
/// Random axes per scale of [`NEAR_TURNS`], each turned about both ways.
const NEAR_PER_TURN: usize = 1;
/// An alignment counts as nearly kept at a seed within this angle (radians).
const NEARLY_KEPT: f64 = 0.05;
/// The effort from which the sweep is thorough (see `Sweep::thorough`) and also goes
/// near every state found.
pub(crate) const THOROUGH_EFFORT: u32 = 2;
/// The most alignments nearly kept at a seed that the sweep carries turns onto.
const NEAR_ALIGNMENTS: usize = 4;

/// The smallest rotation turning the unit vector `v` perpendicular to the unit vector
/// `n`, when it is at most `reach`.
fn perpendicular_turn(v: DVec3, n: DVec3, reach: f64) -> Option<DMat3> {
    let off = v.dot(n);
    if off.abs() < 1e-15 {
        return None;
    }
    let target = (v - n * off).normalize_or_zero();
    if target == DVec3::ZERO || v.angle_between(target) > reach {
        return None;
    }
    Some(rotation_between(v, target))
}

/// The smallest rotation taking the unit vector `u` to the unit vector `w`.
fn rotation_between(u: DVec3, w: DVec3) -> DMat3 {
    let axis = u.cross(w);
    let s = axis.length();
    if s < 1e-15 {
        // Parallel: no turn; opposite: a half turn about any perpendicular axis.
        return if u.dot(w) > 0.0 {
            DMat3::IDENTITY
        } else {
            DMat3::from_axis_angle(u.any_orthonormal_vector(), std::f64::consts::PI)
        };
    }
    DMat3::from_axis_angle(axis / s, s.atan2(u.dot(w)))
}

/// The directions, each once up to sign.
fn distinct(directions: Vec<DVec3>) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::new();
    for d in directions {
        if d.length_squared() > 0.5 && !out.iter().any(|o| o.dot(d).abs() > 1.0 - 1e-12) {
            out.push(d);
        }
    }
    out
}

fn rotation_of(angles: [f64; 3]) -> DMat3 {
    Pose::from_array([0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]).rotation()
}

/// The normal where the Gauss-map arcs `(a1, a2)` and `(b1, b2)` cross, if they do
/// (strictly inside both).
fn arcs_cross(a1: DVec3, a2: DVec3, b1: DVec3, b2: DVec3) -> Option<DVec3> {
    let (na, nb) = (a1.cross(a2), b1.cross(b2));
    let d = na.cross(nb);
    let len = d.length();
    if len < 1e-12 {
        return None;
    }
    let d = d / len;
    let between = |p: DVec3, q: DVec3, n: DVec3, x: DVec3| p.cross(x).dot(n) > 1e-12 && x.cross(q).dot(n) > 1e-12;
    [d, -d]
        .into_iter()
        .find(|&x| between(a1, a2, na, x) && between(b1, b2, nb, x))
}

/// The signed area of a planar polygon, positive counter-clockwise about `n`.
fn area(polygon: &[DVec3], n: DVec3) -> f64 {
    0.5 * newell(polygon.iter().copied()).dot(n)
}

fn centroid(polygon: &[DVec3]) -> DVec3 {
    polygon.iter().copied().sum::<DVec3>() / polygon.len() as f64
}

/// The parts of facet `f` of difference `own` that lie inside no other difference (by
/// more than `tol`), as convex polygons of some area, also cut where a coplanar facet
/// of another difference showing another contact ends.
fn outside_others(f: &Facet, own: usize, differences: &[Difference], tol: f64) -> Vec<Vec<DVec3>> {
    let around = Aabb::around(f.polygon.iter().copied());
    let mut pieces = vec![f.polygon.clone()];
    for (m, d) in differences.iter().enumerate() {
        if m == own || !d.meets(&around, tol) {
            continue;
        }
        // A facet of `d` in `f`'s plane: `d` lies behind that plane and never holds
        // `f`'s points, but where the facets overlap both contacts hold: each part of
        // the region, inside the other facet and out of it, is sampled, unless both
        // show one contact (pieces of one face in one plane, which make many parts).
        if let Some(g) = d.facets.iter().find(|g| coplanar(g, f, tol)) {
            if adds_a_contact(g, f, tol) {
                pieces = pieces.into_iter().flat_map(|piece| split_by(piece, g, tol)).collect();
            }
            continue;
        }
        let mut kept = Vec::new();
        for piece in pieces {
            // What is left lies inside `d`.
            peel(
                piece,
                d.facets.iter().map(|g| (g.normal, g.offset - tol)),
                f.normal,
                tol,
                &mut kept,
            );
        }
        pieces = kept;
        if pieces.is_empty() {
            break;
        }
    }
    pieces
}

/// Whether two facets lie in one plane, facing the same way.
fn coplanar(g: &Facet, f: &Facet, tol: f64) -> bool {
    g.normal.dot(f.normal) > 1.0 - 1e-12 && (g.offset - f.offset).abs() <= tol
}

/// Whether facet `g`, in the plane of `f`, shows a contact `f` does not: where it
/// covers part of `f`, that part shows one state more. Pieces of one face in one plane
/// show the same contact on both sides of their seam, and need no cut there.
fn adds_a_contact(g: &Facet, f: &Facet, tol: f64) -> bool {
    coplanar(g, f, tol) && (g.contact.is_none() || g.contact != f.contact)
}

/// The elements of `part` whose closure holds `p` (within `eps`): the vertex at it with
/// its edges and faces, else the edges through it with their faces, else the faces it
/// lies in; sorted, and empty off the boundary (a corner of a cut between pieces).
fn holders_of(part: &Part, p: DVec3, eps: f64) -> Vec<ElementId> {
    let mut held = Vec::new();
    if let Some((id, v)) = part
        .vertices()
        .iter()
        .enumerate()
        .find(|(_, v)| v.position.distance(p) <= eps)
    {
        held.push(ElementId::Vertex(VertexId(id as u32)));
        held.extend(v.edges.iter().map(|&e| ElementId::Edge(e)));
        held.extend(v.faces.iter().map(|&f| ElementId::Face(f)));
    } else {
        for (id, edge) in part.edges().iter().enumerate() {
            let [a, b] = edge.vertices.map(|v| part.vertex(v).position);
            if point_segment(p, &Segment::new(a, b)).0 <= eps {
                held.push(ElementId::Edge(EdgeId(id as u32)));
                held.extend(edge.faces.iter().map(|&f| ElementId::Face(f)));
            }
        }
        if held.is_empty() {
            for (id, face) in part.faces().iter().enumerate() {
                let inside = face.signed_distance(p).abs() <= eps
                    && face
                        .triangles
                        .iter()
                        .any(|t| in_triangle(p, t.map(|v| part.vertex(v).position), eps));
                if inside {
                    held.push(ElementId::Face(FaceId(id as u32)));
                }
            }
        }
    }
    held.sort();
    held.dedup();
    held
}

/// Whether `p`, in the triangle's plane, lies in it or within `eps` of it.
fn in_triangle(p: DVec3, [a, b, c]: [DVec3; 3], eps: f64) -> bool {
    let n = (b - a).cross(c - a).normalize_or_zero();
    [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(p - u).dot(n) >= -eps * u.distance(v))
}

/// The lowest-dimensional element whose closure holds every one of `points` (indices
/// into `holders`); `None` when none does.
fn common_element(holders: &[Vec<ElementId>], points: &[usize]) -> Option<ElementId> {
    let (&first, rest) = points.split_first()?;
    holders[first]
        .iter()
        .copied()
        .filter(|e| rest.iter().all(|&i| holders[i].contains(e)))
        .min_by_key(|e| e.dimension())
}

/// A convex polygon in the plane of facet `g`, cut into its part inside `g`'s polygon
/// and the parts outside each of its edges (those of some area).
fn split_by(polygon: Vec<DVec3>, g: &Facet, tol: f64) -> Vec<Vec<DVec3>> {
    let k = g.polygon.len();
    let edges = (0..k).map(|i| {
        let (p, q) = (g.polygon[i], g.polygon[(i + 1) % k]);
        let outward = (q - p).cross(g.normal);
        (outward, outward.dot(p))
    });
    let mut parts = Vec::new();
    let rest = peel(polygon, edges, g.normal, tol, &mut parts);
    if rest.len() >= 3 && area(&rest, g.normal).abs() > tol * tol {
        parts.push(rest);
    }
    parts
}

/// Peels off a convex polygon (normal `normal`) its parts outside each half-space
/// `n · x <= cut` in turn, pushing those of some area to `parts`; returns what is left
/// inside them all (fewer than three points when nothing is).
fn peel(
    polygon: Vec<DVec3>,
    half_spaces: impl Iterator<Item = (DVec3, f64)>,
    normal: DVec3,
    tol: f64,
    parts: &mut Vec<Vec<DVec3>>,
) -> Vec<DVec3> {
    let mut rest = polygon;
    for (n, cut) in half_spaces {
        if rest.iter().all(|p| n.dot(*p) <= cut) {
            continue;
        }
        let outside = clip_convex(&rest, -n, -cut);
        if outside.len() >= 3 && area(&outside, normal).abs() > tol * tol {
            parts.push(outside);
        }
        rest = clip_convex(&rest, n, cut);
        if rest.len() < 3 {
            break;
        }
    }
    rest
}

/// Which points near a stretch's ends [`meeting_points`] samples besides its middles.
#[derive(Clone, Copy)]
struct Ends {
    /// Every end, also at an edge of either facet (else only where another
    /// difference's boundary cuts the segment).
    every: bool,
    /// How far inside both ends of every stretch longer than four times this (zero:
    /// not at all).
    inset: f64,
}

/// The samples where facets `f1` and `f2` (of differences `own`) meet: the middle of
/// every stretch of their common segment inside no other difference (of every part of
/// it, where a difference with a facet in the plane of either covers some of it), the
/// ends of those stretches where another difference's boundary cuts the segment, and
/// points just inside both ends (`ends`).
fn meeting_points(
    f1: &Facet,
    f2: &Facet,
    own: [usize; 2],
    differences: &[Difference],
    tol: f64,
    ends: Ends,
    out: &mut Vec<DVec3>,
) {
    let d = f1.normal.cross(f2.normal);
    let len = d.length();
    if len < 1e-9 {
        return;
    }
    let d = d / len;
    // A point on both planes: x0 = a n1 + b n2.
    let c = f1.normal.dot(f2.normal);
    let det = 1.0 - c * c;
    let a = (f1.offset - c * f2.offset) / det;
    let b = (f2.offset - c * f1.offset) / det;
    let x0 = f1.normal * a + f2.normal * b;
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for f in [f1, f2] {
        let k = f.polygon.len();
        for i in 0..k {
            let (p, q) = (f.polygon[i], f.polygon[(i + 1) % k]);
            let outward = (q - p).cross(f.normal);
            let (s, h) = (outward.dot(d), outward.dot(p - x0));
            // outward · (x0 + s d − p) <= 0
            if s.abs() < 1e-15 {
                if h < 0.0 {
                    return;
                }
            } else if s > 0.0 {
                hi = hi.min(h / s);
            } else {
                lo = lo.max(h / s);
            }
        }
    }
    if hi - lo <= tol {
        return;
    }
    let mut stretches = vec![(lo, hi)];
    // Where another difference only touches the segment, with a facet in the plane of
    // one of the two (faces of several pieces in one plane), the segment shows one
    // more contact: each end of such a stretch parts two states, both sampled.
    let mut cuts = Vec::new();
    let segment = Aabb::around([x0 + d * lo, x0 + d * hi]);
    for (m, diff) in differences.iter().enumerate() {
        if own.contains(&m) || !diff.meets(&segment, tol) {
            continue;
        }
        if diff
            .facets
            .iter()
            .any(|g| adds_a_contact(g, f1, tol) || adds_a_contact(g, f2, tol))
        {
            if let Some((a, b)) = diff.inside_along(x0, d, -tol) {
                cuts.extend([a, b].into_iter().filter(|c| c.is_finite()));
            }
        }
        let Some((a, b)) = diff.inside_along(x0, d, tol) else {
            continue;
        };
        let mut next = Vec::new();
        for (s, e) in stretches {
            if b <= s || a >= e {
                next.push((s, e));
                continue;
            }
            if a > s {
                next.push((s, a));
            }
            if b < e {
                next.push((b, e));
            }
        }
        stretches = next;
    }
    cuts.sort_by(f64::total_cmp);
    for (s, e) in stretches {
        // The middle of every part of the stretch between the cuts.
        let inner = cuts.iter().copied().filter(|&c| c > s + tol && c < e - tol);
        let mut from = s;
        for to in inner.chain([e]) {
            if to - from > tol {
                out.push(x0 + d * (0.5 * (from + to)));
            }
            from = to;
        }
        // Both ends: another difference's boundary (three contacts), or an edge of
        // either facet (a contact at an element's end, or a third facet of the same
        // difference).
        for end in [s, e] {
            if ends.every || (end > lo + tol && end < hi - tol) {
                out.push(x0 + d * end);
            }
        }
        // Just inside both ends: where the two contacts hold robustly only on a sliver
        // of the stretch (a face balanced on a rim edge, lifted off the rim's face by
        // less than the separation but at one end), the middle shows no witness.
        let inset = ends.inset;
        if inset > 0.0 && e - s > 4.0 * inset {
            out.extend([x0 + d * (s + inset), x0 + d * (e - inset)]);
        }
    }
}

/// A small deterministic generator (SplitMix64): the same rotations on every run.
struct SplitMix(u64);

impl SplitMix {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactKind;
    use crate::examples::cube_and_slab;

    fn kinds(finds: &SliceFinds) -> Vec<(usize, ContactKind)> {
        let mut counts: Vec<(usize, ContactKind)> = Vec::new();
        for (state, _) in &finds.states {
            let kind = state[0].kind;
            assert_eq!(state.len(), 1, "a single contact: {state:?}");
            match counts.iter_mut().find(|(_, k)| *k == kind) {
                Some((n, _)) => *n += 1,
                None => counts.push((1, kind)),
            }
        }
        counts.sort_by_key(|(_, k)| *k);
        counts
    }

    /// Rotation pinned at a generic turn, the translations free enough to go all round:
    /// the states are the facets of the Minkowski difference of two boxes, a zonotope
    /// of six generators in general position, so 2·C(6,2) = 30 facets: a face of either
    /// box on a vertex of the other (6 + 6) and 18 pairs of crossing edges.
    #[test]
    fn a_pinned_generic_turn_shows_every_facet_of_the_two_boxes_zonotope() {
        let (slab, cube) = cube_and_slab();
        let (rx, ry, rz) = (0.3, 0.2, 0.1);
        let bounds = Bounds::try_new([-150.0, -150.0, -50.0, rx, ry, rz], [150.0, 150.0, 50.0, rx, ry, rz]).unwrap();
        let problem = Problem::new(&slab, &cube, bounds, DAffine3::IDENTITY);
        let finds = problem.states_in_slices(&bounds, Density::WIDE, false);
        assert_eq!(finds.slices, 1);
        assert_eq!(
            kinds(&finds),
            vec![
                (6, ContactKind::FaceVertex),
                (6, ContactKind::VertexFace),
                (18, ContactKind::EdgeEdge)
            ]
        );
        for (state, pose) in &finds.states {
            assert_eq!(problem.verify(pose).as_ref(), Some(state));
        }
    }

    /// The cube free to turn on the slab (small x, y bounds): its 26 states (DOMAIN
    /// section 8), each a corner, an edge or a face of the cube on the slab, found by
    /// the sweep alone: the corners at generic turns, the edges and faces at the
    /// alignments.
    #[test]
    fn the_sweep_alone_finds_the_26_states_of_a_cube_free_to_turn_on_a_slab() {
        let (slab, cube) = cube_and_slab();
        let pi = std::f64::consts::PI;
        let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -pi, -pi, -pi], [1.0, 1.0, 30.0, pi, pi, pi]).unwrap();
        let problem = Problem::new(&slab, &cube, bounds, DAffine3::IDENTITY);
        let finds = problem.states_in_slices(&bounds, Density::WIDE, false);
        assert_eq!(
            kinds(&finds),
            vec![
                (6, ContactKind::FaceFace),
                (12, ContactKind::FaceEdge),
                (8, ContactKind::FaceVertex)
            ]
        );
    }

    /// The cube lying flat on the slab, tilting up to 10° about x and y: from that one
    /// witness, the sweep near it finds the four states with an edge of the cube's
    /// bottom on the slab (DOMAIN section 8: 1 + 4 + 4 states in all). Those hold only
    /// where a tilt lays the edge exactly flat, which no random turn hits: they show
    /// where the sweep carries its turns onto the alignments kept at the seed.
    #[test]
    fn the_sweep_near_a_face_on_the_slab_finds_each_bottom_edge_on_the_slab() {
        let (slab, cube) = cube_and_slab();
        let tilt = 10f64.to_radians();
        let bounds = Bounds::try_new(
            [-1.0, -1.0, 0.0, -tilt, -tilt, -tilt],
            [1.0, 1.0, 30.0, tilt, tilt, tilt],
        )
        .unwrap();
        let problem = Problem::new(&slab, &cube, bounds, DAffine3::IDENTITY);
        let flat = Pose::from_array([0.0; 6]);
        let state = problem.verify(&flat).expect("flat on the slab");
        assert_eq!(state.len(), 1);
        assert_eq!(state[0].kind, ContactKind::FaceFace);
        let finds = problem.states_near(&[flat], false);
        let mut edges: Vec<PrincipalContact> = finds
            .states
            .iter()
            .filter(|(s, _)| s.len() == 1 && s[0].kind == ContactKind::FaceEdge)
            .map(|(s, _)| s[0])
            .collect();
        edges.sort();
        edges.dedup();
        assert_eq!(edges.len(), 4, "{edges:?}");
        for (state, pose) in &finds.states {
            assert_eq!(problem.verify(pose).as_ref(), Some(state));
            assert!(bounds.contains(pose, 1e-9, 1e-12), "{pose:?}");
        }
    }

    /// The box `[lo, hi]` as a difference: its six faces as facets (corners
    /// counter-clockwise seen from outside), those normal to z first: a region cut
    /// by the other facets first would be split by them anyway.
    /// The cube turned about x rests on its bottom edge along x, which lies on the slab
    /// only where ry and rz are exactly zero. A box of poses just off that (ry from
    /// 1e-3 to 2e-3 rad: the edge's ends stand 0.01 to 0.02 apart in height, far
    /// beyond the contact tolerance and the separation) shows the edge's lower corner
    /// on the slab at its own rotations; carried onto the edge's alignment with the
    /// slab, the edge itself.
    #[test]
    fn an_open_box_next_to_an_alignment_shows_the_state_that_needs_it() {
        let (slab, cube) = cube_and_slab();
        let bounds = Bounds::try_new([-1.0, -1.0, -1.0, 0.2, -0.01, 0.0], [1.0, 1.0, 1.0, 0.4, 0.01, 0.0]).unwrap();
        let problem = Problem::new(&slab, &cube, bounds, DAffine3::IDENTITY);
        let open = Bounds::try_new([0.0, 0.0, -0.05, 0.3, 1e-3, 0.0], [1.0, 1.0, 0.05, 0.31, 2e-3, 0.0]).unwrap();
        let top = ElementId::Face(FaceId(
            slab.faces()
                .iter()
                .position(|f| f.normal.z > 0.5)
                .expect("the slab's top") as u32,
        ));
        let edge = crate::testing::edge_between(&cube, DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0));
        let on_the_slab = vec![PrincipalContact {
            fixed: top,
            moving: edge,
            kind: ContactKind::FaceEdge,
        }];
        let own = problem.states_in_slices(&open, Density::LOCAL, false);
        assert!(!own.states.is_empty(), "the corner on the slab shows in the box");
        assert!(own.states.iter().all(|(s, _)| *s != on_the_slab), "{:?}", own.states);
        let carried = problem.states_in_open_box(&open, &on_the_slab, false);
        let (_, pose) = carried
            .states
            .iter()
            .find(|(s, _)| *s == on_the_slab)
            .expect("the edge on the slab at the aligned rotations");
        assert!(pose.ry.abs() < 1e-12 && pose.rz == 0.0, "{pose:?}");
        assert_eq!(problem.clean_state(pose), Some(on_the_slab));
    }

    /// The hexagonal peg tilted 0.0111 rad about x over its hole: its bottom face rests
    /// on the hole's front rim edge (e15) and its corner v0 on the wall f5. At this
    /// turn the face stands off the top face beside the rim by more than the
    /// separation only where the bounds' y = −1 ends the stretch where the two
    /// contacts' facets meet; its middle is too close to read as a witness. The sample
    /// just inside the stretch's end shows the state.
    #[test]
    fn a_state_robust_only_at_one_end_of_its_stretch_shows_next_to_that_end() {
        let (block, peg) = (
            crate::testing::fixture("block_with_hex_hole.off"),
            crate::testing::fixture("hex_peg.off"),
        );
        let (rx, tilt) = (-0.0111, 1f64.to_radians());
        let bounds = Bounds::try_new([-1.0, -1.0, 0.0, -tilt, -tilt, 0.0], [1.0, 1.0, 45.0, tilt, tilt, 0.0]).unwrap();
        let problem = Problem::new(&block, &peg, bounds, DAffine3::IDENTITY);
        let slice = Bounds::try_new([-1.0, -1.0, 0.0, rx, 0.0, 0.0], [1.0, 1.0, 45.0, rx, 0.0, 0.0]).unwrap();
        let mut balanced = vec![
            crate::testing::contact("f5", "v0", ContactKind::FaceVertex),
            crate::testing::contact("e15", "f2", ContactKind::EdgeFace),
        ];
        balanced.sort();
        let finds = problem.states_in_slices(&slice, Density::LOCAL, false);
        let (_, pose) = finds
            .states
            .iter()
            .find(|(s, _)| *s == balanced)
            .expect("the face balanced on the rim");
        assert!(pose.y < -0.98, "next to the bound y = -1: {pose:?}");
        assert_eq!(problem.clean_state(pose), Some(balanced));
    }

    /// The y of the samples on the line x = 1.5, z = 0 (where the wall of the tests'
    /// third box meets the top of their first), in order.
    fn ys_on_the_wall(samples: &[DVec3]) -> Vec<f64> {
        let mut ys: Vec<f64> = samples
            .iter()
            .filter(|p| (p.x - 1.5).abs() < 1e-12 && p.z.abs() < 1e-12)
            .map(|p| p.y)
            .collect();
        ys.sort_by(f64::total_cmp);
        ys
    }

    fn box_difference(lo: DVec3, hi: DVec3) -> Difference {
        let corner = |bits: [bool; 3]| {
            DVec3::new(
                if bits[0] { hi.x } else { lo.x },
                if bits[1] { hi.y } else { lo.y },
                if bits[2] { hi.z } else { lo.z },
            )
        };
        let mut facets = Vec::new();
        for k in [2, 0, 1] {
            for high in [false, true] {
                let normal = if high { DVec3::AXES[k] } else { -DVec3::AXES[k] };
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let mut polygon: Vec<DVec3> = [(false, false), (true, false), (true, true), (false, true)]
                    .iter()
                    .map(|&(a, b)| {
                        let mut bits = [false; 3];
                        bits[k] = high;
                        bits[i] = a;
                        bits[j] = b;
                        corner(bits)
                    })
                    .collect();
                if area(&polygon, normal) < 0.0 {
                    polygon.reverse();
                }
                let offset = normal.dot(polygon[0]);
                facets.push(Facet {
                    normal,
                    offset,
                    polygon,
                    contact: None,
                });
            }
        }
        Difference {
            facets,
            bounds: Aabb { min: lo, max: hi },
        }
    }

    /// Two boxes side by side under the plane z = 0, their tops in it and overlapping
    /// over [1, 2] in x: the top of the first is cut where the second's top begins, so
    /// that a sample lies on each top alone and one on both (before, the first top was
    /// one region, its centre on both). A third box whose side x = 1.5 meets the first
    /// top along a segment, over which the second's top lies from y = 1 on: that
    /// stretch is cut at y = 1 too, a sample on each side.
    #[test]
    fn coplanar_facets_of_other_differences_cut_the_regions_and_stretches_they_cover() {
        let tol = 1e-9;
        let first = || box_difference(DVec3::new(0.0, 0.0, -1.0), DVec3::new(2.0, 2.0, 0.0));
        let second = || box_difference(DVec3::new(1.0, 1.0, -1.0), DVec3::new(3.0, 3.0, 0.0));
        let top = |d: &Difference| d.facets.iter().find(|f| f.normal == DVec3::Z).unwrap().clone();
        let differences = [first(), second()];
        let regions = outside_others(&top(&differences[0]), 0, &differences, tol);
        let total: f64 = regions.iter().map(|r| area(r, DVec3::Z)).sum();
        assert!((total - 4.0).abs() < 1e-12, "the regions cover the top: {total}");
        let on_second = |p: DVec3| p.x > 1.0 && p.y > 1.0;
        let inside: Vec<bool> = regions.iter().map(|r| on_second(centroid(r))).collect();
        assert!(inside.contains(&true) && inside.contains(&false), "{regions:?}");
        for r in &regions {
            // No region straddles the second top's outline.
            let c = on_second(centroid(r));
            assert!(r.iter().all(|&p| on_second(p + (centroid(r) - p) * 1e-6) == c), "{r:?}");
        }

        // A side wall x = 1.5 of a third box, crossing the first top along y in [0, 2].
        let third = box_difference(DVec3::new(1.5, -1.0, -5.0), DVec3::new(4.0, 4.0, 5.0));
        let wall = third.facets.iter().find(|f| f.normal == -DVec3::X).unwrap().clone();
        let differences = [first(), second(), third];
        let on_segment = |inset: f64| {
            let mut out = Vec::new();
            let ends = Ends { every: false, inset };
            meeting_points(&top(&differences[0]), &wall, [0, 2], &differences, tol, ends, &mut out);
            ys_on_the_wall(&out)
        };
        let ys = on_segment(0.0);
        assert!(ys.iter().any(|&y| y > 0.0 && y < 1.0), "{ys:?}");
        assert!(ys.iter().any(|&y| y > 1.0 && y < 2.0), "{ys:?}");
        // The stretch y in [0, 2] is also read a quarter inside each end.
        let inset = on_segment(0.25);
        assert_eq!(inset.len(), ys.len() + 2, "{inset:?}");
        assert!(inset.contains(&0.25) && inset.contains(&1.75), "{inset:?}");
    }

    /// The region and the stretch of the test above, where the second top names the
    /// contact the first top names (two pieces of one face touching one vertex): the
    /// same state on both sides of the second top's outline, so the first top is one
    /// region and only the stretch's middle is sampled. Named otherwise, both are cut.
    #[test]
    fn a_coplanar_facet_showing_the_same_contact_does_not_cut_the_stretch() {
        let tol = 1e-9;
        let contact = |f: u32| Some((ElementId::Face(FaceId(f)), ElementId::Vertex(VertexId(0))));
        let named = |d: Difference, f: u32| Difference {
            facets: d
                .facets
                .into_iter()
                .map(|facet| Facet {
                    contact: if facet.normal == DVec3::Z { contact(f) } else { None },
                    ..facet
                })
                .collect(),
            ..d
        };
        // The first top names face 7; the second names `second_top`.
        let tops = |second_top: u32| {
            (
                named(box_difference(DVec3::new(0.0, 0.0, -1.0), DVec3::new(2.0, 2.0, 0.0)), 7),
                named(
                    box_difference(DVec3::new(1.0, 1.0, -1.0), DVec3::new(3.0, 3.0, 0.0)),
                    second_top,
                ),
            )
        };
        let samples_on_the_wall = |second_top: u32| {
            let (first, second) = tops(second_top);
            let third = box_difference(DVec3::new(1.5, -1.0, -5.0), DVec3::new(4.0, 4.0, 5.0));
            let top = first.facets.iter().find(|f| f.normal == DVec3::Z).unwrap().clone();
            let wall = third.facets.iter().find(|f| f.normal == -DVec3::X).unwrap().clone();
            let mut out = Vec::new();
            let ends = Ends {
                every: false,
                inset: 0.0,
            };
            meeting_points(&top, &wall, [0, 2], &[first, second, third], tol, ends, &mut out);
            ys_on_the_wall(&out)
        };
        let near = |ys: Vec<f64>, expected: &[f64]| {
            ys.len() == expected.len() && ys.iter().zip(expected).all(|(y, e)| (y - e).abs() < 1e-6)
        };
        let regions = |second_top: u32| {
            let (first, second) = tops(second_top);
            let top = first.facets.iter().find(|f| f.normal == DVec3::Z).unwrap().clone();
            outside_others(&top, 0, &[first, second], tol).len()
        };
        assert_eq!(regions(7), 1);
        assert!(regions(8) > 1);
        assert!(near(samples_on_the_wall(7), &[1.0]), "{:?}", samples_on_the_wall(7));
        assert!(
            near(samples_on_the_wall(8), &[0.5, 1.5]),
            "{:?}",
            samples_on_the_wall(8)
        );
    }

    /// The L-block's convex pieces name its faces: a face of a piece names the block's
    /// face in its plane when it lies wholly in it, a face split between two pieces is
    /// named by both, and a face left unnamed is one a cut between the pieces extends
    /// (the piece's face in its plane reaches off it).
    #[test]
    fn the_faces_of_the_l_blocks_pieces_name_the_blocks_faces() {
        let (block, _) = crate::examples::l_block_and_box();
        let eps = 1e-9 * block.bounds().diagonal();
        let mut named: std::collections::BTreeMap<ElementId, usize> = Default::default();
        let mut extended = Vec::new();
        for polytope in block.convex_pieces() {
            let piece = Piece::new(&block, polytope, &DAffine3::IDENTITY, eps);
            for &n in &piece.normals {
                let h = piece.support(n);
                let support: Vec<usize> = (0..piece.vertices.len())
                    .filter(|&i| n.dot(piece.vertices[i]) >= h - eps)
                    .collect();
                for (f, face) in block.faces().iter().enumerate() {
                    let id = ElementId::Face(FaceId(f as u32));
                    let in_plane = face.normal.dot(n) > 1.0 - 1e-12 && (face.offset - h).abs() <= eps;
                    if in_plane && support.iter().any(|&i| !piece.holders[i].contains(&id)) {
                        extended.push(id);
                    }
                }
                match common_element(&piece.holders, &support) {
                    Some(ElementId::Face(f)) => {
                        let face = block.face(f);
                        assert!(face.normal.dot(n) > 1.0 - 1e-12 && (face.offset - h).abs() <= eps);
                        *named.entry(ElementId::Face(f)).or_default() += 1;
                    }
                    Some(other) => panic!("a piece's face names {other:?}"),
                    // A cut between pieces: its corners lie on several faces.
                    None => {}
                }
            }
        }
        for f in 0..block.faces().len() {
            let id = ElementId::Face(FaceId(f as u32));
            assert!(named.contains_key(&id) || extended.contains(&id), "{id:?}: {named:?}");
        }
        assert!(named.values().any(|&k| k == 2), "{named:?}");
    }

    #[test]
    fn arcs_cross_where_their_great_circles_meet_inside_both() {
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let n = arcs_cross(x, y, (x + y - z).normalize(), (x + y + z).normalize()).expect("they cross");
        assert!(n.abs_diff_eq((x + y).normalize(), 1e-12), "{n}");
        // Arcs on the same great circle, or apart, do not.
        assert!(arcs_cross(x, y, -x, -y).is_none());
        assert!(arcs_cross(x, (x + z).normalize(), y, (y + z).normalize()).is_none());
    }

    #[test]
    fn a_state_that_holds_only_by_the_grace_of_the_tolerance_shows_in_a_sliver_slice() {
        use crate::testing::{contact, fixture};
        // The square peg turned in the chamfered hole (rx pinned at 0): its bottom
        // corner v0 on the left chamfer f5 and its front right edge e8 lying in the
        // hole's front wall f9. With R z = (cos rz sin ry, sin rz sin ry, cos ry), e8
        // lies in the wall only while sin rz sin ry is within the contact tolerance over
        // its length (80 mm); the bottom edge e1 from v0 rises off the chamfer only
        // while -rz is above the loose tolerance over its (28 mm); e8 reaches below the
        // wall's top only while ry tilts it down past v0's height. Exactly, a product
        // of two turns vanishes and neither turn does: no pose. Within the tolerance, a
        // sliver about (ry, rz) = (5e-5, -2e-5), narrower than the halving's floor.
        let (hole, peg) = (fixture("block_with_chamfered_hole.off"), fixture("peg.off"));
        let d = std::f64::consts::PI / 180.0;
        let bounds =
            Bounds::try_new([-2.0, -2.0, 0.0, 0.0, -2.0 * d, -d], [2.0, 2.0, 45.0, 0.0, 2.0 * d, d]).expect("bounds");
        let problem = Problem::new(&hole, &peg, bounds, DAffine3::IDENTITY);
        let mut target = vec![
            contact("f5", "v0", ContactKind::FaceVertex),
            contact("f9", "e8", ContactKind::FaceEdge),
        ];
        target.sort();
        // By hand: v0 at x = 35 - inset on the chamfer (x + z = 80), v4 (e8's foot) on
        // the wall's plane y = 35.
        let by_hand = |ry: f64, rz: f64, inset: f64| {
            let rotation = DMat3::from_rotation_z(rz) * DMat3::from_rotation_y(ry);
            let (v0, v4) = (
                rotation * DVec3::new(36.0, 36.0, 10.0),
                rotation * DVec3::new(64.0, 36.0, 10.0),
            );
            let x = 35.0 - inset;
            Pose::from_array([x - v0.x, 35.0 - v4.y, 80.0 - x - v0.z, 0.0, ry, rz])
        };
        let witnessed = |pose: Pose| {
            let placement = pose.to_affine(&DAffine3::IDENTITY);
            let report = problem.scene().evaluate(&placement, crate::tolerance::CONTACT_REL);
            crate::testing::witnesses(problem.scene(), &placement, &report, &target)
        };
        assert!(witnessed(by_hand(5e-5, -2e-5, 3e-4)));
        assert!(witnessed(by_hand(3e-5, -3e-5, 5e-4)));
        // Either turn alone, or the product ten times larger: no witness.
        for (ry, rz) in [(5e-5, 0.0), (0.0, -2e-5), (5e-5, -2e-4), (5e-4, -2e-5)] {
            assert!(!witnessed(by_hand(ry, rz, 3e-4)), "{ry} {rz}");
        }
        // The last proofs' conditions never exclude a witness; the slices at the sliver's
        // rotations find the state, each with a verified witness.
        let x = by_hand(5e-5, -2e-5, 3e-4).to_array();
        assert_eq!(
            problem.last_exclusion(&target, &Bounds::try_new(x, x).expect("a point")),
            None
        );
        let finds = problem.states_in_slivers(std::slice::from_ref(&target), false);
        let (_, pose) = finds[0]
            .states
            .iter()
            .find(|(state, _)| *state == target)
            .expect("the sliver's state");
        assert!(witnessed(*pose));
    }
}
