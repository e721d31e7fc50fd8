//! The one tolerance policy of the crate.
//!
//! Every geometric comparison is made against a length scale `L`, the larger
//! bounding-box diagonal of the parts involved (DOMAIN.md section 7), times one of the
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

/// Asserts that two floating-point values (or iterables of them, element-wise)
/// are within an absolute tolerance, printing both on failure.
#[macro_export]
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

/// Largest deviation `max |RᵀR − I|` accepted for the rotation part of a rigid
/// transform (dimensionless; admits matrices written with ~7 significant digits).
pub const RIGID_REL: f64 = 1e-6;

/// Two unit directions whose cross product is shorter than this are parallel.
pub const PARALLEL_SIN: f64 = 1e-9;

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

/// Round-off allowed in a dot product of unit vectors or a coordinate of a unit vector
/// (dimensionless): an edge leaving a vertex runs on the inner side of a face's plane
/// when its direction's dot product with the face's normal is at most this; a box
/// around an arc of unit vectors is grown by this much.
pub const UNIT_ROUNDOFF: f64 = 1e-12;

/// A unit axis and a unit direction whose dot product is smaller than this in
/// magnitude are perpendicular (dimensionless): moving along the direction does not
/// move along the axis.
pub const ORTHOGONAL_DOT: f64 = 1e-15;

/// A face's triangles may miss its area by this fraction before the triangulation is
/// reported as failed (its loops intersect or touch).
pub const TRIANGULATION_REL: f64 = 1e-6;
