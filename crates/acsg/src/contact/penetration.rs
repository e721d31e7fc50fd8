//! Penetration of two parts at a pose, on their exact convex pieces.
//!
//! Two convex polytopes are compared by the separating axis theorem (SAT): the candidate
//! axes are the face normals of both polytopes and the cross products of their edge
//! directions. Along each axis the projections of the two polytopes are intervals; their
//! overlap is how far one polytope must move along that axis to just touch the other.
//! The smallest overlap over the candidates is
//! - when positive, the exact penetration depth (minimum translation distance): the
//!   normals of the Minkowski difference's facets are among the candidates;
//! - when zero, touching;
//! - when negative, minus the largest separation along a candidate axis, a lower bound
//!   of the Euclidean distance (equal to it when the closest features are face-vertex
//!   or edge-edge).
//!
//! A non-convex part is handled through its exact convex pieces
//! ([`Part::convex_pieces`]), taking the worst pair (docs/concepts.md#feasibility). Because the
//! pieces are solids, a part wholly inside the other is reported as penetrating (a
//! surface-only test would miss it).

use glam::{DAffine3, DVec3};

use super::gauss::{self, GaussHull, Placed};
use super::separation::{Hull, Separation, separate};
use crate::model::{Part, length_scale};
use crate::tolerance::{ORTHOGONAL_DOT, PARALLEL_SIN, SEPARATION_REL, WELD_REL, scaled};

/// Penetration of two parts at a pose, over all nearby pairs of their convex pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct PenetrationReport {
    /// The worst (largest) value over all pairs of pieces: the exact [`Separation::depth`]
    /// for an examined pair, minus the gap between the bounding boxes for a pair whose
    /// boxes are farther apart than the margin (`SEPARATION_REL · L`). So `depth > 0`
    /// means an examined pair penetrates by `depth`, and `depth <= 0` means the parts
    /// are at least `-depth` apart. `f64::NEG_INFINITY` when a part has no pieces.
    pub depth: f64,
    /// The pair `(fixed piece, moving piece)` achieving `depth` (indices into
    /// [`Part::convex_pieces`]), `None` when a part has no pieces.
    pub pieces: Option<(usize, usize)>,
    /// For every examined pair `(fixed piece, moving piece, axis, offset)`: the plane
    /// `axis · p = offset` in the fixed part's frame of [`Separation`] (a separating
    /// plane whenever that pair does not penetrate). Pairs whose bounding boxes are
    /// farther apart than the margin are not examined and have no plane here.
    pub certificates: Vec<(usize, usize, DVec3, f64)>,
}

/// The round-off allowed, relative to the coordinates' size, when a hinted axis says a
/// pair of pieces cannot penetrate as deep as another ([`penetration_excess`]): far
/// above the error of a projection, so that the answer is exactly the one without
/// hints.
const HINT_ROUND_OFF: f64 = 1e-9;

/// Pieces with more faces than this are compared over the facets of the Minkowski
/// difference (module `gauss`) rather than over all pairs of edge directions.
const LARGE_PIECE_FACES: usize = 24;

/// A part's convex pieces, prepared once for many penetration checks.
#[derive(Debug)]
pub struct PreparedPieces {
    hulls: Vec<Hull>,
    /// The topology of the large pieces, for the facet-restricted test.
    gauss: Vec<Option<GaussHull>>,
}

impl PreparedPieces {
    /// Prepares a part's pieces in its own frame.
    #[must_use]
    pub fn new(part: &Part) -> PreparedPieces {
        let eps = scaled(WELD_REL, part.bounds().diagonal());
        let pieces = part.convex_pieces();
        let gauss: Vec<Option<GaussHull>> = pieces
            .iter()
            .map(|p| {
                (p.faces().len() > LARGE_PIECE_FACES)
                    .then(|| GaussHull::new(p, eps))
                    .flatten()
            })
            .collect();
        // Every hull keeps its face normals and edge directions, large ones too: a large
        // piece against a small one (no Gauss map) goes through the plain SAT, which
        // needs both pieces' axes.
        let hulls = pieces.iter().map(|p| Hull::new(p, None)).collect();
        PreparedPieces { hulls, gauss }
    }
}

