//! The linear solve behind a small trait: analyse a pattern once, factorise values (many times
//! on the same pattern), solve.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef, CholeskySymbolicParams,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, Side};

use crate::SolveError;

/// A direct solver for symmetric positive definite sparse systems, split into the three
/// phases a contact solver needs: the pattern is analysed once, then values are factorised and
/// right-hand sides solved as often as needed.
///
/// Matrices are passed in full symmetric storage (both triangles), as
/// [`crate::AssembledSystem::stiffness`] returns them.
pub trait LinearSolver: Send + Sync {
    /// A short name for reports.
    fn name(&self) -> &str;

    /// Symbolic analysis (ordering, elimination tree) of the square `pattern`. Discards any
    /// earlier analysis and factorisation.
    fn analyse(&mut self, pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<(), SolveError>;

    /// Numeric factorisation of `matrix`, which must have the analysed pattern.
    fn factorise(&mut self, matrix: SparseColMatRef<'_, usize, f64>) -> Result<(), SolveError>;

    /// Overwrites each column of `rhs` with the solution of the factorised system.
    fn solve_in_place(&self, rhs: MatMut<'_, f64>) -> Result<(), SolveError>;

    /// The solution of the factorised system for one right-hand side.
    fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut x = rhs.to_vec();
        let n = x.len();
        self.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1))?;
        Ok(x)
    }
}

/// The fill-reducing ordering of the Cholesky factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// Approximate minimum degree (faer's built-in AMD).
    #[default]
    Amd,
    /// The natural order (no permutation; for tests and already ordered matrices).
    Natural,
}

/// How the numeric factorisation of [`CholeskySolver`] is parallelised.
///
/// A [`Par`] converts into [`FactorisationParallelism::Fixed`], so
/// `builder.factorisation_parallelism(Par::Seq)` reads as before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FactorisationParallelism {
    /// Sequential for a factor with fewer than
    /// [`FactorisationParallelism::PARALLEL_MIN_FACTOR_ENTRIES`] stored entries, all rayon
    /// threads above (the default): on small factors the threads cost more than they save.
    #[default]
    Auto,
    /// Always this parallelism.
    Fixed(Par),
}

impl FactorisationParallelism {
    /// Stored entries of the factor from which [`FactorisationParallelism::Auto`] factorises
    /// in parallel: 5e7, about 3.5e5 unknowns of the lowest-order VEM on quadrilaterals
    /// (1.1e7 entries at 1e5 unknowns, 1.8e8 at 1e6). Measured with two cores (see
    /// `docs/benchmarks.md`): the parallel factorisation is slower than the sequential one at
    /// 1e4 and 1e5 unknowns.
    pub const PARALLEL_MIN_FACTOR_ENTRIES: usize = 50_000_000;

    /// The parallelism for a factor of `factor_entries` stored entries.
    pub fn for_factor(self, factor_entries: usize) -> Par {
        match self {
            FactorisationParallelism::Fixed(par) => par,
            FactorisationParallelism::Auto
                if factor_entries < Self::PARALLEL_MIN_FACTOR_ENTRIES =>
            {
                Par::Seq
            }
            FactorisationParallelism::Auto => Par::rayon(0),
        }
    }
}

impl From<Par> for FactorisationParallelism {
    fn from(par: Par) -> Self {
        FactorisationParallelism::Fixed(par)
    }
}

/// Settings of [`CholeskySolver`], built and checked by [`CholeskySettings::builder`]
/// (or [`Default`]).
///
/// ```
/// use vem_elastic::{CholeskySettings, CholeskySolver, Ordering};
/// let settings = CholeskySettings::builder()
///     .ordering(Ordering::Natural)
///     .singular_pivot_tolerance(1e-10)
///     .build()?;
/// assert_eq!(settings.ordering(), Ordering::Natural);
/// let solver = CholeskySolver::new(settings);
/// assert_eq!(solver.settings().singular_pivot_tolerance(), 1e-10);
/// // A pivot tolerance outside [0, 1) is an error when the settings are built.
/// assert!(CholeskySettings::builder().singular_pivot_tolerance(1.5).build().is_err());
/// # Ok::<(), vem_elastic::SolveError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CholeskySettings {
    ordering: Ordering,
    factorisation_parallelism: FactorisationParallelism,
    solve_parallelism: Par,
    singular_pivot_tolerance: f64,
}

