//! Distances between points, segments (edges) and planar regions (faces).
//!
//! Exact Euclidean distances (up to floating-point rounding) between segments (edges),
//! points (vertices) and planar polygons with holes (faces), in the style of parry's
//! `query` module. All inputs are assumed to be expressed in one common frame; the
//! functions make no geometric tolerance decisions of their own (the caller compares the
//! returned distances against the policy of [`crate::tolerance`]).

use glam::{DVec2, DVec3};

/// A straight segment from `a` to `b` (an edge placed in the common frame). It may be
/// degenerate (`a == b`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start point (parameter 0).
    pub a: DVec3,
    /// End point (parameter 1).
    pub b: DVec3,
}

impl Segment {
    /// The segment from `a` to `b`.
    #[must_use]
    pub fn new(a: DVec3, b: DVec3) -> Segment {
        Segment { a, b }
    }

    /// The point at parameter `t` (`a` at 0, `b` at 1).
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.a + (self.b - self.a) * t
    }
}

/// A planar polygon with holes (a face placed in the common frame), borrowing its
/// boundary and triangulation.
///
/// `loops[0]` is the outer loop (counter-clockwise around `normal`), the other loops are
/// holes (clockwise); each loop is closed implicitly (its last point connects to its
/// first). All points lie in the plane `normal · p = offset`, `normal` being a unit
/// vector. `triangles` is a triangulation of the region; the queries here only use the
/// loops (containment is decided by the crossing number over all loops), so the
/// triangulation is carried for callers and may be empty.
#[derive(Clone, Copy, Debug)]
pub struct PlanarRegion<'a> {
    /// Unit normal of the plane.
    pub normal: DVec3,
    /// Plane offset: points `p` of the region satisfy `normal · p = offset`.
    pub offset: f64,
    /// The outer loop first, then one loop per hole.
    pub loops: &'a [Vec<DVec3>],
    /// A triangulation of the region (not used by the queries).
    pub triangles: &'a [[DVec3; 3]],
}

impl PlanarRegion<'_> {
    /// Every boundary segment of every loop (the closing segment included).
    pub fn boundary_segments(&self) -> impl Iterator<Item = Segment> + '_ {
        self.loops.iter().flat_map(|lp| {
            let n = lp.len();
            (0..n).map(move |i| Segment::new(lp[i], lp[(i + 1) % n]))
        })
    }

    /// Signed distance of `p` from the region's plane (positive on the normal's side).
    #[must_use]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// The orthogonal projection of `p` onto the region's plane.
    #[must_use]
    pub fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * self.signed_distance(p)
    }

    /// Whether the orthogonal projection of `p` onto the plane lies inside the region
    /// (crossing number over all loops, so points inside a hole are outside). Points on
    /// the boundary may go either way; every query here treats that case exactly anyway,
    /// because the boundary distance is then the plane distance.
    #[must_use]
    pub fn contains_projection(&self, p: DVec3) -> bool {
        let drop = dominant_axis(self.normal);
        let q = to_2d(self.project(p), drop);
        let mut inside = false;
        for lp in self.loops {
            let n = lp.len();
            for i in 0..n {
                let u = to_2d(lp[i], drop);
                let v = to_2d(lp[(i + 1) % n], drop);
                if (u.y > q.y) != (v.y > q.y) {
                    let x = u.x + (q.y - u.y) / (v.y - u.y) * (v.x - u.x);
                    if q.x < x {
                        inside = !inside;
                    }
                }
            }
        }
        inside
    }
}

/// Index of the largest component of `n` in absolute value.
fn dominant_axis(n: DVec3) -> usize {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    }
}

/// Drops coordinate `drop` of `p`.
fn to_2d(p: DVec3, drop: usize) -> DVec2 {
    match drop {
        0 => DVec2::new(p.y, p.z),
        1 => DVec2::new(p.z, p.x),
        _ => DVec2::new(p.x, p.y),
    }
}