/// Penetration of the moving part, placed by `moving_to_fixed`, into the fixed part.
///
/// Every pair of convex pieces whose bounding boxes (in the fixed frame) are within the
/// margin `SEPARATION_REL · L` of each other is tested exactly with SAT, `L` being the
/// larger bounding-box diagonal of the two parts; the other pairs count as separated by
/// their box gap. A part wholly inside the other penetrates, since the pieces are
/// solids. The moving part's pieces are transformed once per call.
#[must_use]
pub fn penetration(fixed: &Part, moving: &Part, moving_to_fixed: &DAffine3) -> PenetrationReport {
    let length = length_scale(fixed, moving);
    penetration_prepared(
        &PreparedPieces::new(fixed),
        &PreparedPieces::new(moving),
        moving_to_fixed,
        length,
    )
}

/// [`penetration`] with both parts' pieces prepared; `length` is `L`.
#[must_use]
pub fn penetration_prepared(
    fixed: &PreparedPieces,
    moving: &PreparedPieces,
    moving_to_fixed: &DAffine3,
    length: f64,
) -> PenetrationReport {
    let mut pieces = PiecesAtPose::new(fixed, moving, moving_to_fixed);
    let margin = scaled(SEPARATION_REL, length);
    let mut report = PenetrationReport {
        depth: f64::NEG_INFINITY,
        pieces: None,
        certificates: Vec::new(),
    };
    for i in 0..fixed.hulls.len() {
        for j in 0..moving.hulls.len() {
            let gap = pieces.box_gap(i, j);
            let depth = if gap > margin {
                -gap
            } else {
                let s = pieces.separate(i, j, f64::NEG_INFINITY);
                report.certificates.push((i, j, s.axis, s.offset));
                s.depth
            };
            if report.pieces.is_none() || depth > report.depth {
                report.depth = depth;
                report.pieces = Some((i, j));
            }
        }
    }
    report
}

/// How deep the parts penetrate, or 0 when they do not: the positive part of
/// [`penetration_prepared`]'s depth, computed with early exits (a pair of pieces is
/// dropped at its first separating axis), for the optimiser's residual.
#[must_use]
pub fn penetration_excess(fixed: &PreparedPieces, moving: &PreparedPieces, moving_to_fixed: &DAffine3) -> f64 {
    let mut pieces = PiecesAtPose::new(fixed, moving, moving_to_fixed);
    let mut excess: f64 = 0.0;
    AXIS_HINTS.with_borrow_mut(|hints| {
        let hints = hints.for_pieces(fixed, moving);
        let per_fixed = moving.hulls.len();
        for i in 0..fixed.hulls.len() {
            for j in 0..per_fixed {
                // A pair penetrates by at most its boxes' overlap along any axis: one
                // that cannot beat the deepest so far is dropped, and so is its SAT at
                // the first axis that overlaps no more than that; first the axis that
                // answered for the pair last time (nearby poses mostly share it).
                if -pieces.box_gap(i, j) > excess {
                    let hint = &mut hints[i * per_fixed + j];
                    if pieces.clearly_below(i, j, *hint, excess) {
                        continue;
                    }
                    let separation = pieces.separate(i, j, excess);
                    *hint = separation.axis;
                    excess = excess.max(separation.depth);
                }
            }
        }
    });
    excess
}

/// Per thread, the axis that last answered each pair of pieces in
/// [`penetration_excess`] (which searches, local optimisations and slides call for
/// many nearby poses), for the pieces it was last called with.
#[derive(Default)]
struct AxisHints {
    /// The prepared pieces (by address) the hints are for.
    owner: (usize, usize),
    axes: Vec<DVec3>,
}

