//! A recall oracle by rotation slices (docs/concepts.md#ground-truth).
//!
//! For a fixed rotation R, B touches A without penetrating exactly at the translations
//! t on the boundary of U = ∪ M_ij, M_ij = P_i ⊕ (−R Q_j), over the convex pieces P_i
//! of A and Q_j of B. Each M_ij is built here from its point set p − R q (facet normals:
//! the pieces' face normals, B's turned by R, and cross products of the pieces' edge
//! directions; the facets found must close). On each slice the oracle samples
//! 1. one point inside every cell of every facet clipped to the translation box, the
//!    cells cut out by the traces of the other M's boundaries on the facet's plane;
//! 2. one point inside every piece of the segments where facets of two different M's
//!    meet, the pieces cut where the segment enters or leaves a third M;
//! 3. the points where three facets meet, at least two of them from different M's (the
//!    cut points of step 2 and the segments' own ends);
//!
//! and keeps the samples on ∂U inside the translation bounds: inside no M, with free
//! space next to them (a probe pushed out of every facet they lie on is inside none).
//! P(X) is read there by the independent evaluator of `common::principal`; robust
//! states without a degenerate contact must all be in the generated graph.
//!
//! The slices (`rotation_slices`) are the rotations where contacts of higher kinematic
//! level live (identity, single-axis turns, bound corners, a face of B antiparallel to a
//! face of A, an edge parallel to a face, an edge parallel to a concave edge) plus
//! seeded random ones: in the bounds, on their faces and edges, and in the bounds shrunk
//! about their centre.
//!
//! The pieces come from `Part::convex_pieces`, but only after their volumes and first
//! moments, from hulls built here, add up to the part's own, integrated from its faces.

use std::collections::{BTreeMap, HashSet};
use std::f64::consts::{PI, TAU};
use std::time::{Duration, Instant};

use acsg::contact::PrincipalContact;
use acsg::model::Part;
use acsg::pose::{Bounds, Pose};
use glam::{DMat3, DVec2, DVec3};
use rayon::prelude::*;

use super::hull::{Rng, hull_facets};
use super::principal::{Evaluator, TOUCH_REL, Verdict};

/// A sample lies at least this far (relative to L) inside its cell of a facet, or from
/// the ends of its piece of segment, so that nearby contacts are clearly made or broken.
pub const SAMPLE_MARGIN_REL: f64 = 5e-6;

/// How far (relative to L) a sample is pushed out of every facet it lies on to check
/// that free space is there (it is not a seam between two M's glued face to face).
pub const PROBE_REL: f64 = 1e-7;

/// Differences p − R q within this distance (relative to L) of a support plane count as
/// on it: far above round-off, far below the slivers of nearly aligned rotations (whose
/// facets, lumped by a coarser tolerance, would overlap).
pub const FACET_REL: f64 = 1e-11;

/// The relative tolerance for piece volumes and moments against the part's.
pub const PIECES_REL: f64 = 1e-9;

// ---------------------------------------------------------------------------------
// Convex pieces, checked
// ---------------------------------------------------------------------------------

/// A convex piece as the oracle uses it: its corners, face normals and edge directions,
/// all from a hull built here.
#[derive(Clone, Debug)]
pub struct Piece {
    pub points: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub edge_directions: Vec<DVec3>,
    pub volume: f64,
    /// ∫ x dV over the piece.
    pub moment: DVec3,
}

/// The piece spanned by `points`: its hull's facets, edges, volume and first moment.
pub fn piece_from_points(points: &[DVec3], eps: f64) -> Piece {
    let facets = hull_facets(points, eps);
    let mut normals = Vec::new();
    let mut polygons = Vec::new();
    for (n, _, on) in &facets {
        let on_points: Vec<DVec3> = on.iter().map(|&i| points[i]).collect();
        normals.push(*n);
        polygons.push(convex_polygon(&on_points, *n, eps));
    }
    let mut edge_directions: Vec<DVec3> = Vec::new();
    for i in 0..facets.len() {
        for j in i + 1..facets.len() {
            let shared = facets[i].2.iter().filter(|k| facets[j].2.contains(k)).count();
            let d = facets[i].0.cross(facets[j].0);
            if shared >= 2 && d.length() > 1e-9 {
                push_direction(&mut edge_directions, d.normalize());
            }
        }
    }
    // Volume and moment from tetrahedra joining an inner point to the facets.
    let inner = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let (mut volume, mut moment) = (0.0, DVec3::ZERO);
    for poly in &polygons {
        for k in 1..poly.len().saturating_sub(1) {
            let (a, b, c) = (poly[0], poly[k], poly[k + 1]);
            let v = (a - inner).dot((b - inner).cross(c - inner)) / 6.0;
            volume += v;
            moment += v * (inner + a + b + c) / 4.0;
        }
    }
    Piece {
        points: points.to_vec(),
        normals,
        edge_directions,
        volume,
        moment,
    }
}

/// The part's volume and first moment by the divergence theorem over its face loops
/// (outer loops counter-clockwise seen from outside, holes clockwise, so a fan of every
/// loop adds up with signs): V = Σ a·(b×c)/6, ∫x_k dV = Σ N_k (a_k² + b_k² + c_k² +
/// a_k b_k + b_k c_k + c_k a_k) / 24 with N = (b−a)×(c−a).
pub fn part_volume_and_moment(part: &Part) -> (f64, DVec3) {
    let (mut volume, mut moment) = (0.0, DVec3::ZERO);
    for f in part.faces() {
        for l in &f.loops {
            let p: Vec<DVec3> = l.vertices.iter().map(|v| part.vertex(*v).position).collect();
            for k in 1..p.len() - 1 {
                let (a, b, c) = (p[0], p[k], p[k + 1]);
                let n = (b - a).cross(c - a);
                volume += a.dot(b.cross(c)) / 6.0;
                let s = a * a + b * b + c * c + a * b + b * c + c * a;
                moment += n * s / 24.0;
            }
        }
    }
    (volume, moment)
}

