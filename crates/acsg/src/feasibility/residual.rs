//! Residuals of principal contacts at a pose: each vanishes exactly when its contact
//! holds with the contact region inside both elements' relative interiors (with a
//! margin) and the elements next to a point contact fall away from it.
//!
//! Every function works in the frame of the first element's part, with the second
//! part's points brought in by `map`; mirrored kinds (v-f against f-v) call the same
//! function with the parts swapped.

use glam::{DAffine3, DVec3};

use crate::geometry::{PlanarRegion, Segment, clip_convex, point_segment};
use crate::model::{EdgeId, FaceId, Part, VertexId};
use crate::tolerance::ROUNDOFF_REL;

/// A face's plane and loops as points, in its part's own frame.
#[derive(Clone, Debug)]
pub(crate) struct FaceShape {
    pub normal: DVec3,
    pub offset: f64,
    pub loops: Vec<Vec<DVec3>>,
    /// A point well inside the face: the centroid of its largest triangle.
    pub inner: DVec3,
    /// Points spread over the face's interior (for overlap tests of two faces).
    pub samples: Vec<DVec3>,
    /// The face's triangles, for the overlap of two faces when no sample lies in it.
    pub triangles: Vec<[DVec3; 3]>,
    /// The most margin the face allows from its boundary: a quarter of its width scale.
    pub widest_margin: f64,
}

impl FaceShape {
    pub fn all(part: &Part) -> Vec<FaceShape> {
        part.faces()
            .iter()
            .map(|f| {
                let at = |v: VertexId| part.vertex(v).position;
                let loops: Vec<Vec<DVec3>> = f
                    .loops
                    .iter()
                    .map(|l| l.vertices.iter().map(|&v| at(v)).collect())
                    .collect();
                let mut samples = Vec::new();
                let mut inner = (at(f.outer().vertices[0]), -1.0);
                for t in &f.triangles {
                    let [a, b, c] = t.map(at);
                    let centroid = (a + b + c) / 3.0;
                    let area = (b - a).cross(c - a).length();
                    if area > inner.1 {
                        inner = (centroid, area);
                    }
                    samples.push(centroid);
                    samples.extend([(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5].map(|m| (m + centroid) * 0.5));
                }
                let perimeter: f64 = loops
                    .iter()
                    .flat_map(|l| (0..l.len()).map(move |i| l[i].distance(l[(i + 1) % l.len()])))
                    .sum();
                let width = if perimeter > 0.0 { 2.0 * f.area / perimeter } else { 0.0 };
                FaceShape {
                    normal: f.normal,
                    offset: f.offset,
                    loops,
                    inner: inner.0,
                    samples,
                    triangles: f.triangles.iter().map(|t| t.map(at)).collect(),
                    widest_margin: 0.25 * width,
                }
            })
            .collect()
    }

    /// The margin kept from the face's boundary: the search's margin, at most
    /// [`FaceShape::widest_margin`].
    pub fn margin(&self, m: Margins) -> f64 {
        m.margin.min(self.widest_margin)
    }

    fn region(&self) -> PlanarRegion<'_> {
        PlanarRegion {
            normal: self.normal,
            offset: self.offset,
            loops: &self.loops,
            triangles: &[],
        }
    }

