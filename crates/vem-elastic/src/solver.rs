//! The linear solve behind one trait: analyse a pattern once (optionally with unknowns to
//! eliminate last), factorise values on it as often as needed, solve, read the trailing factor.
//!
//! [`CholeskySolver`] implements it over faer's sparse Cholesky. Its symbolic analysis
//! ([`CholeskyAnalysis`]) and numeric factor ([`CholeskyFactor`]) are immutable once made and
//! held behind [`Arc`]s, so that several solvers share them: a clone of a solver, or a solver
//! made with [`CholeskySolver::from_analysis`] or [`CholeskySolver::from_factor`], costs no
//! analysis and no factorisation, and a new factorisation on one of them leaves the others
//! untouched.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, simplicial, supernodal, supernodal::SupernodalLltRef,
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::IndexCore;
use faer::{Conj, Index, Mat, MatMut, Par, Side};

use crate::ordering::elimination_order;
pub use crate::ordering::Ordering;
use crate::SolveError;

/// faer's symbolic factorisation, with 32-bit indices when the pattern and its factor fit
/// them: its structure (supernodes, the rows of `L`) and the permuted matrix every numeric
/// factorisation reads take half the memory of 64-bit ones. 64-bit indices for larger
/// problems (a factor of more than `u32::MAX` values).
#[derive(Debug)]
enum Symbolic {
    Narrow(SymbolicCholesky<u32>),
    Wide(SymbolicCholesky<usize>),
}

/// `$body` with `$s` bound to the symbolic factorisation `$symbolic` (a `&Symbolic`),
/// whatever its index type.
macro_rules! with_symbolic {
    ($symbolic:expr, $s:ident => $body:expr) => {
        match $symbolic {
            Symbolic::Narrow($s) => $body,
            Symbolic::Wide($s) => $body,
        }
    };
}

/// The elimination order of `symbolic` (position -> original unknown).
fn forward<I: Index>(symbolic: &SymbolicCholesky<I>) -> &[I] {
    symbolic
        .perm()
        .map(|p| p.arrays().0)
        .expect("every analysis has an explicit permutation")
}

/// The inverse of [`forward`] (original unknown -> position).
fn inverse<I: Index>(symbolic: &SymbolicCholesky<I>) -> &[I] {
    symbolic
        .perm()
        .map(|p| p.arrays().1)
        .expect("every analysis has an explicit permutation")
}

/// The symbolic factorisation of `pattern` in the order `order` (inverse `inverse`) with
/// 32-bit indices; `None` when the pattern or the factor does not fit them. The pattern is
/// copied to 32-bit indices for the analysis (half its size, dropped before the return).
fn narrow_symbolic(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    order: &[usize],
    inverse: &[usize],
) -> Result<Option<SymbolicCholesky<u32>>, SolveError> {
    let n = pattern.ncols();
    let fits = |x: usize| u32::try_from(x).is_ok_and(|x| x < u32::MAX);
    if !fits(n) || !fits(pattern.row_idx().len()) {
        return Ok(None);
    }
    let narrow = |x: usize| x as u32;
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(pattern.row_idx().len());
    col_ptr.push(0u32);
    for j in 0..n {
        row_idx.extend(pattern.row_idx_of_col_raw(j).iter().map(|&i| narrow(i)));
        col_ptr.push(narrow(row_idx.len()));
    }
    let order: Vec<u32> = order.iter().map(|&i| narrow(i)).collect();
    let inverse: Vec<u32> = inverse.iter().map(|&i| narrow(i)).collect();
    let narrow_pattern =
        SymbolicSparseColMatRef::new_unsorted_checked(n, n, &col_ptr, None, &row_idx);
    match factorize_symbolic_cholesky(
        narrow_pattern,
        Side::Lower,
        SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, n)),
        CholeskySymbolicParams::default(),
    ) {
        Ok(symbolic) => Ok(Some(symbolic)),
        Err(faer::sparse::FaerError::IndexOverflow) => Ok(None),
        Err(e) => Err(backend(e)),
    }
}

/// A direct solver for symmetric positive definite sparse systems, split into the phases a
/// contact solver needs: the pattern is analysed once (with the unknowns that couple to the
/// contact rows eliminated last, if asked), then values are factorised and right-hand sides
/// solved as often as needed; the trailing block of the factor is the Cholesky factor of the
/// Schur complement onto the trailing unknowns.
///
/// Matrices are passed in full symmetric storage (both triangles, as
/// [`crate::AssembledSystem::stiffness`] returns them) or as their lower triangle: only the
/// entries on and below the diagonal are read.
pub trait LinearSolver: Send + Sync {
    /// A short name for reports.
    fn name(&self) -> &str;