/// The part's convex pieces, each rebuilt from its corners, after checking that their
/// volumes and moments add up to the part's (to `PIECES_REL`).
pub fn checked_pieces(part: &Part) -> Result<Vec<Piece>, String> {
    let scale = part.bounds().diagonal();
    let pieces: Vec<Piece> = part
        .convex_pieces()
        .iter()
        .map(|p| piece_from_points(p.vertices(), 1e-9 * scale))
        .collect();
    check_pieces(part, pieces)
}

/// `pieces`, when their volumes and first moments add up to the part's (to
/// `PIECES_REL`) and none is flat.
pub fn check_pieces(part: &Part, pieces: Vec<Piece>) -> Result<Vec<Piece>, String> {
    let scale = part.bounds().diagonal();
    let (volume, moment) = part_volume_and_moment(part);
    let sum_volume: f64 = pieces.iter().map(|p| p.volume).sum();
    let sum_moment: DVec3 = pieces.iter().map(|p| p.moment).sum();
    if (sum_volume - volume).abs() > PIECES_REL * volume.abs() {
        return Err(format!(
            "{}: the {} convex pieces hold volume {sum_volume}, the part {volume}",
            part.name(),
            pieces.len()
        ));
    }
    if (sum_moment - moment).length() > PIECES_REL * volume.abs() * scale {
        return Err(format!(
            "{}: the convex pieces' first moment {sum_moment} differs from the part's {moment}",
            part.name()
        ));
    }
    if pieces.iter().any(|p| p.volume <= 0.0 || p.normals.len() < 4) {
        return Err(format!("{}: a convex piece is flat", part.name()));
    }
    Ok(pieces)
}

/// Adds a unit direction to a list of directions up to sign, unless already there.
fn push_direction(list: &mut Vec<DVec3>, d: DVec3) {
    if !list.iter().any(|e| e.cross(d).length() < 1e-12) {
        list.push(d);
    }
}

/// The convex hull of coplanar points, counter-clockwise about `normal`, by gift
/// wrapping with a tolerance: points within `eps` of a hull edge's line count as on it,
/// and the farthest of those is taken, so round-off in nearly collinear points (which
/// upsets sorting-based hulls) cannot drop a corner.
pub fn convex_polygon(points: &[DVec3], normal: DVec3, eps: f64) -> Vec<DVec3> {
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let mut pts: Vec<(DVec2, DVec3)> = Vec::new();
    for p in points {
        let q = DVec2::new(p.dot(u), p.dot(v));
        if !pts.iter().any(|(r, _)| r.distance(q) <= eps) {
            pts.push((q, *p));
        }
    }
    if pts.len() < 3 {
        return pts.iter().map(|p| p.1).collect();
    }
    let start = (0..pts.len())
        .min_by(|&i, &j| {
            pts[i]
                .0
                .x
                .total_cmp(&pts[j].0.x)
                .then(pts[i].0.y.total_cmp(&pts[j].0.y))
        })
        .unwrap_or(0);
    let mut hull = vec![start];
    let mut current = start;
    for _ in 0..pts.len() {
        let c = pts[current].0;
        let mut next = if current == 0 { 1 } else { 0 };
        for j in 0..pts.len() {
            if j == current || j == next {
                continue;
            }
            let (e, w) = (pts[next].0 - c, pts[j].0 - c);
            // How far j lies left of the line current → next.
            let left = e.perp_dot(w) / e.length();
            if left < -eps || (left.abs() <= eps && w.length() > e.length()) {
                next = j;
            }
        }
        // Back at a corner already taken (the start, or the corner after it when the
        // start lies inside a hull edge): the cycle from there is the hull.
        if let Some(pos) = hull.iter().position(|&h| h == next) {
            hull.drain(..pos);
            break;
        }
        hull.push(next);
        current = next;
    }
    hull.into_iter().map(|i| pts[i].1).collect()
}

// ---------------------------------------------------------------------------------
// Minkowski differences
// ---------------------------------------------------------------------------------

/// A facet of a Minkowski difference: its plane n·x = h and its polygon,
/// counter-clockwise about n.
#[derive(Clone, Debug)]
pub struct Facet {
    pub normal: DVec3,
    pub offset: f64,
    pub polygon: Vec<DVec3>,
}

/// M = P ⊕ (−R Q) for one pair of pieces at one rotation.
#[derive(Clone, Debug)]
pub struct Minkowski {
    pub fixed_piece: usize,
    pub moving_piece: usize,
    pub facets: Vec<Facet>,
    pub lo: DVec3,
    pub hi: DVec3,
}

impl Minkowski {
    /// max over facets of n·x − h: negative inside (minus the distance to the
    /// boundary), positive outside.
    pub fn depth(&self, x: DVec3) -> f64 {
        self.facets
            .iter()
            .map(|f| f.normal.dot(x) - f.offset)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Builds P ⊕ (−R Q) from its point set: a candidate direction n is a facet normal when
/// at least three non-collinear differences reach the support value h(n) (within a
/// tolerance). The facets found must close (their vector areas cancel), else a missing
/// or lumped facet is suspected: the tolerance is tried at `FACET_REL · scale`, then
/// finer (nearly aligned rotations make slivers), then coarser; `None` when none closes.
pub fn minkowski_difference(p: &Piece, q: &Piece, r: DMat3, scale: f64) -> Option<Minkowski> {
    for tol in [FACET_REL, FACET_REL * 1e-2, FACET_REL * 1e2].map(|rel| rel * scale) {
        let facets = minkowski_facets(p, q, r, tol);
        let total_area: f64 = facets.iter().map(|f| vector_area(&f.polygon).length()).sum();
        let closure: DVec3 = facets.iter().map(|f| vector_area(&f.polygon)).sum();
        if closure.length() > 1e-7 * total_area {
            continue;
        }
        let (lo, hi) = facets.iter().flat_map(|f| f.polygon.iter()).fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), d| (lo.min(*d), hi.max(*d)),
        );
        return Some(Minkowski {
            fixed_piece: 0,
            moving_piece: 0,
            facets,
            lo,
            hi,
        });
    }
    None
}