/// Distance from `p` to the segment `s`, and the parameter `t ∈ [0, 1]` of the closest
/// point `s.at(t)`. A degenerate segment yields `t = 0`.
#[must_use]
pub fn point_segment(p: DVec3, s: &Segment) -> (f64, f64) {
    let d = s.b - s.a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((p - s.a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.distance(s.at(t)), t)
}

/// Distance between two segments and the parameters `(s, t)` of a closest pair
/// `s1.at(s)`, `s2.at(t)`, both in `[0, 1]`.
///
/// The clamped closest-point algorithm of Ericson, "Real-Time Collision Detection",
/// 5.1.9, handling degenerate (zero-length) and parallel segments. Its result is then
/// compared with the four end-point-to-segment distances, so that nearly parallel
/// segments, where the unclamped line solution is ill-conditioned, still get the exact
/// minimum (the minimum of two non-parallel segments is either interior to both, where
/// the line solution is well conditioned, or involves an end point).
#[must_use]
pub fn segment_segment(s1: &Segment, s2: &Segment) -> (f64, f64, f64) {
    let d1 = s1.b - s1.a;
    let d2 = s2.b - s2.a;
    let r = s1.a - s2.a;
    let a = d1.length_squared();
    let e = d2.length_squared();
    let f = d2.dot(r);
    let (s, t) = if a <= 0.0 && e <= 0.0 {
        (0.0, 0.0)
    } else if a <= 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            // Parallel (to machine precision): any s will do, the end-point checks
            // below settle the exact minimum.
            let mut s = if denom > f64::EPSILON * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    let mut best = (s1.at(s).distance(s2.at(t)), s, t);
    for (p, on_first, end) in [
        (s1.a, true, 0.0),
        (s1.b, true, 1.0),
        (s2.a, false, 0.0),
        (s2.b, false, 1.0),
    ] {
        let other = if on_first { s2 } else { s1 };
        let (d, u) = point_segment(p, other);
        if d < best.0 {
            best = if on_first { (d, end, u) } else { (d, u, end) };
        }
    }
    best
}

/// Distance from `p` to the region and the closest point of the region.
///
/// When the projection of `p` onto the plane lies inside the region the distance is the
/// plane distance; otherwise the closest point lies on a boundary segment.
#[must_use]
pub fn point_region(p: DVec3, region: &PlanarRegion<'_>) -> (f64, DVec3) {
    if region.contains_projection(p) {
        return (region.signed_distance(p).abs(), region.project(p));
    }
    let mut best = (f64::INFINITY, p);
    for seg in region.boundary_segments() {
        let (d, t) = point_segment(p, &seg);
        if d < best.0 {
            best = (d, seg.at(t));
        }
    }
    best
}

/// Distance between a segment and a region.
///
/// Zero when the segment meets the region's plane at a point inside the region;
/// otherwise the minimum over the segment's end points against the region and the
/// segment against each boundary segment. This is exact: if a closest pair had both
/// points interior (to the segment and to the region) at positive distance, the
/// connecting vector would be normal to the plane and to the segment, so the segment
/// would be parallel to the plane and could slide along itself at constant distance
/// until an end point or the region's boundary is reached.
#[must_use]
pub fn segment_region(seg: &Segment, region: &PlanarRegion<'_>) -> f64 {
    let da = region.signed_distance(seg.a);
    let db = region.signed_distance(seg.b);
    if (da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0) {
        let x = if da == db { seg.a } else { seg.at(da / (da - db)) };
        if region.contains_projection(x) {
            return 0.0;
        }
    }
    let mut best = point_region(seg.a, region).0.min(point_region(seg.b, region).0);
    for edge in region.boundary_segments() {
        best = best.min(segment_segment(seg, &edge).0);
    }
    best
}

/// Distance between two regions.
///
/// The minimum over each region's boundary segments against the other region. This is
/// exact for two planar polygons. If they are disjoint and a closest pair had both
/// points interior, the connecting vector would be normal to both planes; a direction
/// lying in both planes exists (the planes' common line, or any in-plane direction when
/// they are parallel), and translating both points along it keeps their distance until
/// one of them reaches its region's boundary, so some closest pair involves a boundary
/// point. If they intersect, the intersection is a bounded set lying in both planes
/// whose extreme points lie on the boundary of one region, so some boundary segment of
/// one region meets the other (and its [`segment_region`] distance is zero).
#[must_use]
pub fn region_region(r1: &PlanarRegion<'_>, r2: &PlanarRegion<'_>) -> f64 {
    let mut best = f64::INFINITY;
    for seg in r1.boundary_segments() {
        best = best.min(segment_region(&seg, r2));
    }
    for seg in r2.boundary_segments() {
        best = best.min(segment_region(&seg, r1));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use glam::DQuat;

    /// A 2D polygon with holes and a hand-made triangulation, in local coordinates.
    struct Shape2 {
        loops: Vec<Vec<DVec2>>,
        triangles: Vec<[DVec2; 3]>,
    }

    fn v2(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    fn square_with_hole() -> Shape2 {
        let o = [v2(0.0, 0.0), v2(1.0, 0.0), v2(1.0, 1.0), v2(0.0, 1.0)];
        let h = [v2(0.25, 0.25), v2(0.75, 0.25), v2(0.75, 0.75), v2(0.25, 0.75)];
        let hole = vec![h[0], h[3], h[2], h[1]];
        let triangles = (0..4)
            .flat_map(|i| {
                let j = (i + 1) % 4;
                [[o[i], o[j], h[j]], [o[i], h[j], h[i]]]
            })
            .collect();
        Shape2 {
            loops: vec![o.to_vec(), hole],
            triangles,
        }
    }

    fn l_shape() -> Shape2 {
        let o = vec![
            v2(0.0, 0.0),
            v2(1.0, 0.0),
            v2(1.0, 0.5),
            v2(0.5, 0.5),
            v2(0.5, 1.0),
            v2(0.0, 1.0),
        ];
        let triangles = (1..5).map(|i| [o[0], o[i], o[i + 1]]).collect();
        Shape2 {
            loops: vec![o],
            triangles,
        }
    }

    fn in_triangle(p: DVec2, t: &[DVec2; 3]) -> bool {
        let c = |a: DVec2, b: DVec2| (b - a).perp_dot(p - a);
        let (d0, d1, d2) = (c(t[0], t[1]), c(t[1], t[2]), c(t[2], t[0]));
        d0 >= -1e-12 && d1 >= -1e-12 && d2 >= -1e-12
    }

    /// A placed region: owned 3D data plus the rigid map from local coordinates.
    struct Placed {
        loops: Vec<Vec<DVec3>>,
        triangles: Vec<[DVec3; 3]>,
        normal: DVec3,
        offset: f64,
        /// Samples of the closed region (grid spacing 1/40, filtered by the triangulation).
        samples: Vec<DVec3>,
    }

    impl Placed {
        fn new(shape: &Shape2, rot: DQuat, shift: DVec3) -> Placed {
            let map = |p: DVec2| rot * p.extend(0.0) + shift;
            let normal = rot * DVec3::Z;
            let loops = shape
                .loops
                .iter()
                .map(|lp| lp.iter().map(|&p| map(p)).collect())
                .collect();
            let triangles = shape
                .triangles
                .iter()
                .map(|t| [map(t[0]), map(t[1]), map(t[2])])
                .collect();
            let n = 40;
            let mut samples = Vec::new();
            for i in 0..=n {
                for j in 0..=n {
                    let p = v2(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    if shape.triangles.iter().any(|t| in_triangle(p, t)) {
                        samples.push(map(p));
                    }
                }
            }
            Placed {
                loops,
                triangles,
                normal,
                offset: normal.dot(shift),
                samples,
            }
        }

        fn region(&self) -> PlanarRegion<'_> {
            PlanarRegion {
                normal: self.normal,
                offset: self.offset,
                loops: &self.loops,
                triangles: &self.triangles,
            }
        }
    }

    /// Every point of a sampled region is within this distance of a sample (grid 1/40,
    /// all vertices on grid lines, so every grid cell is wholly in or out).
    const REGION_RES: f64 = 0.5 * std::f64::consts::SQRT_2 / 40.0;

    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next()
        }
        fn vec(&mut self, lo: f64, hi: f64) -> DVec3 {
            DVec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
        }
        fn rot(&mut self) -> DQuat {
            let axis = self.vec(-1.0, 1.0).try_normalize().unwrap_or(DVec3::X);
            DQuat::from_axis_angle(axis, self.range(0.0, std::f64::consts::TAU))
        }
    }

    fn seg_samples(s: &Segment, n: u32) -> Vec<DVec3> {
        (0..n).map(|i| s.at(f64::from(i) / f64::from(n - 1))).collect()
    }

    fn sampled_min(a: &[DVec3], b: &[DVec3]) -> f64 {
        a.iter()
            .flat_map(|p| b.iter().map(move |q| p.distance_squared(*q)))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    fn check(exact: f64, sampled: f64, res: f64) {
        assert!(exact <= sampled + 1e-12, "exact {exact} > sampled {sampled}");
        assert!(
            exact >= sampled - res - 1e-12,
            "exact {exact} < sampled {sampled} - {res}"
        );
    }

    fn d3(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn point_region_hand_cases() {
        let placed = Placed::new(&square_with_hole(), DQuat::IDENTITY, DVec3::ZERO);
        let r = placed.region();
        let (d, c) = point_region(d3(0.1, 0.1, 2.0), &r);
        assert_near!(d, 2.0, 1e-15);
        assert!(c.distance(d3(0.1, 0.1, 0.0)) < 1e-15);
        // Beyond the edge x = 1.
        let (d, c) = point_region(d3(1.3, 0.5, 0.4), &r);
        assert_near!(d, 0.5, 1e-15);
        assert!(c.distance(d3(1.0, 0.5, 0.0)) < 1e-15);
        // Inside the hole: the rim x = 0.25 is nearest.
        let (d, c) = point_region(d3(0.3, 0.5, 0.0), &r);
        assert_near!(d, 0.05, 1e-15);
        assert!(c.distance(d3(0.25, 0.5, 0.0)) < 1e-15);
        let (d, _) = point_region(d3(0.3, 0.5, 0.12), &r);
        assert_near!(d, 0.13, 1e-15);
    }

    #[test]
    fn segment_segment_hand_cases() {
        // Crossing.
        let (d, s, t) = segment_segment(
            &Segment::new(d3(-1.0, 0.0, 0.0), d3(1.0, 0.0, 0.0)),
            &Segment::new(d3(0.0, -1.0, 0.0), d3(0.0, 1.0, 0.0)),
        );
        assert_near!(d, 0.0, 1e-15);
        assert_near!(s, 0.5, 1e-15);
        assert_near!(t, 0.5, 1e-15);
        // Skew: x axis and the line (t, 1 - t, 2)... closest at distance 2 along z.
        let (d, s, t) = segment_segment(
            &Segment::new(d3(0.0, 0.0, 0.0), d3(2.0, 0.0, 0.0)),
            &Segment::new(d3(0.0, 2.0, 2.0), d3(2.0, 0.0, 2.0)),
        );
        assert_near!(d, 2.0, 1e-15);
        assert_near!(s, 1.0, 1e-15);
        assert_near!(t, 1.0, 1e-15);
        // Skew with clamping: second segment ends before reaching the x axis' span.
        let (d, _, _) = segment_segment(
            &Segment::new(d3(0.0, 0.0, 0.0), d3(1.0, 0.0, 0.0)),
            &Segment::new(d3(3.0, -1.0, 1.0), d3(3.0, 1.0, 1.0)),
        );
        assert_near!(d, 5.0_f64.sqrt(), 1e-15);
        // Parallel overlapping.
        let (d, s, t) = segment_segment(
            &Segment::new(d3(0.0, 0.0, 0.0), d3(2.0, 0.0, 0.0)),
            &Segment::new(d3(1.0, 0.5, 0.0), d3(3.0, 0.5, 0.0)),
        );
        assert_near!(d, 0.5, 1e-15);
        assert_near!(d3(2.0 * s, 0.0, 0.0).distance(d3(1.0 + 2.0 * t, 0.5, 0.0)), 0.5, 1e-15);
        // Parallel disjoint (collinear).
        let (d, _, _) = segment_segment(
            &Segment::new(d3(0.0, 0.0, 0.0), d3(1.0, 0.0, 0.0)),
            &Segment::new(d3(3.0, 0.0, 0.0), d3(2.0, 0.0, 0.0)),
        );
        assert_near!(d, 1.0, 1e-15);
        // Degenerate.
        let p = Segment::new(d3(0.5, 1.0, 0.0), d3(0.5, 1.0, 0.0));
        let (d, s, t) = segment_segment(&p, &Segment::new(d3(0.0, 0.0, 0.0), d3(2.0, 0.0, 0.0)));
        assert_near!(d, 1.0, 1e-15);
        assert_near!(s, 0.0, 0.0);
        assert_near!(t, 0.25, 1e-15);
        let (d, _, _) = segment_segment(&p, &Segment::new(d3(0.5, 1.0, 3.0), d3(0.5, 1.0, 3.0)));
        assert_near!(d, 3.0, 1e-15);
        assert_eq!(point_segment(d3(1.0, 1.0, 0.0), &p), (0.5, 0.0));
    }

    #[test]
    fn segment_region_hand_cases() {
        let placed = Placed::new(&square_with_hole(), DQuat::IDENTITY, DVec3::ZERO);
        let r = placed.region();
        // Through the interior.
        assert_eq!(
            segment_region(&Segment::new(d3(0.1, 0.1, -1.0), d3(0.1, 0.2, 1.0)), &r),
            0.0
        );
        // Through the hole, vertically: distance to the rim.
        assert_near!(
            segment_region(&Segment::new(d3(0.5, 0.5, -1.0), d3(0.5, 0.5, 1.0)), &r),
            0.25,
            1e-15
        );
        // Parallel above the interior.
        assert_near!(
            segment_region(&Segment::new(d3(0.1, 0.1, 0.3), d3(0.9, 0.1, 0.3)), &r),
            0.3,
            1e-15
        );
    }

    #[test]
    fn segment_segment_brute_force() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for case in 0..100 {
            let s1 = Segment::new(rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0));
            let mut s2 = Segment::new(rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0));
            if case % 5 == 0 {
                // Parallel to s1.
                s2.b = s2.a + (s1.b - s1.a) * rng.range(-1.5, 1.5);
            }
            let (d, s, t) = segment_segment(&s1, &s2);
            assert_near!(d, s1.at(s).distance(s2.at(t)), 1e-12);
            let n = 200;
            let res = 0.5 * (s1.a.distance(s1.b) + s2.a.distance(s2.b)) / f64::from(n - 1);
            check(d, sampled_min(&seg_samples(&s1, n), &seg_samples(&s2, n)), res);
            let p = rng.vec(-1.5, 1.5);
            let (dp, tp) = point_segment(p, &s1);
            assert_near!(dp, p.distance(s1.at(tp)), 1e-12);
            check(
                dp,
                sampled_min(&[p], &seg_samples(&s1, 2000)),
                0.5 * s1.a.distance(s1.b) / 1999.0,
            );
        }
    }

    #[test]
    fn region_queries_brute_force() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let shapes = [square_with_hole(), l_shape()];
        for case in 0..80 {
            let shape = &shapes[case % 2];
            let rot = rng.rot();
            let shift = rng.vec(-1.0, 1.0);
            let placed = Placed::new(shape, rot, shift);
            let r = placed.region();
            let local =
                |rng: &mut Rng| rot * d3(rng.range(-0.3, 1.3), rng.range(-0.3, 1.3), rng.range(-0.5, 0.5)) + shift;

            let p = local(&mut rng);
            let (d, c) = point_region(p, &r);
            assert_near!(d, p.distance(c), 1e-12);
            check(d, sampled_min(&[p], &placed.samples), REGION_RES);

            let seg = Segment::new(local(&mut rng), local(&mut rng));
            let n = 200;
            let res = REGION_RES + 0.5 * seg.a.distance(seg.b) / f64::from(n - 1);
            check(
                segment_region(&seg, &r),
                sampled_min(&seg_samples(&seg, n), &placed.samples),
                res,
            );

            // A second region nearby; every third case coplanar with the first.
            let other = &shapes[(case / 2) % 2];
            let (rot2, shift2) = if case % 3 == 0 {
                let spin = DQuat::from_axis_angle(DVec3::Z, rng.range(0.0, std::f64::consts::TAU));
                (
                    rot * spin,
                    rot * d3(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), 0.0) + shift,
                )
            } else {
                (rng.rot(), local(&mut rng))
            };
            let placed2 = Placed::new(other, rot2, shift2);
            let r2 = placed2.region();
            let d = region_region(&r, &r2);
            assert_near!(d, region_region(&r2, &r), 1e-15);
            check(d, sampled_min(&placed.samples, &placed2.samples), 2.0 * REGION_RES);
        }
    }
}
