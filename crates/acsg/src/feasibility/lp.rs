//! A small linear programme over a box: is `lo_i ≤ a_i · x ≤ hi_i` (every row) empty
//! for `x` in a box of six variables? Answered by an active-set simplex that minimises
//! the largest violation, and a "yes" only with a Farkas certificate checked on its
//! own: a non-negative combination of the rows whose left side cannot reach its
//! right side anywhere in the box. So round-off in the simplex can only cost a proof,
//! never make a wrong one.

/// Variables of the programme.
pub(crate) const VARS: usize = 6;
/// With the violation `v` as one more unknown.
const N: usize = VARS + 1;

/// One two-sided row `lo ≤ a · x ≤ hi` (a side may be infinite).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Row {
    pub a: [f64; VARS],
    pub lo: f64,
    pub hi: f64,
}

/// A one-sided constraint `g · z ≤ b` over `z = (x, v)`; `row` names the row it comes
/// from (`None` for the box and the bound on `v`), with the sign it was taken with.
#[derive(Clone, Copy, Debug)]
struct Half {
    g: [f64; N],
    b: f64,
    row: Option<(usize, f64)>,
}

/// What the programme finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Outcome {
    /// No point of the box satisfies every row (with a checked certificate).
    Empty,
    /// A point of the box that satisfies every row.
    Point([f64; VARS]),
    /// Neither: the simplex gave up (cycling, a singular basis) or could not certify.
    Unknown,
}

/// Whether no point of the box `[lo, hi]` satisfies every row, proved: `false` when
/// a point does, or when the simplex gives up (cycling, a singular basis).
#[cfg(test)]
pub(crate) fn proves_empty(rows: &[Row], lo: &[f64; VARS], hi: &[f64; VARS]) -> bool {
    solve(rows, lo, hi) == Outcome::Empty
}

/// Finds a point of the box `[lo, hi]` that satisfies every row, or proves there is
/// none.
pub(crate) fn solve(rows: &[Row], lo: &[f64; VARS], hi: &[f64; VARS]) -> Outcome {
    let point = |z: &[f64; N]| Outcome::Point(std::array::from_fn(|k| z[k]));
    let mut halves: Vec<Half> = Vec::with_capacity(2 * rows.len() + 2 * VARS + 1);
    for (i, row) in rows.iter().enumerate() {
        let norm = row.a.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm <= 0.0 || !norm.is_finite() {
            if row.lo > 0.0 || row.hi < 0.0 {
                return Outcome::Empty; // 0 outside its range: empty whatever x
            }
            continue;
        }
        for (sign, bound) in [(1.0, row.hi), (-1.0, -row.lo)] {
            if bound.is_finite() {
                let mut g = [0.0; N];
                for (gk, ak) in g.iter_mut().zip(&row.a) {
                    *gk = sign * ak / norm;
                }
                g[VARS] = -1.0;
                halves.push(Half {
                    g,
                    b: bound / norm,
                    row: Some((i, sign / norm)),
                });
            }
        }
    }
    let first_box = halves.len();
    for k in 0..VARS {
        for (sign, bound) in [(-1.0, -lo[k]), (1.0, hi[k])] {
            let mut g = [0.0; N];
            g[k] = sign;
            halves.push(Half { g, b: bound, row: None });
        }
    }
    // v ≥ −1: bounded below, and a negative v already shows a point inside.
    let mut g = [0.0; N];
    g[VARS] = -1.0;
    halves.push(Half { g, b: 1.0, row: None });
    if first_box == 0 {
        return Outcome::Point(std::array::from_fn(|k| 0.5 * (lo[k] + hi[k])));
    }
    // Start at the box's lower corner with v its largest violation: a vertex.
    let mut z = [0.0; N];
    z[..VARS].copy_from_slice(lo);
    let violation = |h: &Half, z: &[f64; N]| dot(&h.g[..VARS], &z[..VARS]) - h.b;
    let (worst, v0) = (0..first_box)
        .map(|j| (j, violation(&halves[j], &z)))
        .fold((0, f64::NEG_INFINITY), |acc, x| if x.1 > acc.1 { x } else { acc });
    if v0 <= 0.0 {
        return point(&z);
    }
    z[VARS] = v0;
    let mut active: [usize; N] = std::array::from_fn(|k| if k < VARS { first_box + 2 * k } else { worst });
    let basis = |active: &[usize; N]| invert(&std::array::from_fn(|r| halves[active[r]].g));
    let Some(mut inverse) = basis(&active) else {
        return Outcome::Unknown;
    };
    // Which halves are active, for the ratio test's scan over all of them.
    let mut is_active = vec![false; halves.len()];
    for &j in &active {
        is_active[j] = true;
    }
    for iteration in 1..=200 {
        // Multipliers of the active constraints for min v: Mᵀ λ = −e_v.
        let lambda: [f64; N] = std::array::from_fn(|i| -inverse[VARS][i]);
        // Bland's rule: the lowest-numbered constraint with a negative multiplier.
        let leave = (0..N).filter(|&i| lambda[i] < -1e-12).min_by_key(|&i| active[i]);
        let Some(leave) = leave else {
            return if z[VARS] <= 0.0 {
                point(&z)
            } else if certified(&halves, &active, &lambda, lo, hi) {
                Outcome::Empty
            } else {
                Outcome::Unknown
            };
        };
        let d: [f64; N] = std::array::from_fn(|j| -inverse[j][leave]);
        let mut step = f64::INFINITY;
        let mut enter = None;
        for (j, h) in halves.iter().enumerate() {
            if is_active[j] {
                continue;
            }
            let gd = dot(&h.g, &d);
            if gd > 1e-12 {
                let s = ((h.b - dot(&h.g, &z)) / gd).max(0.0);
                if s < step {
                    step = s;
                    enter = Some(j);
                }
            }
        }
        let Some(enter) = enter else {
            return Outcome::Unknown;
        };
        for k in 0..N {
            z[k] += step * d[k];
        }
        if z[VARS] <= 0.0 {
            return point(&z);
        }
        is_active[active[leave]] = false;
        is_active[enter] = true;
        active[leave] = enter;
        // One row of the basis changed: the inverse follows in O(N²), from scratch
        // every [`REFRESH`] steps or when the pivot is small, against drift.
        let updated = (iteration % REFRESH != 0)
            .then(|| replaced_row(&inverse, leave, &halves[enter].g))
            .flatten();
        inverse = match updated.or_else(|| basis(&active)) {
            Some(inverse) => inverse,
            None => return Outcome::Unknown,
        };
    }
    Outcome::Unknown
}