/// The facets of P ⊕ (−R Q), unchecked.
pub fn minkowski_facets(p: &Piece, q: &Piece, r: DMat3, tol: f64) -> Vec<Facet> {
    let turned: Vec<DVec3> = q.points.iter().map(|x| r * *x).collect();
    let diffs: Vec<DVec3> = p
        .points
        .iter()
        .flat_map(|a| turned.iter().map(move |b| *a - *b))
        .collect();
    let mut candidates: Vec<DVec3> = p.normals.clone();
    candidates.extend(q.normals.iter().map(|n| -(r * *n)));
    for ea in &p.edge_directions {
        for eb in &q.edge_directions {
            let c = ea.cross(r * *eb);
            if c.length() > 1e-9 {
                candidates.push(c.normalize());
                candidates.push(-c.normalize());
            }
        }
    }
    let mut facets: Vec<Facet> = Vec::new();
    let mut seen: Vec<Vec<usize>> = Vec::new();
    for n in candidates {
        let h = diffs.iter().map(|d| n.dot(*d)).fold(f64::NEG_INFINITY, f64::max);
        let on: Vec<usize> = (0..diffs.len()).filter(|&i| n.dot(diffs[i]) >= h - tol).collect();
        if on.len() < 3 || seen.contains(&on) {
            continue;
        }
        let points: Vec<DVec3> = on.iter().map(|&i| diffs[i]).collect();
        let polygon = convex_polygon(&points, n, tol);
        if polygon.len() < 3 {
            continue; // collinear: an edge of M, not a facet
        }
        seen.push(on);
        facets.push(Facet {
            normal: n,
            offset: h,
            polygon,
        });
    }
    facets
}

/// The vector area (area times unit normal, by the winding) of a polygon.
pub fn vector_area(poly: &[DVec3]) -> DVec3 {
    let mut s = DVec3::ZERO;
    for k in 1..poly.len().saturating_sub(1) {
        s += (poly[k] - poly[0]).cross(poly[k + 1] - poly[0]);
    }
    s * 0.5
}

// ---------------------------------------------------------------------------------
// Convex polygons cut by planes
// ---------------------------------------------------------------------------------

/// The part of a convex polygon where n·x ≤ h.
fn clip(poly: &[DVec3], n: DVec3, h: f64) -> Vec<DVec3> {
    split(poly, n, h).0
}

/// A convex polygon cut by the plane n·x = h into its parts below and above.
fn split(poly: &[DVec3], n: DVec3, h: f64) -> (Vec<DVec3>, Vec<DVec3>) {
    let side: Vec<f64> = poly.iter().map(|p| n.dot(*p) - h).collect();
    if side.iter().all(|&s| s <= 0.0) {
        return (poly.to_vec(), Vec::new());
    }
    if side.iter().all(|&s| s >= 0.0) {
        return (Vec::new(), poly.to_vec());
    }
    let (mut below, mut above) = (Vec::new(), Vec::new());
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        let (p, q, sp, sq) = (poly[i], poly[j], side[i], side[j]);
        if sp <= 0.0 {
            below.push(p);
        }
        if sp >= 0.0 {
            above.push(p);
        }
        if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
            let x = p + (q - p) * (sp / (sp - sq));
            below.push(x);
            above.push(x);
        }
    }
    (below, above)
}

/// The vertex average of a convex polygon and its distance to the nearest edge line.
fn inner_point(poly: &[DVec3], normal: DVec3) -> (DVec3, f64) {
    let c = poly.iter().copied().sum::<DVec3>() / poly.len() as f64;
    let mut margin = f64::INFINITY;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let e = b - a;
        if e.length() > 1e-300 {
            margin = margin.min((e.cross(c - a)).dot(normal).abs() / e.length());
        }
    }
    (c, margin)
}

/// The parameter interval of the line x0 + s d inside every half-space n·x ≤ h, with
/// the half-spaces that bound it; half-spaces parallel to the line hold within `tol`.
fn clip_line(
    x0: DVec3,
    d: DVec3,
    planes: impl Iterator<Item = (DVec3, f64)>,
    tol: f64,
) -> Option<(f64, f64, usize, usize)> {
    let (mut lo, mut hi, mut lo_plane, mut hi_plane) = (f64::NEG_INFINITY, f64::INFINITY, usize::MAX, usize::MAX);
    for (k, (n, h)) in planes.enumerate() {
        let (a, b) = (n.dot(d), h - n.dot(x0));
        if a.abs() < 1e-12 {
            if b < -tol {
                return None;
            }
        } else if a > 0.0 {
            if b / a < hi {
                hi = b / a;
                hi_plane = k;
            }
        } else if b / a > lo {
            lo = b / a;
            lo_plane = k;
        }
    }
    (lo < hi).then_some((lo, hi, lo_plane, hi_plane))
}

// ---------------------------------------------------------------------------------
// Rotation slices
// ---------------------------------------------------------------------------------

/// One fixed rotation, as pose angles (rx, ry, rz) in radians, and why it was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    pub angles: [f64; 3],
    pub why: String,
}

/// Which rotations to slice at.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceOptions {
    /// Seeded pseudo-random rotations in the bounds.
    pub random: usize,
    /// Seeded pseudo-random rotations on each face of the box of rotation bounds (one
    /// angle at a bound), and on each of its edges (two angles at bounds): states that
    /// need a turn as large as allowed live there.
    pub random_on_faces: usize,
    pub random_on_edges: usize,
    /// Seeded pseudo-random rotations in the bounds shrunk about their centre by each
    /// of these factors, this many per factor: a part in a tight hole only turns a
    /// little before it jams.
    pub shrunk: Vec<f64>,
    pub random_shrunk: usize,
    pub seed: u64,
    /// Rotations put on each "edge parallel to a face" constraint, projected from the
    /// bounds' centre, identity and this many random rotations.
    pub projections: usize,
    /// On each one-parameter family (a face of B antiparallel to a face of A, a concave
    /// edge parallel to an edge), also the rotations where an edge turns parallel to a
    /// face.
    pub family_roots: bool,
}

