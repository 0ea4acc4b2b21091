//! Dense convex quadratic programs with bounds and disks,
//!
//! ```text
//! minimise q(x) = 1/2 x'Hx - d'x   subject to   lower_i <= x_i <= upper_i,
//!                                               |(x_j, x_j+1)| <= r  for every disk (j, r),
//! ```
//!
//! the interface problem of the condensed solver in space, where the friction force of a node
//! lies in the disk of radius `b_i` of its tangent plane. Solved by a projected Newton method on
//! the separable convex set (Bertsekas' projected Newton of [`BoxQp`](super::box_qp::BoxQp),
//! carried over to disks):
//!
//! - a bound, or a disk's rim, is **binding** when `x` is within `eps` of it (the current size
//!   of the projected gradient) and the gradient pushes outward;
//! - the Newton step is taken in the subspace the binding constraints leave free: every free
//!   scalar, both coordinates of a disk that is not binding, and the tangent direction
//!   `tau = (-n_y, n_x)` of a binding disk (`n = x / |x|`), whose curvature adds `mu / r` to the
//!   reduced Hessian (`mu = -g . n >= 0`, the multiplier of the rim: the Hessian of the
//!   Lagrangian, so that the slip direction of a sliding node converges quadratically, not
//!   linearly as with the rim held fixed);
//! - a binding bound or rim moves along the scaled gradient (onto the bound);
//! - an Armijo search along the projection arc `x(a) = P(x + a p)` (`P`: clamping of the
//!   scalars, radial return of the disks) keeps every step a descent step: for a disk the
//!   scaling is one number, so that the projected scaled gradient is a descent direction.
//!
//! Units and stopping test as for the box QP: `x` is a force, the gradient a length, and the
//! projected gradient is measured as a force, `|x - P(x - D g)|_inf` with `D = diag(H)^-1`
//! (on a disk the inverse of the larger of its two diagonal entries).

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};

use super::box_qp::{hessian_apply, quadratic_gradient, BoxQpOutcome, ReducedFactor, DEAD};

/// A disk constraint `|(x_first, x_first+1)| <= radius`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Disk {
    /// The first of its two variables.
    pub first: usize,
    /// Its radius, `>= 0`.
    pub radius: f64,
}

/// A QP with bounds and disks (borrowed data). The variables of a disk have the bounds
/// `-inf, +inf`.
pub(crate) struct DiskQp<'a> {
    pub hessian: MatRef<'a, f64>,
    pub linear: &'a [f64],
    pub lower: &'a [f64],
    pub upper: &'a [f64],
    pub disks: &'a [Disk],
}

const ARMIJO: f64 = 1e-4;
/// As in the box QP: a bound within `eps` is binding, `eps` at most this fraction of the box
/// width or of the disk's radius.
const EPS_WIDTH: f64 = 0.25;
const MAX_HALVINGS: usize = 60;

/// One column of the basis `Z` of the Newton subspace: a unit vector or a disk's tangent.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Direction {
    Unit(usize),
    Tangent { first: usize, tau: [f64; 2] },
}

impl Direction {
    /// The name of the column in a kept factor (`m` variables): `i` for a unit vector,
    /// `m + first` for a disk's tangent (whichever way it points).
    fn key(&self, m: usize) -> usize {
        match *self {
            Direction::Unit(i) => i,
            Direction::Tangent { first, .. } => m + first,
        }
    }

    /// The (variable, coefficient) entries of the column.
    fn entries(&self) -> impl Iterator<Item = (usize, f64)> {
        let (a, b) = match *self {
            Direction::Unit(i) => ((i, 1.0), None),
            Direction::Tangent { first, tau } => ((first, tau[0]), Some((first + 1, tau[1]))),
        };
        std::iter::once(a).chain(b)
    }
}