impl CholeskySettings {
    /// The default singular-pivot tolerance, `1e-9` (see
    /// [`CholeskySettingsBuilder::singular_pivot_tolerance`]).
    pub const DEFAULT_SINGULAR_PIVOT_TOLERANCE: f64 = 1e-9;

    /// A builder starting from the defaults.
    pub fn builder() -> CholeskySettingsBuilder {
        CholeskySettingsBuilder {
            settings: Self::default(),
        }
    }

    /// The fill-reducing ordering.
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// Parallelism of the numeric factorisation.
    pub fn factorisation_parallelism(&self) -> FactorisationParallelism {
        self.factorisation_parallelism
    }

    /// Parallelism of the triangular solves.
    pub fn solve_parallelism(&self) -> Par {
        self.solve_parallelism
    }

    /// The relative pivot under which the matrix counts as not positive definite.
    pub fn singular_pivot_tolerance(&self) -> f64 {
        self.singular_pivot_tolerance
    }
}

impl Default for CholeskySettings {
    /// AMD, factorisation parallelism chosen by the factor's size
    /// ([`FactorisationParallelism::Auto`]), sequential solves, pivot tolerance `1e-9`.
    fn default() -> Self {
        Self {
            ordering: Ordering::Amd,
            factorisation_parallelism: FactorisationParallelism::Auto,
            solve_parallelism: Par::Seq,
            singular_pivot_tolerance: Self::DEFAULT_SINGULAR_PIVOT_TOLERANCE,
        }
    }
}

/// Builder of [`CholeskySettings`]; [`CholeskySettingsBuilder::build`] checks the values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CholeskySettingsBuilder {
    settings: CholeskySettings,
}

impl CholeskySettingsBuilder {
    /// The fill-reducing ordering (default AMD).
    pub fn ordering(mut self, ordering: Ordering) -> Self {
        self.settings.ordering = ordering;
        self
    }

    /// Parallelism of the numeric factorisation (default
    /// [`FactorisationParallelism::Auto`]; a [`Par`] fixes it).
    pub fn factorisation_parallelism(
        mut self,
        parallelism: impl Into<FactorisationParallelism>,
    ) -> Self {
        self.settings.factorisation_parallelism = parallelism.into();
        self
    }

    /// Parallelism of the triangular solves (default sequential: a parallel supernodal solve
    /// was measured 20x slower, see `dependencies.md`).
    pub fn solve_parallelism(mut self, parallelism: Par) -> Self {
        self.settings.solve_parallelism = parallelism;
        self
    }

    /// A pivot `d_k` (the square of the diagonal of `L`) with `d_k <= tolerance * A_kk` (the
    /// matching diagonal entry of the permuted matrix) counts as zero: the matrix is reported
    /// as not positive definite. In exact arithmetic a floating body gives `d_k = 0`; in
    /// floating point a pivot of the order of round-off, which faer may accept. Measured with
    /// the lowest-order VEM (up to 6.4e5 unknowns): floating or sliding bodies reach at most
    /// `d_k / A_kk = 4e-12`, held bodies at least `1e-6` even for `lambda / mu = 1e6`.
    /// Default `1e-9`, in `[0, 1)`.
    pub fn singular_pivot_tolerance(mut self, tolerance: f64) -> Self {
        self.settings.singular_pivot_tolerance = tolerance;
        self
    }

    /// The settings, checked: the pivot tolerance must lie in `[0, 1)`.
    pub fn build(self) -> Result<CholeskySettings, SolveError> {
        let tol = self.settings.singular_pivot_tolerance;
        if !(0.0..1.0).contains(&tol) {
            return Err(SolveError::InvalidSetting {
                reason: format!("singular_pivot_tolerance = {tol} is outside [0, 1)"),
            });
        }
        Ok(self.settings)
    }
}

/// Sparse Cholesky `L L^T` with faer: the symbolic analysis (AMD ordering, supernodal or
/// simplicial structure) is kept and reused for every factorisation of new values on the same
/// pattern.
///
/// ```
/// use faer::sparse::{SparseColMat, Triplet};
/// use vem_elastic::{CholeskySolver, LinearSolver};
/// // [[4, 1], [1, 3]] x = [1, 2]  =>  x = [1/11, 7/11]
/// let a = SparseColMat::<usize, f64>::try_new_from_triplets(2, 2, &[
///     Triplet::new(0, 0, 4.0), Triplet::new(1, 0, 1.0),
///     Triplet::new(0, 1, 1.0), Triplet::new(1, 1, 3.0),
/// ]).unwrap();
/// let mut solver = CholeskySolver::default();
/// solver.analyse(a.symbolic())?;
/// solver.factorise(a.as_ref())?;
/// let x = solver.solve(&[1.0, 2.0])?;
/// assert!((x[0] - 1.0 / 11.0).abs() < 1e-15 && (x[1] - 7.0 / 11.0).abs() < 1e-15);
/// # Ok::<(), vem_elastic::SolveError>(())
/// ```
#[derive(Debug, Default)]
pub struct CholeskySolver {
    settings: CholeskySettings,
    analysis: Option<Analysis>,
    factor: Option<Factor>,
}