impl Default for SliceOptions {
    fn default() -> SliceOptions {
        SliceOptions {
            random: 1000,
            random_on_faces: 40,
            random_on_edges: 20,
            shrunk: vec![0.1, 0.01, 0.001],
            random_shrunk: 200,
            seed: 0x5eed_ac59,
            projections: 10,
            family_roots: true,
        }
    }
}

/// The rotation R = Rz(rz) Ry(ry) Rx(rx) of pose angles, as the library builds it.
pub fn rotation_of(angles: [f64; 3]) -> DMat3 {
    Pose::from_array([0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]).rotation()
}

/// Pose angles (rx, ry, rz) of a rotation, with ry in [−π/2, π/2].
pub fn angles_of(m: DMat3) -> [f64; 3] {
    // Row i, column j of R is m.col(j)[i].
    let (r00, r10, r20) = (m.x_axis.x, m.x_axis.y, m.x_axis.z);
    let (r21, r22) = (m.y_axis.z, m.z_axis.z);
    [r21.atan2(r22), (-r20).atan2(r21.hypot(r22)), r10.atan2(r00)]
}

fn angle_bounds(bounds: &Bounds) -> ([f64; 3], [f64; 3]) {
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    ([lo[3], lo[4], lo[5]], [hi[3], hi[4], hi[5]])
}

fn angles_in_bounds(a: [f64; 3], bounds: &Bounds) -> bool {
    let (lo, hi) = angle_bounds(bounds);
    (0..3).all(|i| a[i] >= lo[i] && a[i] <= hi[i])
}

/// An upper bound on the rotation angle of any rotation in the bounds.
fn largest_turn(bounds: &Bounds) -> f64 {
    let (lo, hi) = angle_bounds(bounds);
    (0..3).map(|i| lo[i].abs().max(hi[i].abs())).sum::<f64>().min(PI)
}

/// The smallest rotation taking unit `u` to unit `w`.
fn rotation_between(u: DVec3, w: DVec3) -> DMat3 {
    let axis = u.cross(w);
    if axis.length() < 1e-15 {
        if u.dot(w) > 0.0 {
            return DMat3::IDENTITY;
        }
        return DMat3::from_axis_angle(u.any_orthonormal_vector(), PI);
    }
    DMat3::from_axis_angle(axis.normalize(), axis.length().atan2(u.dot(w)))
}

/// A rotation near `base` with (R u)·w = 0: `base` turned about (base u) × w.
fn project_to_perpendicular(u: DVec3, w: DVec3, base: DMat3) -> Option<DMat3> {
    let x = base * u;
    let axis = x.cross(w);
    if axis.length() < 1e-12 {
        return None;
    }
    let r = DMat3::from_axis_angle(axis.normalize(), -x.dot(w).clamp(-1.0, 1.0).asin()) * base;
    ((r * u).dot(w).abs() < 1e-12).then_some(r)
}

/// Unit directions of a part: signed face normals, unsigned edge directions, unsigned
/// directions of its concave edges.
fn part_directions(part: &Part) -> (Vec<DVec3>, Vec<DVec3>, Vec<DVec3>) {
    let mut normals: Vec<DVec3> = Vec::new();
    for f in part.faces() {
        if !normals.iter().any(|n| n.distance(f.normal) < 1e-12) {
            normals.push(f.normal);
        }
    }
    let (mut edges, mut concave) = (Vec::new(), Vec::new());
    for e in part.edges() {
        let [a, b] = e.vertices.map(|v| part.vertex(v).position);
        let d = (b - a).normalize();
        push_direction(&mut edges, d);
        if !e.convex {
            push_direction(&mut concave, d);
        }
    }
    (normals, edges, concave)
}

/// A one-parameter family of rotations R(φ) = Rot(w, φ) · R0 with R u = w.
struct Family {
    u: DVec3,
    w: DVec3,
    r0: DMat3,
}

impl Family {
    fn at(&self, phi: f64) -> DMat3 {
        DMat3::from_axis_angle(self.w, phi) * self.r0
    }

    fn angles(&self, phi: f64) -> [f64; 3] {
        angles_of(self.at(phi))
    }
}

/// Bisection between an in-bounds `inside` and an out-of-bounds `outside` parameter,
/// returning a parameter in bounds next to the boundary.
fn bisect_bounds(family: &Family, bounds: &Bounds, mut inside: f64, mut outside: f64) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (inside + outside);
        if angles_in_bounds(family.angles(mid), bounds) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    inside
}

/// Points of a family in bounds: per run of the parameter in bounds its two ends, its
/// middle, the point nearest the bounds' centre, and (with `roots`) where one of
/// `perpendiculars` (u', w') gets (R u')·w' = 0.
fn family_points(family: &Family, bounds: &Bounds, perpendiculars: &[(DVec3, DVec3)], roots: bool) -> Vec<f64> {
    const STEPS: usize = 7200;
    let step = TAU / STEPS as f64;
    let phi = |k: usize| -PI + k as f64 * step;
    let inside: Vec<bool> = (0..STEPS)
        .map(|k| angles_in_bounds(family.angles(phi(k)), bounds))
        .collect();
    if !inside.iter().any(|&x| x) {
        return Vec::new();
    }
    let (lo, hi) = angle_bounds(bounds);
    let centre_distance = |a: [f64; 3]| {
        (0..3)
            .map(|i| {
                let w = (hi[i] - lo[i]).max(1e-12);
                ((a[i] - 0.5 * (lo[i] + hi[i])) / w).powi(2)
            })
            .sum::<f64>()
    };
    let mut out = Vec::new();
    // Runs of consecutive in-bounds steps (cyclic): start where the previous is out.
    let starts: Vec<usize> = (0..STEPS)
        .filter(|&k| inside[k] && !inside[(k + STEPS - 1) % STEPS])
        .collect();
    let runs: Vec<Vec<usize>> = if starts.is_empty() {
        vec![(0..STEPS).collect()]
    } else {
        starts
            .iter()
            .map(|&s| {
                let mut run = vec![s];
                while inside[(run[run.len() - 1] + 1) % STEPS] {
                    run.push((run[run.len() - 1] + 1) % STEPS);
                }
                run
            })
            .collect()
    };
    for run in runs {
        // Unwrapped parameters along the run.
        let first = phi(run[0]);
        let params: Vec<f64> = (0..run.len()).map(|i| first + i as f64 * step).collect();
        let (a, b) = (params[0], params[params.len() - 1]);
        if !starts.is_empty() {
            out.push(bisect_bounds(family, bounds, a, a - step));
            out.push(bisect_bounds(family, bounds, b, b + step));
        }
        out.push(0.5 * (a + b));
        let best = params
            .iter()
            .copied()
            .min_by(|x, y| centre_distance(family.angles(*x)).total_cmp(&centre_distance(family.angles(*y))))
            .unwrap_or(a);
        out.push(best);
        if roots {
            for (u, w) in perpendiculars {
                let g = |x: f64| (family.at(x) * *u).dot(*w);
                // A constraint that holds all along the family adds nothing.
                if params.iter().all(|&x| g(x).abs() < 1e-9) {
                    continue;
                }
                for pair in params.windows(2) {
                    let (mut x0, mut x1) = (pair[0], pair[1]);
                    let (g0, g1) = (g(x0), g(x1));
                    if g0 == 0.0 {
                        out.push(x0);
                    } else if g0 * g1 < 0.0 {
                        let s0 = g0.signum();
                        for _ in 0..60 {
                            let m = 0.5 * (x0 + x1);
                            if g(m).signum() == s0 {
                                x0 = m;
                            } else {
                                x1 = m;
                            }
                        }
                        out.push(0.5 * (x0 + x1));
                    }
                }
            }
        }
    }
    out.retain(|&x| angles_in_bounds(family.angles(x), bounds));
    out
}

