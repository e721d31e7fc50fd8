//! A small Levenberg–Marquardt solver over the six pose variables, kept inside the
//! bounds by projection, with a forward-difference Jacobian.

use crate::pose::{Bounds, Pose};

/// Iteration limit of one local optimisation.
const MAX_ITERATIONS: usize = 150;
/// A run whose sum of squares fell by less than a tenth over the last
/// [`STALL_WINDOW`] iterations has stalled (an infeasible target crawling along its
/// best compromise): it stops there.
const STALL_WINDOW: usize = 10;
const STALL_RATIO: f64 = 0.9;

fn sum_squares(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// Solves the 6x6 system `m x = b` by Gaussian elimination with partial pivoting;
/// `None` if singular.
fn solve6(mut m: [[f64; 6]; 6], mut b: [f64; 6]) -> Option<[f64; 6]> {
    for col in 0..6 {
        let pivot = (col..6).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[pivot][col].abs() < 1e-300 {
            return None;
        }
        m.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = m[col];
        for row in col + 1..6 {
            let f = m[row][col] / pivot_row[col];
            for (cell, &p) in m[row].iter_mut().zip(&pivot_row).skip(col) {
                *cell -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 6];
    for row in (0..6).rev() {
        let tail: f64 = (row + 1..6).map(|k| m[row][k] * x[k]).sum();
        x[row] = (b[row] - tail) / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Minimises the sum of squared residuals over poses in `bounds`, from `start`.
/// `scale` is the length scale L (for step sizes and the stopping threshold).
pub(crate) fn minimise(residuals: impl Fn(&Pose, &mut Vec<f64>), start: Pose, bounds: &Bounds, scale: f64) -> Pose {
    let (lo, hi) = (bounds.min.to_array(), bounds.max.to_array());
    let steps = [1e-7 * scale, 1e-7 * scale, 1e-7 * scale, 1e-7, 1e-7, 1e-7];
    let clamp = |x: [f64; 6]| std::array::from_fn::<f64, 6, _>(|i| x[i].max(lo[i]).min(hi[i]));
    let eval = |x: &[f64; 6], out: &mut Vec<f64>| residuals(&Pose::from_array(*x), out);
    let stop = (1e-11 * scale).powi(2);

    let mut x = clamp(start.to_array());
    let mut r = Vec::new();
    eval(&x, &mut r);
    let mut f = sum_squares(&r);
    let mut lambda = 1e-3;
    let mut probe = Vec::new();
    let mut checkpoint = f;
    for it in 0..MAX_ITERATIONS {
        if f <= stop {
            break;
        }
        if it > 0 && it % STALL_WINDOW == 0 {
            if f > STALL_RATIO * checkpoint {
                break;
            }
            checkpoint = f;
        }
        // Forward differences, stepping inwards at an upper bound.
        let mut jac = vec![[0.0; 6]; r.len()];
        for i in 0..6 {
            let mut xp = x;
            let h = if x[i] + steps[i] <= hi[i] { steps[i] } else { -steps[i] };
            if x[i] + h < lo[i] {
                continue; // a fixed component
            }
            xp[i] += h;
            eval(&xp, &mut probe);
            for (row, (&rp, &r0)) in jac.iter_mut().zip(probe.iter().zip(&r)) {
                row[i] = (rp - r0) / h;
            }
        }
        let mut a = [[0.0; 6]; 6];
        let mut g = [0.0; 6];
        for (row, &ri) in jac.iter().zip(&r) {
            for i in 0..6 {
                g[i] += row[i] * ri;
                for j in 0..6 {
                    a[i][j] += row[i] * row[j];
                }
            }
        }
        // Active bounds: a component on a bound that descent would push outwards stays
        // there for this step, so that the step slides along the bound instead of being
        // cut short by the projection.
        for i in 0..6 {
            let span = (hi[i] - lo[i]).abs().max(steps[i]);
            let at_lower = x[i] <= lo[i] + 1e-12 * span && g[i] > 0.0;
            let at_upper = x[i] >= hi[i] - 1e-12 * span && g[i] < 0.0;
            if at_lower || at_upper || hi[i] <= lo[i] {
                a[i] = [0.0; 6];
                for row in &mut a {
                    row[i] = 0.0;
                }
                a[i][i] = 1.0;
                g[i] = 0.0;
            }
        }
        let largest = (0..6).map(|i| a[i][i]).fold(0.0, f64::max);
        if largest == 0.0 {
            break;
        }
        let mut improved = false;
        while lambda < 1e12 {
            let mut m = a;
            for (i, row) in m.iter_mut().enumerate() {
                row[i] += lambda * (a[i][i] + 1e-9 * largest);
            }
            let Some(delta) = solve6(m, g.map(|v| -v)) else {
                lambda *= 4.0;
                continue;
            };
            let candidate = clamp(std::array::from_fn(|i| x[i] + delta[i]));
            eval(&candidate, &mut probe);
            let fc = sum_squares(&probe);
            if fc < f {
                x = candidate;
                std::mem::swap(&mut r, &mut probe);
                f = fc;
                lambda = (lambda / 3.0).max(1e-12);
                improved = true;
                break;
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    Pose::from_array(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonlinear_system_inside_the_bounds() {
        let bounds = Bounds::try_new([-10.0, -10.0, 0.0, -1.0, -1.0, -1.0], [10.0, 10.0, 10.0, 1.0, 1.0, 1.0]).unwrap();
        // Zero at x = 3, y = -2, z = 1, rx = 0.5 (others free): a curved system.
        let residuals = |p: &Pose, out: &mut Vec<f64>| {
            out.clear();
            out.extend([
                p.x * p.x - 9.0 + (p.x - 3.0),
                p.y + 2.0,
                (p.z - 1.0) * (1.0 + p.rx.sin()),
                p.rx.sin() - 0.5f64.sin(),
            ]);
        };
        let x = minimise(
            residuals,
            Pose::from_array([1.0, 0.0, 5.0, 0.0, 0.0, 0.0]),
            &bounds,
            10.0,
        );
        crate::assert_near!(x.x, 3.0, 1e-8);
        crate::assert_near!(x.y, -2.0, 1e-8);
        crate::assert_near!(x.z, 1.0, 1e-8);
        crate::assert_near!(x.rx, 0.5, 1e-8);
        // A minimum outside the bounds: the solver stops on the bound.
        let outside = |p: &Pose, out: &mut Vec<f64>| {
            out.clear();
            out.push(p.z + 5.0);
        };
        let y = minimise(outside, Pose::from_array([0.0, 0.0, 5.0, 0.0, 0.0, 0.0]), &bounds, 10.0);
        crate::assert_near!(y.z, 0.0, 1e-12);
    }
}
