//! The one tolerance policy of the crate.
//!
//! Every geometric comparison is made against a length scale `L`, the larger
//! bounding-box diagonal of the parts involved (docs/concepts.md#tolerances), times one of the
//! named relative constants below. Nothing else in the crate invents an epsilon.

/// A listed contact holds when its elements are this close, relative to `L`.
pub const CONTACT_REL: f64 = 1e-9;

/// A pair that is not a listed (or implied) contact must be at least this far apart,
/// relative to `L`.
pub const SEPARATION_REL: f64 = 1e-6;

/// Distance, relative to the part's own diagonal, under which two input points are
/// the same point (welding of STL soups, snapping to a cutting plane).
pub const WELD_REL: f64 = 1e-9;

/// Distance, relative to the part's own diagonal, within which a mesh facet counts as
/// lying in a face's plane. It is looser than [`WELD_REL`] because binary STL stores
/// single-precision coordinates (relative rounding about 6e-8).
pub const COPLANAR_REL: f64 = 1e-6;

/// Smallest relative area (area / L²) a face or facet may have.
pub const AREA_REL: f64 = 1e-12;

/// A length tolerance: a relative constant scaled by the length scale `l`.
#[must_use]
pub fn scaled(rel: f64, l: f64) -> f64 {
    rel * l
}

/// `true` when `a` and `b` differ by at most `tol` (absolute).
///
/// ```
/// assert!(acsg::tolerance::near(1.0, 1.0 + 1e-12, 1e-9));
/// assert!(!acsg::tolerance::near(1.0, 1.1, 1e-9));
/// ```
#[must_use]
pub fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Asserts that two floating-point values are within an absolute tolerance, printing
/// both on failure (the crate's own tests; not exported).
#[cfg(test)]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            $crate::tolerance::near(a, b, tol),
            "assert_near failed: {} = {a}, {} = {b}, |diff| = {} > tol {tol}",
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
}
#[cfg(test)]
pub(crate) use assert_near;

/// Largest deviation `max |RᵀR − I|` accepted for the rotation part of a rigid
/// transform (dimensionless; admits matrices written with ~7 significant digits).
pub const RIGID_REL: f64 = 1e-6;

/// Two unit directions whose cross product is shorter than this are parallel.
pub const PARALLEL_SIN: f64 = 1e-9;
/// The sine of the largest angle at which the reading over the overlap
/// (docs/concepts.md#tolerances) takes an edge or a face as lying on a face without being
/// within the tolerance of its plane from end to end, only over the part of it over the
/// face (an edge lying on a wall and passing over the wall's rim). A stretch whose two
/// ends lie within the contact tolerance of the plane, as far apart as the loosest
/// reading of a witness keeps two contact points (just under the separation), tilts by
/// at most `2 · CONTACT_REL / LOOSE_CONTACT_REL` ≈ 2.02e-3 (the loose reading is at
/// `0.99 · SEPARATION_REL`): DOMAIN reads it lying
/// in the face, and so must this reading. A steeper stretch within the tolerance is
/// shorter than the separation: a sliver no witness is read by.
pub const FLUSH_TILT: f64 = 2.1e-3;

/// Element pairs that do not touch are searched for the smallest gap up to this
/// distance, relative to `L`; farther pairs are reported only as "at least this far".
pub const GAP_SEARCH_REL: f64 = 1e-2;

/// The farthest a part's points may lie from the origin, relative to the part's own
/// diagonal. Coordinates are `f64` (about 16 significant digits); a point at distance
/// `c` is known to `c · 2.2e-16`, and the contact tolerance is [`CONTACT_REL`] of the
/// diagonal `d`. At `c = 1e4 · d` that rounding is 1/450 of the tolerance, enough for
/// the arithmetic of the contact tests; farther out, states appear and vanish by
/// rounding (a cube 1e12 from the origin gave 54 states instead of 7).
pub const OFFSET_REL: f64 = 1e4;

/// Round-off allowed in a dimensionless quantity computed in a few operations: a dot
/// or cross product of unit vectors, a ratio of two lengths, an angle in radians. An
/// edge leaving a vertex runs on the inner side of a face's plane when its direction's
/// dot product with the face's normal is at most this; two lines are parallel when
/// their directions' cross product is below it.
pub const ROUNDOFF_REL: f64 = 1e-12;

/// A unit axis and a unit direction whose dot product is smaller than this in
/// magnitude are perpendicular (dimensionless): moving along the direction does not
/// move along the axis.
pub const ORTHOGONAL_DOT: f64 = 1e-15;

/// A face's triangles may miss its area by this fraction before the triangulation is
/// reported as failed (its loops intersect or touch).
pub const TRIANGULATION_REL: f64 = 1e-6;

/// Forward-difference step of the local solver: this times `L` for the translations,
/// this many radians for the rotations.
pub const DIFFERENCE_STEP_REL: f64 = 1e-7;

/// A local solve has converged when the root of its sum of squared residuals is below
/// this times `L` (two orders below the contact tolerance, so that a polished witness
/// holds its contacts with room to spare).
pub const SOLVED_REL: f64 = 1e-11;

/// A pose component within this fraction of its range (or of its difference step) of
/// a bound is on that bound.
pub const AT_BOUND_REL: f64 = 1e-12;

/// The Levenberg–Marquardt damping adds at least this fraction of the largest diagonal
/// entry, so that a zero column (a component no residual depends on) cannot make the
/// system singular.
pub const DAMPING_FLOOR_REL: f64 = 1e-9;

/// A magnitude below this is zero: a pivot that makes a linear system singular, a
/// normal too short to normalise.
pub const NEGLIGIBLE: f64 = 1e-300;

/// Slack on the half turn for angles given in radians, so that `3.1415927` (π rounded
/// up in the 8th digit) still reads as a half turn.
pub const RADIAN_SLACK: f64 = 1e-6;

/// The half-size of the first box around a witness that a search below a known state
/// examines (translations relative to `L`, angles in radians).
pub const NEAR_REL: f64 = 1e-4;

/// Counting the degrees of freedom a state leaves: an entry of the (normalised)
/// contact-normal matrix below this counts as 0 in the rank.
pub const RANK_REL: f64 = 1e-7;

/// The smallest tilt, in radians, a contact's direction is allowed off its plane.
pub const MIN_TILT: f64 = 1e-9;

/// Step, in radians, of the central differences that measure how fast a rotation
/// condition changes along each angle.
pub const ROTATION_PROBE: f64 = 1e-6;

/// Edges of a CAD loop join head to tail when their ends are this close, relative to
/// the size of the coordinates (STEP and IGES).
pub const JOIN_REL: f64 = 1e-7;

/// The smallest size (millimetres) a CAD reader scales its tolerances by, so that a
/// model whose points all coincide still gets a positive tolerance.
pub const SIZE_FLOOR: f64 = 1e-9;

/// Consecutive points of a CAD loop closer than this fraction of the coplanarity
/// tolerance are one point.
pub const DUPLICATE_FRACTION: f64 = 1e-3;