/// The rotations to slice at for parts `a` (fixed) and `b` (moving) within `bounds`.
pub fn rotation_slices(a: &Part, b: &Part, bounds: &Bounds, options: &SliceOptions) -> Vec<Slice> {
    let (lo, hi) = angle_bounds(bounds);
    let mut slices: Vec<Slice> = Vec::new();
    let add = |angles: [f64; 3], why: String, slices: &mut Vec<Slice>| {
        if angles_in_bounds(angles, bounds)
            && !slices
                .iter()
                .any(|s| (0..3).all(|i| (s.angles[i] - angles[i]).abs() < 1e-12))
        {
            slices.push(Slice { angles, why });
        }
    };
    // Identity (or the centre when identity is out), single-axis turns, corners.
    let rest = |i: usize| {
        if lo[i] <= 0.0 && hi[i] >= 0.0 {
            0.0
        } else {
            0.5 * (lo[i] + hi[i])
        }
    };
    let base = [rest(0), rest(1), rest(2)];
    add(base, "identity".into(), &mut slices);
    for i in 0..3 {
        for value in [lo[i], hi[i], 0.5 * lo[i], 0.5 * hi[i]] {
            let mut angles = base;
            angles[i] = value;
            add(
                angles,
                format!("single-axis turn {}={value:.6}", ["rx", "ry", "rz"][i]),
                &mut slices,
            );
        }
    }
    for corner in 0..8 {
        let angles = std::array::from_fn(|i| if corner >> i & 1 == 1 { hi[i] } else { lo[i] });
        add(angles, format!("bound corner {corner}"), &mut slices);
    }

    let turn = largest_turn(bounds);
    let (normals_a, edges_a, concave_a) = part_directions(a);
    let (normals_b, edges_b, concave_b) = part_directions(b);
    // (R u)·w = 0: an edge of B parallel to a face of A, or a face of B parallel to an
    // edge of A; reachable when u·w is within the largest turn of 0.
    let mut perpendiculars: Vec<(DVec3, DVec3)> = Vec::new();
    let pairs = edges_b
        .iter()
        .flat_map(|u| normals_a.iter().map(move |w| (*u, *w)))
        .chain(normals_b.iter().flat_map(|u| edges_a.iter().map(move |w| (*u, *w))));
    for (u, w) in pairs {
        let known = perpendiculars
            .iter()
            .any(|(x, y)| x.cross(u).length() < 1e-12 && y.cross(w).length() < 1e-12);
        if !known && u.dot(w).abs() <= turn.sin() + 1e-12 {
            perpendiculars.push((u, w));
        }
    }
    // R u = w: a face of B antiparallel to a face of A, or an edge parallel to a concave
    // edge (either way round); reachable when the angle between them is within the turn.
    let mut families: Vec<(DVec3, DVec3, String)> = Vec::new();
    for (i, nb) in normals_b.iter().enumerate() {
        for (j, na) in normals_a.iter().enumerate() {
            families.push((*nb, -*na, format!("B normal {i} antiparallel to A normal {j}")));
        }
    }
    let concave_pairs = edges_b
        .iter()
        .flat_map(|u| concave_a.iter().map(move |w| (*u, *w)))
        .chain(concave_b.iter().flat_map(|u| edges_a.iter().map(move |w| (*u, *w))));
    for (u, w) in concave_pairs {
        families.push((u, w, "edge parallel to a concave edge".into()));
        families.push((u, -w, "edge parallel to a concave edge".into()));
    }
    for (u, w, why) in families {
        if u.dot(w).clamp(-1.0, 1.0).acos() > turn + 1e-12 {
            continue;
        }
        let family = Family {
            u,
            w,
            r0: rotation_between(u, w),
        };
        debug_assert!((family.at(0.3) * family.u).distance(family.w) < 1e-12);
        for phi in family_points(&family, bounds, &perpendiculars, options.family_roots) {
            add(angles_of(family.at(phi)), format!("{why}, φ={phi:.6}"), &mut slices);
        }
    }
    // Edge-parallel-to-face rotations projected from a few base rotations.
    let mut rng = Rng::new(options.seed);
    let random_angles = |rng: &mut Rng| std::array::from_fn(|i| rng.range(lo[i], hi[i]));
    let centre = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
    let mut bases: Vec<[f64; 3]> = vec![centre, base];
    bases.extend((0..options.projections).map(|_| random_angles(&mut rng)));
    for (k, (u, w)) in perpendiculars.iter().enumerate() {
        for start in &bases {
            if let Some(r) = project_to_perpendicular(*u, *w, rotation_of(*start)) {
                add(angles_of(r), format!("edge parallel to a face ({k})"), &mut slices);
            }
        }
    }
    for k in 0..options.random {
        add(random_angles(&mut rng), format!("random {k}"), &mut slices);
    }
    for &factor in &options.shrunk {
        for k in 0..options.random_shrunk {
            let a: [f64; 3] = random_angles(&mut rng);
            let angles = std::array::from_fn(|i| centre[i] + factor * (a[i] - centre[i]));
            add(
                angles,
                format!("random in the bounds shrunk by {factor} {k}"),
                &mut slices,
            );
        }
    }
    let bound = |i: usize, side: usize| if side == 0 { lo[i] } else { hi[i] };
    for i in 0..3 {
        for side in 0..2 {
            for k in 0..options.random_on_faces {
                let mut angles = random_angles(&mut rng);
                angles[i] = bound(i, side);
                add(angles, format!("random on a bound face {k}"), &mut slices);
            }
        }
    }
    for free in 0..3 {
        let (i, j) = ((free + 1) % 3, (free + 2) % 3);
        for sides in 0..4 {
            for k in 0..options.random_on_edges {
                let mut angles = random_angles(&mut rng);
                angles[i] = bound(i, sides & 1);
                angles[j] = bound(j, sides >> 1);
                add(angles, format!("random on a bound edge {k}"), &mut slices);
            }
        }
    }
    slices
}