    /// Symbolic analysis (ordering, elimination tree) of the square `pattern`. Discards any
    /// earlier analysis and factorisation.
    fn analyse(&mut self, pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<(), SolveError> {
        self.analyse_with_trailing(pattern, &[])
    }

    /// Symbolic analysis that eliminates the unknowns `trailing` last, in the order given,
    /// after the others in the solver's fill-reducing order. With `P A P' = L L'` split as
    ///
    /// ```text
    /// L = [ L_II    0  ]     S = A_TT - A_TI A_II^-1 A_IT = L_TT L_TT'
    ///     [ L_TI  L_TT ]
    /// ```
    ///
    /// the trailing block of the factor is the Cholesky factor of the Schur complement `S` of
    /// `A` onto `trailing` ([`LinearSolver::trailing_factor`]). Discards any earlier analysis
    /// and factorisation.
    ///
    /// # Errors
    /// [`SolveError::Mismatch`] for a non-square pattern, an index out of range or repeated in
    /// `trailing`; [`SolveError::Backend`] when the ordering fails.
    fn analyse_with_trailing(
        &mut self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        trailing: &[usize],
    ) -> Result<(), SolveError>;

    /// Numeric factorisation of `matrix`, which must have the analysed pattern (a
    /// refactorisation when values change on the same pattern).
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

    /// The trailing block `L_TT` of the last factorisation (dense, lower triangular, rows and
    /// columns in the order of the `trailing` unknowns given to
    /// [`LinearSolver::analyse_with_trailing`]): the Cholesky factor of the Schur complement
    /// onto them, `S = L_TT L_TT'`, so that `(A^-1)_TT = S^-1`.
    ///
    /// # Errors
    /// [`SolveError::OutOfOrder`] before a successful factorisation.
    fn trailing_factor(&self) -> Result<Mat<f64>, SolveError>;

    /// What the analysis and the last factorisation measured (sizes of a solver that has not
    /// analysed anything are zero).
    fn statistics(&self) -> FactorStatistics;
}

/// What a solver reports of its factor.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FactorStatistics {
    /// The ordering used ([`Ordering::Auto`] resolved; `None` before an analysis).
    pub ordering: Option<Ordering>,
    /// Unknowns.
    pub n: usize,
    /// Stored values of the factor `L` (the supernodal factor stores its diagonal blocks
    /// whole): its memory is `8 factor_entries` bytes.
    pub factor_entries: usize,
    /// Multiply-adds of one numeric factorisation, `sum_j c_j^2` over the columns of `L` with
    /// `c_j` their stored entries (counted from the symbolic structure, as stored).
    pub flops: f64,
    /// The smallest relative pivot of the last successful factorisation
    /// ([`CholeskySolver::smallest_relative_pivot`]).
    pub smallest_relative_pivot: Option<f64>,
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
    /// with AMD (1.1e7 entries at 1e5 unknowns, 1.8e8 at 1e6). Measured with two cores (see
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
    /// [`Ordering::Auto`], factorisation parallelism chosen by the factor's size
    /// ([`FactorisationParallelism::Auto`]), sequential solves, pivot tolerance `1e-9`.
    fn default() -> Self {
        Self {
            ordering: Ordering::Auto,
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
    /// The fill-reducing ordering (default [`Ordering::Auto`]).
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
    /// was measured 20x slower).
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

    /// The settings, checked: the pivot tolerance must lie in `[0, 1)`; nested dissection
    /// needs the `metis` feature.
    pub fn build(self) -> Result<CholeskySettings, SolveError> {
        let tol = self.settings.singular_pivot_tolerance;
        if !(0.0..1.0).contains(&tol) {
            return Err(SolveError::InvalidSetting {
                reason: format!("singular_pivot_tolerance = {tol} is outside [0, 1)"),
            });
        }
        if self.settings.ordering == Ordering::NestedDissection
            && !Ordering::nested_dissection_available()
        {
            return Err(SolveError::InvalidSetting {
                reason: "ordering = nested dissection needs vem-elastic's `metis` feature"
                    .to_string(),
            });
        }
        Ok(self.settings)
    }
}

/// The symbolic analysis of a pattern: the elimination order, faer's symbolic factorisation
/// (elimination tree, supernodes, the structure of `L`) and a fingerprint of the pattern.
/// Immutable; shared between solvers behind an [`Arc`] ([`CholeskySolver::shared_analysis`]).
#[derive(Debug)]
pub struct CholeskyAnalysis {
    symbolic: Symbolic,
    n: usize,
    /// Number of unknowns eliminated last.
    n_trailing: usize,
    nnz: usize,
    fingerprint: u64,
    ordering: Ordering,
    flops: f64,
}

impl CholeskyAnalysis {
    /// Analyses `pattern` with the elimination order `order` (new position -> original
    /// unknown), whose last `n_trailing` unknowns are the trailing ones.
    fn new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        order: &[usize],
        n_trailing: usize,
        ordering: Ordering,
    ) -> Result<Self, SolveError> {
        Self::with_indices(pattern, order, n_trailing, ordering, true)
    }

    /// [`CholeskyAnalysis::new`], with 32-bit indices only if `narrow` allows them (the tests
    /// compare both).
    fn with_indices(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        order: &[usize],
        n_trailing: usize,
        ordering: Ordering,
        narrow: bool,
    ) -> Result<Self, SolveError> {
        let n = pattern.nrows();
        if n != pattern.ncols() {
            return Err(SolveError::Mismatch {
                reason: format!("the matrix is {} x {}, not square", n, pattern.ncols()),
            });
        }
        if order.len() != n {
            return Err(SolveError::Mismatch {
                reason: format!("the order has {} unknowns, the matrix {n}", order.len()),
            });
        }
        let mut inverse = vec![usize::MAX; n];
        for (new, &old) in order.iter().enumerate() {
            if old >= n || inverse[old] != usize::MAX {
                return Err(SolveError::Mismatch {
                    reason: format!("the order is not a permutation (unknown {old})"),
                });
            }
            inverse[old] = new;
        }
        // The natural order, too, is passed as an explicit permutation: faer's `Identity`
        // ordering skips the symmetric permutation step that selects the `Side::Lower`
        // triangle of a full-storage matrix.
        let narrow_symbolic = if narrow {
            narrow_symbolic(pattern, order, &inverse)?
        } else {
            None
        };
        let symbolic = match narrow_symbolic {
            Some(symbolic) => Symbolic::Narrow(symbolic),
            None => Symbolic::Wide(
                factorize_symbolic_cholesky(
                    pattern,
                    Side::Lower,
                    SymmetricOrdering::Custom(PermRef::new_checked(order, &inverse, n)),
                    CholeskySymbolicParams::default(),
                )
                .map_err(backend)?,
            ),
        };
        let flops = with_symbolic!(&symbolic, s => factor_flops(s));
        Ok(Self {
            symbolic,
            n,
            n_trailing,
            nnz: pattern.row_idx().len(),
            fingerprint: fingerprint(pattern),
            ordering,
            flops,
        })
    }

    /// Unknowns.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Unknowns eliminated last.
    pub fn n_trailing(&self) -> usize {
        self.n_trailing
    }

    /// The ordering used ([`Ordering::Auto`] resolved).
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// The elimination order: `order[k]` is the unknown eliminated at step `k` (a copy: the
    /// analysis stores it with the index type of its structure).
    pub fn elimination_order(&self) -> Vec<usize> {
        with_symbolic!(&self.symbolic, s => forward(s).iter().map(|&i| i.zx()).collect())
    }

    /// Stored values of the factor `L`.
    pub fn factor_entries(&self) -> usize {
        with_symbolic!(&self.symbolic, s => s.len_val())
    }

    /// True when faer's structure holds 32-bit indices (every pattern whose size and factor
    /// fit them), half the memory of 64-bit ones.
    pub fn has_narrow_indices(&self) -> bool {
        matches!(self.symbolic, Symbolic::Narrow(_))
    }

    /// Multiply-adds of one numeric factorisation (see [`FactorStatistics::flops`]).
    pub fn flops(&self) -> f64 {
        self.flops
    }

    /// True when faer chose the supernodal (blocked) factorisation.
    pub fn is_supernodal(&self) -> bool {
        with_symbolic!(&self.symbolic, s => matches!(s.raw(), SymbolicCholeskyRaw::Supernodal(_)))
    }

    fn check_pattern(&self, pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<(), SolveError> {
        if pattern.nrows() != self.n
            || pattern.ncols() != self.n
            || pattern.row_idx().len() != self.nnz
            || fingerprint(pattern) != self.fingerprint
        {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "the matrix ({} x {}, {} entries) does not have the analysed pattern ({} x {}, {} entries)",
                    pattern.nrows(),
                    pattern.ncols(),
                    pattern.row_idx().len(),
                    self.n,
                    self.n,
                    self.nnz
                ),
            });
        }
        Ok(())
    }
}

