//! The prover's second-order test: in a small box of rotations every condition of a
//! state is linear in the translation and the turn away from the box's centre, up to a
//! remainder that shrinks with the square of the box. Linear programming then sees
//! what propagation one condition at a time cannot: conditions that each hold
//! somewhere in the box but nowhere together (a vertex held on a face by a bound
//! while two others must keep their distance, say), which is how the states that hold
//! only in the limit of a larger one show up.
//!
//! With `x = (t, δ)`, `δ` the angles minus the box's central angles, a point `w` of
//! the moving part is at `R w + t = R_c w + Σ δ_k J_k w + t + e` with
//! `|e| ≤ ½ (Σ |δ_k|)² |w|`: every second derivative of `Rz Ry Rx` applied to `w` is
//! a product of rotations and at most two unit generators, of norm at most `|w|`.

use std::cell::RefCell;

use glam::{DMat3, DVec3};
use rustc_hash::FxHashMap;

use super::{Apart, ConvexPart, IVec, Link, Prover, over_face, sides};

/// A face as [`Linearised::apart_from_face`] tests a point against it: its plane, a
/// cover of it by convex parts, and its rim.
struct Cover<'s> {
    plane: (DVec3, f64),
    parts: &'s [ConvexPart],
    /// The pieces of the rim the point must keep clear of for the clearance to hold
    /// (those a contact may hold it at).
    rims: &'s [[DVec3; 2]],
}
use crate::feasibility::interval::Interval;
use crate::feasibility::lp::{self, Row, VARS};
use crate::pose::Bounds;

/// Above this sum of the tilts' (`rx`, `ry`) half-widths the remainder is mostly too
/// coarse to prove anything the interval tests do not, at the default effort; each
/// unit of effort widens it by as much, up to [`MAX_TURN`]. (0.01 until the turn met
/// with the translation was bounded axis by axis; since, four times that proves 57
/// more of the built-in example's candidates and finds two more states, for about
/// half as much time again.)
pub(super) const TURN_PER_EFFORT: f64 = 0.04;
/// The widest rotation box the test is tried in, whatever the effort.
pub(super) const MAX_TURN: f64 = 0.05;

/// A scalar that is affine in `x` up to a remainder: `base + coef · x ± err`.
#[derive(Clone, Copy, Debug)]
struct Affine {
    base: f64,
    coef: [f64; VARS],
    err: f64,
}

impl Affine {
    /// Its range over the box.
    fn range(&self, lo: &[f64; VARS], hi: &[f64; VARS]) -> Interval {
        let (mut a, mut b) = (self.base - self.err, self.base + self.err);
        for k in 0..VARS {
            let (p, q) = (self.coef[k] * lo[k], self.coef[k] * hi[k]);
            a += p.min(q);
            b += p.max(q);
        }
        Interval::new(a, b)
    }

    /// `a · self + b · other` (`a`, `b` ≥ 0).
    fn blend(&self, a: f64, other: &Affine, b: f64) -> Affine {
        Affine {
            base: a * self.base + b * other.base,
            coef: std::array::from_fn(|k| a * self.coef[k] + b * other.coef[k]),
            err: a * self.err + b * other.err,
        }
    }

    /// The row `lo ≤ self ≤ hi`, the remainder and `slack` moved to the bounds.
    fn row(&self, lo: f64, hi: f64, slack: f64) -> Row {
        let widen = self.err + slack;
        Row {
            a: self.coef,
            lo: lo - self.base - widen,
            hi: hi - self.base + widen,
        }
    }
}

/// The rotation at the box's centre and its derivatives there.
struct Turn {
    r: DMat3,
    /// `∂R/∂rx`, `∂R/∂ry`, `∂R/∂rz` at the centre.
    by_rx: DMat3,
    by_ry: DMat3,
    by_rz: DMat3,
    /// Σ of the half-widths of the angles.
    s: f64,
    /// The half-widths of the angles.
    h: [f64; 3],
    /// The second derivatives `∂²R/∂θj∂θk` at the centre, for `(j, k)` = (x, x),
    /// (y, y), (z, z), (x, y), (x, z), (y, z). Over the box each is within `s` of
    /// its value here (in the operator norm): every third derivative is a product of
    /// rotations and unit generators, of norm at most 1.
    hessian: [DMat3; 6],
    /// Centre of the translation box, its half-widths and its half-diagonal.
    t_c: DVec3,
    t_h: DVec3,
    d: f64,
}

/// A vector of the moving part as the linear forms at one box use it: turned by the
/// rotation at the box's centre, with its derivatives by the angles there. A point or
/// direction met many times in a box (a vertex against every face near it) is turned
/// once.
#[derive(Clone, Copy, Debug)]
struct Spun {
    /// `R v`.
    turned: DVec3,
    /// `∂(R v)/∂θk`.
    jacobian: [DVec3; 3],
    /// `∂²(R v)/∂θj∂θk`, in [`Turn`]'s `hessian` order.
    hessian: [DVec3; 6],
    /// `|v|`.
    length: f64,
}

impl Turn {
    /// `v` turned at the box's centre, with its derivatives.
    fn spin(&self, v: DVec3) -> Spun {
        Spun {
            turned: self.r * v,
            jacobian: self.jacobian(v),
            hessian: self.hessian.map(|m| m * v),
            length: v.length(),
        }
    }