#[derive(Debug)]
struct Factor {
    values: Vec<f64>,
    smallest_relative_pivot: f64,
}

#[derive(Debug)]
struct Analysis {
    symbolic: SymbolicCholesky<usize>,
    n: usize,
    /// Number of unknowns eliminated last (see [`CholeskySolver::analyse_with_trailing`]).
    n_trailing: usize,
    nnz: usize,
    fingerprint: u64,
}

impl CholeskySolver {
    /// A solver with `settings` (checked when they were built).
    pub fn new(settings: CholeskySettings) -> Self {
        Self {
            settings,
            analysis: None,
            factor: None,
        }
    }

    /// The settings in force.
    pub fn settings(&self) -> &CholeskySettings {
        &self.settings
    }

    /// Number of stored values of the factor `L` (after [`LinearSolver::analyse`]).
    pub fn factor_len(&self) -> Option<usize> {
        self.analysis.as_ref().map(|a| a.symbolic.len_val())
    }

    /// The parallelism the numeric factorisation uses for the analysed pattern (after
    /// [`LinearSolver::analyse`]): [`FactorisationParallelism::for_factor`] of the factor's size.
    pub fn factorisation_par(&self) -> Option<Par> {
        self.factor_len()
            .map(|len| self.settings.factorisation_parallelism.for_factor(len))
    }

    /// True when the analysis chose the supernodal (blocked) factorisation.
    pub fn is_supernodal(&self) -> Option<bool> {
        self.analysis
            .as_ref()
            .map(|a| matches!(a.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)))
    }

    /// The smallest relative pivot `d_k / A_kk` (`d_k = L_kk^2`, `A_kk` the matching diagonal
    /// entry of the permuted matrix) of the last successful factorisation: 1 for a diagonal
    /// matrix, small for an ill-conditioned one. A diagnostic of how firmly the body is held.
    pub fn smallest_relative_pivot(&self) -> Option<f64> {
        self.factor.as_ref().map(|f| f.smallest_relative_pivot)
    }

    /// Symbolic analysis that eliminates the unknowns `trailing` last, in the order given, after
    /// the others in the solver's fill-reducing order ([`Ordering::Amd`] of the matrix without
    /// them, or natural). With `P A P' = L L'` split as
    ///
    /// ```text
    /// L = [ L_II    0  ]     S = A_TT - A_TI A_II^-1 A_IT = L_TT L_TT'
    ///     [ L_TI  L_TT ]
    /// ```
    ///
    /// the trailing block of the factor is the Cholesky factor of the Schur complement `S` of
    /// `A` onto `trailing`; [`CholeskySolver::trailing_factor`] returns it after a
    /// factorisation. Discards any earlier analysis and factorisation.
    ///
    /// # Errors
    /// [`SolveError::Mismatch`] for a non-square pattern, an index out of range or repeated in
    /// `trailing`; [`SolveError::Backend`] when the ordering fails.
    pub fn analyse_with_trailing(
        &mut self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        trailing: &[usize],
    ) -> Result<(), SolveError> {
        self.analysis = None;
        self.factor = None;
        let n = pattern.nrows();
        if n != pattern.ncols() {
            return Err(SolveError::Mismatch {
                reason: format!("the matrix is {} x {}, not square", n, pattern.ncols()),
            });
        }
        let forward = trailing_last_order(pattern, trailing, self.settings.ordering)?;
        let mut inverse = vec![0; n];
        for (new, &old) in forward.iter().enumerate() {
            inverse[old] = new;
        }
        // The natural order, too, is passed as an explicit permutation: faer's `Identity`
        // ordering skips the symmetric permutation step that selects the `Side::Lower`
        // triangle of a full-storage matrix.
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&forward, &inverse, n)),
            CholeskySymbolicParams::default(),
        )
        .map_err(backend)?;
        self.analysis = Some(Analysis {
            symbolic,
            n,
            n_trailing: trailing.len(),
            nnz: pattern.row_idx().len(),
            fingerprint: fingerprint(pattern),
        });
        Ok(())
    }

    /// The trailing block `L_TT` of the last factorisation (dense, lower triangular, rows and
    /// columns in the order of the `trailing` unknowns given to
    /// [`CholeskySolver::analyse_with_trailing`]): the Cholesky factor of the Schur complement
    /// onto them, `S = L_TT L_TT'`, so that `(A^-1)_TT = S^-1`.
    ///
    /// # Errors
    /// [`SolveError::OutOfOrder`] before a successful factorisation.
    pub fn trailing_factor(&self) -> Result<Mat<f64>, SolveError> {
        let (Some(analysis), Some(factor)) = (&self.analysis, &self.factor) else {
            return Err(SolveError::OutOfOrder {
                reason: "trailing factor before a successful factorise",
            });
        };
        let first = analysis.n - analysis.n_trailing;
        let mut block = Mat::<f64>::zeros(analysis.n_trailing, analysis.n_trailing);
        match analysis.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (col_ptr, row_idx) = (s.col_ptr(), s.row_idx());
                for j in first..analysis.n {
                    for k in col_ptr[j]..col_ptr[j + 1] {
                        block[(row_idx[k] - first, j - first)] = factor.values[k];
                    }
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = SupernodalLltRef::new(s, &factor.values);
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let (start, values, pattern) = (node.start(), node.val(), node.pattern());
                    let width = values.ncols();
                    if start + width <= first {
                        continue;
                    }
                    // Rows of the supernode: its own columns, then `pattern` (all below them).
                    for j in start.max(first)..start + width {
                        let c = j - start;
                        for i in c..width {
                            block[(start + i - first, j - first)] = values[(i, c)];
                        }
                        for (r, &row) in pattern.iter().enumerate() {
                            block[(row - first, j - first)] = values[(width + r, c)];
                        }
                    }
                }
            }
        }
        Ok(block)
    }
}