/// A numeric Cholesky factor: the values of `L` on a [`CholeskyAnalysis`] and the smallest
/// relative pivot. Immutable; shared between solvers behind an [`Arc`]
/// ([`CholeskySolver::shared_factor`]).
#[derive(Debug)]
pub struct CholeskyFactor {
    analysis: Arc<CholeskyAnalysis>,
    values: Vec<f64>,
    smallest_relative_pivot: f64,
}

impl CholeskyFactor {
    /// The analysis the factor was computed on.
    pub fn analysis(&self) -> &Arc<CholeskyAnalysis> {
        &self.analysis
    }

    /// The smallest relative pivot `d_k / A_kk` (see
    /// [`CholeskySolver::smallest_relative_pivot`]).
    pub fn smallest_relative_pivot(&self) -> f64 {
        self.smallest_relative_pivot
    }
}

/// Sparse Cholesky `L L^T` with faer: the symbolic analysis (fill-reducing ordering, supernodal
/// or simplicial structure) is kept and reused for every factorisation of new values on the
/// same pattern; analysis and factor are shared with the solver's clones.
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
/// // A clone shares the factor: it solves without factorising again.
/// let shared = solver.clone();
/// assert_eq!(shared.solve(&[1.0, 2.0])?, x);
/// # Ok::<(), vem_elastic::SolveError>(())
/// ```
#[derive(Debug, Default, Clone)]
pub struct CholeskySolver {
    settings: CholeskySettings,
    analysis: Option<Arc<CholeskyAnalysis>>,
    factor: Option<Arc<CholeskyFactor>>,
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

    /// A solver on an existing analysis (shared, not copied): ready to factorise.
    pub fn from_analysis(settings: CholeskySettings, analysis: Arc<CholeskyAnalysis>) -> Self {
        Self {
            settings,
            analysis: Some(analysis),
            factor: None,
        }
    }

    /// A solver on an existing factor and its analysis (shared, not copied): ready to solve.
    pub fn from_factor(settings: CholeskySettings, factor: Arc<CholeskyFactor>) -> Self {
        Self {
            settings,
            analysis: Some(Arc::clone(&factor.analysis)),
            factor: Some(factor),
        }
    }

    /// The settings in force.
    pub fn settings(&self) -> &CholeskySettings {
        &self.settings
    }

    /// The analysis, to share with other solvers (after an analysis).
    pub fn shared_analysis(&self) -> Option<Arc<CholeskyAnalysis>> {
        self.analysis.clone()
    }

    /// The factor of the last successful factorisation, to share with other solvers.
    pub fn shared_factor(&self) -> Option<Arc<CholeskyFactor>> {
        self.factor.clone()
    }

    /// Symbolic analysis with an explicit elimination order (`order[k]` the unknown eliminated
    /// at step `k`, a permutation of `0..n`) whose last `n_trailing` unknowns are the trailing
    /// ones: the analysis of a matrix that shares an ordering with another (the ordering of a
    /// stiffness reused for the same stiffness plus contact terms). Discards any earlier
    /// analysis and factorisation.
    ///
    /// # Errors
    /// [`SolveError::Mismatch`] for a non-square pattern, an order that is not a permutation of
    /// its unknowns or `n_trailing` above `n`; [`SolveError::Backend`] when faer fails.
    pub fn analyse_with_order(
        &mut self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        order: &[usize],
        n_trailing: usize,
    ) -> Result<(), SolveError> {
        self.analysis = None;
        self.factor = None;
        if n_trailing > order.len() {
            return Err(SolveError::Mismatch {
                reason: format!("{n_trailing} trailing unknowns of {}", order.len()),
            });
        }
        let ordering = self.settings.ordering.resolve(order.len() - n_trailing);
        self.analysis = Some(Arc::new(CholeskyAnalysis::new(
            pattern, order, n_trailing, ordering,
        )?));
        Ok(())
    }

    /// Number of stored values of the factor `L` (after an analysis).
    pub fn factor_len(&self) -> Option<usize> {
        self.analysis.as_ref().map(|a| a.factor_entries())
    }

    /// The parallelism the numeric factorisation uses for the analysed pattern (after
    /// an analysis): [`FactorisationParallelism::for_factor`] of the factor's size.
    pub fn factorisation_par(&self) -> Option<Par> {
        self.factor_len()
            .map(|len| self.settings.factorisation_parallelism.for_factor(len))
    }

    /// True when the analysis chose the supernodal (blocked) factorisation.
    pub fn is_supernodal(&self) -> Option<bool> {
        self.analysis.as_ref().map(|a| a.is_supernodal())
    }

    /// The smallest relative pivot `d_k / A_kk` (`d_k = L_kk^2`, `A_kk` the matching diagonal
    /// entry of the permuted matrix) of the last successful factorisation: 1 for a diagonal
    /// matrix, small for an ill-conditioned one. A diagnostic of how firmly the body is held.
    pub fn smallest_relative_pivot(&self) -> Option<f64> {
        self.factor.as_ref().map(|f| f.smallest_relative_pivot)
    }

