//! Matrix-free convex quadratic programs with separable constraints,
//!
//! ```text
//! minimise q(x) = 1/2 x'Hx - d'x   subject to   lower_i <= x_i <= upper_i,
//!                                               |(x_j, x_j+1)| <= r  for every disk (j, r),
//! ```
//!
//! with `H` symmetric positive (semi)definite and known only through its action `x -> Hx`:
//! the interface problem of the condensed solver when its interface is too large for the dense
//! `H` (`Hx = B K^-1 B' x`, one pair of triangular solves per body).
//!
//! Solved by **MPGP**, Dostál's modified proportioning with gradient projections (MPRGP for
//! bounds, extended to separable convex sets by Dostál and Kozubek): conjugate gradients on the
//! free variables while the gradient of the active constraints is small against the free one
//! (proportional iterates), and
//!
//! - an **expansion step** when a conjugate gradient step would leave the set: the projected
//!   conjugate gradient step `P(x - step p)` (the "projcg" expansion of Kružík et al.,
//!   *Active set expansion strategies in MPRGP algorithm*, 2020, PERMON's option with its
//!   fallback), kept when its energy is below that of the step's feasible part; otherwise
//!   the feasible part, then a projected gradient step `x <- P(x - alpha g)` of fixed length
//!   `alpha = 1.9 / |H|` (`|H|` estimated by power iterations and raised to the Rayleigh
//!   quotient of a conjugate direction above it; a step that raises `q` halves `alpha` for
//!   good), which may add many constraints at once;
//! - a **proportioning step** when the chopped gradient `beta` (the part of the projected
//!   gradient on the active constraints) dominates: the exact minimisation along `-beta` when it
//!   stays feasible (always for sign bounds: it only releases), else the projected gradient
//!   step.
//!
//! The free set is the set of variables strictly inside their bounds, and the disks strictly
//! inside their rim. On a rim `n = x / |x|` (outward) the projected gradient is `g` when
//! `g . n >= 0` (the descent direction points inward) and its tangential part `g - (g . n) n`
//! otherwise; on a disk of radius 0 it vanishes.
//!
//! Stopping test: `|g^P|_inf <= tolerance` (a length in the interface problem: a gap or slip
//! residual), then confirmed with a freshly computed gradient.
//!
//! MPGP moves a node sliding on its disk's rim by projected gradient steps only, which
//! converge linearly at the rate of the condition of `H`. With disks the condensed solver
//! therefore takes [`Mprgp::solve_by_newton`]: the projected Newton method of the dense disk QP
//! (`disk_qp`: a binding rim's tangent with the rim's curvature `mu / r` in the Newton
//! subspace, an Armijo search along the projection arc), its Newton systems
//! `(Z'HZ + C) y = -Z'g` solved inexactly by conjugate gradients on the products `x -> Hx`,
//! with Eisenstat and Walker's forcing terms, preconditioned by the Ritz pairs of the products
//! kept from the earlier systems and solves (`kept_products`).

use super::disk_qp::{armijo_on_arc, newton_subspace, project, Disk};
use super::kept_products::KeptProducts;

/// The action `x -> H x` of the problem's matrix (with the error of the caller's products).
type Product<'f, E> = dyn FnMut(&[f64]) -> Result<Vec<f64>, E> + 'f;

/// The outcome of [`Mprgp::solve`].
#[derive(Debug, Clone)]
pub(crate) struct MprgpOutcome {
    pub x: Vec<f64>,
    /// `H x` at the returned `x` (computed afresh at the end, not by recurrence).
    pub hx: Vec<f64>,
    /// Iterations (MPGP: conjugate gradient, expansion and proportioning steps; the Newton
    /// method: Newton steps).
    pub iterations: usize,
    pub converged: bool,
}

/// The constraint set of the problem (borrowed data). The variables of a disk have the bounds
/// `-inf, +inf`.
pub(crate) struct Mprgp<'a> {
    pub linear: &'a [f64],
    pub lower: &'a [f64],
    pub upper: &'a [f64],
    pub disks: &'a [Disk],
    /// Per variable, the weight of its projected gradient in the stopping test (empty: 1);
    /// a problem solved in scaled variables `x = S y` stops on `|S^-1 g^P|_inf`, its
    /// unscaled gradient.
    pub weights: &'a [f64],
}