    fn plane_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// The largest [`FaceShape::inside_depth`] along a segment: at the middle of every
    /// piece between the places where the segment's projection crosses the face's
    /// boundary (the depth is largest inside a piece, not at fixed fractions of the
    /// segment, which miss a short piece inside the face), and at nine even samples.
    pub fn deepest_along(&self, p0: DVec3, p1: DVec3) -> f64 {
        let region = self.region();
        let (q0, q1) = (region.project(p0), region.project(p1));
        let d = q1 - q0;
        let mut cuts = vec![0.0, 1.0];
        for s in region.boundary_segments() {
            // Where q0 + t d meets the boundary segment's line, within both.
            let e = s.b - s.a;
            let n = self.normal;
            let denom = d.cross(e).dot(n);
            if denom.abs() <= f64::EPSILON * d.length() * e.length() {
                continue;
            }
            let w = s.a - q0;
            let t = w.cross(e).dot(n) / denom;
            let u = w.cross(d).dot(n) / denom;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                cuts.push(t);
            }
        }
        cuts.sort_by(f64::total_cmp);
        let middles = cuts.windows(2).map(|w| 0.5 * (w[0] + w[1]));
        let even = (1..10).map(|k| f64::from(k) / 10.0);
        middles
            .chain(even)
            .map(|t| self.inside_depth(p0.lerp(p1, t)))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// How far inside the face's outline the projection of `p` lies (negative outside).
    pub fn inside_depth(&self, p: DVec3) -> f64 {
        let region = self.region();
        let edge_distance = region
            .boundary_segments()
            .map(|s| point_segment(region.project(p), &s).0)
            .fold(f64::INFINITY, f64::min);
        if region.contains_projection(p) {
            edge_distance
        } else {
            -edge_distance
        }
    }
}

/// Penalty keeping a value at least `margin` (hinge, zero when satisfied).
pub(crate) fn hinge(value: f64, margin: f64) -> f64 {
    (margin - value).max(0.0)
}

/// One part's side of a contact: the part and its face shapes.
#[derive(Clone, Copy)]
pub(crate) struct Side<'p> {
    pub part: &'p Part,
    pub faces: &'p [FaceShape],
}

/// The interior margin, from which the clearances of neighbouring corners and the
/// margins along edges follow.
#[derive(Clone, Copy)]
pub(crate) struct Margins {
    pub margin: f64,
}

impl Margins {
    /// The clearance asked of a neighbouring corner at distance `d` from a contact: a
    /// slope of 1/100 (half a degree) is enough to keep it off the contact, and the
    /// margin at most. Asking more would rule out contacts at the edge of their normal
    /// cones.
    fn clearance(self, d: f64) -> f64 {
        self.margin.min(0.01 * d)
    }
    fn along(self, length: f64) -> f64 {
        (self.margin / length).min(0.25)
    }
}

/// A face of `a` against a vertex of `b`: the vertex on the plane, inside the face, its
/// neighbours rising off the plane.
pub(crate) fn face_vertex(a: Side, f: FaceId, b: Side, v: VertexId, map: &DAffine3, m: Margins, out: &mut Vec<f64>) {
    let face = &a.faces[f.index()];
    let p = map.transform_point3(b.part.vertex(v).position);
    out.push(face.plane_distance(p));
    out.push(hinge(face.inside_depth(p), face.margin(m)));
    for w in neighbours(b.part, v) {
        let q = map.transform_point3(w);
        out.push(hinge(face.normal.dot(q - p), m.clearance(p.distance(q))));
    }
}

/// A face of `a` against an edge of `b`: both ends on the plane, part of the edge inside
/// the face, the edge's faces rising off the plane.
pub(crate) fn face_edge(a: Side, f: FaceId, b: Side, e: EdgeId, map: &DAffine3, m: Margins, out: &mut Vec<f64>) {
    let face = &a.faces[f.index()];
    let [p0, p1] = b.part.edge_points(e).map(|p| map.transform_point3(p));
    out.push(face.plane_distance(p0));
    out.push(face.plane_distance(p1));
    let deepest = face.deepest_along(p0, p1);
    out.push(hinge(deepest, face.margin(m)));
    // The edge's faces rise off the plane: across the edge, not at its ends, which may
    // lie beyond the face.
    rises(b.part, e, map, face.normal, m, out);
}

/// A face of `a` against a face of `b`: `b`'s face in the plane, the two overlapping
/// over an area.
#[allow(clippy::too_many_arguments)]
pub(crate) fn face_face(
    a: Side,
    f: FaceId,
    b: Side,
    g: FaceId,
    map: &DAffine3,
    back: &DAffine3,
    m: Margins,
    out: &mut Vec<f64>,
) {
    let (face, other) = (&a.faces[f.index()], &b.faces[g.index()]);
    for p in other.loops.iter().flatten() {
        out.push(face.plane_distance(map.transform_point3(*p)));
    }
    let margin = face.margin(m).min(other.margin(m));
    out.push(hinge(overlap_depth(face, other, map, back, margin), margin));
}