// ---------------------------------------------------------------------------------
// Sampling one slice
// ---------------------------------------------------------------------------------

/// Where on ∂U a sample was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SampleKind {
    /// Inside an exposed cell of one facet.
    Facet,
    /// On a piece of the segment where facets of two M's meet.
    Segment,
    /// Where facets of three M's meet.
    Triple,
}

impl SampleKind {
    pub fn label(self) -> &'static str {
        match self {
            SampleKind::Facet => "facet",
            SampleKind::Segment => "segment",
            SampleKind::Triple => "triple",
        }
    }
}

/// A facet of some M clipped to the translation box.
struct Patch {
    m: usize,
    normal: DVec3,
    offset: f64,
    polygon: Vec<DVec3>,
    lo: DVec3,
    hi: DVec3,
}

/// A translation on one slice, with a direction along which free space lies next to it.
struct Candidate {
    t: DVec3,
    /// Leaves every facet the candidate lies on at unit rate (n·d = 1 for each).
    outward: DVec3,
    kind: SampleKind,
}

/// The translation box's faces as half-spaces n·x ≤ h.
fn box_planes(bounds: &Bounds) -> [(DVec3, f64); 6] {
    let (lo, hi) = (bounds.min.translation(), bounds.max.translation());
    [
        (DVec3::X, hi.x),
        (-DVec3::X, -lo.x),
        (DVec3::Y, hi.y),
        (-DVec3::Y, -lo.y),
        (DVec3::Z, hi.z),
        (-DVec3::Z, -lo.z),
    ]
}

fn boxes_meet(lo1: DVec3, hi1: DVec3, lo2: DVec3, hi2: DVec3, pad: f64) -> bool {
    (lo1 - pad).cmple(hi2).all() && (lo2 - pad).cmple(hi1).all()
}

/// Every Minkowski difference of a slice that reaches into the translation box; `None`
/// when one of them cannot be built cleanly (the slice is then skipped).
pub fn slice_minkowskis(
    fixed: &[Piece],
    moving: &[Piece],
    r: DMat3,
    bounds: &Bounds,
    scale: f64,
) -> Option<Vec<Minkowski>> {
    let tol = TOUCH_REL * scale;
    let (lo, hi) = (bounds.min.translation(), bounds.max.translation());
    let mut out = Vec::new();
    for (i, p) in fixed.iter().enumerate() {
        for (j, q) in moving.iter().enumerate() {
            let mut m = minkowski_difference(p, q, r, scale)?;
            if boxes_meet(m.lo, m.hi, lo, hi, tol) {
                m.fixed_piece = i;
                m.moving_piece = j;
                out.push(m);
            }
        }
    }
    Some(out)
}

/// The facets of every M clipped to the translation box, those with some area left.
fn box_patches(ms: &[Minkowski], bounds: &Bounds, scale: f64) -> Vec<Patch> {
    let planes = box_planes(bounds);
    let mut out = Vec::new();
    for (m, mk) in ms.iter().enumerate() {
        for f in &mk.facets {
            let mut poly = f.polygon.clone();
            for (n, h) in planes {
                poly = clip(&poly, n, h);
            }
            if poly.len() < 3 || vector_area(&poly).length() < (1e-9 * scale).powi(2) {
                continue;
            }
            let (lo, hi) = poly.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            out.push(Patch {
                m,
                normal: f.normal,
                offset: f.offset,
                polygon: poly,
                lo,
                hi,
            });
        }
    }
    out
}

/// Step 1: one point inside every cell of every patch, the cells cut out by the traces
/// of the other M's boundaries on the patch's plane.
fn facet_candidates(patches: &[Patch], ms: &[Minkowski], scale: f64, out: &mut Vec<Candidate>) {
    let tol = TOUCH_REL * scale;
    let margin = SAMPLE_MARGIN_REL * scale;
    for patch in patches {
        let mut cuts: Vec<(DVec3, f64)> = Vec::new();
        for (k, mk) in ms.iter().enumerate() {
            if k == patch.m || !boxes_meet(patch.lo, patch.hi, mk.lo, mk.hi, tol) {
                continue;
            }
            let mut inside = patch.polygon.clone();
            // M_k grown by the tolerance, so that a facet of M_k in the patch's own
            // plane keeps the patch instead of losing it to round-off.
            for f in &mk.facets {
                inside = clip(&inside, f.normal, f.offset + tol);
                if inside.len() < 3 {
                    break;
                }
            }
            if inside.len() < 3 {
                continue;
            }
            // The facets of M_k that bound its trace on the patch.
            for f in &mk.facets {
                let on = inside
                    .iter()
                    .filter(|p| (f.normal.dot(**p) - f.offset).abs() <= 2.0 * tol)
                    .count();
                if on >= 2 && f.normal.cross(patch.normal).length() > 1e-9 {
                    cuts.push((f.normal, f.offset));
                }
            }
        }
        let mut cells = vec![patch.polygon.clone()];
        for (n, h) in cuts {
            let mut next = Vec::with_capacity(cells.len() + 1);
            for cell in cells {
                let (below, above) = split(&cell, n, h);
                for part in [below, above] {
                    if part.len() >= 3 {
                        next.push(part);
                    }
                }
            }
            cells = next;
        }
        for cell in cells {
            let (c, room) = inner_point(&cell, patch.normal);
            if room >= margin {
                out.push(Candidate {
                    t: c,
                    outward: patch.normal,
                    kind: SampleKind::Facet,
                });
            }
        }
    }
}