/// `a . b`.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `H x` by `apply`, or zero without a product when `x = 0` (a cold start).
fn product_at<E>(
    x: &[f64],
    apply: impl FnOnce(&[f64]) -> Result<Vec<f64>, E>,
) -> Result<Vec<f64>, E> {
    if x.iter().all(|&v| v == 0.0) {
        Ok(vec![0.0; x.len()])
    } else {
        apply(x)
    }
}

/// The proportioning constant `Gamma` (Dostál's recommended value).
const GAMMA: f64 = 1.0;
/// The fixed step length relative to `1 / |H|` (in `(0, 2)`).
const STEP: f64 = 1.9;
/// A disk point within this fraction of its radius from the rim is on it.
const RIM: f64 = 1e-12;

impl Mprgp<'_> {
    /// `P(x)`: the scalars clamped, the disks' points returned radially.
    fn project(&self, x: &mut [f64]) {
        project(self.lower, self.upper, self.disks, x);
    }

    /// True for the variables of a disk.
    fn in_disk(&self) -> Vec<bool> {
        let mut in_disk = vec![false; self.linear.len()];
        for disk in self.disks {
            in_disk[disk.first] = true;
            in_disk[disk.first + 1] = true;
        }
        in_disk
    }

    /// The free gradient `phi` (the gradient on the free variables, zero elsewhere) and the
    /// chopped gradient `beta` (the projected gradient on the active constraints).
    fn split(&self, x: &[f64], g: &[f64], in_disk: &[bool]) -> (Vec<f64>, Vec<f64>) {
        let m = x.len();
        let mut phi = vec![0.0; m];
        let mut beta = vec![0.0; m];
        for i in (0..m).filter(|&i| !in_disk[i]) {
            let (at_lower, at_upper) = (x[i] <= self.lower[i], x[i] >= self.upper[i]);
            match (at_lower, at_upper) {
                // A point: nothing moves.
                (true, true) => {}
                (true, false) => beta[i] = g[i].min(0.0),
                (false, true) => beta[i] = g[i].max(0.0),
                (false, false) => phi[i] = g[i],
            }
        }
        for disk in self.disks {
            let (a, b) = (disk.first, disk.first + 1);
            if disk.radius <= 0.0 {
                continue;
            }
            let norm = x[a].hypot(x[b]);
            if norm < disk.radius * (1.0 - RIM) {
                phi[a] = g[a];
                phi[b] = g[b];
            } else {
                let n = [x[a] / norm, x[b] / norm];
                let outward = (g[a] * n[0] + g[b] * n[1]).min(0.0);
                beta[a] = g[a] - outward * n[0];
                beta[b] = g[b] - outward * n[1];
            }
        }
        (phi, beta)
    }

    /// The largest `a >= 0` with `x - a p` in the set.
    fn feasible_step(&self, x: &[f64], p: &[f64], in_disk: &[bool]) -> f64 {
        let mut step = f64::INFINITY;
        for i in (0..x.len()).filter(|&i| !in_disk[i]) {
            if p[i] > 0.0 {
                step = step.min((x[i] - self.lower[i]) / p[i]);
            } else if p[i] < 0.0 {
                step = step.min((x[i] - self.upper[i]) / p[i]);
            }
        }
        for disk in self.disks {
            let (a, b) = (disk.first, disk.first + 1);
            let pp = p[a] * p[a] + p[b] * p[b];
            if pp == 0.0 {
                continue;
            }
            let xp = x[a] * p[a] + x[b] * p[b];
            let c = x[a] * x[a] + x[b] * x[b] - disk.radius * disk.radius;
            // |x - a p|^2 = r^2: the larger root.
            let root = (xp + (xp * xp - pp * c).max(0.0).sqrt()) / pp;
            step = step.min(root.max(0.0));
        }
        step.max(0.0)
    }

    /// `|W g^P|` per variable with `W` the [`weights`](Self::weights).
    fn weighted<'s>(&'s self, phi: &'s [f64], beta: &'s [f64]) -> impl Iterator<Item = f64> + 's {
        phi.iter()
            .zip(beta)
            .enumerate()
            .map(|(i, (a, b))| (a + b).abs() * self.weights.get(i).copied().unwrap_or(1.0))
    }

    /// `|W g^P|_inf` with `W` the [`weights`](Self::weights).
    fn projected_gradient(&self, phi: &[f64], beta: &[f64]) -> f64 {
        self.weighted(phi, beta).fold(0.0f64, f64::max)
    }

    /// `|W g^P|` per variable at `x` with gradient `g`: what the stopping test of
    /// [`Mprgp::solve`] measures, variable by variable.
    pub fn violations(&self, x: &[f64], g: &[f64]) -> Vec<f64> {
        let (phi, beta) = self.split(x, g, &self.in_disk());
        self.weighted(&phi, &beta).collect()
    }

    /// Minimises from `start` (projected onto the set) until `|g^P|_inf <= tolerance` or
    /// `max_iterations` iterations, with `apply(x) = H x` and `norm` an estimate of `|H|_2`
    /// from below (power iterations). An error of `apply` ends the solve with it.
    pub fn solve<E>(
        &self,
        start: &[f64],
        tolerance: f64,
        max_iterations: usize,
        norm: f64,
        mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
    ) -> Result<MprgpOutcome, E> {
        let m = self.linear.len();
        let in_disk = self.in_disk();
        let mut x = start.to_vec();
        self.project(&mut x);
        let linear = self.linear;
        let gradient_at = |apply: &mut Product<'_, E>, x: &[f64]| -> Result<Vec<f64>, E> {
            let mut g = product_at(x, |x| apply(x))?;
            for (gi, di) in g.iter_mut().zip(linear) {
                *gi -= di;
            }
            Ok(g)
        };
        let energy = |x: &[f64], g: &[f64]| -> f64 {
            // q = 1/2 x'(Hx - d) - 1/2 d'x = 1/2 x'(g - d).
            0.5 * x
                .iter()
                .zip(g)
                .zip(self.linear)
                .map(|((x, g), d)| x * (g - d))
                .sum::<f64>()
        };
        // The round-off of q: a rise below it is no sign of a too long step.
        let noise = |x: &[f64], g: &[f64]| -> f64 {
            8.0 * f64::EPSILON
                * x.iter()
                    .zip(g)
                    .zip(self.linear)
                    .map(|((x, g), d)| (x * g).abs() + (x * d).abs())
                    .sum::<f64>()
        };
        // The projected gradient step of fixed length `alpha`, halved for good when it raises
        // the energy beyond round-off (|H| was underestimated).
        let projected_step = |apply: &mut Product<'_, E>,
                              x: &mut Vec<f64>,
                              g: &mut Vec<f64>,
                              alpha: &mut f64|
         -> Result<(), E> {
            let before = energy(x, g);
            let mut trial: Vec<f64> = x
                .iter()
                .zip(g.iter())
                .map(|(x, g)| x - *alpha * g)
                .collect();
            self.project(&mut trial);
            let g_trial = gradient_at(apply, &trial)?;
            if energy(&trial, &g_trial) > before + noise(&trial, &g_trial) {
                *alpha *= 0.5;
            }
            *x = trial;
            *g = g_trial;
            Ok(())
        };
        let mut alpha = if norm > 0.0 { STEP / norm } else { 1.0 };
        let mut g = gradient_at(&mut apply, &x)?;
        let (mut phi, mut beta) = self.split(&x, &g, &in_disk);
        let mut p = phi.clone();
        let mut iterations = 0;
        let mut converged = false;
        loop {
            let pg = self.projected_gradient(&phi, &beta);
            if pg <= tolerance {
                // Confirmed with the gradient computed afresh (the recurrences drift).
                g = gradient_at(&mut apply, &x)?;
                (phi, beta) = self.split(&x, &g, &in_disk);
                if self.projected_gradient(&phi, &beta) <= tolerance {
                    converged = true;
                    break;
                }
                p = phi.clone();
            }
            if iterations == max_iterations {
                break;
            }
            iterations += 1;
            // The reduced free gradient: the part of the free gradient step the set allows.
            let mut moved: Vec<f64> = (0..m).map(|i| x[i] - alpha * phi[i]).collect();
            self.project(&mut moved);
            let reduced_phi: f64 = (0..m).map(|i| (x[i] - moved[i]) / alpha * phi[i]).sum();
            let chopped = dot(&beta, &beta);
            if chopped <= GAMMA * GAMMA * reduced_phi {
                // Proportional: conjugate gradients on the free set.
                let ap = apply(&p)?;
                let curvature = dot(&p, &ap);
                if curvature.is_nan() || curvature <= 0.0 {
                    break;
                }
                // A Rayleigh quotient above the estimate of |H|: the step length shrinks.
                alpha = alpha.min(STEP * dot(&p, &p) / curvature);
                let step = dot(&g, &p) / curvature;
                let feasible = self.feasible_step(&x, &p, &in_disk);
                if step <= feasible {
                    for i in 0..m {
                        x[i] -= step * p[i];
                        g[i] -= step * ap[i];
                    }
                    (phi, beta) = self.split(&x, &g, &in_disk);
                    let gamma = dot(&phi, &ap) / curvature;
                    for i in 0..m {
                        p[i] = phi[i] - gamma * p[i];
                    }
                } else {
                    // Expansion. First the projected conjugate gradient step `P(x - step p)`
                    // ("projcg", Kružík et al. 2020), kept when its energy is below the
                    // feasible step's: it adds at once every constraint the whole step meets
                    // (the fixed length `alpha` is often much shorter than `step`).
                    let mut trial: Vec<f64> = (0..m).map(|i| x[i] - step * p[i]).collect();
                    self.project(&mut trial);
                    let g_trial = gradient_at(&mut apply, &trial)?;
                    let at_feasible = energy(&x, &g) - feasible * dot(&g, &p)
                        + 0.5 * feasible * feasible * curvature;
                    let accepted = energy(&trial, &g_trial) <= at_feasible;
                    if accepted {
                        x = trial;
                        g = g_trial;
                    } else {
                        // The feasible part, then a projected gradient step.
                        for i in 0..m {
                            x[i] -= feasible * p[i];
                            g[i] -= feasible * ap[i];
                        }
                        self.project(&mut x);
                        projected_step(&mut apply, &mut x, &mut g, &mut alpha)?;
                    }
                    (phi, beta) = self.split(&x, &g, &in_disk);
                    p = phi.clone();
                }
            } else {
                // Proportioning: release the active constraints along the chopped gradient.
                let ab = apply(&beta)?;
                let curvature = dot(&beta, &ab);
                let step = if curvature > 0.0 {
                    chopped / curvature
                } else {
                    f64::INFINITY
                };
                let feasible = self.feasible_step(&x, &beta, &in_disk);
                if step <= feasible {
                    for i in 0..m {
                        x[i] -= step * beta[i];
                        g[i] -= step * ab[i];
                    }
                    self.project(&mut x);
                } else {
                    projected_step(&mut apply, &mut x, &mut g, &mut alpha)?;
                }
                (phi, beta) = self.split(&x, &g, &in_disk);
                p = phi.clone();
            }
        }
        let hx: Vec<f64> = g.iter().zip(self.linear).map(|(g, d)| g + d).collect();
        Ok(MprgpOutcome {
            x,
            hx,
            iterations,
            converged,
        })
    }
}