/// `P(x)`, the projection onto the feasible set: the scalars clamped to `lower..=upper`, the
/// disks' points returned radially (shared by the projected Newton method here and MPGP).
pub(crate) fn project(lower: &[f64], upper: &[f64], disks: &[Disk], x: &mut [f64]) {
    for (i, xi) in x.iter_mut().enumerate() {
        *xi = xi.max(lower[i]).min(upper[i]);
    }
    for disk in disks {
        let (a, b) = (x[disk.first], x[disk.first + 1]);
        let norm = a.hypot(b);
        if norm > disk.radius {
            let s = if norm > 0.0 { disk.radius / norm } else { 0.0 };
            x[disk.first] = a * s;
            x[disk.first + 1] = b * s;
        }
    }
}

/// The subspace of a projected Newton step at `x` and the step of the binding constraints.
pub(crate) struct NewtonSubspace {
    /// The basis `Z`: every free scalar, both coordinates of a disk that is not binding, the
    /// tangent of a binding rim.
    pub basis: Vec<Direction>,
    /// The curvature `C` added to each column: `mu / r` for a rim's tangent (`mu = -g . n`,
    /// the rim's multiplier: the Hessian of the Lagrangian), zero otherwise.
    pub curvature: Vec<f64>,
    /// The step: on the binding constraints a bound's scaled gradient step and a point's
    /// radial step onto its rim; on the free scalars the scaled gradient step until
    /// [`NewtonSubspace::set_newton_step`] replaces it.
    pub step: Vec<f64>,
}

impl NewtonSubspace {
    /// The Newton step `y` in the subspace: the free scalars' entries of `step` become those
    /// of `Z y`, a rim's tangential move is added to its radial one.
    pub fn set_newton_step(&mut self, y: &[f64]) {
        for (direction, &ya) in self.basis.iter().zip(y) {
            match *direction {
                Direction::Unit(i) => self.step[i] = ya,
                Direction::Tangent { first, tau } => {
                    self.step[first] += ya * tau[0];
                    self.step[first + 1] += ya * tau[1];
                }
            }
        }
    }

    /// `Z v`, a vector of the `m` variables.
    pub fn expand(&self, v: &[f64], m: usize) -> Vec<f64> {
        let mut x = vec![0.0; m];
        for (direction, &va) in self.basis.iter().zip(v) {
            for (i, c) in direction.entries() {
                x[i] += c * va;
            }
        }
        x
    }

    /// `Z' w`.
    pub fn restrict(&self, w: &[f64]) -> Vec<f64> {
        self.basis
            .iter()
            .map(|d| d.entries().map(|(i, c)| c * w[i]).sum())
            .collect()
    }
}

/// The Newton subspace at `x` (gradient `g`): a bound, or a disk's rim, is binding when `x`
/// is within `eps = min(pg, EPS_WIDTH` of the box's width or the disk's radius`)` of it and
/// the gradient pushes outward; a binding bound moves along the scaled gradient `-D g`
/// (`scaling = diag(D)`, the projection clamps it), a binding point of a disk radially onto
/// its rim. Shared by the dense projected Newton method and its operator form (`mprgp`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn newton_subspace(
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    in_disk: &[bool],
    x: &[f64],
    g: &[f64],
    pg: f64,
    scaling: &[f64],
) -> NewtonSubspace {
    let m = x.len();
    let mut step: Vec<f64> = (0..m).map(|i| -g[i] * scaling[i]).collect();
    let mut basis = Vec::with_capacity(m);
    let mut curvature = Vec::with_capacity(m);
    for i in (0..m).filter(|&i| !in_disk[i]) {
        let eps = pg.min(EPS_WIDTH * (upper[i] - lower[i]));
        let binding =
            (x[i] <= lower[i] + eps && g[i] > 0.0) || (x[i] >= upper[i] - eps && g[i] < 0.0);
        if !binding {
            basis.push(Direction::Unit(i));
            curvature.push(0.0);
        }
    }
    for disk in disks {
        let (a, b) = (disk.first, disk.first + 1);
        if disk.radius <= 0.0 {
            // A point: nothing moves (the projection undoes the gradient step).
            continue;
        }
        let norm = x[a].hypot(x[b]);
        let eps = pg.min(EPS_WIDTH * disk.radius);
        let outward = if norm > 0.0 {
            -(g[a] * x[a] + g[b] * x[b]) / norm
        } else {
            0.0
        };
        if norm >= disk.radius - eps && outward > 0.0 {
            let n = [x[a] / norm, x[b] / norm];
            let tau = [-n[1], n[0]];
            // Radial: onto the rim (a longer outward step would be cut back by the
            // projection, and shrink the tangential step with it); tangential: the Newton
            // step.
            let radial = disk.radius - norm;
            step[a] = radial * n[0];
            step[b] = radial * n[1];
            basis.push(Direction::Tangent { first: a, tau });
            curvature.push(outward / disk.radius);
        } else {
            basis.push(Direction::Unit(a));
            basis.push(Direction::Unit(b));
            curvature.extend([0.0, 0.0]);
        }
    }
    NewtonSubspace {
        basis,
        curvature,
        step,
    }
}