    /// Solves `K x = b` for a right-hand side `b` that vanishes outside the trailing unknowns
    /// (those [`LinearSolver::analyse_with_trailing`] eliminated last), given
    /// `y = L_GG^-1 b_G` in the trailing order (`L_GG` the [`LinearSolver::trailing_factor`]).
    /// The forward substitution of such a `b` touches the trailing block only, which a caller
    /// that keeps `L_GG` does densely; what is left is the backward substitution of the whole
    /// factor, about half the work of [`LinearSolver::solve_in_place`]. `x` (length `n`)
    /// receives the solution in the original numbering.
    ///
    /// # Errors
    /// [`SolveError::OutOfOrder`] before a factorisation, [`SolveError::Mismatch`] for vectors
    /// of the wrong length.
    pub fn solve_from_trailing(&self, y: &[f64], x: &mut [f64]) -> Result<(), SolveError> {
        let Some(factor) = &self.factor else {
            return Err(SolveError::OutOfOrder {
                reason: "solve before a successful factorise",
            });
        };
        let analysis = &factor.analysis;
        if y.len() != analysis.n_trailing || x.len() != analysis.n {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "{} trailing values and {} unknowns for a factor with {} trailing of {}",
                    y.len(),
                    x.len(),
                    analysis.n_trailing,
                    analysis.n
                ),
            });
        }
        let first = analysis.n - analysis.n_trailing;
        let mut z = Mat::<f64>::zeros(analysis.n, 1);
        for (p, &v) in y.iter().enumerate() {
            z[(first + p, 0)] = v;
        }
        let par = self.settings.solve_parallelism;
        with_symbolic!(&analysis.symbolic, symbolic => {
            match symbolic.raw() {
                SymbolicCholeskyRaw::Simplicial(s) => {
                    let l = SparseColMatRef::new(s.factor(), &factor.values);
                    faer::sparse::linalg::triangular_solve::solve_lower_triangular_transpose_in_place(
                        l,
                        Conj::No,
                        z.as_mut(),
                        par,
                    );
                }
                SymbolicCholeskyRaw::Supernodal(s) => {
                    let mut scratch =
                        MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, par))
                            .map_err(|_| backend("out of memory for the solve workspace"))?;
                    SupernodalLltRef::new(s, &factor.values).l_transpose_solve_with_conj(
                        Conj::No,
                        z.as_mut(),
                        par,
                        MemStack::new(&mut scratch),
                    );
                }
            }
            // Position `new` of the factor holds the original unknown `forward[new]`.
            for (new, &old) in forward(symbolic).iter().enumerate() {
                x[old.zx()] = z[(new, 0)];
            }
        });
        Ok(())
    }

    /// The part of the factor that a solve with its right-hand side on `unknowns` reaches,
    /// for [`CholeskySolver::solve_on_support`]: made once per set of unknowns (a contact
    /// interface), used for every solve on it.
    ///
    /// # Errors
    /// [`SolveError::OutOfOrder`] before an analysis, [`SolveError::Mismatch`] for an unknown
    /// out of range.
    pub fn support(&self, unknowns: &[usize]) -> Result<SolveSupport, SolveError> {
        let Some(analysis) = &self.analysis else {
            return Err(SolveError::OutOfOrder {
                reason: "support before an analysis",
            });
        };
        SolveSupport::new(analysis, unknowns)
    }

    /// `(K^-1 b)` at the support's unknowns for a `b` that vanishes outside them: `values`
    /// holds `b` on the unknowns (in the order [`CholeskySolver::support`] was given them)
    /// and receives the solution there. The forward substitution of such a `b` is non-zero
    /// only on the elimination-tree ancestors of its unknowns, and the solution at them needs
    /// the backward substitution only there: both run over the supernodes of those ancestors
    /// ([`SolveSupport::reached_fraction`] of the factor's entries), the rest of the factor
    /// is not read. Equal to a full solve up to round-off (a test).
    ///
    /// # Errors
    /// [`SolveError::OutOfOrder`] before a factorisation, [`SolveError::Mismatch`] for a
    /// support of another analysis or values of the wrong length.
    pub fn solve_on_support(
        &self,
        support: &SolveSupport,
        values: &mut [f64],
    ) -> Result<(), SolveError> {
        let rows = values.len();
        self.solve_many_on_support(
            support,
            MatMut::from_column_major_slice_mut(values, rows, 1),
        )
    }

    /// [`CholeskySolver::solve_on_support`] for the columns of `values` at once (a row per
    /// unknown of the support, a column per right-hand side): the factor is read once for all
    /// of them, so `k` columns cost far less than `k` solves. The work space holds the
    /// reached rows only (the widths of the reached supernodes) times `k`.
    ///
    /// # Errors
    /// As [`CholeskySolver::solve_on_support`].
    pub fn solve_many_on_support(
        &self,
        support: &SolveSupport,
        mut values: MatMut<'_, f64>,
    ) -> Result<(), SolveError> {
        let Some(factor) = &self.factor else {
            return Err(SolveError::OutOfOrder {
                reason: "solve before a successful factorise",
            });
        };
        let analysis = &factor.analysis;
        if !Arc::ptr_eq(analysis, &support.analysis) || values.nrows() != support.unknowns.len() {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "{} values for a support of {} unknowns{}",
                    values.nrows(),
                    support.unknowns.len(),
                    if Arc::ptr_eq(analysis, &support.analysis) {
                        ""
                    } else {
                        " made on another analysis"
                    }
                ),
            });
        }
        let k = values.ncols();
        if !analysis.is_supernodal() {
            // The simplicial factor (small systems): a full solve.
            let mut x = Mat::<f64>::zeros(analysis.n, k);
            for (row, &i) in support.unknowns.iter().enumerate() {
                for c in 0..k {
                    x[(i, c)] = values[(row, c)];
                }
            }
            self.solve_in_place(x.as_mut())?;
            for (row, &i) in support.unknowns.iter().enumerate() {
                for c in 0..k {
                    values[(row, c)] = x[(i, c)];
                }
            }
            return Ok(());
        }
        // Row `compact[p]` of `x` holds factor position `p` (of a reached supernode).
        let compact = &support.compact;
        let mut x = Mat::<f64>::zeros(support.reached_rows, k);
        with_symbolic!(&analysis.symbolic, symbolic => {
            let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() else {
                unreachable!("a supernodal analysis");
            };
            let l = SupernodalLltRef::new(s, &factor.values);
            let par = self.settings.solve_parallelism;
            // The work space holds the reached supernodes' rows only: the rest of the factor
            // is never read.
            for (row, &p) in support.positions.iter().enumerate() {
                for c in 0..k {
                    x[(compact[p], c)] = values[(row, c)];
                }
            }
            let mut tmp = Mat::<f64>::zeros(support.longest_pattern, k);
            // L z = b over the reached supernodes, in elimination order.
            for &node in &support.supernodes {
                let node = l.supernode(node);
                let (start, block, pattern) = (node.start(), node.val(), node.pattern());
                let (width, at) = (block.ncols(), compact[start]);
                let (top, bottom) = block.split_at_row(width);
                faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                    top,
                    x.as_mut().subrows_mut(at, width),
                    par,
                );
                let below = tmp.as_mut().subrows_mut(0, pattern.len());
                faer::linalg::matmul::matmul(
                    below,
                    faer::Accum::Replace,
                    bottom,
                    x.as_ref().subrows(at, width),
                    1.0,
                    par,
                );
                for c in 0..k {
                    for (j, &i) in pattern.iter().enumerate() {
                        x[(compact[i.zx()], c)] -= tmp[(j, c)];
                    }
                }
            }
            // L' x = z over the same supernodes, backwards: the solution at the support's
            // unknowns needs it only at their ancestors.
            for &node in support.supernodes.iter().rev() {
                let node = l.supernode(node);
                let (start, block, pattern) = (node.start(), node.val(), node.pattern());
                let (width, at) = (block.ncols(), compact[start]);
                let (top, bottom) = block.split_at_row(width);
                for c in 0..k {
                    for (j, &i) in pattern.iter().enumerate() {
                        tmp[(j, c)] = x[(compact[i.zx()], c)];
                    }
                }
                faer::linalg::matmul::matmul(
                    x.as_mut().subrows_mut(at, width),
                    faer::Accum::Add,
                    bottom.transpose(),
                    tmp.as_ref().subrows(0, pattern.len()),
                    -1.0,
                    par,
                );
                faer::linalg::triangular_solve::solve_upper_triangular_in_place(
                    top.transpose(),
                    x.as_mut().subrows_mut(at, width),
                    par,
                );
            }
        });
        for (row, &p) in support.positions.iter().enumerate() {
            for c in 0..k {
                values[(row, c)] = x[(compact[p], c)];
            }
        }
        Ok(())
    }
}

