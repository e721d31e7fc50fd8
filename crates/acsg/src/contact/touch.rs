//! I(a, b) = relint(a) ∩ relint(b) for a pair of placed elements, under a tolerance,
//! and the principal rule of docs/concepts.md#principal-contacts.
//!
//! Relative interiors are shrunk by the tolerance `tol`: a point counts as inside an
//! edge only when it is farther than `tol` from both end points, inside a face only
//! when it is farther than `tol` from the face's boundary. A point touching near an
//! edge's end is thereby classified as touching the end vertex, so every contact point
//! is attributed to the lowest-dimensional elements it lies on.
//!
//! Crossings that only occur when the parts penetrate (an edge piercing a face, two
//! faces crossing along a line) are not contacts; the penetration check reports them.

use glam::DVec3;

use super::placed::{PlacedPart, Shape};
use crate::geometry::{
    PlanarRegion, Segment, clip_convex, point_region, point_segment, region_region, segment_region, segment_segment,
};
use crate::model::{ElementId, FaceId, Part};
use crate::tolerance::FLUSH_TILT;

/// How an edge or face lying on a face is read where it passes beyond the face's rim
/// at a tiny angle (docs/concepts.md#tolerances).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reading {
    /// On the face when within the tolerance of its plane from end to end (every
    /// corner): the contact module's reading, which the prover's rules follow.
    Ends,
    /// On the face when within the tolerance over their overlap only, whatever lies
    /// beyond the face's rim does, up to [`FLUSH_TILT`]: DOMAIN's reading. A witness is
    /// robust only where both readings agree.
    Overlap,
}

/// The set I(a, b) where two elements touch.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TouchSet {
    /// A single point.
    Point(DVec3),
    /// Segments (an edge lying along an edge, or in a face).
    Segments(Vec<Segment>),
    /// Convex planar pieces whose union is the overlap of two coplanar faces; `normal`
    /// orients them (counter-clockwise).
    Region { normal: DVec3, pieces: Vec<Vec<DVec3>> },
}

impl TouchSet {
    fn dimension(&self) -> u8 {
        match self {
            TouchSet::Point(_) => 0,
            TouchSet::Segments(_) => 1,
            TouchSet::Region { .. } => 2,
        }
    }

    /// Whether `other` lies in the closure of this set (within `tol`).
    fn closure_contains(&self, other: &TouchSet, tol: f64) -> bool {
        match (self, other) {
            (TouchSet::Segments(segs), TouchSet::Point(p)) => segs.iter().any(|s| point_segment(*p, s).0 <= tol),
            (TouchSet::Region { normal, pieces }, TouchSet::Point(p)) => pieces
                .iter()
                .any(|piece| convex_outside_distance(piece, *normal, *p) <= tol),
            (TouchSet::Region { normal, pieces }, TouchSet::Segments(segs)) => {
                segs.iter().all(|s| segment_covered(s, pieces, *normal, tol))
            }
            _ => false,
        }
    }
}

/// How far `p` lies outside a convex planar polygon (counter-clockwise around `normal`),
/// counting the distance from the plane too; negative or zero inside.
fn convex_outside_distance(piece: &[DVec3], normal: DVec3, p: DVec3) -> f64 {
    let n = piece.len();
    let plane = normal.dot(p - piece[0]).abs();
    let sides = (0..n).map(|i| {
        let (u, v) = (piece[i], piece[(i + 1) % n]);
        let outward = (v - u).cross(normal).normalize_or_zero();
        outward.dot(p - u)
    });
    sides.fold(plane, f64::max)
}

/// Whether a segment is covered by the union of convex pieces grown by `tol`.
fn segment_covered(s: &Segment, pieces: &[Vec<DVec3>], normal: DVec3, tol: f64) -> bool {
    let length = s.a.distance(s.b);
    if length <= tol {
        return pieces
            .iter()
            .any(|piece| convex_outside_distance(piece, normal, s.a) <= tol);
    }
    let mut intervals: Vec<(f64, f64)> = Vec::new();
    for piece in pieces {
        if normal.dot(s.a - piece[0]).abs() > tol || normal.dot(s.b - piece[0]).abs() > tol {
            continue;
        }
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let n = piece.len();
        for i in 0..n {
            let (u, v) = (piece[i], piece[(i + 1) % n]);
            let outward = (v - u).cross(normal).normalize_or_zero();
            let (da, db) = (outward.dot(s.a - u) - tol, outward.dot(s.b - u) - tol);
            if da > 0.0 && db > 0.0 {
                hi = -1.0;
                break;
            }
            if da > 0.0 {
                lo = lo.max(da / (da - db));
            } else if db > 0.0 {
                hi = hi.min(da / (da - db));
            }
        }
        if hi > lo {
            intervals.push((lo, hi));
        }
    }
    intervals.sort_by(|x, y| x.0.total_cmp(&y.0));
    let slack = tol / length;
    let mut reached = 0.0;
    for (lo, hi) in intervals {
        if lo > reached + slack {
            return false;
        }
        reached = f64::max(reached, hi);
    }
    reached >= 1.0 - slack
}