/// The Armijo search along the projection arc `x(a) = P(x + a p)` from `x` (gradient `g`),
/// `a = 1, 1/2, ...`: the accepted point and `H (x(a) - x)` (one product `apply` per trial),
/// `None` when no decrease is representable in floating point.
///
/// The round-off of q's change near the minimiser: the radial return of a point moved along a
/// rim is exact to `eps r`, which `mu` turns into an error of `eps r |g|` in q, far above the
/// decrease of a tangential step of size `e` (`O(e^2)`) once `e` is below about `sqrt(eps)`. A
/// full step whose change is below that round-off is the Newton step of a converging
/// iteration: taken as it is (the projected gradient decides).
#[allow(clippy::too_many_arguments)]
#[allow(clippy::type_complexity)]
pub(crate) fn armijo_on_arc<E>(
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    x: &[f64],
    g: &[f64],
    p: &[f64],
    mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
) -> Result<Option<(Vec<f64>, Vec<f64>)>, E> {
    let m = x.len();
    let noise = 8.0
        * f64::EPSILON
        * (x.iter().zip(g).map(|(x, g)| (x * g).abs()).sum::<f64>()
            + disks
                .iter()
                .map(|d| d.radius * g[d.first].hypot(g[d.first + 1]))
                .sum::<f64>());
    let mut alpha = 1.0;
    for _ in 0..MAX_HALVINGS {
        let mut trial: Vec<f64> = (0..m).map(|i| x[i] + alpha * p[i]).collect();
        project(lower, upper, disks, &mut trial);
        let step: Vec<f64> = trial.iter().zip(x).map(|(t, x)| t - x).collect();
        let slope: f64 = (0..m).map(|i| step[i] * g[i]).sum();
        if slope >= 0.0 && !(alpha == 1.0 && slope.abs() <= noise) {
            // Not a descent step: a shorter one is not either unless the arc bends.
            alpha *= 0.5;
            continue;
        }
        let h_step = apply(&step)?;
        let change: f64 = slope + 0.5 * (0..m).map(|i| step[i] * h_step[i]).sum::<f64>();
        let unresolved = alpha == 1.0 && change.abs() <= noise && slope.abs() <= noise;
        if (slope < 0.0 && -change >= -ARMIJO * slope) || unresolved {
            return Ok(Some((trial, h_step)));
        }
        alpha *= 0.5;
    }
    Ok(None)
}