/// The area over which two faces overlap, seen along the first's normal (the second
/// projected onto the first's plane): the sum over pairs of their triangles of the
/// areas the two have in common. `map` takes the second face's part to the first's.
pub(crate) fn overlap_area(face: &FaceShape, other: &FaceShape, map: &DAffine3) -> f64 {
    let mut area = 0.0;
    for t in &face.triangles {
        for u in &other.triangles {
            let [a, b, c] = u.map(|p| {
                let q = map.transform_point3(p);
                q - face.normal * face.plane_distance(q)
            });
            // The other triangle's sides, each with the direction its outside lies in.
            let turn = (b - a).cross(c - a).dot(face.normal).signum();
            let mut poly = t.to_vec();
            for (x, y) in [(a, b), (b, c), (c, a)] {
                let outward = (y - x).cross(face.normal).normalize_or_zero() * turn;
                poly = clip_convex(&poly, outward, outward.dot(x));
                if poly.len() < 3 {
                    break;
                }
            }
            if poly.len() >= 3 {
                let twice: DVec3 = (1..poly.len() - 1)
                    .map(|i| (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]))
                    .sum();
                area += 0.5 * twice.dot(face.normal).abs();
            }
        }
    }
    area
}

/// How deep two faces overlap, seen along the first's normal: the largest, over points
/// of either, of how far inside both outlines a point lies (negative when they do not
/// overlap). The samples first; when they give less than `enough`, the centres of the
/// overlaps of the faces' triangles too (a small overlap may hold no sample). `map`
/// takes the second face's part to the first's, `back` the other way.
pub(crate) fn overlap_depth(face: &FaceShape, other: &FaceShape, map: &DAffine3, back: &DAffine3, enough: f64) -> f64 {
    let depth_in_both = |p_a: DVec3, p_b: DVec3| face.inside_depth(p_a).min(other.inside_depth(p_b));
    let mut deepest = other
        .samples
        .iter()
        .map(|&p| depth_in_both(map.transform_point3(p), p))
        .chain(face.samples.iter().map(|&p| depth_in_both(p, back.transform_point3(p))))
        .fold(f64::NEG_INFINITY, f64::max);
    if deepest < enough {
        // The centres of the overlaps of the two faces' triangles (the other face's
        // projected onto this plane, turned to run the same way round).
        for t in &face.triangles {
            for u in &other.triangles {
                let [a, b, c] = u.map(|p| {
                    let q = map.transform_point3(p);
                    q - face.normal * face.plane_distance(q)
                });
                let mut poly = t.to_vec();
                for (x, y) in [(a, c), (c, b), (b, a)] {
                    let outward = (y - x).cross(face.normal).normalize_or_zero();
                    poly = clip_convex(&poly, outward, outward.dot(x));
                    if poly.len() < 3 {
                        break;
                    }
                }
                if poly.len() >= 3 {
                    let centre = poly.iter().copied().sum::<DVec3>() / poly.len() as f64;
                    deepest = deepest.max(depth_in_both(centre, back.transform_point3(centre)));
                }
            }
        }
    }
    deepest
}

