//! Products of the Schur operator kept for later Newton systems: a spectral preconditioner.
//!
//! Every conjugate gradient product of the iterative interface's projected Newton steps is a
//! product `s -> H s` of the same operator `H = S B K^-1 B' S` (a Coulomb fixed point changes
//! only the radii of the disks, not `H`), and each costs a pair of triangular solves per body,
//! while work on vectors of the interface's `m` unknowns is nearly free. [`KeptProducts`]
//! keeps the pairs `(s, H s)` of the products, in the full interface coordinates, as an
//! orthonormal basis `Q` of their span with `HQ` and the projection `T = Q'HQ` (Rayleigh-Ritz),
//! each pair added at `O(r m)` dense work (`r` the vectors kept, at most [`CAPACITY`]).
//!
//! The Ritz pairs `(theta_j, u_j = Q y_j)` of `T` whose residual
//! `|H u_j - theta_j u_j| = sqrt(y_j' (HQ)'(HQ) y_j - theta_j^2)` is below
//! [`RITZ_RESIDUAL`]` theta_j` (the largest first: a Krylov space finds the ends of the
//! spectrum first, and the compliance `H` has a few large eigenvalues, the smooth modes, and a
//! cluster of small ones) give the **spectral preconditioner** (Carpentieri, Duff and Giraud's
//! spectral low-rank update, here shrinking the largest eigenvalues)
//!
//! ```text
//! P = I + U (c Theta^-1 - I) U',   c = the largest Ritz value not taken,
//! ```
//!
//! which maps the eigenvalues `theta_j` of `H` (as far as the Ritz pairs have converged) to `c`
//! and leaves the others: the
//! conjugate gradients then see the condition `c / lambda_min` instead of
//! `lambda_max / lambda_min`. `P` is symmetric positive definite whatever the accuracy of the
//! Ritz pairs (`U` has orthonormal columns and `c / theta_j > 0`), and so is its restriction
//! `Z'PZ = I + (Z'U)(c Theta^-1 - I)(Z'U)'` to a Newton subspace (`Z` has orthonormal
//! columns: unit vectors and the rims' unit tangents): conjugate gradients preconditioned by it
//! solve the same Newton system `(Z'HZ + C) y = -Z'g` (their stopping test stays on the
//! unpreconditioned residual), only in fewer products.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par, Side};

use super::disk_qp::NewtonSubspace;

/// The most vectors kept; at this count the basis is compressed to its [`KEPT_ON_COMPRESSION`]
/// Ritz vectors of the largest Ritz values.
pub(crate) const CAPACITY: usize = 240;
/// The Ritz vectors kept when the basis is compressed.
const KEPT_ON_COMPRESSION: usize = 120;
/// A Ritz pair enters the preconditioner when its residual is below this fraction of its value:
/// a loose test (a preconditioner only has to be positive definite; on the block pressed flat
/// at n = 24, before [`IN_THE_SPAN`] was raised, `0.1` saved 12 % of a Coulomb fixed point's
/// products, `0.3` 19 %, `1` 30 %; with it raised, `1` saves 35 %).
pub(crate) const RITZ_RESIDUAL: f64 = 1.0;
/// The most Ritz pairs in the preconditioner (its dense work per refresh is `m r k`).
const MAX_RITZ: usize = 80;
/// A vector whose part outside the basis is below this fraction of its norm adds nothing: its
/// image is a combination of the kept images divided by that fraction, so their round-off
/// would be amplified by its inverse, and passed on to every later vector (seen with `1e-8`:
/// `HQ` wrong in the first digit after a few hundred conjugate gradient directions).
const IN_THE_SPAN: f64 = 0.1;
/// The Ritz pairs are made again when this many vectors were added since the last ones.
const REFRESH_AFTER: usize = 4;