    fn new(lo: &[f64; VARS], hi: &[f64; VARS]) -> Turn {
        let c: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k + 3] + hi[k + 3]));
        let (rx, ry, rz) = (
            DMat3::from_rotation_x(c[0]),
            DMat3::from_rotation_y(c[1]),
            DMat3::from_rotation_z(c[2]),
        );
        let skew = |v: DVec3| DMat3::from_cols(v.cross(DVec3::X), v.cross(DVec3::Y), v.cross(DVec3::Z));
        let (kx, ky, kz) = (skew(DVec3::X), skew(DVec3::Y), skew(DVec3::Z));
        let t_lo = DVec3::new(lo[0], lo[1], lo[2]);
        let t_hi = DVec3::new(hi[0], hi[1], hi[2]);
        let hessian = [
            rz * ry * rx * kx * kx,
            rz * ry * ky * ky * rx,
            rz * kz * kz * ry * rx,
            rz * ry * ky * rx * kx,
            rz * kz * ry * rx * kx,
            rz * kz * ry * ky * rx,
        ];
        Turn {
            r: rz * ry * rx,
            by_rx: rz * ry * rx * kx,
            by_ry: rz * ry * ky * rx,
            by_rz: rz * kz * ry * rx,
            s: (0..3).map(|k| 0.5 * (hi[k + 3] - lo[k + 3])).sum(),
            h: std::array::from_fn(|k| 0.5 * (hi[k + 3] - lo[k + 3])),
            hessian,
            t_c: 0.5 * (t_lo + t_hi),
            t_h: 0.5 * (t_hi - t_lo),
            d: 0.5 * (t_hi - t_lo).length(),
        }
    }

    /// The derivatives of `R v` by the three angles.
    fn jacobian(&self, v: DVec3) -> [DVec3; 3] {
        [self.by_rx * v, self.by_ry * v, self.by_rz * v]
    }

    /// A bound on `|(R v − R_c v) · Δt|` over the box, `Δt` the translation off the
    /// box's centre, less its second-order part (`second(v) · d`): the first-order
    /// turn `Σ δ_k J_k v` met with `Δt` component by component. A turn that keeps `v`
    /// (a turn about `v` itself) or moves it across a thin side of the box costs little,
    /// where `s |v| d` would charge every turn against the box's whole diagonal.
    fn bilinear(&self, v: &Spun) -> f64 {
        self.bilinear_of(v.jacobian, v.length)
    }

    /// [`Turn::bilinear`] for a direction whose derivatives by the angles are
    /// `derivatives` and whose length is at most `size`.
    fn bilinear_of(&self, derivatives: [DVec3; 3], size: f64) -> f64 {
        let exact: f64 = derivatives
            .iter()
            .zip(self.h)
            .map(|(j, h)| h * j.abs().dot(self.t_h))
            .sum();
        // Round-off of the products, and never more than the isotropic bound.
        let isotropic = self.s * size * self.d;
        (exact + 1e-12 * isotropic).min(isotropic)
    }

    /// How far `R v` is from its linear part at most.
    fn second(&self, v: &Spun) -> f64 {
        0.5 * self.s * self.s * v.length
    }

    /// How far `n · R v` is from its linear part at most: ½ Σ h_j h_k sup |n · ∂²R/∂θj∂θk v|
    /// over the box (Taylor's remainder), never more than [`Turn::second`] gives. A
    /// turn that moves `v` within a plane normal to `n` leaves little of it. The part
    /// of `n` along z is turned by the tilts only (`Rz` keeps z), so it pays for `rx`
    /// and `ry` alone: a height over a floor stays linear however wide the yaw.
    fn second_along(&self, n: DVec3, v: &Spun) -> f64 {
        let Some((across, along_z)) = self.split_along_z(n) else {
            return self.remainder(n, v, self.h, self.s);
        };
        let [hx, hy, _] = self.h;
        let split = self.remainder(across, v, self.h, self.s) + self.remainder(along_z, v, [hx, hy, 0.0], self.tilts());
        split.min(self.second(v) * n.length())
    }

    /// `n` as its part across z and its part along z, which the yaw does not turn;
    /// `None` when the split gains nothing (no yaw in the box, or no part along z).
    fn split_along_z(&self, n: DVec3) -> Option<(DVec3, DVec3)> {
        (self.h[2] != 0.0 && n.z != 0.0).then(|| (DVec3::new(n.x, n.y, 0.0), DVec3::new(0.0, 0.0, n.z)))
    }

    /// The sum of the tilts' (`rx`, `ry`) half-widths.
    fn tilts(&self) -> f64 {
        self.h[0] + self.h[1]
    }

    /// [`Turn::second_along`] over angle half-widths `h` summing to `s`, for a `n`
    /// whose value along `R v` depends on no angle whose half-width is left out.
    fn remainder(&self, n: DVec3, v: &Spun, h: [f64; 3], s: f64) -> f64 {
        if n == DVec3::ZERO {
            return 0.0;
        }
        let weights = [
            h[0] * h[0],
            h[1] * h[1],
            h[2] * h[2],
            2.0 * h[0] * h[1],
            2.0 * h[0] * h[2],
            2.0 * h[1] * h[2],
        ];
        // Off the centre each second derivative moves by at most `s` (times |n| |v|),
        // and the weights add up to s²; the round-off of the products is covered too.
        let spread = (s + 1e-12) * n.length() * v.length;
        let along: f64 = v
            .hessian
            .iter()
            .zip(weights)
            .map(|(mv, w)| w * (n.dot(*mv).abs() + spread))
            .sum();
        (0.5 * along).min(0.5 * s * s * v.length * n.length())
    }

    /// `n · (R w + t)`.
    fn on_moving_point(&self, n: DVec3, w: &Spun) -> Affine {
        let j = w.jacobian;
        Affine {
            base: n.dot(w.turned),
            coef: [n.x, n.y, n.z, n.dot(j[0]), n.dot(j[1]), n.dot(j[2])],
            err: self.second_along(n, w),
        }
    }

    /// `(R m) · (a − t)`: a point of the fixed part against a direction of the moving
    /// part (the bilinear term `δ · Δt` in the remainder).
    fn on_fixed_point(&self, m: &Spun, a: DVec3) -> Affine {
        let (u, j) = (m.turned, m.jacobian);
        let arm = a - self.t_c;
        Affine {
            base: u.dot(a),
            coef: [-u.x, -u.y, -u.z, j[0].dot(arm), j[1].dot(arm), j[2].dot(arm)],
            err: self.bilinear(m) + self.second_along(arm, m) + self.second(m) * self.d,
        }
    }

    /// An interval that holds [`Turn::on_moving_point`]`(n, w)`'s range over the box
    /// `[lo, hi]` (angles as offsets from the centre), at the cost of one product: the
    /// turn's terms bounded by `|n| |w|` per radian (every derivative of `R` is a
    /// rotation times a unit generator), its remainder by [`Turn::second`].
    fn moving_point_hull(&self, n: DVec3, w: DVec3, lo: &[f64; VARS], hi: &[f64; VARS]) -> Interval {
        let base = n.dot(self.r * w);
        let reach = |n: DVec3, turn: f64, s: f64| n.length() * w.length() * (turn + 0.5 * s * s);
        let whole = reach(n, turn_reach(lo, hi), self.s);
        // As in `second_along`, the part of `n` along z moves with the tilts only.
        let rest = match self.split_along_z(n) {
            Some((across, along_z)) => {
                whole.min(reach(across, turn_reach(lo, hi), self.s) + reach(along_z, tilt_reach(lo, hi), self.tilts()))
            }
            None => whole,
        };
        hull(base, n.to_array(), lo, hi, rest)
    }

    /// An interval that holds [`Turn::on_fixed_point`]`(m, a)`'s range over the box, as
    /// [`Turn::moving_point_hull`] does.
    fn fixed_point_hull(&self, m: &Spun, a: DVec3, lo: &[f64; VARS], hi: &[f64; VARS]) -> Interval {
        let u = m.turned;
        let arm = (a - self.t_c).length();
        let size = m.length * arm;
        let err = self.bilinear(m) + self.second(m) * (arm + 2.0 * self.d);
        hull(u.dot(a), (-u).to_array(), lo, hi, size * turn_reach(lo, hi) + err)
    }

    /// `(da × R db) · (a0 − R b0 − t)`: two edges crossing.
    fn crossing(&self, a0: DVec3, da: DVec3, b0: DVec3, db: DVec3) -> Affine {
        let (b0, db) = (self.spin(b0), self.spin(db));
        let (u, uj) = (db.turned, db.jacobian);
        let (p, pj) = (b0.turned, b0.jacobian);
        let n = da.cross(u);
        let g = a0 - p - self.t_c;
        let rot = |k: usize| da.cross(uj[k]).dot(g) - n.dot(pj[k]);
        let s = self.s;
        let du = s + 0.5 * s * s;
        Affine {
            base: n.dot(a0 - p),
            coef: [-n.x, -n.y, -n.z, rot(0), rot(1), rot(2)],
            // (da × r) · g = r · (g × da): the remainder r of `R db` met along g × da.
            err: self.second_along(n, &b0)
                + self.second_along(g.cross(da), &db)
                + self.second(&db) * self.d
                + self.bilinear_of(uj.map(|j| da.cross(j)), da.length() * db.length)
                + du * du * b0.length,
        }
    }
}