/// Steps 2 and 3: the segments where patches of two different M's meet, cut where they
/// enter or leave a third M; a point inside every piece, and the cut points themselves.
fn segment_candidates(patches: &[Patch], ms: &[Minkowski], bounds: &Bounds, scale: f64, out: &mut Vec<Candidate>) {
    let tol = TOUCH_REL * scale;
    let margin = SAMPLE_MARGIN_REL * scale;
    let planes_of = |m: usize| ms[m].facets.iter().map(|f| (f.normal, f.offset));
    let mut triples: HashSet<[i64; 3]> = HashSet::new();
    let grid = 1e-7 * scale;
    for (i, f) in patches.iter().enumerate() {
        for g in &patches[i + 1..] {
            if f.m == g.m || !boxes_meet(f.lo, f.hi, g.lo, g.hi, tol) {
                continue;
            }
            let d = f.normal.cross(g.normal);
            if d.length() < 1e-6 {
                continue;
            }
            let x0 = (f.offset * g.normal.cross(d) + g.offset * d.cross(f.normal)) / d.length_squared();
            let d = d.normalize();
            let own = planes_of(f.m).chain(planes_of(g.m)).chain(box_planes(bounds));
            let Some((s0, s1, p0, p1)) = clip_line(x0, d, own, tol) else {
                continue;
            };
            if s1 - s0 < -tol {
                continue;
            }
            // The segment's ends where another facet of the same two M's bounds it are
            // corners of U too (a vertex in a concave corner of the other part).
            let own_normal = |k: usize| {
                let n = ms[f.m].facets.len();
                if k < n {
                    Some(ms[f.m].facets[k].normal)
                } else {
                    ms[g.m].facets.get(k - n).map(|x| x.normal)
                }
            };
            for (s, plane) in [(s0, p0), (s1, p1)] {
                if let Some(h) = own_normal(plane) {
                    push_triple(x0 + d * s, [f.normal, g.normal, h], grid, &mut triples, out);
                }
            }
            if s1 - s0 < 2.0 * margin {
                continue;
            }
            let (a, b) = (x0 + d * s0, x0 + d * s1);
            let mut cuts = vec![s0, s1];
            for (l, ml) in ms.iter().enumerate() {
                if l == f.m || l == g.m || !boxes_meet(a.min(b), a.max(b), ml.lo, ml.hi, tol) {
                    continue;
                }
                let Some((e0, e1, q0, q1)) = clip_line(x0, d, planes_of(l), tol) else {
                    continue;
                };
                for (s, plane) in [(e0, q0), (e1, q1)] {
                    if s > s0 && s < s1 {
                        cuts.push(s);
                        let h = ms[l].facets[plane].normal;
                        push_triple(x0 + d * s, [f.normal, g.normal, h], grid, &mut triples, out);
                    }
                }
            }
            cuts.sort_by(f64::total_cmp);
            // The direction that leaves both facets at unit rate: n_F·d = n_G·d = 1.
            let c = f.normal.dot(g.normal);
            if 1.0 + c < 1e-6 {
                continue;
            }
            let outward = (f.normal + g.normal) / (1.0 + c);
            for w in cuts.windows(2) {
                if w[1] - w[0] >= 2.0 * margin {
                    out.push(Candidate {
                        t: x0 + d * (0.5 * (w[0] + w[1])),
                        outward,
                        kind: SampleKind::Segment,
                    });
                }
            }
        }
    }
}

/// A point where three facets meet, once (points are merged on a grid of size `grid`), with
/// the direction that leaves all three: n_i · d = 1 for the three normals.
fn push_triple(t: DVec3, normals: [DVec3; 3], grid: f64, seen: &mut HashSet<[i64; 3]>, out: &mut Vec<Candidate>) {
    let n = DMat3::from_cols(normals[0], normals[1], normals[2]).transpose();
    if n.determinant().abs() <= 1e-9 || (n.inverse() * DVec3::ONE).length() > 1e3 {
        return;
    }
    if seen.insert((t / grid).round().as_i64vec3().to_array()) {
        out.push(Candidate {
            t,
            outward: n.inverse() * DVec3::ONE,
            kind: SampleKind::Triple,
        });
    }
}

/// Whether a candidate lies on ∂U: inside no M deeper than the touching tolerance, and
/// with free space just outside it along its outward direction.
fn on_union_boundary(c: &Candidate, ms: &[Minkowski], scale: f64) -> bool {
    let tol = TOUCH_REL * scale;
    let probe = c.t + c.outward * (PROBE_REL * scale);
    ms.iter().all(|m| m.depth(c.t) >= -tol && m.depth(probe) > tol)
}

fn in_translation_bounds(t: DVec3, bounds: &Bounds) -> bool {
    let (lo, hi) = (bounds.min.translation(), bounds.max.translation());
    t.cmpge(lo).all() && t.cmple(hi).all()
}