/// The kept products `(s, H s)` of one operator `H` (see the module's documentation).
#[derive(Debug, Clone)]
pub(crate) struct KeptProducts {
    /// Keep nothing (the unpreconditioned method; the tests' comparison).
    enabled: bool,
    /// `Q`, `m x CAPACITY`, its first `rank` columns orthonormal.
    basis: Mat<f64>,
    /// `HQ`.
    images: Mat<f64>,
    /// `T = Q'HQ` (symmetrised).
    projected: Mat<f64>,
    /// `(HQ)'(HQ)`, for the Ritz residuals.
    image_gram: Mat<f64>,
    rank: usize,
    /// The Ritz vectors `U` of the preconditioner (`m x k`) and the factors `c / theta_j - 1`.
    ritz: Mat<f64>,
    factors: Vec<f64>,
    /// The rank at which the Ritz pairs were made.
    ritz_rank: usize,
    /// Vectors added since the Ritz pairs were made.
    since_refresh: usize,
}

impl Default for KeptProducts {
    fn default() -> Self {
        Self::new()
    }
}

impl KeptProducts {
    /// An empty store that keeps products.
    pub fn new() -> Self {
        Self {
            enabled: true,
            basis: Mat::zeros(0, 0),
            images: Mat::zeros(0, 0),
            projected: Mat::zeros(0, 0),
            image_gram: Mat::zeros(0, 0),
            rank: 0,
            ritz: Mat::zeros(0, 0),
            factors: Vec::new(),
            ritz_rank: 0,
            since_refresh: 0,
        }
    }

    /// A store that keeps nothing: the preconditioner is the identity (the method before the
    /// kept products, for the tests' comparison).
    #[cfg(test)]
    pub fn disabled() -> Self {
        Self {
            enabled: false,
            ..Self::new()
        }
    }

    /// The number of orthonormal vectors kept.
    #[cfg(test)]
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// The number of Ritz pairs in the preconditioner.
    #[cfg(test)]
    pub fn ritz_pairs(&self) -> usize {
        self.factors.len()
    }