impl AxisHints {
    /// The hints for these pieces, all unset when they are not the last ones'. Any axis
    /// is a safe hint (a pair's overlap along every axis is at least its penetration
    /// depth), so a stale one, or one at a reused address, costs only its test.
    fn for_pieces(&mut self, fixed: &PreparedPieces, moving: &PreparedPieces) -> &mut [DVec3] {
        let owner = (std::ptr::from_ref(fixed) as usize, std::ptr::from_ref(moving) as usize);
        let pairs = fixed.hulls.len() * moving.hulls.len();
        if self.owner != owner || self.axes.len() != pairs {
            self.owner = owner;
            self.axes.clear();
            self.axes.resize(pairs, DVec3::ZERO);
        }
        &mut self.axes
    }
}

thread_local! {
    static AXIS_HINTS: std::cell::RefCell<AxisHints> = std::cell::RefCell::default();
}

/// Whether the parts penetrate by more than `depth` (at least 0): the same answer as
/// `penetration_prepared(..).depth > depth`, with early exits (a pair of pieces is
/// dropped at its first axis that overlaps by `depth` or less, and the first pair that
/// penetrates by more answers).
#[must_use]
pub fn penetrates_beyond(
    fixed: &PreparedPieces,
    moving: &PreparedPieces,
    moving_to_fixed: &DAffine3,
    depth: f64,
) -> bool {
    let mut pieces = PiecesAtPose::new(fixed, moving, moving_to_fixed);
    let depth = depth.max(0.0);
    (0..fixed.hulls.len()).any(|i| {
        (0..moving.hulls.len()).any(|j| -pieces.box_gap(i, j) > depth && pieces.separate(i, j, depth).depth > depth)
    })
}

/// Both parts' pieces with the moving part placed: hulls moved once, Gauss-map views
/// placed when first needed.
struct PiecesAtPose<'p> {
    fixed: &'p PreparedPieces,
    moving: &'p PreparedPieces,
    moving_to_fixed: DAffine3,
    moved: Vec<Hull>,
    fixed_gauss: Vec<Option<Placed<'p>>>,
    moving_gauss: Vec<Option<Placed<'p>>>,
}

impl<'p> PiecesAtPose<'p> {
    fn new(fixed: &'p PreparedPieces, moving: &'p PreparedPieces, moving_to_fixed: &DAffine3) -> PiecesAtPose<'p> {
        PiecesAtPose {
            fixed,
            moving,
            moving_to_fixed: *moving_to_fixed,
            moved: moving.hulls.iter().map(|h| h.transformed(moving_to_fixed)).collect(),
            fixed_gauss: vec![None; fixed.gauss.len()],
            moving_gauss: vec![None; moving.gauss.len()],
        }
    }

    /// The gap between the boxes of fixed piece `i` and moving piece `j`.
    fn box_gap(&self, i: usize, j: usize) -> f64 {
        self.fixed.hulls[i].box_gap(&self.moved[j])
    }

    /// Whether fixed piece `i` and moving piece `j` overlap along `axis` (unit, or zero
    /// for none) by less than `depth`, with room to spare for round-off: then they
    /// penetrate by less than `depth`, which their SAT would find too (the same answer
    /// for [`penetration_excess`], the pair unable to raise it).
    fn clearly_below(&self, i: usize, j: usize, axis: DVec3, depth: f64) -> bool {
        if axis == DVec3::ZERO {
            return false;
        }
        let (min_a, max_a) = self.fixed.hulls[i].extent(axis);
        let (min_b, max_b) = self.moved[j].extent(axis);
        let overlap = (max_a - min_b).min(max_b - min_a);
        let size = [min_a, max_a, min_b, max_b].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        overlap <= depth - HINT_ROUND_OFF * size
    }

    /// SAT on fixed piece `i` and moving piece `j`: by Gauss maps when both have one.
    fn separate(&mut self, i: usize, j: usize, stop_at: f64) -> Separation {
        match (&self.fixed.gauss[i], &self.moving.gauss[j]) {
            (Some(ga), Some(gb)) => {
                let ga = self.fixed_gauss[i].get_or_insert_with(|| ga.placed(&DAffine3::IDENTITY));
                let gb = self.moving_gauss[j].get_or_insert_with(|| gb.placed(&self.moving_to_fixed));
                gauss::separate(ga, gb, stop_at)
            }
            _ => separate(&self.fixed.hulls[i], &self.moved[j], stop_at),
        }
    }
}