/// The elimination order (new position -> original unknown): the unknowns not in `trailing` in
/// `ordering` (AMD of the matrix restricted to them), then `trailing` as given.
fn trailing_last_order(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    trailing: &[usize],
    ordering: Ordering,
) -> Result<Vec<usize>, SolveError> {
    let n = pattern.nrows();
    const TRAILING: usize = usize::MAX;
    let mut local = vec![0usize; n];
    for &t in trailing {
        if t >= n || local[t] == TRAILING {
            return Err(SolveError::Mismatch {
                reason: format!("trailing unknown {t} is out of range (n = {n}) or repeated"),
            });
        }
        local[t] = TRAILING;
    }
    let leading: Vec<usize> = (0..n).filter(|&i| local[i] != TRAILING).collect();
    for (k, &i) in leading.iter().enumerate() {
        local[i] = k;
    }
    let mut order = match ordering {
        Ordering::Natural => leading.clone(),
        Ordering::Amd => {
            // The pattern of the leading block, in full storage (rows stay sorted: the
            // renumbering is monotone).
            let mut col_ptr = Vec::with_capacity(leading.len() + 1);
            let mut row_idx = Vec::with_capacity(pattern.row_idx().len());
            col_ptr.push(0);
            for &j in &leading {
                row_idx.extend(
                    pattern
                        .row_idx_of_col_raw(j)
                        .iter()
                        .filter(|&&i| local[i] != TRAILING)
                        .map(|&i| local[i]),
                );
                col_ptr.push(row_idx.len());
            }
            let m = leading.len();
            let block = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
            let (mut forward, mut inverse) = (vec![0usize; m], vec![0usize; m]);
            let mut scratch =
                MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(m, row_idx.len()))
                    .map_err(|_| backend("out of memory for the ordering workspace"))?;
            amd::order_maybe_unsorted(
                &mut forward,
                &mut inverse,
                block,
                amd::Control::default(),
                MemStack::new(&mut scratch),
            )
            .map_err(backend)?;
            forward.iter().map(|&k| leading[k]).collect()
        }
    };
    order.extend_from_slice(trailing);
    Ok(order)
}