impl DiskQp<'_> {
    /// `P(x)`: the scalars clamped, the disks' points returned radially.
    fn project(&self, x: &mut [f64]) {
        project(self.lower, self.upper, self.disks, x);
    }

    /// `H x`.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        hessian_apply(self.hessian, x)
    }

    /// `g = H x - d`.
    fn gradient(&self, x: &[f64]) -> Vec<f64> {
        quadratic_gradient(self.hessian, self.linear, x)
    }

    /// `|x - P(x - D g)|_inf`, a force.
    fn projected_gradient(&self, x: &[f64], g: &[f64], scaling: &[f64]) -> f64 {
        let mut y: Vec<f64> = (0..x.len()).map(|i| x[i] - g[i] * scaling[i]).collect();
        self.project(&mut y);
        x.iter()
            .zip(&y)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
    }

    /// Minimises from `start` (projected onto the set) until the scaled projected gradient is
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

    /// [`DiskQp::solve`] with the reduced factor `kept` of an earlier step or solve with the
    /// same `H` (updated on return; see [`DiskQp::reduced_newton_step`]).
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
        let inverse = |d: f64| {
            1.0 / if d > 0.0 {
                d
            } else {
                largest.max(f64::MIN_POSITIVE)
            }
        };
        let mut scaling: Vec<f64> = diagonal.iter().map(|&d| inverse(d)).collect();
        let mut in_disk = vec![false; m];
        for disk in self.disks {
            let (a, b) = (disk.first, disk.first + 1);
            let s = inverse(diagonal[a].max(diagonal[b]));
            scaling[a] = s;
            scaling[b] = s;
            in_disk[a] = true;
            in_disk[b] = true;
        }
        let mut x = start.to_vec();
        self.project(&mut x);
        let mut g = self.gradient(&x);
        let mut outcome = BoxQpOutcome {
            x: Vec::new(),
            iterations: 0,
            converged: false,
        };
        loop {
            let pg = self.projected_gradient(&x, &g, &scaling);
            if pg <= tolerance {
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
            // The Newton subspace and the scaled gradient step of the binding constraints.
            let mut subspace = newton_subspace(
                self.lower, self.upper, self.disks, &in_disk, &x, &g, pg, &scaling,
            );
            let newton = self.reduced_newton_step(&subspace.basis, &subspace.curvature, &g, kept);
            if let Some(y) = newton {
                subspace.set_newton_step(&y);
            }
            let p = subspace.step;
            let trial = armijo_on_arc(self.lower, self.upper, self.disks, &x, &g, &p, |v| {
                Ok::<_, std::convert::Infallible>(self.apply(v))
            });
            match trial {
                Ok(Some((trial, h_step))) => {
                    for i in 0..m {
                        g[i] += h_step[i];
                    }
                    x = trial;
                }
                // No decrease representable in floating point: x is as good as it gets.
                _ => break,
            }
        }
        outcome.x = x;
        outcome
    }

    /// The entry `(a, b)` of the reduced matrix `Z'HZ + C`.
    fn reduced_entry(&self, a: &Direction, b: &Direction, curvature: f64) -> f64 {
        let h = self.hessian;
        let mut value = 0.0;
        for (i, ci) in a.entries() {
            for (j, cj) in b.entries() {
                value += ci * cj * h[(i, j)];
            }
        }
        if a.key(self.linear.len()) == b.key(self.linear.len()) {
            value += curvature;
        }
        value
    }

    /// `y = -(Z'HZ + C)^-1 Z'g` for the basis `Z` (`basis`) and the curvature `C` of the
    /// binding rims.
    ///
    /// The factor `kept` of an earlier step's reduced matrix (or of an earlier solve with the
    /// same `H`: the steps of a Coulomb fixed point) preconditions conjugate gradients on this
    /// step's matrix, which differs from the kept one by the turn of the sliding nodes'
    /// tangents and their curvatures `mu / r`: small changes once the binding set settles, so
    /// that a few iterations (`O(k^2)` each) replace the dense factorisation (`O(k^3 / 3)`).
    /// It is first brought to the basis by deletions and appends (`O(k^2)` each) when few
    /// columns joined or left it ([`UPDATE_CHANGES`]). When more changed, or the iterations
    /// do not converge within [`CG_ITERATIONS`], the reduced matrix is factorised anew (dense
    /// Cholesky, shifted slightly if it is only semidefinite; such a factor is not kept) and
    /// kept. `None` if even the shifted matrix cannot be factorised.
    fn reduced_newton_step(
        &self,
        basis: &[Direction],
        curvature: &[f64],
        g: &[f64],
        kept: &mut ReducedFactor,
    ) -> Option<Vec<f64>> {
        let k = basis.len();
        if k == 0 {
            return None;
        }
        let m = self.linear.len();
        let gradient: Vec<f64> = basis
            .iter()
            .map(|d| d.entries().map(|(i, c)| c * g[i]).sum())
            .collect();
        if kept
            .positions()
            .iter()
            .any(|&key| key != DEAD && key >= 2 * m)
        {
            // Made for another problem.
            *kept = ReducedFactor::default();
        }
        if kept.k() > 0 && self.update(basis, curvature, kept) {
            if let Some(y) = self.preconditioned_cg(basis, curvature, &gradient, kept) {
                return Some(y);
            }
        }
        let mut reduced = Mat::<f64>::from_fn(k, k, |a, b| {
            self.reduced_entry(
                &basis[a],
                &basis[b],
                if a == b { curvature[a] } else { 0.0 },
            )
        });
        let trace = (0..k).map(|a| reduced[(a, a)]).sum::<f64>();
        let mut shift = 0.0;
        for _ in 0..4 {
            if let Ok(llt) = reduced.llt(Side::Lower) {
                let mut rhs = Mat::<f64>::from_fn(k, 1, |a, _| -gradient[a]);
                llt.solve_in_place(rhs.as_mut());
                *kept = if shift == 0.0 {
                    let keys: Vec<usize> = basis.iter().map(|d| d.key(m)).collect();
                    ReducedFactor::from_factor(&keys, llt.L())
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

    /// Brings `kept` to the columns of `basis` by deletions and appends (the appended rows
    /// from this step's reduced matrix); `false` (and `kept` cleared) when too much changed
    /// or a pivot fell below round-off.
    fn update(&self, basis: &[Direction], curvature: &[f64], kept: &mut ReducedFactor) -> bool {
        let m = self.linear.len();
        // The column of every key of the basis.
        let mut column = vec![usize::MAX; 2 * m];
        for (a, d) in basis.iter().enumerate() {
            column[d.key(m)] = a;
        }
        let mut in_kept = vec![false; 2 * m];
        let mut removed = Vec::new();
        for (p, &key) in kept.positions().iter().enumerate() {
            if key == DEAD {
                continue;
            }
            if key >= 2 * m || column[key] == usize::MAX {
                removed.push(p);
            } else {
                in_kept[key] = true;
            }
        }
        let added: Vec<usize> = (0..basis.len())
            .filter(|&a| !in_kept[basis[a].key(m)])
            .collect();
        let changes = removed.len() + added.len();
        if changes as f64 > (UPDATE_CHANGES * basis.len() as f64).max(8.0) {
            *kept = ReducedFactor::default();
            return false;
        }
        for &p in removed.iter().rev() {
            kept.delete(p);
        }
        for a in added {
            let entry = |key: usize| {
                let b = column[key];
                self.reduced_entry(
                    &basis[a],
                    &basis[b],
                    if a == b { curvature[a] } else { 0.0 },
                )
            };
            if !kept.append(basis[a].key(m), entry) {
                *kept = ReducedFactor::default();
                return false;
            }
        }
        true
    }

    /// Conjugate gradients on `(Z'HZ + C) y = -Z'g` (`gradient = Z'g`) preconditioned by the
    /// factor `kept` (on the same columns), to a residual of [`CG_TOLERANCE`] relative to
    /// `Z'g`; `None` without convergence in [`CG_ITERATIONS`] steps.
    fn preconditioned_cg(
        &self,
        basis: &[Direction],
        curvature: &[f64],
        gradient: &[f64],
        kept: &ReducedFactor,
    ) -> Option<Vec<f64>> {
        let (k, m) = (basis.len(), self.linear.len());
        let keys: Vec<usize> = basis.iter().map(|d| d.key(m)).collect();
        let mut column = vec![usize::MAX; 2 * m];
        for (a, &key) in keys.iter().enumerate() {
            column[key] = a;
        }
        // z = (L L')^-1 r.
        let precondition = |r: &[f64]| -> Vec<f64> {
            let mut keyed = vec![0.0; 2 * m];
            for (&key, &ri) in keys.iter().zip(r) {
                keyed[key] = -ri;
            }
            let mut z = vec![0.0; k];
            for (key, value) in kept.solve(&keyed) {
                z[column[key]] = value;
            }
            z
        };
        // (Z'HZ + C) v.
        let apply = |v: &[f64]| -> Vec<f64> {
            let mut x = vec![0.0; m];
            for (d, &va) in basis.iter().zip(v) {
                for (i, c) in d.entries() {
                    x[i] += c * va;
                }
            }
            let hx = self.apply(&x);
            basis
                .iter()
                .zip(v.iter().zip(curvature))
                .map(|(d, (&va, &c))| d.entries().map(|(i, ci)| ci * hx[i]).sum::<f64>() + c * va)
                .collect()
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut r: Vec<f64> = gradient.iter().map(|x| -x).collect();
        let target = CG_TOLERANCE * dot(&r, &r).sqrt();
        let mut y = vec![0.0; k];
        if target == 0.0 {
            return Some(y);
        }
        let mut z = precondition(&r);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        for _ in 0..CG_ITERATIONS {
            let ap = apply(&p);
            let curvature_p = dot(&p, &ap);
            if !(curvature_p > 0.0 && rz > 0.0) {
                return None;
            }
            let alpha = rz / curvature_p;
            for a in 0..k {
                y[a] += alpha * p[a];
                r[a] -= alpha * ap[a];
            }
            if dot(&r, &r).sqrt() <= target {
                return Some(y);
            }
            z = precondition(&r);
            let rz_next = dot(&r, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            for a in 0..k {
                p[a] = z[a] + beta * p[a];
            }
        }
        None
    }
}

/// The limit on the conjugate gradient steps of a Newton step preconditioned by a kept factor
/// (beyond it the reduced matrix is factorised anew: the iterations cost `O(k^2)` each, a
/// factorisation `O(k^3 / 3)`).
const CG_ITERATIONS: usize = 8;
/// The kept factor is brought to a new basis when at most this fraction of its columns (or 8)
/// changed: each change costs `O(k^2)` in scalar loops, against a blocked factorisation's
/// `O(k^3 / 3)`.
const UPDATE_CHANGES: f64 = 0.02;

/// The residual of the preconditioned conjugate gradients relative to the reduced gradient:
/// the Newton step to about the accuracy of a direct solve.
const CG_TOLERANCE: f64 = 1e-11;

#[cfg(test)]
mod tests {
    use super::*;

    use crate::solver::uniform as next;

    /// One disk with `H = h I`: the minimiser is the radial return of `d / h`.
    #[test]
    fn an_isotropic_disk_problem_is_the_radial_return() {
        for (h, d, r) in [
            (2.0, [3.0, 4.0], 1.0),
            (2.0, [0.3, -0.4], 1.0),
            (1e-6, [-3e-6, 1e-6], 0.5),
            (5.0, [1.0, 1.0], 0.0),
        ] {
            let hessian = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { h } else { 0.0 });
            let qp = DiskQp {
                hessian: hessian.as_ref(),
                linear: &d,
                lower: &[f64::NEG_INFINITY; 2],
                upper: &[f64::INFINITY; 2],
                disks: &[Disk {
                    first: 0,
                    radius: r,
                }],
            };
            let out = qp.solve(&[0.0, 0.0], 1e-14, 100);
            assert!(out.converged);
            let mut expected = [d[0] / h, d[1] / h];
            let norm = expected[0].hypot(expected[1]);
            if norm > r {
                expected = [expected[0] * r / norm, expected[1] * r / norm];
            }
            for k in 0..2 {
                assert!(
                    (out.x[k] - expected[k]).abs() < 1e-12,
                    "{:?} {expected:?}",
                    out.x
                );
            }
        }
    }

    /// Random positive definite problems with a sign bound and disks: the answer satisfies
    /// the KKT conditions (which characterise the unique minimiser): the gradient vanishes
    /// inside, and on a rim it is `-mu n` with `mu >= 0`.
    #[test]
    fn random_problems_satisfy_the_kkt_conditions() {
        let mut seed = 5u64;
        for case in 0..50 {
            let n = 7;
            let a = Mat::<f64>::from_fn(n, n, |_, _| next(&mut seed));
            let h = &a * a.transpose() + Mat::<f64>::identity(n, n) * 0.1;
            let d: Vec<f64> = (0..n).map(|_| 3.0 * next(&mut seed)).collect();
            let mut lower = vec![f64::NEG_INFINITY; n];
            let upper = vec![f64::INFINITY; n];
            lower[0] = 0.0;
            let disks = [
                Disk {
                    first: 1,
                    radius: 0.2 + 0.5 * next(&mut seed).abs(),
                },
                Disk {
                    first: 3,
                    radius: 0.3,
                },
                Disk {
                    first: 5,
                    radius: 0.05 * (case % 3) as f64,
                },
            ];
            let qp = DiskQp {
                hessian: h.as_ref(),
                linear: &d,
                lower: &lower,
                upper: &upper,
                disks: &disks,
            };
            let out = qp.solve(&vec![0.0; n], 1e-13, 200);
            assert!(out.converged, "case {case}: {} iterations", out.iterations);
            assert!(
                out.iterations < 40,
                "case {case}: {} iterations",
                out.iterations
            );
            let g = qp.gradient(&out.x);
            let tol = 1e-10;
            // The sign bound.
            assert!(out.x[0] >= 0.0);
            if out.x[0] > tol {
                assert!(g[0].abs() < tol, "case {case}: {}", g[0]);
            } else {
                assert!(g[0] > -tol);
            }
            for disk in &disks {
                let (i, j) = (disk.first, disk.first + 1);
                let norm = out.x[i].hypot(out.x[j]);
                assert!(norm <= disk.radius * (1.0 + 1e-15) + 1e-300);
                if norm < disk.radius - tol {
                    assert!(g[i].hypot(g[j]) < tol, "case {case}: inside, {g:?}");
                } else if disk.radius > 0.0 {
                    // g = -mu n: the tangential part vanishes, mu >= 0.
                    let (ni, nj) = (out.x[i] / norm, out.x[j] / norm);
                    let tangential = -g[i] * nj + g[j] * ni;
                    let mu = -(g[i] * ni + g[j] * nj);
                    assert!(
                        tangential.abs() < tol,
                        "case {case}: tangential {tangential}"
                    );
                    assert!(mu > -tol, "case {case}: mu {mu}");
                }
            }
        }
    }

    /// A sequence of problems with the same `H` and growing radii (the steps of a Coulomb
    /// fixed point), solved with the factor kept from one to the next (conjugate gradients
    /// preconditioned by it) and each afresh: the same minimisers.
    #[test]
    fn a_kept_factor_gives_the_answers_of_fresh_solves() {
        let mut seed = 11u64;
        for case in 0..10 {
            let n = 40;
            let a = Mat::<f64>::from_fn(n, n, |_, _| next(&mut seed));
            let h = &a * a.transpose() + Mat::<f64>::identity(n, n) * 0.5;
            let d: Vec<f64> = (0..n).map(|_| 3.0 * next(&mut seed)).collect();
            let mut lower = vec![f64::NEG_INFINITY; n];
            let upper = vec![f64::INFINITY; n];
            // Ten normal forces, then fifteen disks.
            for l in lower.iter_mut().take(10) {
                *l = 0.0;
            }
            let radii: Vec<f64> = (0..15).map(|_| 0.1 + 0.4 * next(&mut seed).abs()).collect();
            let mut kept = ReducedFactor::default();
            let mut warm = vec![0.0; n];
            for scale in [0.5, 0.7, 1.0, 1.3, 1.31] {
                let disks: Vec<Disk> = radii
                    .iter()
                    .enumerate()
                    .map(|(k, &r)| Disk {
                        first: 10 + 2 * k,
                        radius: scale * r,
                    })
                    .collect();
                let qp = DiskQp {
                    hessian: h.as_ref(),
                    linear: &d,
                    lower: &lower,
                    upper: &upper,
                    disks: &disks,
                };
                let with = qp.solve_with(&warm, 1e-13, 200, &mut kept);
                let fresh = qp.solve(&vec![0.0; n], 1e-13, 200);
                assert!(with.converged && fresh.converged, "case {case}");
                let scale_x = fresh.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (x, y) in with.x.iter().zip(&fresh.x) {
                    assert!(
                        (x - y).abs() <= 1e-9 * scale_x,
                        "case {case}: {x} against {y}"
                    );
                }
                warm = with.x;
            }
        }
    }
}