    /// Keeps the product `image = H s`: the part of `s` outside the basis (classical
    /// Gram-Schmidt, repeated once when it cancels more than half the norm, Kahan's "twice is
    /// enough"), normalised, with `H` of it from the same combination of the kept images.
    pub fn add(&mut self, s: &[f64], image: &[f64]) {
        let m = s.len();
        if !self.enabled || m == 0 || image.len() != m {
            return;
        }
        if self.basis.nrows() != m {
            *self = Self {
                enabled: true,
                basis: Mat::zeros(m, CAPACITY),
                images: Mat::zeros(m, CAPACITY),
                projected: Mat::zeros(CAPACITY, CAPACITY),
                image_gram: Mat::zeros(CAPACITY, CAPACITY),
                ..Self::new()
            };
        }
        let norm = s.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 || !norm.is_finite() || image.iter().any(|v| !v.is_finite()) {
            return;
        }
        let r = self.rank;
        let mut v = Mat::from_fn(m, 1, |i, _| s[i]);
        let mut hv = Mat::from_fn(m, 1, |i, _| image[i]);
        let mut current = norm;
        for _ in 0..2 {
            if r == 0 {
                break;
            }
            let q = self.basis.as_ref().subcols(0, r);
            let hq = self.images.as_ref().subcols(0, r);
            let mut c = Mat::<f64>::zeros(r, 1);
            matmul(
                c.as_mut(),
                Accum::Replace,
                q.transpose(),
                v.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(v.as_mut(), Accum::Add, q, c.as_ref(), -1.0, Par::Seq);
            matmul(hv.as_mut(), Accum::Add, hq, c.as_ref(), -1.0, Par::Seq);
            let next = v.col(0).norm_l2();
            let cancelled = next < 0.5 * current;
            current = next;
            if !cancelled {
                break;
            }
        }
        if current <= IN_THE_SPAN * norm {
            return;
        }
        for i in 0..m {
            self.basis[(i, r)] = v[(i, 0)] / current;
            self.images[(i, r)] = hv[(i, 0)] / current;
        }
        // T's and (HQ)'(HQ)'s new column and row.
        let q = self.basis.as_ref().subcols(0, r + 1);
        let hq = self.images.as_ref().subcols(0, r + 1);
        let mut t_column = Mat::<f64>::zeros(r + 1, 1);
        let mut t_row = Mat::<f64>::zeros(r + 1, 1);
        let mut g_column = Mat::<f64>::zeros(r + 1, 1);
        matmul(
            t_column.as_mut(),
            Accum::Replace,
            q.transpose(),
            hq.subcols(r, 1),
            1.0,
            Par::Seq,
        );
        matmul(
            t_row.as_mut(),
            Accum::Replace,
            hq.transpose(),
            q.subcols(r, 1),
            1.0,
            Par::Seq,
        );
        matmul(
            g_column.as_mut(),
            Accum::Replace,
            hq.transpose(),
            hq.subcols(r, 1),
            1.0,
            Par::Seq,
        );
        for j in 0..=r {
            // Q'HQ is symmetric in exact arithmetic: the mean of q_j'Hq_r and q_r'Hq_j.
            let t = 0.5 * (t_column[(j, 0)] + t_row[(j, 0)]);
            self.projected[(j, r)] = t;
            self.projected[(r, j)] = t;
            self.image_gram[(j, r)] = g_column[(j, 0)];
            self.image_gram[(r, j)] = g_column[(j, 0)];
        }
        self.rank = r + 1;
        self.since_refresh += 1;
        if self.rank == CAPACITY {
            self.compress();
        }
    }

    /// The eigenpairs of `T` (ascending).
    fn ritz_pairs_of_t(&self) -> Option<(Vec<f64>, Mat<f64>)> {
        let r = self.rank;
        let t = self.projected.as_ref().submatrix(0, 0, r, r).to_owned();
        let eigen = t.self_adjoint_eigen(Side::Lower).ok()?;
        let values: Vec<f64> = eigen.S().column_vector().iter().copied().collect();
        Some((values, eigen.U().to_owned()))
    }

    /// The basis replaced by its [`KEPT_ON_COMPRESSION`] Ritz vectors of the largest Ritz
    /// values (`Q <- Q Y`, `HQ <- HQ Y`, `T <- Theta`, `(HQ)'(HQ) <- Y'(HQ)'(HQ)Y`).
    fn compress(&mut self) {
        let Some((values, vectors)) = self.ritz_pairs_of_t() else {
            self.rank = 0;
            return;
        };
        let (m, r, k) = (self.basis.nrows(), self.rank, KEPT_ON_COMPRESSION);
        let y = vectors.as_ref().subcols(r - k, k);
        let mut basis = Mat::<f64>::zeros(m, k);
        let mut images = Mat::<f64>::zeros(m, k);
        matmul(
            basis.as_mut(),
            Accum::Replace,
            self.basis.as_ref().subcols(0, r),
            y,
            1.0,
            Par::Seq,
        );
        matmul(
            images.as_mut(),
            Accum::Replace,
            self.images.as_ref().subcols(0, r),
            y,
            1.0,
            Par::Seq,
        );
        let mut gy = Mat::<f64>::zeros(r, k);
        matmul(
            gy.as_mut(),
            Accum::Replace,
            self.image_gram.as_ref().submatrix(0, 0, r, r),
            y,
            1.0,
            Par::Seq,
        );
        let mut gram = Mat::<f64>::zeros(k, k);
        matmul(
            gram.as_mut(),
            Accum::Replace,
            y.transpose(),
            gy.as_ref(),
            1.0,
            Par::Seq,
        );
        for j in 0..k {
            for i in 0..m {
                self.basis[(i, j)] = basis[(i, j)];
                self.images[(i, j)] = images[(i, j)];
            }
            for i in 0..k {
                self.projected[(i, j)] = if i == j { values[r - k + j] } else { 0.0 };
                self.image_gram[(i, j)] = 0.5 * (gram[(i, j)] + gram[(j, i)]);
            }
        }
        self.rank = k;
        self.since_refresh = REFRESH_AFTER;
    }

    /// The Ritz pairs of the preconditioner made again from the kept basis when
    /// [`REFRESH_AFTER`] vectors were added since: from the largest Ritz value down while the
    /// residual is below [`RITZ_RESIDUAL`] times the value, `c` the first value not taken.
    fn refresh(&mut self) {
        if self.since_refresh < REFRESH_AFTER || self.rank < 2 {
            return;
        }
        self.since_refresh = 0;
        self.ritz_rank = self.rank;
        self.factors.clear();
        let Some((values, vectors)) = self.ritz_pairs_of_t() else {
            return;
        };
        let r = self.rank;
        let gram = self.image_gram.as_ref().submatrix(0, 0, r, r);
        let mut taken = 0;
        // Keep one Ritz value below the taken ones: the `c` they are mapped to.
        while taken + 1 < r && taken < MAX_RITZ {
            let j = r - 1 - taken;
            let theta = values[j];
            if theta <= 0.0 {
                break;
            }
            let y = vectors.as_ref().col(j);
            let mut gy = Mat::<f64>::zeros(r, 1);
            matmul(gy.as_mut(), Accum::Replace, gram, y.as_mat(), 1.0, Par::Seq);
            let yy: f64 = (0..r).map(|i| y[i] * gy[(i, 0)]).sum();
            let residual = (yy - theta * theta).max(0.0).sqrt();
            if residual > RITZ_RESIDUAL * theta {
                break;
            }
            taken += 1;
        }
        let cut = values[r - 1 - taken];
        if taken == 0 || cut <= 0.0 {
            return;
        }
        let m = self.basis.nrows();
        let mut ritz = Mat::<f64>::zeros(m, taken);
        matmul(
            ritz.as_mut(),
            Accum::Replace,
            self.basis.as_ref().subcols(0, r),
            vectors.as_ref().subcols(r - taken, taken),
            1.0,
            Par::Seq,
        );
        self.ritz = ritz;
        self.factors = (0..taken)
            .map(|a| cut / values[r - taken + a] - 1.0)
            .collect();
    }

    /// The preconditioner `Z'PZ` of a Newton system in the subspace `Z`, from the Ritz pairs
    /// made again if enough products were added since (the identity without Ritz pairs).
    pub fn preconditioner(&mut self, subspace: &NewtonSubspace) -> SpectralPreconditioner {
        if self.enabled {
            self.refresh();
        }
        let k = self.factors.len();
        let restricted: Vec<Vec<f64>> = (0..k)
            .map(|a| {
                let u: Vec<f64> = self.ritz.col(a).iter().copied().collect();
                subspace.restrict(&u)
            })
            .collect();
        SpectralPreconditioner {
            restricted,
            factors: self.factors.clone(),
        }
    }
}

/// `Z'PZ = I + W D W'` with `W = Z'U` and `D = c Theta^-1 - I` (see the module's
/// documentation): symmetric positive definite.
pub(crate) struct SpectralPreconditioner {
    restricted: Vec<Vec<f64>>,
    factors: Vec<f64>,
}

impl SpectralPreconditioner {
    /// `z = r + W D W' r`.
    pub fn apply(&self, r: &[f64]) -> Vec<f64> {
        let mut z = r.to_vec();
        for (w, d) in self.restricted.iter().zip(&self.factors) {
            let c = d * w.iter().zip(r).map(|(a, b)| a * b).sum::<f64>();
            for (zi, wi) in z.iter_mut().zip(w) {
                *zi += c * wi;
            }
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Products of a random positive definite `H` (`300 x 300`, beyond the capacity: compressed
    /// on the way) at vectors that each differ from the last by `1e-4` of
    /// their size (as the conjugate gradient directions of neighbouring Newton systems do):
    /// the kept basis stays orthonormal and its images are `H` of it, `T = Q'HQ`, to round-off
    /// (the images come from combinations of earlier images, so a vector nearly in the span is
    /// refused: its image's error would be amplified and passed on).
    #[test]
    fn the_kept_basis_is_orthonormal_and_its_images_are_its_products() {
        let m = 300;
        let mut seed = 3u64;
        let mut next = || crate::solver::uniform(&mut seed);
        let a = Mat::<f64>::from_fn(m, m, |_, _| next());
        let h = &a * a.transpose() + Mat::<f64>::identity(m, m);
        let mut kept = KeptProducts::new();
        let mut s: Vec<f64> = (0..m).map(|_| next()).collect();
        for _ in 0..280 {
            s.iter_mut().for_each(|v| *v += 1e-4 * next());
            let hs: Vec<f64> = (0..m)
                .map(|i| (0..m).map(|j| h[(i, j)] * s[j]).sum())
                .collect();
            kept.add(&s, &hs);
            // A vector wholly new.
            let t: Vec<f64> = (0..m).map(|_| next()).collect();
            let ht: Vec<f64> = (0..m)
                .map(|i| (0..m).map(|j| h[(i, j)] * t[j]).sum())
                .collect();
            kept.add(&t, &ht);
        }
        let r = kept.rank();
        assert!(r > KEPT_ON_COMPRESSION && r < CAPACITY, "{r}");
        let q = kept.basis.as_ref().subcols(0, r);
        let qq = q.transpose() * q;
        let hq = &h * q;
        let t = q.transpose() * &hq;
        let scale = h.norm_l2();
        for j in 0..r {
            for i in 0..r {
                let identity = if i == j { 1.0 } else { 0.0 };
                assert!((qq[(i, j)] - identity).abs() < 1e-12, "Q'Q {i} {j}");
                assert!(
                    (t[(i, j)] - kept.projected[(i, j)]).abs() < 1e-12 * scale,
                    "T {i} {j}"
                );
            }
            for i in 0..m {
                assert!(
                    (hq[(i, j)] - kept.images[(i, j)]).abs() < 1e-12 * scale,
                    "HQ {i} {j}"
                );
            }
        }
    }

    /// On a diagonal `H` with a few large entries, products of the unit vectors of the large
    /// ones give those eigenpairs exactly, and the preconditioner maps them to the largest
    /// eigenvalue left (`c`): `P H` has the spectrum of `H` cut at `c`.
    #[test]
    fn exact_eigenvectors_are_mapped_to_the_cut() {
        let m = 20;
        let eigenvalues: Vec<f64> = (0..m).map(|i| 1.0 + i as f64 * i as f64).collect();
        let mut kept = KeptProducts::new();
        // The three largest, and one of the small (the cut): 19, 18, 17, then 2.
        for i in [19, 18, 17, 2] {
            let mut s = vec![0.0; m];
            s[i] = 1.0 + i as f64;
            let hs: Vec<f64> = s.iter().zip(&eigenvalues).map(|(a, b)| a * b).collect();
            kept.add(&s, &hs);
        }
        assert_eq!(kept.rank(), 4);
        let subspace = NewtonSubspace {
            basis: (0..m).map(super::super::disk_qp::Direction::Unit).collect(),
            curvature: vec![0.0; m],
            step: vec![0.0; m],
        };
        let p = kept.preconditioner(&subspace);
        assert_eq!(kept.ritz_pairs(), 3);
        let cut = eigenvalues[2];
        for (i, lambda) in eigenvalues.iter().enumerate() {
            let mut e = vec![0.0; m];
            e[i] = 1.0;
            let pe = p.apply(&e);
            let expected = if i >= 17 { cut / lambda } else { 1.0 };
            for (j, v) in pe.iter().enumerate() {
                let want = if j == i { expected } else { 0.0 };
                assert!((v - want).abs() < 1e-13, "{i} {j}: {v} against {want}");
            }
        }
    }
}