/// The smallest relative pivot `d_k / A_kk` of the factor `factor` of `matrix` and the
/// elimination step where it occurs.
fn smallest_relative_pivot(
    symbolic: &SymbolicCholesky<usize>,
    factor: &[f64],
    matrix: SparseColMatRef<'_, usize, f64>,
) -> (f64, usize) {
    let diagonal = |old: usize| {
        let rows = matrix.symbolic().row_idx_of_col_raw(old);
        rows.binary_search(&old)
            .map(|k| matrix.val_of_col(old)[k])
            .unwrap_or(0.0)
    };
    let original = |new: usize| match symbolic.perm() {
        Some(perm) => perm.arrays().0[new],
        None => new,
    };
    let ratio = |new: usize, l_kk: f64| (l_kk * l_kk / diagonal(original(new)), new);
    let smaller = |a: (f64, usize), b: (f64, usize)| if b.0 < a.0 { b } else { a };
    let start = (f64::INFINITY, 0);
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let col_ptr = s.col_ptr();
            (0..s.nrows())
                .map(|k| ratio(k, factor[col_ptr[k]]))
                .fold(start, smaller)
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let l = SupernodalLltRef::new(s, factor);
            (0..s.n_supernodes())
                .flat_map(|k| {
                    let node = l.supernode(k);
                    let block = node.val();
                    (0..block.ncols()).map(move |j| ratio(node.start() + j, block[(j, j)]))
                })
                .fold(start, smaller)
        }
    }
}

/// A hash of a pattern, to check that a matrix has the analysed pattern.
fn fingerprint(pattern: SymbolicSparseColMatRef<'_, usize>) -> u64 {
    const PRIME: u64 = 0x100_0000_01b3;
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for &x in pattern.col_ptr().iter().chain(pattern.row_idx()) {
        hash = (hash ^ x as u64).wrapping_mul(PRIME);
    }
    hash
}

fn backend(reason: impl std::fmt::Display) -> SolveError {
    SolveError::Backend {
        reason: reason.to_string(),
    }
}

impl LinearSolver for CholeskySolver {
    fn name(&self) -> &str {
        "faer sparse Cholesky"
    }