/// Rotation-only values `n · (R d)` over a box, as rows of the linear programme
/// ([`lp`]) in `x = (t, δ)`: linear in the angles off the box's centre, the remainder
/// moved to the row's bounds, and no part in the translation. Conditions that each hold
/// somewhere in a thin box of rotations but nowhere together (two crossings asking one
/// tilt to lean both ways) are refuted together.
pub(crate) struct TurnedRows {
    turn: Turn,
    lo: [f64; VARS],
    hi: [f64; VARS],
}

impl TurnedRows {
    /// The linear forms over `bounds`.
    pub(crate) fn new(bounds: &Bounds) -> TurnedRows {
        let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
        let turn = Turn::new(&lo, &hi);
        // The programme's box: the translation as it is (no row uses it), the angles
        // as offsets from the centre.
        let (mut x_lo, mut x_hi) = (lo, hi);
        for k in 0..3 {
            x_lo[k + 3] = -turn.h[k];
            x_hi[k + 3] = turn.h[k];
        }
        TurnedRows {
            turn,
            lo: x_lo,
            hi: x_hi,
        }
    }

    /// The row `lo ≤ n · (R d) ≤ hi`.
    pub(crate) fn row(&self, n: DVec3, d: DVec3, lo: f64, hi: f64) -> Row {
        let mut form = self.turn.on_moving_point(n, &self.turn.spin(d));
        form.coef[..3].fill(0.0);
        form.row(lo, hi, 0.0)
    }

    /// Whether no rotation of the box satisfies every row, proved.
    pub(crate) fn refuted(&self, rows: &[Row]) -> bool {
        lp::solve(rows, &self.lo, &self.hi) == lp::Outcome::Empty
    }
}

impl Prover<'_> {
    /// The second-order test of a box whose tilts span at most [`MAX_TURN`] (whatever
    /// its yaw): the box narrowed by propagation over the linearised conditions
    /// (rotations too), or `None` when linear programming proves no pose in it shows
    /// the state.
    pub(super) fn linearised(&self, links: &super::Links, bounds: &Bounds) -> Option<Bounds> {
        let (mut lo, mut hi) = (bounds.min.to_array(), bounds.max.to_array());
        let turn = Turn::new(&lo, &hi);
        // A wide yaw alone does not stop it: heights over planes normal to z stay
        // linear (see `Turn::second_along`). (From effort 2 only until the test's cost
        // came down: at the default effort it decides 5 more of the fixture pairs'
        // candidates for about a tenth more CPU time.)
        if turn.tilts() > self.max_turn {
            return Some(*bounds);
        }
        // Angles as offsets from the centre.
        let centre: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k + 3] + hi[k + 3]));
        for k in 0..3 {
            lo[k + 3] -= centre[k];
            hi[k + 3] -= centre[k];
        }
        let mut linear = Linearised {
            prover: self,
            turn,
            centre,
            lo,
            hi,
            rows: Vec::new(),
            either: Vec::new(),
            edges_added: Vec::new(),
            rough: [vec![None; self.b.vertices.len()], vec![None; self.a.vertices.len()]],
            // Sized for the moving part's vertices and normals (up to a bound): growing
            // the map box after box cost more than filling it.
            spins: RefCell::new(FxHashMap::with_capacity_and_hasher(
                (self.b.vertices.len() + self.b.planes.len() + 3).min(SPINS_CAPACITY),
                Default::default(),
            )),
        };
        linear.contacts(links);
        linear.kept_apart(links);
        linear.straddled(links);
        linear.kept_out(&self.edges_through(&bounds.center()))?;
        propagate(&linear.rows, &mut linear.lo, &mut linear.hi)?;
        // The yaw's width costs nothing here (see `Turn::second_along`): the tilts'
        // decide how often the box is proved rather than split.
        let mut budget = if linear.turn.tilts() > NARROW_TURN {
            WIDE_CASES
        } else {
            CASES
        };
        let mut rows = std::mem::take(&mut linear.rows);
        if linear.refute(&mut rows, &mut budget) {
            return None;
        }
        let (mut lo, mut hi) = (linear.lo, linear.hi);
        for k in 0..3 {
            lo[k + 3] += centre[k];
            hi[k + 3] += centre[k];
        }
        Some(Bounds::try_new(lo, hi).unwrap_or(*bounds))
    }
}

