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

/// `H x` for the dense interface Hessian `H` (the columns where `x` is zero skipped: most
/// forces of a contact problem are).
pub(crate) fn hessian_apply(hessian: MatRef<'_, f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (j, &xj) in x.iter().enumerate() {
        if xj != 0.0 {
            for (yi, h) in y.iter_mut().zip(hessian.col(j).iter()) {
                *yi += h * xj;
            }
        }
    }
    y
}

/// The gradient `H x - d` of the interface problem's energy `x'Hx/2 - d'x`.
pub(crate) fn quadratic_gradient(hessian: MatRef<'_, f64>, linear: &[f64], x: &[f64]) -> Vec<f64> {
    let mut g = hessian_apply(hessian, x);
    for (gi, d) in g.iter_mut().zip(linear) {
        *gi -= d;
    }
    g
}

/// A bound-constrained QP (borrowed data). `lower` may hold `-inf`, `upper` `+inf`.
pub(crate) struct BoxQp<'a> {
    pub hessian: MatRef<'a, f64>,
    pub linear: &'a [f64],
    pub lower: &'a [f64],
    pub upper: &'a [f64],
}

/// The Cholesky factor of the reduced Hessian `H_FF` of the last Newton step, kept from one
/// step (and one solve with the same `H`) to the next and brought to the next step's free set
/// `F` by rank-one updates: a variable that leaves `F` is deleted from the factor (a rank-one
/// update of the rows after it), one that joins is appended (a triangular solve). A step whose
/// free set differs from the last one's in a few variables, as along a Coulomb fixed point and
/// the load steps of a history, then costs `O(k^2)` per change instead of a factorisation
/// (`O(k^3 / 3)`, `k = |F|`); a factor that cannot be updated (a pivot below round-off, many
/// changes) is made again.
///
/// Storage: `L` by columns with a leading dimension (the capacity) above its order, so that an
/// append writes one row and a deletion only marks its position: the factor of the free set is
/// `L` restricted to the live positions, in the order of the positions. The dead ones are
/// squeezed out when they are many.
#[derive(Debug, Clone, Default)]
pub(crate) struct ReducedFactor {
    /// The variable at each position (`usize::MAX` for a deleted one).
    order: Vec<usize>,
    /// Live positions.
    live: usize,
    /// Leading dimension of `l`.
    capacity: usize,
    /// `L` by columns (`capacity x capacity`, lower triangular on the positions).
    l: Vec<f64>,
}

/// A factor is updated when the free set changes in at most this fraction of its size (or 8
/// variables), and made again otherwise.
const UPDATE_FRACTION: f64 = 0.25;
/// An appended pivot `d^2 = h - |y|^2` below this fraction of `h` is round-off: the factor is
/// made again (with the shift of a semidefinite `H_FF`).
const PIVOT_FLOOR: f64 = 1e-10;
/// Marks a deleted position.
pub(crate) const DEAD: usize = usize::MAX;

impl ReducedFactor {
    /// The number of variables in the factor.
    pub(crate) fn k(&self) -> usize {
        self.live
    }

    /// The variable at every position ([`DEAD`] for a deleted one).
    pub(crate) fn positions(&self) -> &[usize] {
        &self.order
    }

    /// A factor of the variables `order` from its `L` (`k x k`).
    pub(crate) fn from_factor(order: &[usize], l: MatRef<'_, f64>) -> Self {
        let k = order.len();
        // Room for a quarter more variables before the storage grows (twice the order was
        // 0.5 GB written at every factorisation of a 4e3 x 4e3 reduced matrix).
        let capacity = k + (k / 4).max(16);
        let mut data = vec![0.0; capacity * capacity];
        for j in 0..k {
            for i in j..k {
                data[j * capacity + i] = l[(i, j)];
            }
        }
        Self {
            order: order.to_vec(),
            live: k,
            capacity,
            l: data,
        }
    }

    fn at(&self, i: usize, j: usize) -> usize {
        j * self.capacity + i
    }