/// Distance from a point to a face's boundary.
fn boundary_distance(region: &PlanarRegion<'_>, p: DVec3) -> f64 {
    region
        .boundary_segments()
        .map(|s| point_segment(p, &s).0)
        .fold(f64::INFINITY, f64::min)
}

/// Whether a point touches the relative interior of a face (shrunk by `tol`).
fn point_in_face(region: &PlanarRegion<'_>, p: DVec3, tol: f64) -> bool {
    region.signed_distance(p).abs() <= tol && region.contains_projection(p) && boundary_distance(region, p) > tol
}

/// Whether `p` touches the relative interior of a segment (shrunk by `tol`).
fn point_in_segment(s: &Segment, p: DVec3, tol: f64) -> bool {
    point_segment(p, s).0 <= tol && p.distance(s.a) > tol && p.distance(s.b) > tol
}

fn line_distance(s: &Segment, p: DVec3) -> f64 {
    let d = (s.b - s.a).normalize_or_zero();
    (p - s.a).cross(d).length()
}

/// Two edges: a crossing point, or the overlap of two collinear edges. With
/// [`Reading::Overlap`], a crossing with an end of either edge within `tol` of the
/// other edge, more than `2 tol` from the crossing, is read as the edges running
/// together from that end to the crossing ([`running_together`]).
fn edge_edge(s1: &Segment, s2: &Segment, tol: f64, reading: Reading) -> Option<TouchSet> {
    let collinear = [s2.a, s2.b].iter().all(|&p| line_distance(s1, p) <= tol)
        && [s1.a, s1.b].iter().all(|&p| line_distance(s2, p) <= tol);
    if collinear {
        let len = s1.a.distance(s1.b);
        let dir = (s1.b - s1.a) / len;
        let (ta, tb) = (dir.dot(s2.a - s1.a), dir.dot(s2.b - s1.a));
        let (lo, hi) = (ta.min(tb).max(0.0), ta.max(tb).min(len));
        // The overlap must survive shrinking both relative interiors by tol.
        return (hi - lo > 2.0 * tol).then(|| TouchSet::Segments(vec![Segment::new(s1.a + dir * lo, s1.a + dir * hi)]));
    }
    let (d, s, t) = segment_segment(s1, s2);
    let (p, q) = (s1.at(s), s2.at(t));
    if !(d <= tol && point_in_segment(s1, p, tol) && point_in_segment(s2, q, tol)) {
        return None;
    }
    let crossing = (p + q) * 0.5;
    if reading == Reading::Overlap {
        if let Some(along) = running_together(s1, s2, crossing, tol) {
            return Some(TouchSet::Segments(vec![along]));
        }
    }
    Some(TouchSet::Point(crossing))
}

/// Two crossing edges of which one has an end within `tol` of the other edge, more
/// than `2 tol` from the crossing: that edge has two points on the other's line, so in
/// exact geometry the two are collinear and run together (DOMAIN §7 reads an edge with
/// two points on a face's plane as lying in it; this is the same reading for a line).
/// Within the tolerance they cross at an angle below the tolerance over their
/// distance, a band no exact pose reaches (a box's corner on the L-block's concave
/// corner with the box's edge from it nearly along the floor's edge). The stretch
/// between the end and the crossing, or `None`.
fn running_together(s1: &Segment, s2: &Segment, crossing: DVec3, tol: f64) -> Option<Segment> {
    [(s1.a, s2), (s1.b, s2), (s2.a, s1), (s2.b, s1)]
        .into_iter()
        .find(|(end, other)| point_segment(*end, other).0 <= tol && end.distance(crossing) > 2.0 * tol)
        .map(|(end, _)| Segment::new(crossing, end))
}

