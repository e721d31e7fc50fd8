//! The separating axis test (SAT) on two convex polytopes: the candidate axes are the
//! face normals of both and the cross products of their edge directions; along each
//! axis the projections are intervals whose overlap is how far one polytope must move
//! to just touch the other (see [`super::penetration`] for what the smallest overlap
//! means).

use glam::{DAffine3, DVec3};

use crate::geometry::{Aabb, ConvexPolytope};
/// An edge pair closer to parallel than this gives no axis, and parallel face normals
/// or edge directions are kept once.
use crate::tolerance::PARALLEL_SIN;

/// The result of a separating axis test between two convex polytopes A and B.
///
/// The plane `axis · p = offset` is in A's frame. When `depth <= 0` it separates the two
/// polytopes (`axis · p <= offset` on A, `axis · p >= offset` on B): a certificate of no
/// penetration. When `depth > 0` it is the plane across the axis of least penetration,
/// half-way into the overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Separation {
    /// Minimum translation distance along `axis`: > 0 penetrating (how far B must move
    /// along `axis` to just touch A), 0 touching, < 0 separated (then `-depth` is the gap
    /// along `axis`, a lower bound of the Euclidean distance).
    pub depth: f64,
    /// Unit axis, pointing from A towards B.
    pub axis: DVec3,
    /// Offset of the separating (or least-penetration) plane along `axis`.
    pub offset: f64,
}

impl Separation {
    /// An early answer that the pair does not penetrate: `depth` ≤ 0 along `axis` (an
    /// upper bound of the true depth; the offset is not computed).
    pub(super) fn bound(depth: f64, axis: DVec3) -> Separation {
        Separation {
            depth,
            axis,
            offset: f64::NAN,
        }
    }
}

/// A convex polytope reduced to what SAT needs, in the frame of the comparison.
#[derive(Debug)]
pub(super) struct Hull {
    vertices: Vec<DVec3>,
    /// Distinct face normal directions (unit; antiparallel normals kept once).
    pub(super) normals: Vec<DVec3>,
    /// Distinct edge directions (unit; antiparallel directions kept once).
    pub(super) edges: Vec<DVec3>,
    /// The box around the vertices.
    bounds: Aabb,
}

impl Hull {
    /// The polytope, mapped by `transform` when given (normals by the inverse transpose,
    /// so a non-rigid but invertible map is also handled).
    pub(super) fn new(polytope: &ConvexPolytope, transform: Option<&DAffine3>) -> Hull {
        let normal_matrix = transform.map(|t| t.matrix3.inverse().transpose());
        let point = |p: DVec3| transform.map_or(p, |t| t.transform_point3(p));
        let vector = |v: DVec3| transform.map_or(v, |t| t.transform_vector3(v));
        let vertices: Vec<DVec3> = polytope.vertices().iter().map(|&p| point(p)).collect();
        let mut normals = Vec::new();
        let mut edges = Vec::new();
        for face in polytope.faces() {
            push_direction(&mut normals, normal_matrix.map_or(face.normal, |m| m * face.normal));
            let n = face.points.len();
            for (i, &p) in face.points.iter().enumerate() {
                push_direction(&mut edges, vector(face.points[(i + 1) % n] - p));
            }
        }
        Hull {
            bounds: Aabb::around(vertices.iter().copied()),
            vertices,
            normals,
            edges,
        }
    }

    /// This hull mapped by an invertible affine map (directions stay distinct, since an
    /// invertible linear map keeps non-parallel directions non-parallel).
    pub(super) fn transformed(&self, t: &DAffine3) -> Hull {
        let normal_matrix = t.matrix3.inverse().transpose();
        let vertices: Vec<DVec3> = self.vertices.iter().map(|&p| t.transform_point3(p)).collect();
        Hull {
            bounds: Aabb::around(vertices.iter().copied()),
            vertices,
            normals: self.normals.iter().map(|&n| (normal_matrix * n).normalize()).collect(),
            edges: self.edges.iter().map(|&e| t.transform_vector3(e).normalize()).collect(),
        }
    }