    /// Deletes the variable at position `p`: the live rows after it get the rank-one update
    /// with the part of column `p` below the diagonal.
    pub(crate) fn delete(&mut self, p: usize) {
        let n = self.order.len();
        let rows: Vec<usize> = (p + 1..n).filter(|&i| self.order[i] != DEAD).collect();
        let mut x: Vec<f64> = rows.iter().map(|&i| self.l[self.at(i, p)]).collect();
        for (jj, &j) in rows.iter().enumerate() {
            let ljj = self.l[self.at(j, j)];
            let r = ljj.hypot(x[jj]);
            let (c, s) = (r / ljj, x[jj] / ljj);
            let column = self.at(0, j);
            self.l[column + j] = r;
            for (ii, &i) in rows.iter().enumerate().skip(jj + 1) {
                let lij = (self.l[column + i] + s * x[ii]) / c;
                x[ii] = c * x[ii] - s * lij;
                self.l[column + i] = lij;
            }
        }
        self.order[p] = DEAD;
        self.live -= 1;
    }

    /// Squeezes the deleted positions out (the live ones keep their order).
    fn compact(&mut self, capacity: usize) {
        let live: Vec<usize> = (0..self.order.len())
            .filter(|&i| self.order[i] != DEAD)
            .collect();
        let mut data = vec![0.0; capacity * capacity];
        for (jj, &j) in live.iter().enumerate() {
            for (ii, &i) in live.iter().enumerate().skip(jj) {
                data[jj * capacity + ii] = self.l[self.at(i, j)];
            }
        }
        self.order = live.iter().map(|&i| self.order[i]).collect();
        self.capacity = capacity;
        self.l = data;
    }

    /// `y = L^-1 b` on the live positions (`b` and `y` indexed by position; the dead ones are
    /// 0 on return).
    fn forward(&self, y: &mut [f64]) {
        let n = self.order.len();
        for j in 0..n {
            if self.order[j] == DEAD {
                y[j] = 0.0;
                continue;
            }
            let column = &self.l[self.at(0, j)..self.at(n, j)];
            y[j] /= column[j];
            let yj = y[j];
            for (yi, lij) in y[j + 1..n].iter_mut().zip(&column[j + 1..]) {
                *yi -= lij * yj;
            }
        }
    }

    /// Appends the variable `v` (column `h_v` of `H` given by `column`); `false` when its pivot
    /// is below round-off (the factor is then unchanged).
    pub(crate) fn append(&mut self, v: usize, column: impl Fn(usize) -> f64) -> bool {
        let mut y: Vec<f64> = self
            .order
            .iter()
            .map(|&i| if i == DEAD { 0.0 } else { column(i) })
            .collect();
        self.forward(&mut y);
        let h = column(v);
        let d2 = h - y.iter().map(|x| x * x).sum::<f64>();
        if d2.is_nan() || d2 <= PIVOT_FLOOR * h.abs() {
            return false;
        }
        let n = self.order.len();
        if n == self.capacity {
            let dead = n - self.live;
            self.compact(if 4 * dead > n {
                self.capacity
            } else {
                2 * self.capacity
            });
            // Positions moved: the row of the new variable again.
            return self.append(v, column);
        }
        for (j, &yj) in y.iter().enumerate() {
            let at = self.at(n, j);
            self.l[at] = yj;
        }
        let at = self.at(n, n);
        self.l[at] = d2.sqrt();
        self.order.push(v);
        self.live += 1;
        true
    }

    /// `x = -(L L')^-1 g[order]` on the live positions, as `(variable, value)`.
    pub(crate) fn solve(&self, g: &[f64]) -> Vec<(usize, f64)> {
        let n = self.order.len();
        let mut x: Vec<f64> = self
            .order
            .iter()
            .map(|&i| if i == DEAD { 0.0 } else { -g[i] })
            .collect();
        self.forward(&mut x);
        for j in (0..n).rev() {
            if self.order[j] == DEAD {
                continue;
            }
            let column = &self.l[self.at(0, j)..self.at(n, j)];
            let below: f64 = column[j + 1..]
                .iter()
                .zip(&x[j + 1..n])
                .map(|(l, x)| l * x)
                .sum();
            x[j] = (x[j] - below) / column[j];
        }
        self.order
            .iter()
            .zip(x)
            .filter(|(&i, _)| i != DEAD)
            .map(|(&i, x)| (i, x))
            .collect()
    }
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
/// The bounds within `eps` of which a variable counts as binding, at most this fraction of its
/// box width: a box narrower than the projected gradient (friction bounds of nodes with small
/// normal forces) does not count both its bounds as binding at once.
const EPS_WIDTH: f64 = 0.25;
const MAX_HALVINGS: usize = 60;

impl BoxQp<'_> {
    fn clamp(&self, i: usize, v: f64) -> f64 {
        v.max(self.lower[i]).min(self.upper[i])
    }