/// Two edges crossing at one point inside both, each edge's faces falling away from the
/// other edge. `a`'s frame; `b`'s points mapped by `map`.
pub(crate) fn edge_crossing(a: Side, e: EdgeId, b: Side, x: EdgeId, map: &DAffine3, m: Margins, out: &mut Vec<f64>) {
    let [a0, a1] = a.part.edge_points(e);
    let [b0, b1] = b.part.edge_points(x).map(|p| map.transform_point3(p));
    let (u, w) = (a1 - a0, b1 - b0);
    let n = u.cross(w);
    // Closest points of the two lines, as parameters along each edge.
    let r = a0 - b0;
    let (uu, uw, ww, ur, wr) = (u.dot(u), u.dot(w), w.dot(w), u.dot(r), w.dot(r));
    let det = uu * ww - uw * uw;
    let (s, v) = if det > ROUNDOFF_REL * uu * ww {
        ((uw * wr - ww * ur) / det, (uu * wr - uw * ur) / det)
    } else {
        (0.5, 0.5)
    };
    out.push(if n.length() > ROUNDOFF_REL * u.length() * w.length() {
        n.normalize().dot(b0 - a0)
    } else {
        point_segment(b0, &Segment::new(a0, a1)).0
    });
    let (mu, mw) = (m.along(u.length()), m.along(w.length()));
    out.push(hinge(s, mu) + hinge(1.0 - s, mu));
    out.push(hinge(v, mw) + hinge(1.0 - v, mw));
    // Along the common normal (outward from `a` at e), `a`'s neighbouring corners lie
    // below the contact and `b`'s above it.
    let [fa, ga] = a.part.edge(e).faces.map(|f| a.part.face(f).normal);
    if n.length() > 0.0 {
        let n = n.normalize();
        let n = if n.dot(fa + ga) < 0.0 { -n } else { n };
        // Across each edge, not at its ends: a face may be non-convex, and the edges
        // at an end have nothing to do with a crossing inside the edge.
        rises(a.part, e, &DAffine3::IDENTITY, -n, m, out);
        rises(b.part, x, map, n, m, out);
    }
}

/// Two directions perpendicular to `d` (unit length, orthogonal to each other).
pub(super) fn perpendiculars(d: DVec3) -> [DVec3; 2] {
    let d = d.normalize_or_zero();
    let p = d.any_orthonormal_vector();
    [p, d.cross(p)]
}

/// An edge of `a` against a vertex of `b`: the vertex on the edge's line, inside it.
pub(crate) fn edge_vertex(a: Side, e: EdgeId, b: Side, v: VertexId, map: &DAffine3, m: Margins, out: &mut Vec<f64>) {
    let [a0, a1] = a.part.edge_points(e);
    let p = map.transform_point3(b.part.vertex(v).position);
    let d = a1 - a0;
    out.extend(perpendiculars(d).map(|n| n.dot(p - a0)));
    let s = d.dot(p - a0) / d.length_squared();
    let margin = m.along(d.length());
    out.push(hinge(s, margin) + hinge(1.0 - s, margin));
}

/// Collinear edges overlapping along a segment.
pub(crate) fn edge_along_edge(a: Side, e: EdgeId, b: Side, x: EdgeId, map: &DAffine3, m: Margins, out: &mut Vec<f64>) {
    let [a0, a1] = a.part.edge_points(e);
    let ends = b.part.edge_points(x).map(|p| map.transform_point3(p));
    let d = a1 - a0;
    let across = perpendiculars(d);
    for p in ends {
        out.extend(across.map(|n| n.dot(p - a0)));
    }
    let [s0, s1] = ends.map(|p| d.dot(p - a0) / d.length_squared());
    let overlap = s0.max(s1).min(1.0) - s0.min(s1).max(0.0);
    out.push(hinge(overlap, m.along(d.length())));
}

/// Vertex on vertex.
pub(crate) fn vertex_vertex(a: Side, v: VertexId, b: Side, w: VertexId, map: &DAffine3, out: &mut Vec<f64>) {
    let gap = map.transform_point3(b.part.vertex(w).position) - a.part.vertex(v).position;
    out.extend(gap.to_array());
}

/// Each face of an edge (mapped by `map`) turns to the positive side of `normal`
/// across the edge: its direction into the face, over the edge's length, rises by the
/// clearance of that length.
fn rises(part: &Part, e: EdgeId, map: &DAffine3, normal: DVec3, m: Margins, out: &mut Vec<f64>) {
    let [p, q] = part.edge_points(e);
    let length = p.distance(q);
    for u in part.edge_wedge(e) {
        let u = map.transform_vector3(u);
        out.push(hinge(normal.dot(u) * length, m.clearance(length)));
    }
}

/// The other end points of the edges at a vertex.
pub(crate) fn neighbours(part: &Part, v: VertexId) -> Vec<DVec3> {
    part.vertex(v)
        .edges
        .iter()
        .map(|&e| {
            let [a, b] = part.edge(e).vertices;
            part.vertex(if a == v { b } else { a }).position
        })
        .collect()
}