/// The unknowns of a sparse right-hand side and the supernodes of the factor that solves with
/// it reach (the unknowns' ancestors in the supernodal elimination tree), for
/// [`CholeskySolver::solve_on_support`].
#[derive(Debug, Clone)]
pub struct SolveSupport {
    analysis: Arc<CholeskyAnalysis>,
    /// The unknowns, in the caller's order and numbering.
    unknowns: Vec<usize>,
    /// Their positions in the elimination order.
    positions: Vec<usize>,
    /// The reached supernodes, ascending (empty for a simplicial factor).
    supernodes: Vec<usize>,
    /// The longest row pattern below a reached supernode.
    longest_pattern: usize,
    /// Per factor position, its row in the work space of a solve (the reached supernodes'
    /// columns numbered consecutively; unused elsewhere).
    compact: Vec<usize>,
    /// The rows of that work space: the reached supernodes' widths summed.
    reached_rows: usize,
    /// Factor entries in the reached supernodes.
    reached_entries: usize,
}

/// The supernodes a solve on `support`'s positions reaches, from the supernodal structure
/// (`begin`, `end` of each supernode, `ptr` into `rows`, the rows below each supernode).
fn reach<I: Index>(
    support: &mut SolveSupport,
    n: usize,
    (begin, end): (&[I], &[I]),
    ptr: &[I],
    rows: &[I],
) {
    let n_supernodes = begin.len();
    let mut owner = vec![0usize; n];
    for k in 0..n_supernodes {
        owner[begin[k].zx()..end[k].zx()].fill(k);
    }
    let below = |k: usize| ptr[k + 1].zx() - ptr[k].zx();
    // The supernodal elimination tree: a supernode's parent owns its first row below.
    let parent = |k: usize| (below(k) > 0).then(|| owner[rows[ptr[k].zx()].zx()]);
    let mut reached = vec![false; n_supernodes];
    for &p in &support.positions {
        let mut k = Some(owner[p]);
        while let Some(node) = k {
            if reached[node] {
                break;
            }
            reached[node] = true;
            k = parent(node);
        }
    }
    support.supernodes = (0..n_supernodes).filter(|&k| reached[k]).collect();
    support.compact = vec![usize::MAX; n];
    let mut rows = 0;
    for &k in &support.supernodes {
        for p in begin[k].zx()..end[k].zx() {
            support.compact[p] = rows;
            rows += 1;
        }
    }
    support.reached_rows = rows;
    support.longest_pattern = support
        .supernodes
        .iter()
        .map(|&k| below(k))
        .max()
        .unwrap_or(0);
    support.reached_entries = support
        .supernodes
        .iter()
        .map(|&k| {
            let width = end[k].zx() - begin[k].zx();
            width * (width + below(k))
        })
        .sum();
}

