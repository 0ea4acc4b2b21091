//! Dense convex quadratic programs with bound constraints,
//!
//! ```text
//! minimise q(x) = 1/2 x'Hx - d'x   subject to   lower <= x <= upper,
//! ```
//!
//! solved by the projected Newton method of Bertsekas (1982): at each step the variables at a
//! bound whose gradient pushes outward (within `eps`, the current size of the projected
//! gradient) are moved along the scaled gradient; the others take the Newton step of their
//! reduced problem `H_FF p_F = -g_F`; an Armijo search along the projection arc
//! `x(a) = P(x + a p)` makes the method globally convergent for any positive semidefinite `H`,
//! and it identifies the active bounds in finitely many steps, after which the full Newton
//! step lands on the minimiser. Unlike a plain primal-dual active set it cannot cycle: every
//! step decreases `q`.
//!
//! Units: `x` is a force, the gradient `g = Hx - d` a length; the projected gradient is
//! measured as a force through the diagonal scaling `x - P(x - g / diag(H))`, so that the
//! stopping test is unit-free.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};

/// A bound-constrained QP (borrowed data). `lower` may hold `-inf`, `upper` `+inf`.
pub(crate) struct BoxQp<'a> {
    pub hessian: MatRef<'a, f64>,
    pub linear: &'a [f64],
    pub lower: &'a [f64],
    pub upper: &'a [f64],
}

/// The outcome of [`BoxQp::solve`].
#[derive(Debug, Clone)]
pub(crate) struct BoxQpOutcome {
    pub x: Vec<f64>,
    pub iterations: usize,
    /// True when the scaled projected gradient fell below the tolerance.
    pub converged: bool,
}

const ARMIJO: f64 = 1e-4;
const MAX_HALVINGS: usize = 60;