/// The poses on ∂U sampled on one slice; `None` when the slice is skipped.
pub fn slice_samples(
    fixed: &[Piece],
    moving: &[Piece],
    slice: &Slice,
    bounds: &Bounds,
    scale: f64,
) -> Option<Vec<(Pose, SampleKind)>> {
    let r = rotation_of(slice.angles);
    let ms = slice_minkowskis(fixed, moving, r, bounds, scale)?;
    let patches = box_patches(&ms, bounds, scale);
    let mut candidates = Vec::new();
    facet_candidates(&patches, &ms, scale, &mut candidates);
    segment_candidates(&patches, &ms, bounds, scale, &mut candidates);
    let [rx, ry, rz] = slice.angles;
    // Coplanar facets of different M's give the same segments and points again.
    let mut seen: HashSet<[i64; 3]> = HashSet::new();
    let grid = 1e-7 * scale;
    let poses = candidates
        .into_iter()
        .filter(|c| in_translation_bounds(c.t, bounds) && on_union_boundary(c, &ms, scale))
        .filter(|c| seen.insert((c.t / grid).round().as_i64vec3().to_array()))
        .map(|c| (Pose::from_array([c.t.x, c.t.y, c.t.z, rx, ry, rz]), c.kind))
        .collect();
    Some(poses)
}

// ---------------------------------------------------------------------------------
// The oracle
// ---------------------------------------------------------------------------------

/// A sample pose, with where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub pose: Pose,
    pub kind: SampleKind,
    /// Index into the slices the oracle ran on.
    pub slice: usize,
}

/// One state the oracle found.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundState {
    pub contacts: Vec<PrincipalContact>,
    /// The first robust sample showing it.
    pub first: Sample,
    /// How many robust samples showed it.
    pub samples: usize,
}

/// Counts of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OracleStats {
    pub slices: usize,
    /// Slices where some Minkowski difference could not be built cleanly.
    pub skipped_slices: usize,
    /// Samples on ∂U inside the bounds.
    pub samples: usize,
    pub robust: usize,
    pub non_robust: usize,
    /// Robust samples whose state holds a degenerate contact (left out).
    pub degenerate: usize,
    /// Samples on ∂U where nothing touches, or where an edge pierces a face: either
    /// means the slice construction and the evaluator disagree (an oracle bug).
    pub untouched: usize,
    pub penetrating: usize,
    pub elapsed: Duration,
}

/// What the oracle found for one pair of parts.
#[derive(Clone, Debug)]
pub struct OracleReport {
    pub slices: Vec<Slice>,
    /// The states, sorted.
    pub states: Vec<FoundState>,
    /// Every robust sample with a non-degenerate state, for cross-checks.
    pub robust_samples: Vec<(Sample, Vec<PrincipalContact>)>,
    /// Up to a few samples that contradict the construction, with the reason.
    pub inconsistencies: Vec<(Sample, String)>,
    pub stats: OracleStats,
}

/// The recall oracle for a fixed part `a`, a moving part `b` and pose bounds (assembled
/// pose G = identity).
pub struct Oracle<'a> {
    pub fixed: &'a Part,
    pub moving: &'a Part,
    pub bounds: Bounds,
    pub fixed_pieces: Vec<Piece>,
    pub moving_pieces: Vec<Piece>,
    pub evaluator: Evaluator<'a>,
    pub scale: f64,
}

impl<'a> Oracle<'a> {
    /// Panics when a part's convex pieces do not add up to it.
    pub fn new(fixed: &'a Part, moving: &'a Part, bounds: Bounds) -> Oracle<'a> {
        let check = |p: &Part| checked_pieces(p).unwrap_or_else(|e| panic!("convex pieces fail their check: {e}"));
        Oracle {
            fixed,
            moving,
            bounds,
            fixed_pieces: check(fixed),
            moving_pieces: check(moving),
            evaluator: Evaluator::new(fixed, moving),
            scale: fixed.bounds().diagonal().max(moving.bounds().diagonal()),
        }
    }

    /// The default slices for these parts and bounds.
    pub fn default_slices(&self) -> Vec<Slice> {
        rotation_slices(self.fixed, self.moving, &self.bounds, &SliceOptions::default())
    }

    /// Samples every slice (in parallel) and reads P(X) at every sample.
    pub fn run(&self, slices: &[Slice]) -> OracleReport {
        let start = Instant::now();
        let per_slice: Vec<Option<Vec<(Sample, Verdict)>>> = slices
            .par_iter()
            .enumerate()
            .map(|(k, slice)| {
                let samples = slice_samples(&self.fixed_pieces, &self.moving_pieces, slice, &self.bounds, self.scale)?;
                let read = samples.into_iter().map(|(pose, kind)| {
                    let verdict = self.evaluator.evaluate(&pose);
                    (Sample { pose, kind, slice: k }, verdict)
                });
                Some(read.collect())
            })
            .collect();
        let mut stats = OracleStats {
            slices: slices.len(),
            skipped_slices: per_slice.iter().filter(|s| s.is_none()).count(),
            ..OracleStats::default()
        };
        let mut states: BTreeMap<Vec<PrincipalContact>, FoundState> = BTreeMap::new();
        let mut robust_samples = Vec::new();
        let mut inconsistencies = Vec::new();
        for (sample, verdict) in per_slice.into_iter().flatten().flatten() {
            stats.samples += 1;
            match verdict {
                Verdict::NonRobust(_) => stats.non_robust += 1,
                Verdict::Penetrating(why) => {
                    stats.penetrating += 1;
                    if inconsistencies.len() < 10 {
                        inconsistencies.push((sample, why));
                    }
                }
                Verdict::State(contacts) if contacts.is_empty() => {
                    stats.untouched += 1;
                    if inconsistencies.len() < 10 {
                        inconsistencies.push((sample, "nothing touches on the boundary of U".into()));
                    }
                }
                Verdict::State(contacts) => {
                    stats.robust += 1;
                    if contacts.iter().any(|c| self.evaluator.degenerate(c)) {
                        stats.degenerate += 1;
                        continue;
                    }
                    states
                        .entry(contacts.clone())
                        .and_modify(|s| s.samples += 1)
                        .or_insert_with(|| FoundState {
                            contacts: contacts.clone(),
                            first: sample.clone(),
                            samples: 1,
                        });
                    robust_samples.push((sample, contacts));
                }
            }
        }
        stats.elapsed = start.elapsed();
        OracleReport {
            slices: slices.to_vec(),
            states: states.into_values().collect(),
            robust_samples,
            inconsistencies,
            stats,
        }
    }
}