impl SolveSupport {
    fn new(analysis: &Arc<CholeskyAnalysis>, unknowns: &[usize]) -> Result<Self, SolveError> {
        let n = analysis.n;
        // Position `new` of the factor holds the original unknown `forward[new]`.
        let positions = unknowns
            .iter()
            .map(|&i| {
                with_symbolic!(&analysis.symbolic, s => inverse(s).get(i).map(|p| p.zx()))
                    .ok_or_else(|| SolveError::Mismatch {
                        reason: format!("unknown {i} of a support for a system of {n}"),
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut support = Self {
            analysis: Arc::clone(analysis),
            unknowns: unknowns.to_vec(),
            positions,
            supernodes: Vec::new(),
            longest_pattern: 0,
            compact: Vec::new(),
            reached_rows: 0,
            reached_entries: analysis.factor_entries(),
        };
        with_symbolic!(&analysis.symbolic, symbolic => {
            if let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() {
                reach(
                    &mut support,
                    n,
                    (s.supernode_begin(), s.supernode_end()),
                    s.col_ptr_for_row_idx(),
                    s.row_idx(),
                );
            }
        });
        Ok(support)
    }

    /// The support's unknowns.
    pub fn unknowns(&self) -> &[usize] {
        &self.unknowns
    }

    /// The rows of the work space of a solve on the support (the widths of the reached
    /// supernodes; the system's size for a simplicial factor): a block of `k` right-hand sides
    /// ([`CholeskySolver::solve_many_on_support`]) works on `k` columns of them.
    pub fn reached_rows(&self) -> usize {
        if self.analysis.is_supernodal() {
            self.reached_rows
        } else {
            self.analysis.n
        }
    }

    /// The fraction of the factor's entries a solve on the support reads (1 for a simplicial
    /// factor, solved whole).
    pub fn reached_fraction(&self) -> f64 {
        let total = self.analysis.factor_entries();
        if total == 0 {
            return 1.0;
        }
        (self.reached_entries as f64 / total as f64).min(1.0)
    }
}

/// Multiply-adds of the numeric factorisation: `sum_j c_j^2` over the stored columns.
fn factor_flops<I: Index>(symbolic: &SymbolicCholesky<I>) -> f64 {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => s
            .col_ptr()
            .windows(2)
            .map(|w| {
                let c = (w[1].zx() - w[0].zx()) as f64;
                c * c
            })
            .sum(),
        SymbolicCholeskyRaw::Supernodal(s) => {
            let begin = s.supernode_begin();
            let end = s.supernode_end();
            let ptr = s.col_ptr_for_row_idx();
            (0..s.n_supernodes())
                .map(|k| {
                    let width = end[k].zx() - begin[k].zx();
                    let below = (ptr[k + 1].zx() - ptr[k].zx()) as f64;
                    (0..width)
                        .map(|c| {
                            let entries = (width - c) as f64 + below;
                            entries * entries
                        })
                        .sum::<f64>()
                })
                .sum()
        }
    }
}

/// The matrix permuted by the analysis' order, only the triangle faer's numeric factorisation
/// reads (the lower for the supernodal, the upper for the simplicial factorisation): half the
/// memory of a full-storage copy.
fn permuted_triangle<I: Index>(
    symbolic: &SymbolicCholesky<I>,
    matrix: SparseColMatRef<'_, usize, f64>,
) -> (Vec<I>, Vec<I>, Vec<f64>) {
    let n = symbolic.nrows();
    // Position of each original unknown in the elimination order.
    let position = inverse(symbolic);
    let lower = matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_));
    // Column of the permuted entry (i, j), i >= j, in the triangle kept: (max, min) for the
    // lower triangle, the other way round for the upper one.
    let place = |i: usize, j: usize| -> (usize, usize) {
        let (pi, pj) = (position[i].zx(), position[j].zx());
        let (row, col) = (pi.max(pj), pi.min(pj));
        if lower {
            (row, col)
        } else {
            (col, row)
        }
    };
    // Counted in `usize`, stored in `I` (the analysis checked that the entries fit it).
    let mut counts = vec![0usize; n + 1];
    for j in 0..n {
        for &i in matrix.symbolic().row_idx_of_col_raw(j) {
            if i >= j {
                counts[place(i, j).1 + 1] += 1;
            }
        }
    }
    for k in 0..n {
        counts[k + 1] += counts[k];
    }
    let col_ptr: Vec<I> = counts.iter().map(|&c| I::truncate(c)).collect();
    let entries = counts[n];
    // `counts` becomes the next free slot of each column.
    let mut next = counts;
    let mut row_idx = vec![I::truncate(0); entries];
    let mut values = vec![0.0f64; entries];
    for j in 0..n {
        let rows = matrix.symbolic().row_idx_of_col_raw(j);
        for (&i, &v) in rows.iter().zip(matrix.val_of_col(j)) {
            if i >= j {
                let (row, col) = place(i, j);
                row_idx[next[col]] = I::truncate(row);
                values[next[col]] = v;
                next[col] += 1;
            }
        }
    }
    (col_ptr, row_idx, values)
}

/// The smallest relative pivot `d_k / A_kk` of the factor `factor` of `matrix` and the
/// elimination step where it occurs.
fn smallest_relative_pivot<I: Index>(
    symbolic: &SymbolicCholesky<I>,
    factor: &[f64],
    matrix: SparseColMatRef<'_, usize, f64>,
) -> (f64, usize) {
    let diagonal = |old: usize| {
        matrix
            .symbolic()
            .row_idx_of_col_raw(old)
            .iter()
            .zip(matrix.val_of_col(old))
            .filter(|(&i, _)| i == old)
            .map(|(_, &v)| v)
            .sum::<f64>()
    };
    let original = |new: usize| match symbolic.perm() {
        Some(perm) => perm.arrays().0[new].zx(),
        None => new,
    };
    let ratio = |new: usize, l_kk: f64| (l_kk * l_kk / diagonal(original(new)), new);
    let smaller = |a: (f64, usize), b: (f64, usize)| if b.0 < a.0 { b } else { a };
    let start = (f64::INFINITY, 0);
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let col_ptr = s.col_ptr();
            (0..s.nrows())
                .map(|k| ratio(k, factor[col_ptr[k].zx()]))
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

/// Factor values (32 MiB) from which a factorisation first returns the freed memory to the
/// system ([`crate::release_free_memory`]).
const RELEASE_BEFORE_FACTOR_VALUES: usize = 1 << 22;

/// Factorises `matrix` on `symbolic` into `values` (reallocated to the factor's size), with
/// the permuted triangle faer reads made and dropped around the factorisation.
fn numeric_factor<I: Index>(
    symbolic: &SymbolicCholesky<I>,
    matrix: SparseColMatRef<'_, usize, f64>,
    par: Par,
    values: &mut Vec<f64>,
) -> Result<(), SolveError> {
    // Before a large factor (above glibc's largest mapping threshold), the memory freed since
    // the last phase (the assembly's work) goes back to the system rather than staying
    // resident beside the factor.
    if symbolic.len_val() >= RELEASE_BEFORE_FACTOR_VALUES {
        crate::release_free_memory();
    }
    let (col_ptr, row_idx, permuted) = permuted_triangle(symbolic, matrix);
    let n = symbolic.nrows();
    let a = SparseColMatRef::new(
        SymbolicSparseColMatRef::new_unsorted_checked(n, n, &col_ptr, None, &row_idx),
        &permuted,
    );
    // The factor is the largest allocation of a solve: ask for it first, so that a
    // problem too large for the machine is an error naming the size, not an abort.
    let needed = symbolic.len_val();
    values.clear();
    values
        .try_reserve_exact(needed)
        .map_err(|_| SolveError::Backend {
            reason: format!(
                "cannot allocate the Cholesky factor: {needed} values ({:.1} GiB)",
                needed as f64 * 8.0 / f64::from(1u32 << 30)
            ),
        })?;
    values.resize(needed, 0.0);
    let non_positive = |LltError::NonPositivePivot { index }| SolveError::NotPositiveDefinite {
        step: index.saturating_sub(1),
    };
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let mut scratch = MemBuffer::try_new(
                simplicial::factorize_simplicial_numeric_llt_scratch::<I, f64>(n),
            )
            .map_err(|_| backend("out of memory for the factorisation workspace"))?;
            simplicial::factorize_simplicial_numeric_llt(
                values,
                a,
                LltRegularization::default(),
                s,
                MemStack::new(&mut scratch),
            )
            .map_err(non_positive)?;
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let mut scratch = MemBuffer::try_new(
                supernodal::factorize_supernodal_numeric_llt_scratch::<I, f64>(
                    s,
                    par,
                    Default::default(),
                ),
            )
            .map_err(|_| backend("out of memory for the factorisation workspace"))?;
            supernodal::factorize_supernodal_numeric_llt(
                values,
                a,
                LltRegularization::default(),
                s,
                par,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .map_err(non_positive)?;
        }
    }
    drop((col_ptr, row_idx, permuted));
    Ok(())
}

impl LinearSolver for CholeskySolver {
    fn name(&self) -> &str {
        "faer sparse Cholesky"
    }