    fn analyse(&mut self, pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<(), SolveError> {
        self.analyse_with_trailing(pattern, &[])
    }

    fn factorise(&mut self, matrix: SparseColMatRef<'_, usize, f64>) -> Result<(), SolveError> {
        self.factor = None;
        let analysis = self.analysis.as_ref().ok_or(SolveError::OutOfOrder {
            reason: "factorise before analyse",
        })?;
        let pattern = matrix.symbolic();
        if pattern.nrows() != analysis.n
            || pattern.ncols() != analysis.n
            || pattern.row_idx().len() != analysis.nnz
            || fingerprint(pattern) != analysis.fingerprint
        {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "the matrix ({} x {}, {} entries) does not have the analysed pattern ({} x {}, {} entries)",
                    pattern.nrows(),
                    pattern.ncols(),
                    pattern.row_idx().len(),
                    analysis.n,
                    analysis.n,
                    analysis.nnz
                ),
            });
        }
        let symbolic = &analysis.symbolic;
        let par = self
            .settings
            .factorisation_parallelism
            .for_factor(symbolic.len_val());
        let mut values = vec![0.0; symbolic.len_val()];
        let mut scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| backend("out of memory for the factorisation workspace"))?;
        symbolic
            .factorize_numeric_llt(
                &mut values,
                matrix,
                Side::Lower,
                LltRegularization::default(),
                par,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(
                |LltError::NonPositivePivot { index }| SolveError::NotPositiveDefinite {
                    step: index.saturating_sub(1),
                },
            )?;
        let (smallest, step) = smallest_relative_pivot(symbolic, &values, matrix);
        // NaN (a zero diagonal entry) counts as singular too.
        if smallest.is_nan() || smallest <= self.settings.singular_pivot_tolerance {
            return Err(SolveError::NotPositiveDefinite { step });
        }
        self.factor = Some(Factor {
            values,
            smallest_relative_pivot: smallest,
        });
        Ok(())
    }

    fn solve_in_place(&self, rhs: MatMut<'_, f64>) -> Result<(), SolveError> {
        let (Some(analysis), Some(factor)) = (&self.analysis, &self.factor) else {
            return Err(SolveError::OutOfOrder {
                reason: "solve before a successful factorise",
            });
        };
        if rhs.nrows() != analysis.n {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "the right-hand side has {} rows, the matrix {}",
                    rhs.nrows(),
                    analysis.n
                ),
            });
        }
        let par = self.settings.solve_parallelism;
        let mut scratch = MemBuffer::try_new(
            analysis
                .symbolic
                .solve_in_place_scratch::<f64>(rhs.ncols(), par),
        )
        .map_err(|_| backend("out of memory for the solve workspace"))?;
        faer::sparse::linalg::cholesky::LltRef::new(&analysis.symbolic, &factor.values)
            .solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut scratch));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SparseColMat, Triplet};

    /// A 1D chain of springs (tridiagonal, SPD) with an extra spring between 0 and n-1.
    fn ring(n: usize) -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 4.0 + i as f64 * 0.1));
            let j = (i + 1) % n;
            t.push(Triplet::new(i, j, -1.0));
            t.push(Triplet::new(j, i, -1.0));
        }
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    }

    /// The 5-point Laplacian of an `n x n` grid plus the identity (SPD).
    fn grid(n: usize) -> SparseColMat<usize, f64> {
        let id = |i: usize, j: usize| i * n + j;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                t.push(Triplet::new(id(i, j), id(i, j), 5.0));
                for (a, b) in [(i + 1, j), (i, j + 1)] {
                    if a < n && b < n {
                        t.push(Triplet::new(id(i, j), id(a, b), -1.0));
                        t.push(Triplet::new(id(a, b), id(i, j), -1.0));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(n * n, n * n, &t).unwrap()
    }

    fn apply(a: &SparseColMat<usize, f64>, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        for (j, xj) in x.iter().enumerate() {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                y[i] += v * xj;
            }
        }
        y
    }

    /// The trailing block of the factor is the Cholesky factor of the Schur complement, with
    /// rows in the order the trailing unknowns were given; solves are unchanged by the order.
    /// Checked on a simplicial (ring) and a supernodal (grid) factor.
    #[test]
    fn trailing_factor_is_the_schur_complement_factor() {
        let side = 60;
        let cases = [
            (ring(40), vec![17, 3, 31, 8]),
            // One side of the grid, reversed, plus an interior unknown.
            (
                grid(side),
                (0..side).rev().chain([side * 30 + 30]).collect(),
            ),
        ];
        let mut supernodal_seen = false;
        for (a, trailing) in &cases {
            let n = a.nrows();
            for ordering in [Ordering::Amd, Ordering::Natural] {
                let settings = CholeskySettings::builder()
                    .ordering(ordering)
                    .build()
                    .unwrap();
                let mut solver = CholeskySolver::new(settings);
                solver
                    .analyse_with_trailing(a.symbolic(), trailing)
                    .unwrap();
                solver.factorise(a.as_ref()).unwrap();
                supernodal_seen |= solver.is_supernodal() == Some(true);
                let l = solver.trailing_factor().unwrap();
                let s = &l * l.transpose();
                // (A^-1)_TT = S^-1: solve A x = e_t and compare S x_T with e.
                for (c, &t) in trailing.iter().enumerate() {
                    let mut e = vec![0.0; n];
                    e[t] = 1.0;
                    let x = solver.solve(&e).unwrap();
                    let residual = apply(a, &x)
                        .iter()
                        .zip(&e)
                        .fold(0.0f64, |m, (ax, b)| m.max((ax - b).abs()));
                    assert!(residual < 1e-13, "solve residual {residual}");
                    for r in 0..trailing.len() {
                        let sx: f64 = (0..trailing.len())
                            .map(|k| s[(r, k)] * x[trailing[k]])
                            .sum();
                        let expected = if r == c { 1.0 } else { 0.0 };
                        assert!(
                            (sx - expected).abs() < 1e-12,
                            "S x_T = e: {sx} vs {expected}"
                        );
                    }
                }
                // L_TT is lower triangular with a positive diagonal.
                for i in 0..trailing.len() {
                    assert!(l[(i, i)] > 0.0);
                    for j in i + 1..trailing.len() {
                        assert_eq!(l[(i, j)], 0.0);
                    }
                }
            }
        }
        assert!(
            supernodal_seen,
            "the grid case must exercise the supernodal factor"
        );
    }

    #[test]
    fn repeated_trailing_unknown_is_refused() {
        let a = ring(5);
        let mut solver = CholeskySolver::default();
        assert!(matches!(
            solver.analyse_with_trailing(a.symbolic(), &[1, 1]),
            Err(SolveError::Mismatch { .. })
        ));
        assert!(matches!(
            solver.analyse_with_trailing(a.symbolic(), &[5]),
            Err(SolveError::Mismatch { .. })
        ));
    }
}