/// The open intervals of `s` over which the moving part, placed by `moving_to_fixed`
/// and then translated by `s · direction`, penetrates the fixed part by more than
/// `depth`: one interval per pair of convex pieces that penetrates somewhere on the
/// line (unsorted; the union is where the line is blocked).
///
/// Exact by the separating axis theorem: along each candidate axis the overlap of the
/// projections is affine in `s`, so "overlap more than `depth` on every axis" is an
/// intersection of intervals, and the smallest overlap over the candidates is the
/// penetration depth.
#[must_use]
pub fn blocked_along(
    fixed: &PreparedPieces,
    moving: &PreparedPieces,
    moving_to_fixed: &DAffine3,
    direction: DVec3,
    depth: f64,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for b in moving.hulls.iter().map(|h| h.transformed(moving_to_fixed)) {
        for a in &fixed.hulls {
            if let Some(interval) = blocked_pair(a, &b, direction, depth) {
                out.push(interval);
            }
        }
    }
    out
}

/// [`blocked_along`] for one pair of hulls in the same frame.
fn blocked_pair(a: &Hull, b: &Hull, direction: DVec3, depth: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    // Overlap along `axis` at `s`: max_a − (min_b + s k) and (max_b + s k) − min_a,
    // both more than `depth`.
    let mut narrow = |axis: DVec3| -> bool {
        let (min_a, max_a) = a.extent(axis);
        let (min_b, max_b) = b.extent(axis);
        let k = axis.dot(direction);
        let (upper, lower) = (max_a - min_b - depth, min_a - max_b + depth);
        if k.abs() < ORTHOGONAL_DOT {
            if upper <= 0.0 || lower >= 0.0 {
                lo = f64::INFINITY;
            }
        } else if k > 0.0 {
            hi = hi.min(upper / k);
            lo = lo.max(lower / k);
        } else {
            lo = lo.max(upper / k);
            hi = hi.min(lower / k);
        }
        lo < hi
    };
    for &n in a.normals.iter().chain(&b.normals) {
        if !narrow(n) {
            return None;
        }
    }
    for &ea in &a.edges {
        for &eb in &b.edges {
            let c = ea.cross(eb);
            let length = c.length();
            if length >= PARALLEL_SIN && !narrow(c / length) {
                return None;
            }
        }
    }
    Some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::super::separation::convex_separation;
    use super::*;
    use crate::geometry::ConvexPolytope;

    #[test]
    fn a_cube_sliding_through_another_is_blocked_while_they_overlap() {
        let cube = ConvexPolytope::cuboid(DVec3::ZERO, DVec3::ONE);
        let part_pieces = |c: &ConvexPolytope| PreparedPieces {
            hulls: vec![Hull::new(c, None)],
            gauss: vec![None],
        };
        let (a, b) = (part_pieces(&cube), part_pieces(&cube));
        // B starts at x = −5 and slides along x: the cubes overlap for s in (4, 6), by
        // more than 0.25 for s in (4.25, 5.75).
        let start = DAffine3::from_translation(DVec3::new(-5.0, 0.0, 0.0));
        let blocked = blocked_along(&a, &b, &start, DVec3::X, 0.0);
        assert_eq!(blocked.len(), 1);
        crate::assert_near!(blocked[0].0, 4.0, 1e-12);
        crate::assert_near!(blocked[0].1, 6.0, 1e-12);
        let deep = blocked_along(&a, &b, &start, DVec3::X, 0.25);
        crate::assert_near!(deep[0].0, 4.25, 1e-12);
        crate::assert_near!(deep[0].1, 5.75, 1e-12);
        // Sliding past above the cube: never blocked.
        let above = DAffine3::from_translation(DVec3::new(-5.0, 0.0, 1.5));
        assert!(blocked_along(&a, &b, &above, DVec3::X, 0.0).is_empty());
    }
    use crate::assert_near;
    use glam::{DMat3, DQuat};
    use std::path::Path;

    fn fixture(name: &str) -> Part {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name);
        Part::from_path(&path).expect("fixture loads")
    }

    fn unit_cube() -> ConvexPolytope {
        ConvexPolytope::cuboid(DVec3::ZERO, DVec3::ONE)
    }

    fn shift(x: f64, y: f64, z: f64) -> DAffine3 {
        DAffine3::from_translation(DVec3::new(x, y, z))
    }

    #[test]
    fn overlapping_cubes_penetrate_along_the_shallow_axis() {
        let s = convex_separation(&unit_cube(), &unit_cube(), &shift(0.75, 0.1, -0.2));
        assert_near!(s.depth, 0.25, 1e-12);
        assert_eq!(s.axis, DVec3::X);
        // B below A: the axis still points from A towards B.
        let s = convex_separation(&unit_cube(), &unit_cube(), &shift(0.0, 0.0, -0.9));
        assert_near!(s.depth, 0.1, 1e-12);
        assert_eq!(s.axis, -DVec3::Z);
        assert_near!(s.offset, -0.05, 1e-12);
    }

    #[test]
    fn separated_cubes_give_a_separating_plane() {
        let s = convex_separation(&unit_cube(), &unit_cube(), &shift(0.2, -1.5, 0.3));
        assert_near!(s.depth, -0.5, 1e-12);
        assert_eq!(s.axis, -DVec3::Y);
        assert_near!(s.offset, 0.25, 1e-12); // the plane y = -0.25
    }

    #[test]
    fn touching_and_contained_cubes() {
        let s = convex_separation(&unit_cube(), &unit_cube(), &shift(0.0, 1.0, 0.5));
        assert_near!(s.depth, 0.0, 1e-12);
        let small = ConvexPolytope::cuboid(DVec3::splat(0.4), DVec3::splat(0.5));
        let s = convex_separation(&unit_cube(), &small, &DAffine3::IDENTITY);
        // Leaving through the nearest face (x, y or z = 0) takes 0.5.
        assert_near!(s.depth, 0.5, 1e-12);
    }

    #[test]
    fn rotated_corner_penetrates_a_face() {
        // A unit cube centred at the origin, turned 45° about z: its corner reaches
        // √2/2 along x. Placed so the corner enters A's face x = 1 by 0.1.
        let b = ConvexPolytope::cuboid(DVec3::splat(-0.5), DVec3::splat(0.5));
        let centre = DVec3::new(1.0 + 0.5 * 2f64.sqrt() - 0.1, 0.5, 0.5);
        let pose = DAffine3::from_rotation_translation(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_4), centre);
        let s = convex_separation(&unit_cube(), &b, &pose);
        assert_near!(s.depth, 0.1, 1e-12);
        assert!(s.axis.distance(DVec3::X) < 1e-12);
    }

    #[test]
    fn edge_edge_axis_is_found() {
        // A's ridge along y at x = z = 1 (outward direction (1,0,1)/√2) is crossed by an
        // edge of B along (1,0,-1)/√2 pushed 0.05 into it. Neither A's face normals (x, z)
        // nor B's ((1,0,-1)/√2, (1/2, ±1/√2, 1/2)) is that direction: only the cross
        // product of the two edges gives the depth 0.05.
        let s2 = 0.5f64.sqrt();
        let rotation = DMat3::from_cols(
            DVec3::new(s2, 0.0, -s2),
            DVec3::new(0.5, s2, 0.5),
            DVec3::new(0.5, -s2, 0.5),
        );
        let n = DVec3::new(1.0, 0.0, 1.0).normalize();
        // B's edge along its x at y = z = -0.5 lies at centre - (1,0,1)/2 once rotated.
        let centre = DVec3::new(1.0, 0.5, 1.0) + DVec3::new(0.5, 0.0, 0.5) - 0.05 * n;
        let b = ConvexPolytope::cuboid(DVec3::splat(-0.5), DVec3::splat(0.5));
        let s = convex_separation(&unit_cube(), &b, &DAffine3::from_mat3_translation(rotation, centre));
        assert_near!(s.depth, 0.05, 1e-12);
        assert!(s.axis.distance(n) < 1e-12);
    }

    #[test]
    fn box_in_the_corner_of_the_l_block() {
        let (l_block, boxed) = (fixture("l_block.off"), fixture("box.off"));
        let l = length_scale(&l_block, &boxed);
        let at = |x, y, z| penetration(&l_block, &boxed, &shift(x, y, z));

        let r = at(0.0, 0.0, 0.0);
        assert!(r.depth.abs() <= 1e-9 * l, "touching floor and wall: {}", r.depth);
        assert!(!r.certificates.is_empty());
        // Lifted by 1 the box still touches the wall x = 150 (it only leaves the floor).
        let r = at(0.0, 0.0, 1.0);
        assert!(r.depth.abs() <= 1e-9 * l, "still on the wall: {}", r.depth);
        // Lifted and moved away from the wall: separated by 1.
        assert_near!(at(-1.0, 0.0, 1.0).depth, -1.0, 1e-9 * l);
        assert_near!(at(-3.0, 0.0, 2.0).depth, -2.0, 1e-9 * l);
        // Into the wall by 1, into the floor by 2.
        assert_near!(at(1.0, 0.0, 0.0).depth, 1.0, 1e-9 * l);
        assert_near!(at(0.0, 0.0, -2.0).depth, 2.0, 1e-9 * l);
    }

    #[test]
    fn certificates_separate_the_pieces() {
        let (l_block, boxed) = (fixture("l_block.off"), fixture("box.off"));
        let pose = shift(-1.0, 0.0, 1.0);
        let r = penetration(&l_block, &boxed, &pose);
        assert!(r.depth < 0.0);
        for &(i, j, n, d) in &r.certificates {
            for &p in l_block.convex_pieces()[i].vertices() {
                assert!(n.dot(p) <= d + 1e-9);
            }
            for &p in boxed.convex_pieces()[j].vertices() {
                assert!(n.dot(pose.transform_point3(p)) >= d - 1e-9);
            }
        }
    }

    #[test]
    fn part_inside_the_other_penetrates() {
        // The cube [0,10]^3 moved to [20,30]^3, wholly inside the L's floor slab: no
        // surface of either part meets the other's, yet the pieces overlap. Along every
        // axis the cheapest exit is 30 (20 to the floor's face and 10 of the cube).
        let (l_block, cube) = (fixture("l_block.off"), fixture("cube.off"));
        let r = penetration(&l_block, &cube, &shift(20.0, 20.0, 20.0));
        assert_near!(r.depth, 30.0, 1e-9);
        assert!(r.pieces.is_some());
    }

    #[test]
    fn peg_in_the_hole() {
        let (block, peg) = (fixture("block_with_hole.off"), fixture("peg.off"));
        let l = length_scale(&block, &peg);
        let r = penetration(&block, &peg, &DAffine3::IDENTITY);
        assert_near!(r.depth, -1.0, 1e-9 * l);
        // The peg's pieces stand in the hole: their corners are outside every block piece.
        for piece in peg.convex_pieces() {
            for &p in piece.vertices() {
                assert!(
                    block
                        .convex_pieces()
                        .iter()
                        .all(|q| q.outside_distance(p) >= 1.0 - 1e-9)
                );
            }
        }
        let r = penetration(&block, &peg, &shift(2.0, 0.0, 0.0));
        assert_near!(r.depth, 1.0, 1e-9 * l);
        assert!(!r.certificates.is_empty());
    }
}