    fn analyse_with_trailing(
        &mut self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        trailing: &[usize],
    ) -> Result<(), SolveError> {
        self.analysis = None;
        self.factor = None;
        let (order, ordering) = elimination_order(pattern, trailing, self.settings.ordering)?;
        self.analysis = Some(Arc::new(CholeskyAnalysis::new(
            pattern,
            &order,
            trailing.len(),
            ordering,
        )?));
        Ok(())
    }

    fn factorise(&mut self, matrix: SparseColMatRef<'_, usize, f64>) -> Result<(), SolveError> {
        // The values of the last factor are reused when no other solver shares it.
        let mut values = match self.factor.take().map(Arc::try_unwrap) {
            Some(Ok(factor)) => factor.values,
            _ => Vec::new(),
        };
        let analysis = self.analysis.as_ref().ok_or(SolveError::OutOfOrder {
            reason: "factorise before analyse",
        })?;
        analysis.check_pattern(matrix.symbolic())?;
        let par = self
            .settings
            .factorisation_parallelism
            .for_factor(analysis.factor_entries());
        let (smallest, step) = with_symbolic!(&analysis.symbolic, symbolic => {
            numeric_factor(symbolic, matrix, par, &mut values)?;
            smallest_relative_pivot(symbolic, &values, matrix)
        });
        // NaN (a zero diagonal entry) counts as singular too.
        if smallest.is_nan() || smallest <= self.settings.singular_pivot_tolerance {
            return Err(SolveError::NotPositiveDefinite { step });
        }
        self.factor = Some(Arc::new(CholeskyFactor {
            analysis: Arc::clone(analysis),
            values,
            smallest_relative_pivot: smallest,
        }));
        Ok(())
    }