/// An edge lying in a face's plane: the parts of it inside the face's relative
/// interior. The edge lies in the plane when both its ends do, or with
/// [`Reading::Overlap`] when its stretch over the face does (docs/concepts.md#tolerances:
/// an edge with two points within the tolerance of a face's plane lies in it wherever
/// it overlaps the face), whatever its ends beyond the face's rim do: an edge lying on
/// a wall and passing over the wall's top.
fn edge_face(s: &Segment, region: &PlanarRegion<'_>, tol: f64, reading: Reading) -> Option<TouchSet> {
    let (height_a, height_b) = (region.signed_distance(s.a), region.signed_distance(s.b));
    let s = &if height_a.abs() <= tol && height_b.abs() <= tol {
        *s
    } else if reading == Reading::Overlap {
        stretch_over_face(s, region, (height_a, height_b), tol)?
    } else {
        return None;
    };
    let length = s.a.distance(s.b);
    // Break the edge where it meets the face's boundary; classify each piece by its
    // midpoint.
    let cuts = boundary_cuts(s, region, tol);
    let mut inside: Vec<Segment> = Vec::new();
    for w in cuts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if (t1 - t0) * length <= tol {
            continue;
        }
        if point_in_face(region, s.at(0.5 * (t0 + t1)), tol) {
            match inside.last_mut() {
                Some(last) if last.b.distance(s.at(t0)) <= tol => last.b = s.at(t1),
                _ => inside.push(Segment::new(s.at(t0), s.at(t1))),
            }
        }
    }
    // The edge's own end points are not part of its relative interior.
    inside.retain(|seg| seg.a.distance(seg.b) > 2.0 * tol);
    (!inside.is_empty()).then_some(TouchSet::Segments(inside))
}