impl Mprgp<'_> {
    /// Minimises by the projected Newton method of the dense disk QP (`disk_qp`: the binding
    /// bounds and rims, a rim's tangent with its curvature `mu / r` in the Newton subspace, an
    /// Armijo search along the projection arc) with each Newton system
    /// `(Z'HZ + C) y = -Z'g` solved inexactly by conjugate gradients on products `apply`:
    /// the residual reduced by the forcing term `eta_k` of Eisenstat and Walker (choice 2,
    /// `eta_k = 0.9 (|g^P_k| / |g^P_k-1|)^2` with their safeguard, at most [`ETA_MAX`]), or to
    /// a quarter of `tolerance`. The binding tests measure the projected gradient as a force
    /// with the scaling `1 / |H|` (`norm`, an estimate of `|H|_2`; the diagonal of `H` is not
    /// at hand), and a binding bound moves along `-g / |H|`.
    ///
    /// The conjugate gradients are preconditioned by the spectral preconditioner of `kept`
    /// (`kept_products`: the Ritz pairs of the largest eigenvalues of `H` from the products
    /// kept so far, mapped down to the next Ritz value), and every product of the solve is
    /// added to `kept`: a caller that solves again with the same `H` (the steps of a Coulomb
    /// fixed point) passes the same store (`KeptProducts::disabled` gives plain conjugate
    /// gradients). The preconditioner is symmetric positive definite, so the Newton systems and
    /// the answer are those of the unpreconditioned method; only the products differ.
    ///
    /// Stops as [`Mprgp::solve`] does (`|g^P|_inf <= tolerance`, confirmed with a fresh
    /// gradient), after `max_steps` Newton steps, or when the products exceed `max_products`.
    /// `iterations` of the outcome counts the Newton steps.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_by_newton<E>(
        &self,
        start: &[f64],
        tolerance: f64,
        max_steps: usize,
        max_products: usize,
        norm: f64,
        kept: &mut KeptProducts,
        mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
    ) -> Result<MprgpOutcome, E> {
        let m = self.linear.len();
        let in_disk = self.in_disk();
        let scaling = vec![if norm > 0.0 { 1.0 / norm } else { 1.0 }; m];
        let mut products = 0usize;
        // Every product is kept for the preconditioner of the later Newton systems.
        let mut counted = |x: &[f64], products: &mut usize, kept: &mut KeptProducts| {
            product_at(x, |x| {
                *products += 1;
                let hx = apply(x)?;
                kept.add(x, &hx);
                Ok(hx)
            })
        };
        let mut x = start.to_vec();
        self.project(&mut x);
        let gradient_at = |hx: Vec<f64>| -> Vec<f64> {
            hx.into_iter()
                .zip(self.linear)
                .map(|(h, d)| h - d)
                .collect()
        };
        let mut g = gradient_at(counted(&x, &mut products, kept)?);
        let mut iterations = 0;
        let mut converged = false;
        let (mut previous, mut eta) = (f64::NAN, ETA_MAX);
        loop {
            let (phi, beta) = self.split(&x, &g, &in_disk);
            let pg = self.projected_gradient(&phi, &beta);
            if pg <= tolerance {
                // Confirmed with the gradient computed afresh (the updates drift).
                g = gradient_at(counted(&x, &mut products, kept)?);
                let (phi, beta) = self.split(&x, &g, &in_disk);
                if self.projected_gradient(&phi, &beta) <= tolerance {
                    converged = true;
                    break;
                }
            }
            if iterations == max_steps || products >= max_products {
                break;
            }
            iterations += 1;
            // The projected gradient as a force (the binding tests' eps).
            let mut moved: Vec<f64> = (0..m).map(|i| x[i] - g[i] * scaling[i]).collect();
            self.project(&mut moved);
            let pg_force = x
                .iter()
                .zip(&moved)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            let mut subspace = newton_subspace(
                self.lower, self.upper, self.disks, &in_disk, &x, &g, pg_force, &scaling,
            );
            // The forcing term.
            if previous.is_finite() {
                let next = 0.9 * (pg / previous).powi(2);
                let safeguard = 0.9 * eta * eta;
                eta = if safeguard > 0.1 {
                    next.max(safeguard)
                } else {
                    next
                }
                .min(ETA_MAX);
            }
            previous = pg;
            // Conjugate gradients on (Z'HZ + C) y = -Z'g from y = 0, preconditioned by the
            // spectral preconditioner of the kept products (`kept_products`; the identity
            // until it has Ritz pairs); the stopping test on the unpreconditioned residual.
            let k = subspace.basis.len();
            let preconditioner = kept.preconditioner(&subspace);
            let mut y = vec![0.0; k];
            let mut r: Vec<f64> = subspace.restrict(&g).iter().map(|v| -v).collect();
            let target = eta * dot(&r, &r).sqrt();
            let mut z = preconditioner.apply(&r);
            let mut p = z.clone();
            let mut rz = dot(&r, &z);
            while k > 0 && products < max_products {
                let r_inf = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                if dot(&r, &r).sqrt() <= target || r_inf <= 0.25 * tolerance {
                    break;
                }
                let hv = counted(&subspace.expand(&p, m), &mut products, kept)?;
                let mut ap = subspace.restrict(&hv);
                for ((a, c), pa) in ap.iter_mut().zip(&subspace.curvature).zip(&p) {
                    *a += c * pa;
                }
                let curvature = dot(&p, &ap);
                if curvature.is_nan() || curvature <= 0.0 {
                    break;
                }
                let step = rz / curvature;
                for a in 0..k {
                    y[a] += step * p[a];
                    r[a] -= step * ap[a];
                }
                z = preconditioner.apply(&r);
                let rz_next = dot(&r, &z);
                let ratio = rz_next / rz;
                rz = rz_next;
                for a in 0..k {
                    p[a] = z[a] + ratio * p[a];
                }
            }
            subspace.set_newton_step(&y);
            let trial = armijo_on_arc(
                self.lower,
                self.upper,
                self.disks,
                &x,
                &g,
                &subspace.step,
                |v| counted(v, &mut products, kept),
            )?;
            let Some((trial, h_step)) = trial else {
                // No decrease representable in floating point.
                break;
            };
            for (gi, h) in g.iter_mut().zip(&h_step) {
                *gi += h;
            }
            x = trial;
        }
        let hx: Vec<f64> = g.iter().zip(self.linear).map(|(g, d)| g + d).collect();
        Ok(MprgpOutcome {
            x,
            hx,
            iterations,
            converged,
        })
    }
}