/// Checks the Farkas certificate the optimal multipliers give: the rows' combination
/// `Σ y_i (a_i · x) ≤ Σ y_i b_i` with `y ≥ 0` is violated everywhere in the box.
fn certified(halves: &[Half], active: &[usize; N], lambda: &[f64; N], lo: &[f64; VARS], hi: &[f64; VARS]) -> bool {
    let mut combined = [0.0; VARS];
    let mut rhs = 0.0;
    let mut size = 0.0;
    for (i, &j) in active.iter().enumerate() {
        let h = &halves[j];
        if h.row.is_none() {
            continue;
        }
        let y = lambda[i].max(0.0);
        for (c, g) in combined.iter_mut().zip(&h.g) {
            *c += y * g;
        }
        rhs += y * h.b;
        size += y
            * (h.b.abs()
                + (0..VARS)
                    .map(|k| h.g[k].abs() * lo[k].abs().max(hi[k].abs()))
                    .sum::<f64>());
    }
    let least: f64 = (0..VARS).map(|k| (combined[k] * lo[k]).min(combined[k] * hi[k])).sum();
    least > rhs + 1e-9 * size.max(f64::MIN_POSITIVE)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Simplex steps between inverses computed from scratch.
const REFRESH: usize = 16;

/// The inverse of a matrix `M` whose inverse is `inverse`, once its row `row` is
/// replaced by `g`: with `α = g M⁻¹`, column `row` becomes `M⁻¹ e_row / α_row` and
/// every other column `k` loses `α_k` times that. `None` when `α_row` is too small for
/// the update to be trusted.
fn replaced_row(inverse: &[[f64; N]; N], row: usize, g: &[f64; N]) -> Option<[[f64; N]; N]> {
    let alpha: [f64; N] = std::array::from_fn(|k| (0..N).map(|j| g[j] * inverse[j][k]).sum());
    if alpha[row].abs() < 1e-9 {
        return None;
    }
    let column: [f64; N] = std::array::from_fn(|j| inverse[j][row] / alpha[row]);
    Some(std::array::from_fn(|j| {
        std::array::from_fn(|k| {
            if k == row {
                column[j]
            } else {
                inverse[j][k] - column[j] * alpha[k]
            }
        })
    }))
}

/// The inverse of a small matrix by Gauss–Jordan elimination with partial pivoting;
/// `None` when it is (numerically) singular.
fn invert(m: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut a = *m;
    let mut inv: [[f64; N]; N] = std::array::from_fn(|r| std::array::from_fn(|c| if r == c { 1.0 } else { 0.0 }));
    for col in 0..N {
        let pivot = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for k in 0..N {
            a[col][k] /= p;
            inv[col][k] /= p;
        }
        for r in 0..N {
            if r != col {
                let f = a[r][col];
                if f != 0.0 {
                    for k in 0..N {
                        a[r][k] -= f * a[col][k];
                        inv[r][k] -= f * inv[col][k];
                    }
                }
            }
        }
    }
    Some(inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(a: [f64; VARS], lo: f64, hi: f64) -> Row {
        Row { a, lo, hi }
    }

    const LO: [f64; VARS] = [-1.0; VARS];
    const HI: [f64; VARS] = [1.0; VARS];

    #[test]
    fn a_box_with_a_point_inside_is_not_empty() {
        let rows = [
            row([1.0, 1.0, 0.0, 0.0, 0.0, 0.0], 0.5, 0.6),
            row([1.0, -1.0, 0.0, 0.0, 0.0, 0.0], -0.1, 0.1),
            row([0.0, 0.0, 1.0, 1.0, 1.0, 1.0], 3.9, f64::INFINITY),
        ];
        assert!(!proves_empty(&rows, &LO, &HI));
    }

    #[test]
    fn contradictory_rows_are_proved_empty() {
        // x0 + x1 ≥ 1.5 and x0 − x1 ≥ 0.8 need x0 ≥ 1.15, outside the box.
        let rows = [
            row([1.0, 1.0, 0.0, 0.0, 0.0, 0.0], 1.5, f64::INFINITY),
            row([1.0, -1.0, 0.0, 0.0, 0.0, 0.0], 0.8, f64::INFINITY),
        ];
        assert!(proves_empty(&rows, &LO, &HI));
        // Loosened so that x0 = 1, x1 = 0.5 fits: not empty.
        let rows = [rows[0], row([1.0, -1.0, 0.0, 0.0, 0.0, 0.0], 0.5, f64::INFINITY)];
        assert!(!proves_empty(&rows, &LO, &HI));
    }

    #[test]
    fn a_corner_contradiction_no_single_row_shows_is_found() {
        // The worked case of a vertex forced down by a bound: z = −10a + 50b (on the
        // floor), z ≥ 0, z − 10a... every row alone fits the box, together they do not.
        let m = 1e-4;
        let rows = [
            row([1.0, 10.0, -50.0, 0.0, 0.0, 0.0], -1e-6, 1e-6),
            row([1.0, 10.0, -150.0, 0.0, 0.0, 0.0], m, f64::INFINITY),
            row([1.0, 90.0, -50.0, 0.0, 0.0, 0.0], m, f64::INFINITY),
        ];
        let lo = [0.0, -1e-3, -1e-3, 0.0, 0.0, 0.0];
        let hi = [1.0, 1e-3, 1e-3, 0.0, 0.0, 0.0];
        assert!(proves_empty(&rows, &lo, &hi));
        // Without the bound z ≥ 0 there are points: z < 0, a > 0, b < 0.
        let lo = [-1.0, -1e-3, -1e-3, 0.0, 0.0, 0.0];
        assert!(!proves_empty(&rows, &lo, &hi));
    }

    #[test]
    fn an_inverse_with_a_row_replaced_is_the_inverse_of_the_new_matrix() {
        let m: [[f64; N]; N] =
            std::array::from_fn(|r| std::array::from_fn(|c| if r == c { 2.0 } else { 0.1 * (r + 2 * c) as f64 }));
        let g: [f64; N] = std::array::from_fn(|k| 1.0 + 0.3 * k as f64);
        let inverse = invert(&m).expect("the matrix is well conditioned");
        let updated = replaced_row(&inverse, 3, &g).expect("the pivot is large");
        let mut replaced = m;
        replaced[3] = g;
        let direct = invert(&replaced).expect("the new matrix is well conditioned");
        for r in 0..N {
            for c in 0..N {
                assert!((updated[r][c] - direct[r][c]).abs() < 1e-12, "({r}, {c})");
            }
        }
    }

    #[test]
    fn random_boxes_agree_with_sampling() {
        // Every point sampled inside all rows contradicts a proof of emptiness.
        let mut seed = 0x2545_F491_4F6C_DD1D_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut proved = 0;
        for _ in 0..300 {
            let rows: Vec<Row> = (0..4)
                .map(|_| {
                    let a = std::array::from_fn(|_| next());
                    let c = next() * 1.5;
                    row(a, c - 0.3, c + 0.3)
                })
                .collect();
            let empty = proves_empty(&rows, &LO, &HI);
            proved += usize::from(empty);
            if empty {
                for _ in 0..2000 {
                    let x: [f64; VARS] = std::array::from_fn(|_| next());
                    let inside = rows.iter().all(|r| {
                        let v = dot(&r.a, &x);
                        v >= r.lo && v <= r.hi
                    });
                    assert!(!inside, "{x:?} satisfies rows proved empty");
                }
            }
        }
        assert!(proved > 10, "only {proved} proofs");
    }
}
