//! A small Levenberg–Marquardt solver over the six pose variables, kept inside the
//! bounds by projection, with a forward-difference Jacobian.

use crate::pose::{Bounds, Pose};
use crate::tolerance::{AT_BOUND_REL, DAMPING_FLOOR_REL, DIFFERENCE_STEP_REL, NEGLIGIBLE, SOLVED_REL};

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
        if m[pivot][col].abs() < NEGLIGIBLE {
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
    let step = DIFFERENCE_STEP_REL;
    let limits = Limits {
        lo: bounds.min.to_array(),
        hi: bounds.max.to_array(),
        steps: [step * scale, step * scale, step * scale, step, step, step],
    };
    let eval = |x: &[f64; 6], out: &mut Vec<f64>| residuals(&Pose::from_array(*x), out);
    let stop = (SOLVED_REL * scale).powi(2);

    let mut x = limits.clamp(start.to_array());
    let mut r = Vec::new();
    eval(&x, &mut r);
    let mut f = sum_squares(&r);
    let mut lambda = LAMBDA_START;
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
        let jac = limits.jacobian(eval, &x, &r, &mut probe);
        let (mut a, mut g) = normal_equations(&jac, &r);
        limits.hold_active(&mut a, &mut g, &x);
        let largest = (0..6).map(|i| a[i][i]).fold(0.0, f64::max);
        if largest == 0.0 {
            break;
        }
        let mut improved = false;
        while lambda < LAMBDA_MAX {
            let mut m = a;
            for (i, row) in m.iter_mut().enumerate() {
                row[i] += lambda * (a[i][i] + DAMPING_FLOOR_REL * largest);
            }
            let Some(delta) = solve6(m, g.map(|v| -v)) else {
                lambda *= 4.0;
                continue;
            };
            let candidate = limits.clamp(std::array::from_fn(|i| x[i] + delta[i]));
            eval(&candidate, &mut probe);
            let fc = sum_squares(&probe);
            if fc < f {
                x = candidate;
                std::mem::swap(&mut r, &mut probe);
                f = fc;
                lambda = (lambda / 3.0).max(LAMBDA_MIN);
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

/// The Levenberg–Marquardt damping: its first value, and the range it is kept in (a
/// step that does not improve quadruples it, one that does divides it by 3).
const LAMBDA_START: f64 = 1e-3;
const LAMBDA_MIN: f64 = 1e-12;
const LAMBDA_MAX: f64 = 1e12;

/// The bounds of the six pose components and their difference steps.
struct Limits {
    lo: [f64; 6],
    hi: [f64; 6],
    steps: [f64; 6],
}

impl Limits {
    /// `x` projected into the bounds.
    fn clamp(&self, x: [f64; 6]) -> [f64; 6] {
        std::array::from_fn::<f64, 6, _>(|i| x[i].max(self.lo[i]).min(self.hi[i]))
    }

    /// The Jacobian of the residuals `r` at `x` by forward differences, stepping
    /// inwards at an upper bound; a fixed component (no room for a step) keeps a zero
    /// column.
    fn jacobian(
        &self,
        eval: impl Fn(&[f64; 6], &mut Vec<f64>),
        x: &[f64; 6],
        r: &[f64],
        probe: &mut Vec<f64>,
    ) -> Vec<[f64; 6]> {
        let mut jac = vec![[0.0; 6]; r.len()];
        for i in 0..6 {
            let mut xp = *x;
            let h = if x[i] + self.steps[i] <= self.hi[i] {
                self.steps[i]
            } else {
                -self.steps[i]
            };
            if x[i] + h < self.lo[i] {
                continue; // a fixed component
            }
            xp[i] += h;
            eval(&xp, probe);
            for (row, (&rp, &r0)) in jac.iter_mut().zip(probe.iter().zip(r)) {
                row[i] = (rp - r0) / h;
            }
        }
        jac
    }

    /// Active bounds: a component on a bound that descent would push outwards stays
    /// there for this step, so that the step slides along the bound instead of being
    /// cut short by the projection. Its row and column of the normal equations become
    /// the identity's, its gradient zero.
    fn hold_active(&self, a: &mut [[f64; 6]; 6], g: &mut [f64; 6], x: &[f64; 6]) {
        for i in 0..6 {
            let span = (self.hi[i] - self.lo[i]).abs().max(self.steps[i]);
            let at_lower = x[i] <= self.lo[i] + AT_BOUND_REL * span && g[i] > 0.0;
            let at_upper = x[i] >= self.hi[i] - AT_BOUND_REL * span && g[i] < 0.0;
            if at_lower || at_upper || self.hi[i] <= self.lo[i] {
                a[i] = [0.0; 6];
                for row in a.iter_mut() {
                    row[i] = 0.0;
                }
                a[i][i] = 1.0;
                g[i] = 0.0;
            }
        }
    }
}

/// The Gauss–Newton normal equations `JᵀJ`, `Jᵀr`.
fn normal_equations(jac: &[[f64; 6]], r: &[f64]) -> ([[f64; 6]; 6], [f64; 6]) {
    let mut a = [[0.0; 6]; 6];
    let mut g = [0.0; 6];
    for (row, &ri) in jac.iter().zip(r) {
        for i in 0..6 {
            g[i] += row[i] * ri;
            for j in 0..6 {
                a[i][j] += row[i] * row[j];
            }
        }
    }
    (a, g)
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