    /// The interval of the projections of the vertices onto `axis`.
    pub(super) fn extent(&self, axis: DVec3) -> (f64, f64) {
        self.vertices
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let s = axis.dot(*p);
                (lo.min(s), hi.max(s))
            })
    }

    /// The largest gap between the two bounding boxes along a coordinate axis
    /// (negative when they overlap).
    pub(super) fn box_gap(&self, other: &Hull) -> f64 {
        self.bounds.axis_gap(&other.bounds)
    }
}

/// Adds the unit direction of `v` unless it is zero or parallel to one already listed.
fn push_direction(list: &mut Vec<DVec3>, v: DVec3) {
    let d = v.normalize_or_zero();
    if d != DVec3::ZERO && d.is_finite() && !list.iter().any(|e| e.cross(d).length() < PARALLEL_SIN) {
        list.push(d);
    }
}

/// SAT on two hulls in the same frame. Stops at the first axis whose overlap is at most
/// `stop_at` (0: one that separates or touches; `f64::NEG_INFINITY`: never), the depth
/// then only an upper bound.
pub(super) fn separate(a: &Hull, b: &Hull, stop_at: f64) -> Separation {
    let mut best = Separation {
        depth: f64::INFINITY,
        axis: DVec3::X,
        offset: 0.0,
    };
    if a.vertices.is_empty() || b.vertices.is_empty() {
        best.depth = f64::NEG_INFINITY;
        return best;
    }
    let mut consider = |axis: DVec3| {
        let (min_a, max_a) = a.extent(axis);
        let (min_b, max_b) = b.extent(axis);
        // B above A along `axis`, or below it (then the axis is flipped).
        let (up, down) = (max_a - min_b, max_b - min_a);
        let candidate = if up <= down {
            Separation {
                depth: up,
                axis,
                offset: 0.5 * (max_a + min_b),
            }
        } else {
            Separation {
                depth: down,
                axis: -axis,
                offset: -0.5 * (min_a + max_b),
            }
        };
        let depth = candidate.depth;
        if depth < best.depth {
            best = candidate;
        }
        depth
    };
    for &n in a.normals.iter().chain(&b.normals) {
        let depth = consider(n);
        if depth <= stop_at {
            return Separation::bound(depth, n);
        }
    }
    for &ea in &a.edges {
        for &eb in &b.edges {
            let c = ea.cross(eb);
            let length = c.length();
            if length >= PARALLEL_SIN {
                let depth = consider(c / length);
                if depth <= stop_at {
                    return Separation::bound(depth, c / length);
                }
            }
        }
    }
    best
}

/// Separation of two convex polytopes by the separating axis theorem, in A's frame.
///
/// B's points are mapped into A's frame by `b_to_a` (rigid in practice; any invertible
/// affine map works). The candidate axes are A's face normals, B's face normals and the
/// normalised cross products of each edge direction of A with each of B (near-parallel
/// pairs skipped); parallel directions are tested once. The axis with the smallest
/// overlap wins, the first in that order on ties. Two boxes test 3 + 3 + 3·3 = 15 axes.
///
/// ```
/// use acsg::contact::convex_separation;
/// use acsg::geometry::ConvexPolytope;
/// use glam::{DAffine3, DVec3};
///
/// let a = ConvexPolytope::cuboid(DVec3::ZERO, DVec3::ONE);
/// let b = ConvexPolytope::cuboid(DVec3::ZERO, DVec3::ONE);
/// let s = convex_separation(&a, &b, &DAffine3::from_translation(DVec3::new(0.75, 0.0, 0.0)));
/// assert!((s.depth - 0.25).abs() < 1e-12);
/// assert_eq!(s.axis, DVec3::X);
/// ```
#[must_use]
pub fn convex_separation(a: &ConvexPolytope, b: &ConvexPolytope, b_to_a: &DAffine3) -> Separation {
    separate(&Hull::new(a, None), &Hull::new(b, Some(b_to_a)), f64::NEG_INFINITY)
}