/// One box's linearised conditions as they are gathered: rows that must all hold,
/// and sets of rows of which one must.
struct Linearised<'p, 'a> {
    prover: &'p Prover<'a>,
    turn: Turn,
    /// The box's central angles.
    centre: [f64; 3],
    /// The box in `x = (t, δ)`.
    lo: [f64; VARS],
    hi: [f64; VARS],
    rows: Vec<Row>,
    /// Sets of cases, one of which must hold; a case is rows that must all hold.
    either: Vec<Vec<Vec<Row>>>,
    /// (moving part's edge?, edge, piece) and the point kept out, for the edge points in.
    edges_added: Vec<((bool, usize, usize), DVec3)>,
    /// The vectors of the moving part turned so far ([`Turn::spin`]), by their bits.
    spins: RefCell<FxHashMap<[u64; 3], Spun>>,
    /// The vertices' cheap positions over the box ([`Linearised::rough_position`]), the
    /// moving part's then the fixed part's, each worked out once.
    rough: [Vec<Option<IVec>>; 2],
}

impl Linearised<'_, '_> {
    /// `f` of [`Turn::spin`]`(v)`, turned once per vector and box (`f` turns no other).
    fn with_spun<T>(&self, v: DVec3, f: impl FnOnce(&Spun) -> T) -> T {
        let key = v.to_array().map(f64::to_bits);
        let mut spins = self.spins.borrow_mut();
        f(spins.entry(key).or_insert_with(|| self.turn.spin(v)))
    }

    /// The rows of the contacts.
    fn contacts(&mut self, links: &super::Links) {
        let (turn, s) = (&self.turn, self.prover.slack);
        let mut regions = Vec::new();
        for link in &links.links {
            let row = match *link {
                Link::MovingPointOnFixedPlane { w, n, d } => {
                    self.with_spun(w, |w| turn.on_moving_point(n, w)).row(d, d, s)
                }
                Link::FixedPointOnMovingPlane { a, m, e } => {
                    self.with_spun(m, |m| turn.on_fixed_point(m, a)).row(e, e, s)
                }
                Link::Crossing { a0, da, b0, db } => turn.crossing(a0, da, b0, db).row(0.0, 0.0, s),
                Link::Region { a, b } if b.0 == b.1 => {
                    for k in 0..3 {
                        let h = self.with_spun(b.0, |w| turn.on_moving_point(DVec3::AXES[k], w));
                        self.rows.push(h.row(a.0[k], a.1[k], s));
                    }
                    continue;
                }
                Link::Region { a, b } if a.0 == a.1 => {
                    for k in 0..3 {
                        let h = self.with_spun(DVec3::AXES[k], |m| turn.on_fixed_point(m, a.0));
                        self.rows.push(h.row(b.0[k], b.1[k], s));
                    }
                    continue;
                }
                Link::Region { a, b } => {
                    regions.push((a, b));
                    continue;
                }
            };
            self.rows.push(row);
        }
        if links.meet_regions {
            for (a, b) in regions {
                self.regions_meet(a, b);
            }
        }
    }