    /// `H x`.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        hessian_apply(self.hessian, x)
    }

    /// `g = H x - d`.
    fn gradient(&self, x: &[f64]) -> Vec<f64> {
        quadratic_gradient(self.hessian, self.linear, x)
    }

    /// `|x - P(x - g / diag(H))|_inf`, a force.
    fn projected_gradient(&self, x: &[f64], g: &[f64], scaling: &[f64]) -> f64 {
        (0..x.len()).fold(0.0f64, |m, i| {
            m.max((x[i] - self.clamp(i, x[i] - g[i] * scaling[i])).abs())
        })
    }

    /// Minimises from `start` (projected onto the box) until the scaled projected gradient is
    /// at most `tolerance` (a force) or `max_iterations` steps were taken.
    #[cfg(test)]
    pub fn solve(&self, start: &[f64], tolerance: f64, max_iterations: usize) -> BoxQpOutcome {
        self.solve_with(
            start,
            tolerance,
            max_iterations,
            &mut ReducedFactor::default(),
        )
    }

    /// [`BoxQp::solve`] with the reduced factor `kept` of an earlier solve with the same `H`
    /// (updated on return).
    pub fn solve_with(
        &self,
        start: &[f64],
        tolerance: f64,
        max_iterations: usize,
        kept: &mut ReducedFactor,
    ) -> BoxQpOutcome {
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
            let binding: Vec<bool> = (0..m)
                .map(|i| {
                    let eps = pg.min(EPS_WIDTH * (self.upper[i] - self.lower[i]));
                    (x[i] <= self.lower[i] + eps && g[i] > 0.0)
                        || (x[i] >= self.upper[i] - eps && g[i] < 0.0)
                })
                .collect();
            let free: Vec<usize> = (0..m).filter(|&i| !binding[i]).collect();
            let mut p: Vec<f64> = (0..m).map(|i| -g[i] * scaling[i]).collect();
            if !free.is_empty() {
                if let Some(step) = self.reduced_newton_step(&free, &g, kept) {
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

    /// Brings `kept` to the free set `free` by deletions and appends; `false` (and `kept`
    /// cleared) when too much changed or a pivot fell below round-off.
    fn update(&self, free: &[usize], kept: &mut ReducedFactor) -> bool {
        let m = self.linear.len();
        let mut in_free = vec![false; m];
        for &i in free {
            in_free[i] = true;
        }
        let mut in_kept = vec![false; m];
        for &i in kept.order.iter().filter(|&&i| i != DEAD) {
            in_kept[i] = true;
        }
        let removed: Vec<usize> = (0..kept.order.len())
            .filter(|&p| kept.order[p] != DEAD && !in_free[kept.order[p]])
            .collect();
        let added: Vec<usize> = free.iter().copied().filter(|&i| !in_kept[i]).collect();
        let changes = removed.len() + added.len();
        if changes as f64 > (UPDATE_FRACTION * free.len() as f64).max(8.0) {
            *kept = ReducedFactor::default();
            return false;
        }
        for &p in removed.iter().rev() {
            kept.delete(p);
        }
        for v in added {
            if !kept.append(v, |i| self.hessian[(i, v)]) {
                *kept = ReducedFactor::default();
                return false;
            }
        }
        true
    }

    /// `p_F = -H_FF^-1 g_F`: by the factor `kept` brought to the free set `free` by rank-one
    /// updates, or by a dense Cholesky factorisation (shifted slightly if `H_FF` is only
    /// semidefinite; such a factor is not kept); `None` if even the shifted matrix cannot be
    /// factorised.
    fn reduced_newton_step(
        &self,
        free: &[usize],
        g: &[f64],
        kept: &mut ReducedFactor,
    ) -> Option<Vec<f64>> {
        let k = free.len();
        if kept.k() > 0 && self.update(free, kept) {
            // Back to the order of `free`.
            let mut step = vec![0.0; self.linear.len()];
            for (i, x) in kept.solve(g) {
                step[i] = x;
            }
            return Some(free.iter().map(|&i| step[i]).collect());
        }
        let mut reduced = Mat::<f64>::from_fn(k, k, |a, b| self.hessian[(free[a], free[b])]);
        let trace = (0..k).map(|a| reduced[(a, a)]).sum::<f64>();
        let mut shift = 0.0;
        for _ in 0..4 {
            if let Ok(llt) = reduced.llt(Side::Lower) {
                let mut rhs = Mat::<f64>::from_fn(k, 1, |a, _| -g[free[a]]);
                llt.solve_in_place(rhs.as_mut());
                *kept = if shift == 0.0 {
                    ReducedFactor::from_factor(free, llt.L())
                } else {
                    ReducedFactor::default()
                };
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

    /// A factor brought from one free set to another by deletions and appends gives the
    /// Newton step of the new set, as a factorisation made afresh does.
    #[test]
    fn updated_reduced_factors_solve_the_new_free_set() {
        let mut seed = 11u64;
        let mut next = || crate::solver::uniform(&mut seed);
        let n = 16;
        let a = Mat::<f64>::from_fn(n, n, |_, _| next());
        let h = &a * a.transpose() + Mat::<f64>::identity(n, n) * 0.5;
        let g: Vec<f64> = (0..n).map(|_| next()).collect();
        let zeros = vec![0.0; n];
        let qp = BoxQp {
            hessian: h.as_ref(),
            linear: &zeros,
            lower: &zeros,
            upper: &zeros,
        };
        let sets: [&[usize]; 11] = [
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
            &[0, 2, 3, 5, 6, 7, 8, 9, 10, 11],
            &[1, 2, 3, 5, 6, 7, 9, 10, 11],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
            // From 2 variables (capacity 16), deletions and appends up to a compaction.
            &[0, 1],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
            &[2, 3, 4, 5, 6, 7, 8, 9, 10],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10],
            &[2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14],
        ];
        let mut kept = ReducedFactor::default();
        for free in sets {
            let step = qp.reduced_newton_step(free, &g, &mut kept).unwrap();
            assert_eq!(kept.k(), free.len());
            // H_FF p_F = -g_F.
            for (r, &i) in free.iter().enumerate() {
                let lhs: f64 = free.iter().zip(&step).map(|(&j, p)| h[(i, j)] * p).sum();
                assert!((lhs + g[i]).abs() < 1e-12, "row {r}: {lhs} vs {}", -g[i]);
            }
        }
        // Appends and deletions past the capacity: the deleted positions are squeezed out, then
        // the storage grows.
        let start = h.as_ref().submatrix(0, 0, 1, 1).llt(Side::Lower).unwrap();
        let mut factor = ReducedFactor::from_factor(&[0], start.L());
        for v in 1..n {
            assert!(factor.append(v, |i| h[(i, v)]));
            if v % 3 == 0 {
                let p = factor.order.iter().position(|&i| i == v - 2).unwrap();
                factor.delete(p);
            }
        }
        // The deleted variables back: past the capacity, a compaction.
        for v in (1..n - 2).step_by(3) {
            assert!(factor.append(v, |i| h[(i, v)]));
        }
        assert_eq!(factor.k(), n);
        assert_eq!(factor.order.len(), n, "{:?}", factor.order);
        let x = factor.solve(&g);
        for &(i, _) in &x {
            let lhs: f64 = x.iter().map(|&(j, p)| h[(i, j)] * p).sum();
            assert!(
                (lhs + g[i]).abs() < 1e-12,
                "variable {i}: {lhs} vs {}",
                -g[i]
            );
        }
    }

    /// Random positive definite problems with both kinds of bounds: the answer satisfies the
    /// KKT conditions of the QP (which characterise its unique minimiser).
    #[test]
    fn random_problems_satisfy_the_kkt_conditions() {
        let mut seed = 7u64;
        let mut next = || crate::solver::uniform(&mut seed);
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