/// The largest forcing term of [`Mprgp::solve_by_newton`] (the first Newton step's).
const ETA_MAX: f64 = 0.5;

/// An estimate of `|H|_2` from below: the Rayleigh quotient of `iterations` power iterations
/// from the vector of ones (close to the smoothest mode, which the largest eigenvalue of a
/// Schur complement of the inverse stiffness belongs to).
pub(crate) fn norm_estimate<E>(
    m: usize,
    iterations: usize,
    mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
) -> Result<f64, E> {
    let mut v = vec![1.0 / (m.max(1) as f64).sqrt(); m];
    let mut estimate = 0.0f64;
    for _ in 0..iterations {
        let w = apply(&v)?;
        let quotient: f64 = v.iter().zip(&w).map(|(a, b)| a * b).sum();
        estimate = estimate.max(quotient);
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            break;
        }
        v = w.into_iter().map(|x| x / norm).collect();
    }
    Ok(estimate)
}

#[cfg(test)]
mod tests {
    use super::super::disk_qp::DiskQp;
    use super::*;
    use faer::Mat;
    use std::convert::Infallible;

    use crate::solver::uniform as next;

    fn product(h: &Mat<f64>) -> impl FnMut(&[f64]) -> Result<Vec<f64>, Infallible> + '_ {
        move |x: &[f64]| {
            Ok((0..h.nrows())
                .map(|i| (0..h.ncols()).map(|j| h[(i, j)] * x[j]).sum())
                .collect())
        }
    }

    /// Random positive definite problems with sign bounds, boxes and disks: MPGP and the
    /// projected Newton method with conjugate gradients find the minimiser the dense projected
    /// Newton method (direct Newton systems) finds. MPGP's expansion steps take both branches
    /// here (counted once: 129 projected conjugate gradient steps kept, 8 refused for the
    /// standard expansion).
    #[test]
    fn random_problems_give_the_projected_newton_minimiser() {
        let mut seed = 7u64;
        for case in 0..40 {
            let n = 24;
            let a = Mat::<f64>::from_fn(n, n, |_, _| next(&mut seed));
            let h = &a * a.transpose() + Mat::<f64>::identity(n, n) * 0.2;
            let d: Vec<f64> = (0..n).map(|_| 3.0 * next(&mut seed)).collect();
            let mut lower = vec![f64::NEG_INFINITY; n];
            let mut upper = vec![f64::INFINITY; n];
            // Eight sign bounds, four boxes, then six disks.
            for l in lower.iter_mut().take(8) {
                *l = 0.0;
            }
            for i in 8..12 {
                let b = 0.5 * next(&mut seed).abs();
                lower[i] = -b;
                upper[i] = b;
            }
            let disks: Vec<Disk> = (0..6)
                .map(|k| Disk {
                    first: 12 + 2 * k,
                    radius: if k == 5 && case % 2 == 0 {
                        0.0
                    } else {
                        0.1 + 0.5 * next(&mut seed).abs()
                    },
                })
                .collect();
            let reference = DiskQp {
                hessian: h.as_ref(),
                linear: &d,
                lower: &lower,
                upper: &upper,
                disks: &disks,
            }
            .solve(&vec![0.0; n], 1e-14, 200);
            assert!(reference.converged);
            let qp = Mprgp {
                linear: &d,
                lower: &lower,
                upper: &upper,
                disks: &disks,
                weights: &[],
            };
            let norm = norm_estimate(n, 10, product(&h)).unwrap();
            let mpgp = qp
                .solve(&vec![0.0; n], 1e-13, 20_000, norm, product(&h))
                .unwrap();
            let newton = qp
                .solve_by_newton(
                    &vec![0.0; n],
                    1e-13,
                    200,
                    20_000,
                    norm,
                    &mut KeptProducts::new(),
                    product(&h),
                )
                .unwrap();
            let scale = reference.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (name, out) in [("MPGP", mpgp), ("Newton", newton)] {
                assert!(
                    out.converged,
                    "{name}, case {case}: {} iterations",
                    out.iterations
                );
                for (x, y) in out.x.iter().zip(&reference.x) {
                    assert!(
                        (x - y).abs() <= 1e-9 * scale,
                        "{name}, case {case}: {x} against {y}"
                    );
                }
                // Hx is H x.
                let hx = product(&h)(&out.x).unwrap();
                for (a, b) in out.hx.iter().zip(&hx) {
                    assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{name}");
                }
            }
        }
    }

    /// A Tresca problem on a grid of `N x N` nodes (a normal row and a disk of two tangential
    /// rows per node) whose `H = C^-1 (x) A^-1` is a compliance: `A` the five-point Laplacian
    /// plus `0.05 I` (a few large eigenvalues, the smooth modes, and a cluster of small ones),
    /// `C` a coupling of the three rows of a node. The projected Newton method with the kept
    /// products (the spectral preconditioner) finds the dense projected Newton method's
    /// minimiser as the unpreconditioned one does, in fewer products (counted: 275 against
    /// 398 when written).
    #[test]
    fn kept_products_save_products_and_keep_the_minimiser() {
        use faer::linalg::solvers::DenseSolveCore;
        let side = 12;
        let nodes = side * side;
        let n = 3 * nodes;
        let coupling = [[1.0, 0.2, 0.1], [0.2, 1.0, 0.1], [0.1, 0.1, 1.0]];
        // Rows: the normal rows of the nodes, then two tangential rows per node.
        let row = |node: usize, c: usize| {
            if c == 0 {
                node
            } else {
                nodes + 2 * node + c - 1
            }
        };
        let laplacian = |a: usize, b: usize| -> f64 {
            let (ia, ja, ib, jb) = (a / side, a % side, b / side, b % side);
            if a == b {
                4.05
            } else if ia.abs_diff(ib) + ja.abs_diff(jb) == 1 {
                -1.0
            } else {
                0.0
            }
        };
        let mut stiffness = Mat::<f64>::zeros(n, n);
        for a in 0..nodes {
            for b in 0..nodes {
                for (c, coupling) in coupling.iter().enumerate() {
                    for (e, k) in coupling.iter().enumerate() {
                        stiffness[(row(a, c), row(b, e))] = k * laplacian(a, b);
                    }
                }
            }
        }
        let h = stiffness.llt(faer::Side::Lower).unwrap().inverse();
        // Pressed with a bump, sheared obliquely; the bounds from 0.3 to 1.7 times the
        // friction force without bounds (`H^-1 d`) across the grid: slip, then stick.
        let mut d = vec![0.0; n];
        for node in 0..nodes {
            let (i, j) = ((node / side) as f64, (node % side) as f64);
            d[row(node, 0)] = 1.0 + 0.3 * (0.7 * i).sin() * (0.5 * j).cos();
            d[row(node, 1)] = 0.6;
            d[row(node, 2)] = 0.4 - 0.02 * i;
        }
        let free = product(&stiffness)(&d).unwrap();
        let disks: Vec<Disk> = (0..nodes)
            .map(|node| {
                let (i, j) = ((node / side) as f64, (node % side) as f64);
                let (a, b) = (row(node, 1), row(node, 2));
                Disk {
                    first: a,
                    radius: free[a].hypot(free[b]) * (0.3 + 0.7 * (i + j) / (side - 1) as f64),
                }
            })
            .collect();
        let mut lower = vec![f64::NEG_INFINITY; n];
        lower[..nodes].fill(0.0);
        let upper = vec![f64::INFINITY; n];
        // The radii of the steps of a fixed point (a Coulomb iteration changes only them),
        // each step warm-started from the last.
        let factors = [1.0, 0.9, 0.96, 0.93, 0.945, 0.94];
        let radii = |factor: f64| -> Vec<Disk> {
            disks
                .iter()
                .map(|disk| Disk {
                    first: disk.first,
                    radius: factor * disk.radius,
                })
                .collect()
        };
        let references: Vec<Vec<f64>> = factors
            .iter()
            .map(|&factor| {
                let reference = DiskQp {
                    hessian: h.as_ref(),
                    linear: &d,
                    lower: &lower,
                    upper: &upper,
                    disks: &radii(factor),
                }
                .solve(&vec![0.0; n], 1e-13, 200);
                assert!(reference.converged);
                reference.x
            })
            .collect();
        // Stick and slip nodes both.
        let on_rim = disks
            .iter()
            .filter(|disk| {
                let x = &references[0];
                x[disk.first].hypot(x[disk.first + 1]) >= disk.radius * (1.0 - 1e-9)
            })
            .count();
        assert!(on_rim > 0 && on_rim < nodes, "{on_rim} of {nodes} slip");
        let norm = norm_estimate(n, 3, product(&h)).unwrap();
        let mut counts = Vec::new();
        for mut kept in [KeptProducts::disabled(), KeptProducts::new()] {
            let mut products = 0usize;
            let mut apply = product(&h);
            let mut x = vec![0.0; n];
            for (&factor, reference) in factors.iter().zip(&references) {
                let disks = radii(factor);
                let qp = Mprgp {
                    linear: &d,
                    lower: &lower,
                    upper: &upper,
                    disks: &disks,
                    weights: &[],
                };
                let out = qp
                    .solve_by_newton(&x, 1e-12, 200, 100_000, norm, &mut kept, |v: &[f64]| {
                        products += 1;
                        apply(v)
                    })
                    .unwrap();
                assert!(out.converged, "{} Newton steps", out.iterations);
                let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (x, y) in out.x.iter().zip(reference) {
                    assert!((x - y).abs() <= 1e-9 * scale, "{x} against {y}");
                }
                x = out.x;
            }
            println!(
                "{products} products, {} Ritz pairs at the end",
                kept.ritz_pairs()
            );
            counts.push(products);
        }
        assert!(counts[1] < counts[0], "{counts:?}");
    }

    /// Without active constraints MPGP is conjugate gradients: at most `n` iterations on an
    /// `n x n` problem (in exact arithmetic), and the solution `H^-1 d`.
    #[test]
    fn an_unconstrained_problem_is_solved_by_conjugate_gradients() {
        let n = 12;
        let h = Mat::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                2.0 + i as f64
            } else if i.abs_diff(j) == 1 {
                -1.0
            } else {
                0.0
            }
        });
        // d = H 1: the solution is the vector of ones.
        let ones = vec![1.0; n];
        let d = product(&h)(&ones).unwrap();
        let qp = Mprgp {
            linear: &d,
            lower: &vec![f64::NEG_INFINITY; n],
            upper: &vec![f64::INFINITY; n],
            disks: &[],
            weights: &[],
        };
        let norm = norm_estimate(n, 10, product(&h)).unwrap();
        let out = qp
            .solve(&vec![0.0; n], 1e-12, 100, norm, product(&h))
            .unwrap();
        assert!(out.converged);
        assert!(out.iterations <= n + 2, "{} iterations", out.iterations);
        for x in &out.x {
            assert!((x - 1.0).abs() < 1e-11);
        }
    }
}