    /// A contact along a segment or over an area: the fixed element's box `a` (in G's
    /// frame) meets the moving element's box `b` turned and moved, as propagation asks
    /// ([`Link::Region`]), axis by axis: some corner of `b` reaches up to `a`'s lower
    /// side and some down to its upper side.
    fn regions_meet(&mut self, a: (DVec3, DVec3), b: (DVec3, DVec3)) {
        let s = self.prover.slack;
        let mut corners: Vec<DVec3> = (0..8)
            .map(|c| {
                DVec3::new(
                    if c & 1 == 0 { b.0.x } else { b.1.x },
                    if c & 2 == 0 { b.0.y } else { b.1.y },
                    if c & 4 == 0 { b.0.z } else { b.1.z },
                )
            })
            .collect();
        corners.sort_by(|p, q| {
            p.to_array()
                .partial_cmp(&q.to_array())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        corners.dedup();
        for (k, axis) in DVec3::AXES.into_iter().enumerate() {
            let placed: Vec<Affine> = corners
                .iter()
                .map(|&q| self.with_spun(q, |w| self.turn.on_moving_point(axis, w)))
                .collect();
            let (mut reach_up, mut reach_down) = (Some(Vec::new()), Some(Vec::new()));
            for form in &placed {
                let range = form.range(&self.lo, &self.hi);
                // A corner on the right side wherever the box puts it settles the side.
                if range.lo >= a.0[k] {
                    reach_up = None;
                }
                if range.hi <= a.1[k] {
                    reach_down = None;
                }
                if let Some(cases) = reach_up.as_mut().filter(|_| range.hi >= a.0[k] - s) {
                    cases.push(vec![form.row(a.0[k], f64::INFINITY, s)]);
                }
                if let Some(cases) = reach_down.as_mut().filter(|_| range.lo <= a.1[k] + s) {
                    cases.push(vec![form.row(f64::NEG_INFINITY, a.1[k], s)]);
                }
            }
            for mut cases in [reach_up, reach_down].into_iter().flatten() {
                match cases.len() {
                    1 => self.rows.extend(cases.pop().unwrap_or_default()),
                    _ => self.either.push(cases),
                }
            }
        }
    }

    /// Where a point is, coordinate by coordinate, over the box: the moving part's
    /// point `w` in G's frame, or the fixed part's `a` in the moving part's frame.
    fn position(&self, moving: bool, p: DVec3) -> IVec {
        let (lo, hi) = (&self.lo, &self.hi);
        if moving {
            self.with_spun(p, |w| {
                DVec3::AXES.map(|axis| self.turn.on_moving_point(axis, w).range(lo, hi))
            })
        } else {
            DVec3::AXES.map(|axis| self.with_spun(axis, |m| self.turn.on_fixed_point(m, p)).range(lo, hi))
        }
    }

    /// An enclosure of [`Linearised::position`] from the cheap hulls
    /// ([`Turn::moving_point_hull`], [`Turn::fixed_point_hull`]).
    fn rough_position(&self, moving: bool, p: DVec3) -> IVec {
        let (lo, hi) = (&self.lo, &self.hi);
        if moving {
            DVec3::AXES.map(|axis| self.turn.moving_point_hull(axis, p, lo, hi))
        } else {
            DVec3::AXES.map(|axis| self.with_spun(axis, |m| self.turn.fixed_point_hull(m, p, lo, hi)))
        }
    }

    /// [`Linearised::rough_position`] of a vertex of one part (the moving part's when
    /// `moving`), worked out once per box.
    fn rough_vertex(&mut self, moving: bool, index: usize) -> IVec {
        if let Some(at) = self.rough[usize::from(!moving)][index] {
            return at;
        }
        let shape = if moving { &self.prover.b } else { &self.prover.a };
        let at = self.rough_position(moving, shape.vertices[index]);
        self.rough[usize::from(!moving)][index] = Some(at);
        at
    }

    /// The height of a point over a plane of the other part.
    fn height(&self, moving: bool, p: DVec3, (n, d): (DVec3, f64)) -> Affine {
        let mut h = if moving {
            self.with_spun(p, |w| self.turn.on_moving_point(n, w))
        } else {
            self.with_spun(n, |m| self.turn.on_fixed_point(m, p))
        };
        h.base -= d;
        h
    }

    /// The face–vertex pairs a witness keeps apart: a vertex over a face is at least
    /// the margin off its plane, on one side or the other.
    fn kept_apart(&mut self, links: &super::Links) {
        // A vertex whose cheap position stays beyond a face's box by three margins is
        // nowhere near the face: the pair sets no condition.
        let far = 3.0 * self.prover.margin + self.prover.slack;
        let prover = self.prover;
        let (a, b) = (&prover.a, &prover.b);
        for pair in &links.apart {
            let (moving, index, shape, face, held_rim) = match *pair {
                Apart::FixedFace { face, vertex, held_rim } => (true, vertex, a, face, held_rim),
                Apart::MovingFace { face, vertex, held_rim } => (false, vertex, b, face, held_rim),
            };
            if !near_box(&self.rough_vertex(moving, index), shape.face_boxes[face], far) {
                continue;
            }
            let vertex = if moving { b.vertices[index] } else { a.vertices[index] };
            let cover = Cover {
                plane: shape.planes[face],
                parts: &shape.convex_parts[face],
                rims: held_rim.map_or(&[][..], |k| &links.held_rims[k]),
            };
            self.apart_from_face(moving, vertex, &cover);
        }
    }

    /// A point of one part (the moving part's when `moving`) that a witness keeps off a
    /// face of the other: where it lies over the face, at least the margin off the
    /// face's plane. When the box does not decide whether it lies over the face, each
    /// of the face's convex parts gives the cases: outside one of its sides, or the
    /// margin above or below.
    ///
    /// A point within the margin of the plane is not over the face at all: a witness
    /// keeps it at least the loose contact tolerance (1.98 margins) from the face, as
    /// a checker reads a point that near as touching the face, or near the rim its edge
    /// or corner. (Unless a contact of the target may hold that edge or corner touching
    /// the point: `cover.rims` holds them, and the rule applies only away from them.)
    /// It is then outside a side of each convex part by a clearance, so a point on a
    /// diagonal two triangles share is outside neither.
    fn apart_from_face(&mut self, moving: bool, p: DVec3, cover: &Cover) {
        let face = cover.plane;
        let (m, s) = (self.prover.margin, self.prover.slack);
        // Most pairs are far apart: a cheap hull of the height's range settles them
        // before the linear form is built (it holds that range, so the same pairs go).
        let rough = if moving {
            self.turn.moving_point_hull(face.0, p, &self.lo, &self.hi)
        } else {
            self.with_spun(face.0, |m| self.turn.fixed_point_hull(m, p, &self.lo, &self.hi))
        }
        .sub(Interval::point(face.1));
        if rough.lo >= m || rough.hi <= -m {
            return;
        }
        let h = self.height(moving, p, face);
        let range = h.range(&self.lo, &self.hi);
        if range.lo >= m || range.hi <= -m {
            return;
        }
        let (above, below) = (h.row(m, f64::INFINITY, s), h.row(f64::NEG_INFINITY, -m, s));
        let mut off = Vec::new();
        if range.hi > m {
            off.push(vec![above]);
        }
        if range.lo < -m {
            off.push(vec![below]);
        }
        let at = self.position(moving, p);
        if over_face(cover.parts, face.0, &at, s) {
            match off.len() {
                1 => self.rows.extend(off.pop().unwrap_or_default()),
                _ => self.either.push(off),
            }
            return;
        }
        // 2.5 margins in space: over 1.98 in the plane, the height being under one.
        let off_the_rim = super::clear_of(cover.rims, &at, 2.5 * m);
        for part in cover.parts {
            let (polygon, sign) = (&part.corners[..], part.sense(face.0));
            // Outside the face, by 1.98 margins from it: by 1.98 · sin(α/2) (1.5 here)
            // outside a side; asked of the sides inside the face only (outside a side
            // on the rim, the point is off the face whatever the clearance).
            let clearance = if off_the_rim { 1.5 * m * part.sharpest } else { -s };
            let mut cases = off.clone();
            let mut surely_outside = false;
            for ((x, y), &inner) in sides(polygon).zip(&part.inner) {
                // Depth inside this side, in the face's plane.
                let inward = sign * face.0.cross(y - x) / x.distance(y);
                let depth = self.height(moving, p, (inward, inward.dot(x)));
                // Wholly outside the side's line (within the slack): the part sets no
                // condition (the point is over a neighbouring part, which does, or off
                // the face).
                let range = depth.range(&self.lo, &self.hi);
                if range.hi <= s {
                    surely_outside = true;
                    break;
                }
                let outside = if inner { clearance } else { -s };
                // A case no point of the box meets costs a programme each time the
                // cases are tried: left out.
                if range.lo <= s - outside {
                    cases.push(vec![depth.row(f64::NEG_INFINITY, -outside, s)]);
                }
            }
            if !surely_outside {
                self.either.push(cases);
            }
        }
    }

    /// The ends of a segment through a contact point on both sides of the planes
    /// through it ([`super::Straddle`]), the point at least the margin from either end:
    /// one order of the sides when the box decides it, else the two cases.
    fn straddled(&mut self, links: &super::Links) {
        let s = self.prover.slack;
        for st in &links.straddles {
            let [h0, h1] = st.ends.map(|p| self.height(st.moving, p, st.plane));
            // The point at λ = h0 / (h0 − h1) along the segment, λ ∈ [μ, 1 − μ]: with
            // h0 above and h1 below, (1 − μ) h0 + μ h1 ≥ 0 ≥ μ h0 + (1 − μ) h1.
            let mu = (self.prover.margin / st.ends[0].distance(st.ends[1])).min(0.5);
            let (near0, near1) = (h0.blend(1.0 - mu, &h1, mu), h0.blend(mu, &h1, 1.0 - mu));
            let down_up = [near0.row(0.0, f64::INFINITY, s), near1.row(f64::NEG_INFINITY, 0.0, s)];
            let up_down = [near0.row(f64::NEG_INFINITY, 0.0, s), near1.row(0.0, f64::INFINITY, s)];
            let [r0, r1] = [h0, h1].map(|h| h.range(&self.lo, &self.hi));
            if r0.lo > s || r1.hi < -s {
                self.rows.extend(down_up);
            } else if r0.hi < -s || r1.lo > s {
                self.rows.extend(up_down);
            } else {
                self.either.push(vec![down_up.to_vec(), up_down.to_vec()]);
            }
        }
    }

    /// No vertex, and none of the given edge points, strictly inside a convex piece of
    /// the other part; `None` when one is inside whatever the pose in the box.
    fn kept_out(&mut self, through: &super::Through) -> Option<()> {
        for moving in [true, false] {
            let prover = self.prover;
            let (shape, other) = if moving {
                (&prover.b, &prover.a)
            } else {
                (&prover.a, &prover.b)
            };
            // Where each vertex is does not depend on the piece: once per vertex, and
            // only for the vertices whose cheap position reaches some piece's box
            // (those it misses, the position misses too: `keep_out_at` would pass them).
            let mut at: Vec<Option<IVec>> = Vec::with_capacity(shape.vertices.len());
            for (index, &p) in shape.vertices.iter().enumerate() {
                let rough = self.rough_vertex(moving, index);
                let s = self.prover.slack;
                let reaches = other
                    .piece_boxes
                    .iter()
                    .any(|&piece_box| near_box(&rough, piece_box, s));
                at.push(reaches.then(|| self.position(moving, p)));
            }
            for j in 0..other.pieces.len() {
                for (&p, at) in shape.vertices.iter().zip(&at) {
                    if let Some(at) = at {
                        self.keep_out_at(moving, p, at, j)?;
                    }
                }
            }
        }
        self.edge_points(through)
    }

    /// [`Linearised::kept_out`] for edge points not yet in.
    fn edge_points(&mut self, through: &super::Through) -> Option<()> {
        for (moving, points) in [(true, &through.moving), (false, &through.fixed)] {
            for p in points {
                let key = (moving, p.edge, p.piece);
                // The same edge through the same piece elsewhere (at another pose of
                // the box) is another point to keep out.
                let known =
                    |&(k, at): &((bool, usize, usize), DVec3)| k == key && at.distance(p.point) <= self.prover.slack;
                if !self.edges_added.iter().any(known) {
                    self.edges_added.push((key, p.point));
                    self.keep_out(moving, p.point, p.piece)?;
                }
            }
        }
        Some(())
    }

    /// A point of one part outside at least one plane of a piece of the other: the
    /// plane's row when only one is left, the set of them when several are, `None`
    /// when none is.
    fn keep_out(&mut self, moving: bool, p: DVec3, piece: usize) -> Option<()> {
        let at = self.position(moving, p);
        self.keep_out_at(moving, p, &at, piece)
    }

    /// [`Linearised::keep_out`] with the point's position over the box known (`at`).
    fn keep_out_at(&mut self, moving: bool, p: DVec3, at: &IVec, piece: usize) -> Option<()> {
        let s = self.prover.slack;
        let other = if moving { &self.prover.a } else { &self.prover.b };
        if !near_box(at, other.piece_boxes[piece], s) {
            return Some(());
        }
        let mut left: Vec<Row> = other.pieces[piece]
            .iter()
            .map(|&plane| self.height(moving, p, plane))
            .filter(|h| h.range(&self.lo, &self.hi).hi >= -s)
            .map(|h| h.row(-s, f64::INFINITY, 0.0))
            .collect();
        match left.len() {
            0 => return None,
            1 => self.rows.append(&mut left),
            _ => self.either.push(left.into_iter().map(|row| vec![row]).collect()),
        }
        Some(())
    }

    /// Whether no point satisfies `rows` and one row of each set, proved by cases: a
    /// point the programme finds that breaks a set is split into that set's rows,
    /// each added in turn; a point that breaks none is checked for edges passing
    /// through pieces, which join as new sets. `false` when a point satisfies
    /// everything, or when the budget of programmes runs out.
    fn refute(&mut self, rows: &mut Vec<Row>, budget: &mut usize) -> bool {
        loop {
            if *budget == 0 {
                return false;
            }
            *budget -= 1;
            let x = match lp::solve(rows, &self.lo, &self.hi) {
                lp::Outcome::Empty => return true,
                lp::Outcome::Unknown => {
                    return false;
                }
                lp::Outcome::Point(x) => x,
            };
            let holds = |row: &Row| {
                let v: f64 = row.a.iter().zip(&x).map(|(a, b)| a * b).sum();
                let tol = 1e-9 * (1.0 + v.abs());
                v >= row.lo - tol && v <= row.hi + tol
            };
            let broken = self
                .either
                .iter()
                .position(|cases| !cases.iter().any(|case| case.iter().all(holds)));
            if let Some(broken) = broken {
                for case in self.either[broken].clone() {
                    let before = rows.len();
                    rows.extend(case);
                    let refuted = self.refute(rows, budget);
                    rows.truncate(before);
                    if !refuted {
                        return false;
                    }
                }
                return true;
            }
            // Every set holds at x: look there for edges through pieces.
            let pose = crate::pose::Pose::from_array(std::array::from_fn(|k| {
                if k < 3 { x[k] } else { x[k] + self.centre[k - 3] }
            }));
            let (before_rows, before_sets) = (self.rows.len(), self.either.len());
            if self.edge_points(&self.prover.edges_through(&pose)).is_none() {
                return true;
            }
            // Rows that hold everywhere in the box, as sets of one (`rows` only grows
            // and shrinks by the cases of this search).
            let new_rows: Vec<Vec<Vec<Row>>> = self.rows.drain(before_rows..).map(|row| vec![vec![row]]).collect();
            if new_rows.is_empty() && self.either.len() == before_sets {
                return false;
            }
            self.either.extend(new_rows);
        }
    }
}

/// The largest turn off the box's centre, summed over the three angles (offsets).
fn turn_reach(lo: &[f64; VARS], hi: &[f64; VARS]) -> f64 {
    (3..VARS).map(|k| lo[k].abs().max(hi[k].abs())).sum()
}

/// [`turn_reach`] over the tilts `rx` and `ry` only.
fn tilt_reach(lo: &[f64; VARS], hi: &[f64; VARS]) -> f64 {
    (3..5).map(|k| lo[k].abs().max(hi[k].abs())).sum()
}

/// `base + coef · t ± rest` over the translations of the box, widened for the
/// round-off of computing it otherwise (a hull of an [`Affine`]'s range).
fn hull(base: f64, coef: [f64; 3], lo: &[f64; VARS], hi: &[f64; VARS], rest: f64) -> Interval {
    let (mut a, mut b) = (base - rest, base + rest);
    for k in 0..3 {
        let (p, q) = (coef[k] * lo[k], coef[k] * hi[k]);
        a += p.min(q);
        b += p.max(q);
    }
    let round_off = 1e-9 * (base.abs() + rest + b - a) + 1e-300;
    Interval::new(a - round_off, b + round_off)
}

/// Whether a box of positions comes within `distance` of a box `(lo, hi)` in every
/// coordinate.
fn near_box(at: &IVec, (lo, hi): (DVec3, DVec3), distance: f64) -> bool {
    (0..3).all(|k| at[k].hi >= lo[k] - distance && at[k].lo <= hi[k] + distance)
}

/// The most vectors a box's map of turned vectors is sized for at first.
const SPINS_CAPACITY: usize = 64;

/// Linear programmes one box may spend on the cases of its either-or conditions.
const CASES: usize = 24;
/// Above this sum of the tilts' half-widths a box gets [`WIDE_CASES`] programmes only:
/// it is more often split than proved, and there are many more such boxes.
const NARROW_TURN: f64 = 0.01;
/// Linear programmes for a box wider than [`NARROW_TURN`].
const WIDE_CASES: usize = 6;

/// Narrows the box by each row in turn (a few sweeps); `None` when a variable's range
/// empties.
fn propagate(rows: &[Row], lo: &mut [f64; VARS], hi: &mut [f64; VARS]) -> Option<()> {
    for _ in 0..3 {
        for row in rows {
            for k in 0..VARS {
                let a = row.a[k];
                if a.abs() < 1e-9 {
                    continue;
                }
                // a x_k ∈ [row.lo, row.hi] − Σ_{j≠k} a_j x_j
                let (mut rest_lo, mut rest_hi) = (0.0, 0.0);
                for j in (0..VARS).filter(|&j| j != k) {
                    let (p, q) = (row.a[j] * lo[j], row.a[j] * hi[j]);
                    rest_lo += p.min(q);
                    rest_hi += p.max(q);
                }
                let (num_lo, num_hi) = (row.lo - rest_hi, row.hi - rest_lo);
                let (mut new_lo, mut new_hi) = if a > 0.0 {
                    (num_lo / a, num_hi / a)
                } else {
                    (num_hi / a, num_lo / a)
                };
                // Keep the round-off of the division on the safe side.
                let pad = 1e-12 * (new_lo.abs().max(new_hi.abs()).min(1e300)) + 1e-15;
                new_lo -= pad;
                new_hi += pad;
                if new_lo > lo[k] {
                    lo[k] = new_lo;
                }
                if new_hi < hi[k] {
                    hi[k] = new_hi;
                }
                if lo[k] > hi[k] {
                    return None;
                }
            }
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::testing::Numbers;

    #[test]
    fn the_directional_remainder_bounds_the_rotation_off_its_linear_part() {
        // Boxes of every shape (one angle wide and two narrow, as along a family of
        // poses that turn about one axis, or all wide); sampled angles in them.
        let mut numbers = Numbers(0x2545_F491_4F6C_DD1D);
        let mut tightest: f64 = 0.0;
        for case in 0..400 {
            let centre: [f64; 3] = std::array::from_fn(|_| 0.6 * numbers.next() - 0.3);
            // One angle in four cases wide; the yaw, every other time, as wide as a
            // free turn about the insertion axis.
            let wide = if case % 8 == 6 { 0.3 } else { 0.05 };
            let half: [f64; 3] = std::array::from_fn(|k| if case % 4 == k { wide } else { 1e-4 * numbers.next() });
            let mut lo = [-1.0; VARS];
            let mut hi = [1.0; VARS];
            for k in 0..3 {
                lo[k + 3] = centre[k] - half[k];
                hi[k + 3] = centre[k] + half[k];
            }
            let turn = Turn::new(&lo, &hi);
            let n = DVec3::new(numbers.next() - 0.5, numbers.next() - 0.5, numbers.next() - 0.5).normalize();
            let v = 100.0 * DVec3::new(numbers.next() - 0.5, numbers.next() - 0.5, numbers.next() - 0.5);
            let bound = turn.second_along(n, &turn.spin(v));
            assert!(bound <= turn.second(&turn.spin(v)) * (1.0 + 1e-12));
            let j = turn.jacobian(v);
            for _ in 0..20 {
                let d: [f64; 3] = std::array::from_fn(|k| (2.0 * numbers.next() - 1.0) * half[k]);
                let r = DMat3::from_rotation_z(centre[2] + d[2])
                    * DMat3::from_rotation_y(centre[1] + d[1])
                    * DMat3::from_rotation_x(centre[0] + d[0]);
                let linear = n.dot(turn.r * v) + (0..3).map(|k| d[k] * n.dot(j[k])).sum::<f64>();
                let off = (n.dot(r * v) - linear).abs();
                assert!(off <= bound + 1e-9, "{off} > {bound} in case {case}");
                tightest = tightest.max(off / bound.max(1e-300));
            }
        }
        // The bound is not vacuous: some samples come close to it.
        assert!(tightest > 0.1, "{tightest}");
    }

    #[test]
    fn the_linear_forms_hold_the_true_values_over_the_box() {
        // Boxes thin in some translations and wide in others (a face sliding along a
        // wall), small turns: at sampled poses, the value of a fixed point against a
        // moving direction, and of two edges crossing, stays within the linear form
        // plus its remainder.
        let mut numbers = Numbers(0x5851_F42D_4C95_7F2D);
        let unit = |numbers: &mut Numbers| {
            DVec3::new(numbers.next() - 0.5, numbers.next() - 0.5, numbers.next() - 0.5).normalize()
        };
        let mut tightest: f64 = 0.0;
        for case in 0..600 {
            let mut lo = [0.0; VARS];
            let mut hi = [0.0; VARS];
            for k in 0..VARS {
                let (centre, half) = if k < 3 {
                    let wide = (case + k) % 3 == 0;
                    (
                        200.0 * numbers.next() - 100.0,
                        if wide { 5.0 } else { 1e-3 } * numbers.next(),
                    )
                } else {
                    let wide = (case + k) % 4 == 0;
                    (
                        0.6 * numbers.next() - 0.3,
                        if wide { 0.02 } else { 1e-4 } * numbers.next(),
                    )
                };
                (lo[k], hi[k]) = (centre - half, centre + half);
            }
            let turn = Turn::new(&lo, &hi);
            let centre: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k + 3] + hi[k + 3]));
            let (mut dlo, mut dhi) = (lo, hi);
            for k in 0..3 {
                dlo[k + 3] -= centre[k];
                dhi[k + 3] -= centre[k];
            }
            // Axis-aligned directions half the time: the turns that keep them cost
            // nothing, which is where the bound is tight.
            let axis = |numbers: &mut Numbers| DVec3::AXES[(3.0 * numbers.next()) as usize % 3];
            let m = if case % 2 == 0 {
                axis(&mut numbers)
            } else {
                unit(&mut numbers)
            };
            let a = 150.0 * unit(&mut numbers) * numbers.next();
            let (a0, da) = (150.0 * unit(&mut numbers) * numbers.next(), unit(&mut numbers));
            let (b0, db) = (
                150.0 * unit(&mut numbers) * numbers.next(),
                if case % 2 == 0 {
                    axis(&mut numbers)
                } else {
                    unit(&mut numbers)
                },
            );
            let forms = [turn.on_fixed_point(&turn.spin(m), a), turn.crossing(a0, da, b0, db)];
            for _ in 0..30 {
                let x: [f64; VARS] = std::array::from_fn(|k| dlo[k] + (dhi[k] - dlo[k]) * numbers.next());
                let t = DVec3::new(x[0], x[1], x[2]);
                let r = DMat3::from_rotation_z(centre[2] + x[5])
                    * DMat3::from_rotation_y(centre[1] + x[4])
                    * DMat3::from_rotation_x(centre[0] + x[3]);
                let truth = [(r * m).dot(a - t), da.cross(r * db).dot(a0 - r * b0 - t)];
                for (form, value) in forms.iter().zip(truth) {
                    let linear = form.base + (0..VARS).map(|k| form.coef[k] * x[k]).sum::<f64>();
                    let off = (value - linear).abs();
                    assert!(
                        off <= form.err + 1e-9 * (1.0 + linear.abs()),
                        "{off} > {} in case {case}",
                        form.err
                    );
                    tightest = tightest.max(off / form.err.max(1e-300));
                }
            }
        }
        // Not vacuous: some samples use a good share of the remainder.
        assert!(tightest > 0.05, "{tightest}");
    }

    #[test]
    fn the_cheap_hulls_hold_the_linear_forms_ranges() {
        // Boxes of translations and of small turns (as the test runs in), points and
        // directions at the parts' scale: each hull holds the range it stands for, and
        // is not vacuous.
        let mut numbers = Numbers(0x9E37_79B9_7F4A_7C15);
        let unit = |numbers: &mut Numbers| {
            DVec3::new(numbers.next() - 0.5, numbers.next() - 0.5, numbers.next() - 0.5).normalize()
        };
        let mut tightest: f64 = f64::INFINITY;
        for case in 0..2000 {
            let mut lo = [0.0; VARS];
            let mut hi = [0.0; VARS];
            for k in 0..VARS {
                let (centre, half) = if k < 3 {
                    (200.0 * numbers.next() - 100.0, 10.0 * numbers.next())
                } else if k == 5 && case % 2 == 1 {
                    // A wide yaw with narrow tilts.
                    (0.6 * numbers.next() - 0.3, 0.3 * numbers.next())
                } else {
                    (0.6 * numbers.next() - 0.3, 0.02 * numbers.next())
                };
                (lo[k], hi[k]) = (centre - half, centre + half);
            }
            let turn = Turn::new(&lo, &hi);
            for k in 3..VARS {
                let centre = 0.5 * (lo[k] + hi[k]);
                lo[k] -= centre;
                hi[k] -= centre;
            }
            let (n, p) = (unit(&mut numbers), 150.0 * unit(&mut numbers) * numbers.next());
            for (affine, hull) in [
                (
                    turn.on_moving_point(n, &turn.spin(p)),
                    turn.moving_point_hull(n, p, &lo, &hi),
                ),
                (
                    turn.on_fixed_point(&turn.spin(n), p),
                    turn.fixed_point_hull(&turn.spin(n), p, &lo, &hi),
                ),
            ] {
                let range = affine.range(&lo, &hi);
                assert!(hull.lo <= range.lo && range.hi <= hull.hi, "{range:?} not in {hull:?}");
                tightest = tightest.min((hull.hi - hull.lo) / (range.hi - range.lo).max(1e-300));
            }
        }
        assert!(tightest < 2.0, "every hull is more than twice its range: {tightest}");
    }
}
