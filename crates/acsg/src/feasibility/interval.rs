//! Interval arithmetic for conservative tests over boxes of poses.

use crate::pose::Bounds;

/// A closed interval `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Interval {
    pub lo: f64,
    pub hi: f64,
}

impl Interval {
    pub fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    pub fn point(x: f64) -> Interval {
        Interval { lo: x, hi: x }
    }

    pub fn add(self, o: Interval) -> Interval {
        Interval::new(self.lo + o.lo, self.hi + o.hi)
    }

    pub fn mul(self, o: Interval) -> Interval {
        let c = [self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi];
        Interval::new(
            c.iter().copied().fold(f64::INFINITY, f64::min),
            c.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    }

    pub fn neg(self) -> Interval {
        Interval::new(-self.hi, -self.lo)
    }

    pub fn sub(self, o: Interval) -> Interval {
        self.add(o.neg())
    }

    /// `self / o` for a divisor that does not contain zero.
    pub fn div(self, o: Interval) -> Interval {
        let c = [self.lo / o.lo, self.lo / o.hi, self.hi / o.lo, self.hi / o.hi];
        Interval::new(
            c.iter().copied().filter(|x| !x.is_nan()).fold(f64::INFINITY, f64::min),
            c.iter()
                .copied()
                .filter(|x| !x.is_nan())
                .fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// The intersection (empty when `lo > hi`).
    pub fn meet(self, o: Interval) -> Interval {
        Interval::new(self.lo.max(o.lo), self.hi.min(o.hi))
    }

    pub fn is_empty(self) -> bool {
        self.lo > self.hi
    }

    pub fn contains_zero(self) -> bool {
        self.lo <= 0.0 && self.hi >= 0.0
    }

    pub fn widen(self, by: f64) -> Interval {
        Interval::new(self.lo - by, self.hi + by)
    }

    pub fn width(self) -> f64 {
        self.hi - self.lo
    }

    /// `x²` over the interval (never below zero, unlike `self.mul(self)`).
    pub fn square(self) -> Interval {
        let most = self.lo.abs().max(self.hi.abs());
        let least = if self.contains_zero() {
            0.0
        } else {
            self.lo.abs().min(self.hi.abs())
        };
        Interval::new(least * least, most * most)
    }

    /// cos over an angle interval.
    pub fn cos(self) -> Interval {
        if self.hi - self.lo >= std::f64::consts::TAU {
            return Interval::new(-1.0, 1.0);
        }
        let (a, b) = (self.lo.cos(), self.hi.cos());
        let mut out = Interval::new(a.min(b), a.max(b));
        // Extrema at multiples of π inside the interval.
        let first = (self.lo / std::f64::consts::PI).ceil() as i64;
        let last = (self.hi / std::f64::consts::PI).floor() as i64;
        for k in first..=last {
            let v = if k.rem_euclid(2) == 0 { 1.0 } else { -1.0 };
            out.lo = out.lo.min(v);
            out.hi = out.hi.max(v);
        }
        out
    }

    /// sin over an angle interval.
    pub fn sin(self) -> Interval {
        Interval::new(
            self.lo - std::f64::consts::FRAC_PI_2,
            self.hi - std::f64::consts::FRAC_PI_2,
        )
        .cos()
    }
}

/// A 3x3 matrix of intervals, rows first.
pub(crate) type IntervalMat = [[Interval; 3]; 3];

fn mat_mul(a: &IntervalMat, b: &IntervalMat) -> IntervalMat {
    let mut out = [[Interval::point(0.0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).fold(Interval::point(0.0), |acc, k| acc.add(a[i][k].mul(b[k][j])));
        }
    }
    out
}

/// Enclosures of the elementary rotations `[Rx(rx), Ry(ry), Rz(rz)]` over the
/// bounds' angle box.
pub(crate) fn axis_rotations(bounds: &Bounds) -> [IntervalMat; 3] {
    let angle = |lo: f64, hi: f64| Interval::new(lo, hi);
    let (x, y, z) = (
        angle(bounds.min.rx, bounds.max.rx),
        angle(bounds.min.ry, bounds.max.ry),
        angle(bounds.min.rz, bounds.max.rz),
    );
    let (zero, one) = (Interval::point(0.0), Interval::point(1.0));
    let rx = [
        [one, zero, zero],
        [zero, x.cos(), x.sin().neg()],
        [zero, x.sin(), x.cos()],
    ];
    let ry = [
        [y.cos(), zero, y.sin()],
        [zero, one, zero],
        [y.sin().neg(), zero, y.cos()],
    ];
    let rz = [
        [z.cos(), z.sin().neg(), zero],
        [z.sin(), z.cos(), zero],
        [zero, zero, one],
    ];
    [rx, ry, rz]
}

/// `R d` over a rotation enclosure.
pub(crate) fn rotated(r: &IntervalMat, d: glam::DVec3) -> [Interval; 3] {
    std::array::from_fn(|i| {
        (0..3).fold(Interval::point(0.0), |acc, j| {
            acc.add(r[i][j].mul(Interval::point(d[j])))
        })
    })
}

/// `n · (R d)` over a rotation enclosure (n in G's frame, d in the moving part's).
pub(crate) fn turned_value(r: &IntervalMat, n: glam::DVec3, d: glam::DVec3) -> Interval {
    let turned = rotated(r, d);
    (0..3).fold(Interval::point(0.0), |acc, i| {
        acc.add(turned[i].mul(Interval::point(n[i])))
    })
}

/// The largest length, over the rotations `r` encloses, of the vector whose components
/// are the values `n · (R d)` of `components`: the sine of two edges' angle, say, from
/// the components of `e × R x`.
pub(crate) fn largest_length(r: &IntervalMat, components: &[(glam::DVec3, glam::DVec3); 3]) -> f64 {
    components
        .iter()
        .map(|&(n, d)| {
            let v = turned_value(r, n, d);
            v.lo.abs().max(v.hi.abs())
        })
        .map(|m| m * m)
        .sum::<f64>()
        .sqrt()
}

/// Enclosure of R = Rz(rz) Ry(ry) Rx(rx) over the bounds' angle box.
pub(crate) fn rotation_enclosure(bounds: &Bounds) -> IntervalMat {
    let [rx, ry, rz] = axis_rotations(bounds);
    mat_mul(&mat_mul(&rz, &ry), &rx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pose::Pose;
    use glam::DVec3;

    /// The box holding `R p + t` over the bounds.
    fn reach(bounds: &Bounds, p: DVec3) -> (DVec3, DVec3) {
        let r = rotation_enclosure(bounds);
        let t = [
            Interval::new(bounds.min.x, bounds.max.x),
            Interval::new(bounds.min.y, bounds.max.y),
            Interval::new(bounds.min.z, bounds.max.z),
        ];
        let v: [Interval; 3] =
            std::array::from_fn(|i| (0..3).fold(t[i], |acc, k| acc.add(r[i][k].mul(Interval::point(p[k])))));
        (
            DVec3::new(v[0].lo, v[1].lo, v[2].lo),
            DVec3::new(v[0].hi, v[1].hi, v[2].hi),
        )
    }

    #[test]
    fn reach_boxes_enclose_sampled_poses() {
        let bounds = Bounds::try_new([-1.0, -2.0, 0.0, -0.3, -0.2, -1.5], [1.0, 2.0, 5.0, 0.4, 0.6, 2.5]).unwrap();
        let p = DVec3::new(3.0, -4.0, 7.0);
        let (lo, hi) = reach(&bounds, p);
        let mut state = 0x9e37_79b9_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let x: [f64; 6] = std::array::from_fn(|i| {
                let (a, b) = (bounds.min.to_array()[i], bounds.max.to_array()[i]);
                a + (b - a) * next()
            });
            let q = Pose::from_array(x)
                .to_affine(&glam::DAffine3::IDENTITY)
                .transform_point3(p);
            assert!(
                q.cmpge(lo - 1e-12).all() && q.cmple(hi + 1e-12).all(),
                "{q} outside {lo}..{hi}"
            );
        }
        // With the angles fixed, interval arithmetic is exact: the box is the point
        // plus the translation box.
        let fixed = Bounds::try_new([-1.0, -2.0, 0.0, 0.3, -0.2, 1.1], [1.0, 2.0, 5.0, 0.3, -0.2, 1.1]).unwrap();
        let (flo, fhi) = reach(&fixed, p);
        let q = Pose::from_array([0.0, 0.0, 0.0, 0.3, -0.2, 1.1]).rotation() * p;
        assert!(flo.distance(q + DVec3::new(-1.0, -2.0, 0.0)) < 1e-12, "{flo}");
        assert!(fhi.distance(q + DVec3::new(1.0, 2.0, 5.0)) < 1e-12, "{fhi}");
    }

    #[test]
    fn cos_and_sin_bounds_are_tight_at_extrema() {
        let c = Interval::new(-0.5, 3.5).cos();
        assert!((c.hi - 1.0).abs() < 1e-15 && (c.lo + 1.0).abs() < 1e-15);
        let s = Interval::new(0.1, 0.2).sin();
        assert!((s.lo - 0.1f64.sin()).abs() < 1e-15 && (s.hi - 0.2f64.sin()).abs() < 1e-15);
    }
}