impl BoxQp<'_> {
    fn clamp(&self, i: usize, v: f64) -> f64 {
        v.max(self.lower[i]).min(self.upper[i])
    }

    /// `H x`.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for (j, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                for (yi, h) in y.iter_mut().zip(self.hessian.col(j).iter()) {
                    *yi += h * xj;
                }
            }
        }
        y
    }

    /// `g = H x - d`.
    fn gradient(&self, x: &[f64]) -> Vec<f64> {
        let mut g = self.apply(x);
        for (gi, d) in g.iter_mut().zip(self.linear) {
            *gi -= d;
        }
        g
    }

    /// `|x - P(x - g / diag(H))|_inf`, a force.
    fn projected_gradient(&self, x: &[f64], g: &[f64], scaling: &[f64]) -> f64 {
        (0..x.len()).fold(0.0f64, |m, i| {
            m.max((x[i] - self.clamp(i, x[i] - g[i] * scaling[i])).abs())
        })
    }

    /// Minimises from `start` (projected onto the box) until the scaled projected gradient is
    /// at most `tolerance` (a force) or `max_iterations` steps were taken.
    pub fn solve(&self, start: &[f64], tolerance: f64, max_iterations: usize) -> BoxQpOutcome {
        let m = self.linear.len();
        let diagonal: Vec<f64> = (0..m).map(|i| self.hessian[(i, i)]).collect();
        let largest = diagonal.iter().fold(0.0f64, |a, &d| a.max(d));
        // 1 / H_ii (a stiffness); a zero diagonal (a row touching nothing) gets the largest.
        let scaling: Vec<f64> = diagonal
            .iter()
            .map(|&d| {
                1.0 / if d > 0.0 {
                    d
                } else {
                    largest.max(f64::MIN_POSITIVE)
                }
            })
            .collect();
        let mut x: Vec<f64> = (0..m).map(|i| self.clamp(i, start[i])).collect();
        let mut g = self.gradient(&x);
        let mut outcome = BoxQpOutcome {
            x: Vec::new(),
            iterations: 0,
            converged: false,
        };
        loop {
            let pg = self.projected_gradient(&x, &g, &scaling);
            if pg <= tolerance {
                // Accept on a gradient recomputed from x, not on the updated one.
                g = self.gradient(&x);
                if self.projected_gradient(&x, &g, &scaling) <= tolerance {
                    outcome.converged = true;
                    break;
                }
            }
            if outcome.iterations == max_iterations {
                break;
            }
            outcome.iterations += 1;
            // Binding bounds: within eps of a bound, gradient pushing outward.
            let eps = pg;
            let binding: Vec<bool> = (0..m)
                .map(|i| {
                    (x[i] <= self.lower[i] + eps && g[i] > 0.0)
                        || (x[i] >= self.upper[i] - eps && g[i] < 0.0)
                })
                .collect();
            let free: Vec<usize> = (0..m).filter(|&i| !binding[i]).collect();
            let mut p: Vec<f64> = (0..m).map(|i| -g[i] * scaling[i]).collect();
            if !free.is_empty() {
                if let Some(step) = self.reduced_newton_step(&free, &g) {
                    for (k, &i) in free.iter().enumerate() {
                        p[i] = step[k];
                    }
                }
            }
            // Armijo search along the projection arc.
            let newton_decrease: f64 = free.iter().map(|&i| -g[i] * p[i]).sum();
            let mut alpha = 1.0;
            let mut accepted = false;
            for _ in 0..MAX_HALVINGS {
                let trial: Vec<f64> = (0..m).map(|i| self.clamp(i, x[i] + alpha * p[i])).collect();
                // The change of q from the step s itself, g's + 1/2 s'Hs: no cancellation
                // between two nearly equal values of q near the minimiser.
                let step: Vec<f64> = trial.iter().zip(&x).map(|(t, x)| t - x).collect();
                let h_step = self.apply(&step);
                let change: f64 = (0..m).map(|i| step[i] * (g[i] + 0.5 * h_step[i])).sum();
                let bound_decrease: f64 = (0..m)
                    .filter(|&i| binding[i])
                    .map(|i| -g[i] * step[i])
                    .sum();
                if -change >= ARMIJO * (alpha * newton_decrease + bound_decrease) {
                    for i in 0..m {
                        g[i] += h_step[i];
                    }
                    x = trial;
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if !accepted {
                // No decrease representable in floating point: x is as good as it gets.
                break;
            }
        }
        outcome.x = x;
        outcome
    }

    /// `p_F = -H_FF^-1 g_F` by a dense Cholesky factorisation (shifted slightly if `H_FF` is
    /// only semidefinite); `None` if even the shifted matrix cannot be factorised.
    fn reduced_newton_step(&self, free: &[usize], g: &[f64]) -> Option<Vec<f64>> {
        let k = free.len();
        let mut reduced = Mat::<f64>::from_fn(k, k, |a, b| self.hessian[(free[a], free[b])]);
        let trace = (0..k).map(|a| reduced[(a, a)]).sum::<f64>();
        let mut shift = 0.0;
        for _ in 0..4 {
            if let Ok(llt) = reduced.llt(Side::Lower) {
                let mut rhs = Mat::<f64>::from_fn(k, 1, |a, _| -g[free[a]]);
                llt.solve_in_place(rhs.as_mut());
                return Some((0..k).map(|a| rhs[(a, 0)]).collect());
            }
            let next = if shift == 0.0 {
                1e-14 * trace / k as f64
            } else {
                shift * 1e3
            };
            for a in 0..k {
                reduced[(a, a)] += next - shift;
            }
            shift = next;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(h: &Mat<f64>, d: &[f64], lower: &[f64], upper: &[f64]) -> BoxQpOutcome {
        BoxQp {
            hessian: h.as_ref(),
            linear: d,
            lower,
            upper,
        }
        .solve(&vec![0.0; d.len()], 1e-14, 100)
    }

    /// 1D: minimiser of 1/2 h x^2 - d x on [lo, hi] is clamp(d / h).
    #[test]
    fn scalar_problems_are_clamped_minimisers() {
        for (h, d, lo, hi) in [
            (2.0, 3.0, 0.0, f64::INFINITY),
            (2.0, -3.0, 0.0, f64::INFINITY),
            (4.0, 9.0, -1.0, 1.0),
            (4.0, -9.0, -1.0, 1.0),
            (1e-8, 1e-7, 0.0, f64::INFINITY),
        ] {
            let out = solve(&Mat::from_fn(1, 1, |_, _| h), &[d], &[lo], &[hi]);
            assert!(out.converged);
            let expected = (d / h).max(lo).min(hi);
            assert!((out.x[0] - expected).abs() <= 1e-14 * expected.abs().max(1.0));
        }
    }

    /// Random positive definite problems with both kinds of bounds: the answer satisfies the
    /// KKT conditions of the QP (which characterise its unique minimiser).
    #[test]
    fn random_problems_satisfy_the_kkt_conditions() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for _ in 0..50 {
            let n = 5;
            let a = Mat::<f64>::from_fn(n, n, |_, _| next());
            let h = &a * a.transpose() + Mat::<f64>::identity(n, n) * 0.1;
            let d: Vec<f64> = (0..n).map(|_| 2.0 * next()).collect();
            let lower: Vec<f64> = (0..n)
                .map(|i| if i % 2 == 0 { 0.0 } else { -0.3 })
                .collect();
            let upper: Vec<f64> = (0..n)
                .map(|i| if i % 2 == 0 { f64::INFINITY } else { 0.3 })
                .collect();
            let out = solve(&h, &d, &lower, &upper);
            assert!(out.converged);
            // KKT: g_i >= 0 at lower, <= 0 at upper, = 0 inside.
            let qp = BoxQp {
                hessian: h.as_ref(),
                linear: &d,
                lower: &lower,
                upper: &upper,
            };
            let g = qp.gradient(&out.x);
            for i in 0..n {
                let x = out.x[i];
                assert!(x >= lower[i] - 1e-15 && x <= upper[i] + 1e-15);
                if x > lower[i] + 1e-12 && x < upper[i] - 1e-12 {
                    assert!(g[i].abs() < 1e-12, "interior gradient {}", g[i]);
                } else if x <= lower[i] + 1e-12 {
                    assert!(g[i] > -1e-12);
                } else {
                    assert!(g[i] < 1e-12);
                }
            }
        }
    }
}