    fn solve_in_place(&self, rhs: MatMut<'_, f64>) -> Result<(), SolveError> {
        let Some(factor) = &self.factor else {
            return Err(SolveError::OutOfOrder {
                reason: "solve before a successful factorise",
            });
        };
        let analysis = &factor.analysis;
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
        with_symbolic!(&analysis.symbolic, symbolic => {
            let mut scratch =
                MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par))
                    .map_err(|_| backend("out of memory for the solve workspace"))?;
            LltRef::new(symbolic, &factor.values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                par,
                MemStack::new(&mut scratch),
            );
        });
        Ok(())
    }

    fn trailing_factor(&self) -> Result<Mat<f64>, SolveError> {
        let Some(factor) = &self.factor else {
            return Err(SolveError::OutOfOrder {
                reason: "trailing factor before a successful factorise",
            });
        };
        let analysis = &factor.analysis;
        let first = analysis.n - analysis.n_trailing;
        let mut block = Mat::<f64>::zeros(analysis.n_trailing, analysis.n_trailing);
        with_symbolic!(&analysis.symbolic, symbolic => match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (col_ptr, row_idx) = (s.col_ptr(), s.row_idx());
                for j in first..analysis.n {
                    for k in col_ptr[j].zx()..col_ptr[j + 1].zx() {
                        block[(row_idx[k].zx() - first, j - first)] = factor.values[k];
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
                            block[(row.zx() - first, j - first)] = values[(width + r, c)];
                        }
                    }
                }
            }
        });
        Ok(block)
    }

    fn statistics(&self) -> FactorStatistics {
        match &self.analysis {
            None => FactorStatistics::default(),
            Some(a) => FactorStatistics {
                ordering: Some(a.ordering),
                n: a.n,
                factor_entries: a.factor_entries(),
                flops: a.flops,
                smallest_relative_pivot: self.smallest_relative_pivot(),
            },
        }
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

    /// The analysis with 32-bit indices (the default) and with 64-bit ones (problems too
    /// large for 32-bit ones) factorise to the same values bit for bit and solve alike: every
    /// path that reads the structure (full solve, solve from the trailing block, trailing
    /// factor, solve on a support, the pivot), on a simplicial (ring) and a supernodal (grid)
    /// factor.
    #[test]
    fn narrow_and_wide_indices_factorise_alike() {
        let side = 60;
        let cases = [
            (ring(40), vec![17, 3, 31, 8]),
            (grid(side), (0..side).rev().collect::<Vec<_>>()),
        ];
        let mut supernodal_seen = false;
        for ((a, trailing), ordering) in cases
            .iter()
            .flat_map(|case| [(case, Ordering::Amd), (case, Ordering::Natural)])
        {
            let n = a.nrows();
            let settings = CholeskySettings::default();
            let (order, ordering) = elimination_order(a.symbolic(), trailing, ordering).unwrap();
            let solvers: Vec<CholeskySolver> = [true, false]
                .into_iter()
                .map(|narrow| {
                    let analysis = CholeskyAnalysis::with_indices(
                        a.symbolic(),
                        &order,
                        trailing.len(),
                        ordering,
                        narrow,
                    )
                    .unwrap();
                    assert_eq!(analysis.has_narrow_indices(), narrow);
                    let mut solver = CholeskySolver::from_analysis(settings, Arc::new(analysis));
                    solver.factorise(a.as_ref()).unwrap();
                    solver
                })
                .collect();
            let (narrow, wide) = (&solvers[0], &solvers[1]);
            supernodal_seen |= narrow.is_supernodal() == Some(true);
            let factor = |s: &CholeskySolver| s.shared_factor().unwrap().values.clone();
            assert_eq!(factor(narrow), factor(wide));
            assert_eq!(
                narrow.analysis.as_ref().unwrap().elimination_order(),
                wide.analysis.as_ref().unwrap().elimination_order()
            );
            assert_eq!(narrow.factor_len(), wide.factor_len());
            assert_eq!(
                narrow.smallest_relative_pivot(),
                wide.smallest_relative_pivot()
            );
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            assert_eq!(narrow.solve(&b).unwrap(), wide.solve(&b).unwrap());
            let (ln, lw) = (
                narrow.trailing_factor().unwrap(),
                wide.trailing_factor().unwrap(),
            );
            assert_eq!(ln, lw);
            let y: Vec<f64> = (0..trailing.len()).map(|k| 1.0 + k as f64).collect();
            let (mut xn, mut xw) = (vec![0.0; n], vec![0.0; n]);
            narrow.solve_from_trailing(&y, &mut xn).unwrap();
            wide.solve_from_trailing(&y, &mut xw).unwrap();
            assert_eq!(xn, xw);
            let unknowns = [trailing[0], trailing[1]];
            let (sn, sw) = (
                narrow.support(&unknowns).unwrap(),
                wide.support(&unknowns).unwrap(),
            );
            assert_eq!(sn.supernodes, sw.supernodes);
            assert_eq!(sn.reached_fraction(), sw.reached_fraction());
            let (mut vn, mut vw) = (vec![1.0, -2.0], vec![1.0, -2.0]);
            narrow.solve_on_support(&sn, &mut vn).unwrap();
            wide.solve_on_support(&sw, &mut vw).unwrap();
            assert_eq!(vn, vw);
        }
        assert!(supernodal_seen, "no case was supernodal");
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
            for ordering in [
                Ordering::Amd,
                Ordering::Natural,
                #[cfg(feature = "metis")]
                Ordering::NestedDissection,
            ] {
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
    fn a_right_hand_side_on_the_trailing_unknowns_is_solved_from_the_trailing_factor() {
        let mut kinds = [false; 2];
        for n in [6, 40, 120] {
            let k = grid(n);
            let size = k.nrows();
            let trailing: Vec<usize> = (0..size).filter(|i| i % 7 == 3).collect();
            for supernodal in [false, true] {
                let mut solver = CholeskySolver::default();
                solver
                    .analyse_with_trailing(k.symbolic(), &trailing)
                    .unwrap();
                solver.factorise(k.as_ref()).unwrap();
                if supernodal != solver.is_supernodal().unwrap() {
                    continue;
                }
                kinds[usize::from(supernodal)] = true;
                // b on the trailing unknowns; y = L_GG^-1 b_G by a dense forward substitution.
                let b_g: Vec<f64> = (0..trailing.len())
                    .map(|p| (p as f64 * 0.7).sin())
                    .collect();
                let mut b = vec![0.0; size];
                for (&i, &v) in trailing.iter().zip(&b_g) {
                    b[i] = v;
                }
                let l = solver.trailing_factor().unwrap();
                let mut y = Mat::<f64>::from_fn(b_g.len(), 1, |p, _| b_g[p]);
                faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                    l.as_ref(),
                    y.as_mut(),
                    Par::Seq,
                );
                let y: Vec<f64> = (0..b_g.len()).map(|p| y[(p, 0)]).collect();
                let mut x = vec![0.0; size];
                solver.solve_from_trailing(&y, &mut x).unwrap();
                let full = solver.solve(&b).unwrap();
                let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, e) in x.iter().zip(&full) {
                    assert!((a - e).abs() < 1e-12 * scale, "{a} vs {e}");
                }
            }
        }
        assert_eq!(
            kinds,
            [true, true],
            "both simplicial and supernodal factors"
        );
    }

    /// A solve on a support (one side of the grid and a few scattered unknowns) equals the
    /// full solve there, one right-hand side or a block of them, on simplicial and supernodal
    /// factors, in every ordering; a support of another analysis is refused.
    #[test]
    fn a_solve_on_a_support_equals_the_full_solve_there() {
        let mut kinds = [false; 2];
        for n in [6, 40, 120] {
            let k = grid(n);
            let size = k.nrows();
            let unknowns: Vec<usize> = (0..n).rev().chain([size / 2, size - 1, 7]).collect();
            for ordering in [Ordering::Amd, Ordering::Natural] {
                let settings = CholeskySettings::builder()
                    .ordering(ordering)
                    .build()
                    .unwrap();
                let mut solver = CholeskySolver::new(settings);
                solver.analyse(k.symbolic()).unwrap();
                solver.factorise(k.as_ref()).unwrap();
                let supernodal = solver.is_supernodal().unwrap();
                kinds[usize::from(supernodal)] = true;
                let support = solver.support(&unknowns).unwrap();
                assert_eq!(support.unknowns(), &unknowns[..]);
                let fraction = support.reached_fraction();
                assert!(fraction > 0.0 && fraction <= 1.0, "{fraction}");
                let values: Vec<f64> = (0..unknowns.len())
                    .map(|p| (p as f64 * 0.7).sin() + 0.1)
                    .collect();
                let mut b = vec![0.0; size];
                for (&i, &v) in unknowns.iter().zip(&values) {
                    b[i] = v;
                }
                let full = solver.solve(&b).unwrap();
                let mut on_support = values.clone();
                solver.solve_on_support(&support, &mut on_support).unwrap();
                let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (&i, a) in unknowns.iter().zip(&on_support) {
                    assert!((a - full[i]).abs() < 1e-13 * scale, "{a} vs {}", full[i]);
                }
                // Three right-hand sides at once: each column equals its own full solve.
                let columns = 3;
                let mut many = Mat::<f64>::from_fn(unknowns.len(), columns, |p, c| {
                    ((p * (c + 2)) as f64 * 0.37).cos()
                });
                let given = many.clone();
                solver
                    .solve_many_on_support(&support, many.as_mut())
                    .unwrap();
                for c in 0..columns {
                    let mut b = vec![0.0; size];
                    for (p, &i) in unknowns.iter().enumerate() {
                        b[i] = given[(p, c)];
                    }
                    let full = solver.solve(&b).unwrap();
                    let scale = full.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    for (p, &i) in unknowns.iter().enumerate() {
                        let a = many[(p, c)];
                        assert!((a - full[i]).abs() < 1e-13 * scale, "{a} vs {}", full[i]);
                    }
                }
                // The other analysis' support, or too few values: refused.
                let mut other = CholeskySolver::default();
                other.analyse(k.symbolic()).unwrap();
                other.factorise(k.as_ref()).unwrap();
                assert!(matches!(
                    other.solve_on_support(&support, &mut on_support),
                    Err(SolveError::Mismatch { .. })
                ));
                assert!(matches!(
                    solver.solve_on_support(&support, &mut on_support[1..]),
                    Err(SolveError::Mismatch { .. })
                ));
                assert!(matches!(
                    solver.support(&[size]),
                    Err(SolveError::Mismatch { .. })
                ));
            }
        }
        assert_eq!(
            kinds,
            [true, true],
            "both simplicial and supernodal factors"
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