/// Where a segment meets a face's boundary (within `tol`), as parameters along it,
/// with its ends, sorted: between two cuts a piece lies wholly inside or outside.
fn boundary_cuts(s: &Segment, region: &PlanarRegion<'_>, tol: f64) -> Vec<f64> {
    let mut cuts = vec![0.0, 1.0];
    for g in region.boundary_segments() {
        let (d, t, _) = segment_segment(s, &g);
        if d <= tol {
            cuts.push(t);
        }
        for p in [g.a, g.b] {
            let (d, t) = point_segment(p, s);
            if d <= tol {
                cuts.push(t);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    cuts
}

/// The stretch of `s` over the face (its projection on the face's closure, from the
/// first such point to the last), when the stretch lies within `tol` of the face's
/// plane and is longer than `2 tol`, and the edge tilts off the plane by at most
/// [`FLUSH_TILT`]; `heights` are the signed distances of `s`'s ends from the plane.
/// The height is linear along the edge, so the stretch's two ends decide.
fn stretch_over_face(s: &Segment, region: &PlanarRegion<'_>, heights: (f64, f64), tol: f64) -> Option<Segment> {
    let (h0, h1) = heights;
    let rise = h1 - h0;
    let length = s.a.distance(s.b);
    // Parallel to the plane (and farther than `tol`), or steeper than a flush reading.
    if rise.abs() <= f64::EPSILON * (h0.abs() + h1.abs()) || rise.abs() > FLUSH_TILT * length {
        return None;
    }
    // Where the edge is within `tol` of the plane: too short there, it lies in no plane.
    let (t0, t1) = ((-tol - h0) / rise, (tol - h0) / rise);
    if (t0.max(t1).min(1.0) - t0.min(t1).max(0.0)) * length <= 2.0 * tol {
        return None;
    }
    let flat = Segment::new(region.project(s.a), region.project(s.b));
    let cuts = boundary_cuts(&flat, region, tol);
    let over = |t: f64| {
        let p = flat.at(t);
        region.contains_projection(p) || boundary_distance(region, p) <= tol
    };
    let mut span: Option<(f64, f64)> = None;
    for w in cuts.windows(2) {
        if over(0.5 * (w[0] + w[1])) {
            span = Some((span.map_or(w[0], |(lo, _)| lo), w[1]));
        }
    }
    let (lo, hi) = span?;
    let height = |t: f64| h0 + rise * t;
    (height(lo).abs() <= tol && height(hi).abs() <= tol && (hi - lo) * length > 2.0 * tol)
        .then(|| Segment::new(s.at(lo), s.at(hi)))
}

/// Two coplanar faces facing each other: their overlap, as convex pieces (pairs of
/// triangles clipped against each other), kept where wider than `tol`. Coplanar: one
/// face's outline within `tol` of the other's plane, or with [`Reading::Overlap`] the
/// corners of their overlap.
fn face_face(f: &PlanarRegion<'_>, g: &PlanarRegion<'_>, tol: f64, reading: Reading) -> Option<TouchSet> {
    if f.normal.dot(g.normal) >= 0.0 {
        return None;
    }
    let g_in_f = g.loops[0].iter().all(|&p| f.signed_distance(p).abs() <= tol);
    let f_in_g = f.loops[0].iter().all(|&p| g.signed_distance(p).abs() <= tol);
    // Neither outline within the tolerance of the other's plane: read over the overlap,
    // the faces may still lie on each other where they overlap, with parts beyond the
    // other's outline off its plane (a face flat on a wall and passing over the wall's
    // rim), when nearly flush and neither wholly on one side of the other: the
    // overlap's corners decide, as an edge's stretch over a face does.
    let checked = !(g_in_f || f_in_g);
    let one_side = |loop_: &[DVec3], plane: &PlanarRegion<'_>| {
        loop_.iter().all(|&p| plane.signed_distance(p) > tol) || loop_.iter().all(|&p| plane.signed_distance(p) < -tol)
    };
    if checked
        && (reading == Reading::Ends
            || f.normal.cross(g.normal).length() > FLUSH_TILT
            || one_side(&g.loops[0], f)
            || one_side(&f.loops[0], g))
    {
        return None;
    }
    // The distance along f's normal from f's plane to g's, at a point of f's plane.
    let gap = |p: DVec3| g.signed_distance(p) / g.normal.dot(f.normal);
    let normal = f.normal;
    let mut pieces = Vec::new();
    for tf in f.triangles {
        for tg in g.triangles {
            // g's triangles run clockwise around f's normal: reverse them.
            let mut poly: Vec<DVec3> = tf.to_vec();
            let clip = [tg[0], tg[2], tg[1]].map(|p| f.project(p));
            for i in 0..3 {
                let (u, v) = (clip[i], clip[(i + 1) % 3]);
                let outward = (v - u).cross(normal).normalize_or_zero();
                poly = clip_convex(&poly, outward, outward.dot(u));
                if poly.len() < 3 {
                    break;
                }
            }
            // Clipping can leave two corners a rounding apart: an edge that short has
            // no direction, and the coverage test would read it as a half-plane.
            poly.dedup_by(|q, p| p.distance(*q) <= tol);
            if poly.len() > 1 && poly[0].distance(poly[poly.len() - 1]) <= tol {
                poly.pop();
            }
            if poly.len() >= 3 && inradius_bound(&poly, normal) > tol {
                if checked && poly.iter().any(|&p| gap(p).abs() > tol) {
                    return None;
                }
                pieces.push(poly);
            }
        }
    }
    (!pieces.is_empty()).then_some(TouchSet::Region { normal, pieces })
}

/// Twice the area over the perimeter: a lower bound of the polygon's inradius scale
/// (a sliver of width w has about w / 2).
fn inradius_bound(poly: &[DVec3], normal: DVec3) -> f64 {
    let n = poly.len();
    let area2: f64 = (1..n - 1)
        .map(|i| (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).dot(normal))
        .sum();
    let perimeter: f64 = (0..n).map(|i| poly[i].distance(poly[(i + 1) % n])).sum();
    if perimeter > 0.0 { area2 / perimeter } else { 0.0 }
}

/// I(a, b) of element `a` of the fixed part and element `b` of the moving part, both
/// placed in the fixed part's frame, or `None` when they do not touch.
pub(crate) fn touch(
    fixed: &PlacedPart<'_>,
    a: ElementId,
    moving: &PlacedPart<'_>,
    b: ElementId,
    tol: f64,
    reading: Reading,
) -> Option<TouchSet> {
    use Shape::{Point, Region, Segment};
    match (fixed.shape(a), moving.shape(b)) {
        (Point(p), Point(q)) => (p.distance(q) <= tol).then(|| TouchSet::Point((p + q) * 0.5)),
        (Point(p), Segment(s)) | (Segment(s), Point(p)) => point_in_segment(&s, p, tol).then_some(TouchSet::Point(p)),
        (Point(p), Region(r)) | (Region(r), Point(p)) => point_in_face(&r, p, tol).then_some(TouchSet::Point(p)),
        (Segment(s), Segment(t)) => edge_edge(&s, &t, tol, reading),
        (Segment(s), Region(r)) | (Region(r), Segment(s)) => edge_face(&s, &r, tol, reading),
        (Region(f), Region(g)) => face_face(&f, &g, tol, reading),
    }
}

/// The elements whose closure holds `e`, `e` itself included.
pub(crate) fn closure_holders(part: &Part, e: ElementId) -> Vec<ElementId> {
    let mut out = vec![e];
    match e {
        ElementId::Vertex(v) => {
            let vertex = part.vertex(v);
            out.extend(vertex.edges.iter().map(|&x| ElementId::Edge(x)));
            out.extend(vertex.faces.iter().map(|&x| ElementId::Face(x)));
        }
        ElementId::Edge(x) => out.extend(part.edge(x).faces.iter().map(|&f| ElementId::Face(f))),
        ElementId::Face(_) => {}
    }
    out
}

/// The principal touches among `touches` (docs/concepts.md#principal-contacts): a touch (a,
/// b) is implied, not principal, when a touch (a'', b'') with a ⊆ closure(a''), b ⊆
/// closure(b'') has a set whose closure contains I(a, b).
pub(crate) fn principal(
    fixed: &Part,
    moving: &Part,
    touches: &[(ElementId, ElementId, TouchSet)],
    tol: f64,
) -> Vec<(ElementId, ElementId)> {
    let index: std::collections::HashMap<(ElementId, ElementId), usize> =
        touches.iter().enumerate().map(|(i, (a, b, _))| ((*a, *b), i)).collect();
    touches
        .iter()
        .filter(|(a, b, set)| {
            let holders_a = closure_holders(fixed, *a);
            let holders_b = closure_holders(moving, *b);
            !holders_a.iter().any(|&a2| {
                holders_b.iter().any(|&b2| {
                    (a2, b2) != (*a, *b)
                        && index.get(&(a2, b2)).is_some_and(|&i| {
                            let superior = &touches[i].2;
                            superior.dimension() > set.dimension() && superior.closure_contains(set, tol)
                        })
                })
            })
        })
        .map(|(a, b, _)| (*a, *b))
        .collect()
}

/// Whether a face of either element has the other element wholly more than `gap` off
/// its plane, on one side: a cheap proof that the two are more than `gap` apart.
pub(crate) fn apart_by_plane(
    fixed: &PlacedPart<'_>,
    a: ElementId,
    moving: &PlacedPart<'_>,
    b: ElementId,
    gap: f64,
) -> bool {
    let beyond = |plane: &PlacedPart<'_>, f: FaceId, other: &PlacedPart<'_>, e: ElementId| {
        let region = plane.region(f);
        let side = |p: DVec3| region.normal.dot(p) - region.offset;
        let (mut above, mut below) = (true, true);
        let mut check = |p: DVec3| {
            let d = side(p);
            above &= d > gap;
            below &= d < -gap;
        };
        match e {
            ElementId::Vertex(v) => check(other.vertex(v)),
            ElementId::Edge(x) => {
                let s = other.segment(x);
                check(s.a);
                check(s.b);
            }
            ElementId::Face(g) => {
                for &v in &other.part.face(g).outer().vertices {
                    check(other.vertex(v));
                }
            }
        }
        above || below
    };
    matches!(a, ElementId::Face(f) if beyond(fixed, f, moving, b))
        || matches!(b, ElementId::Face(g) if beyond(moving, g, fixed, a))
}

/// The distance between two placed elements.
pub(crate) fn distance(fixed: &PlacedPart<'_>, a: ElementId, moving: &PlacedPart<'_>, b: ElementId) -> f64 {
    use Shape::{Point, Region, Segment};
    match (fixed.shape(a), moving.shape(b)) {
        (Point(p), Point(q)) => p.distance(q),
        (Point(p), Segment(s)) | (Segment(s), Point(p)) => point_segment(p, &s).0,
        (Point(p), Region(r)) | (Region(r), Point(p)) => point_region(p, &r).0,
        (Segment(s), Segment(t)) => segment_segment(&s, &t).0,
        (Segment(s), Region(r)) | (Region(r), Segment(s)) => segment_region(&s, &r),
        (Region(f), Region(g)) => region_region(&f, &g),
    }
}
