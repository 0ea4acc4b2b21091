//! The linear solve behind a small trait: analyse a pattern once, factorise values (many times
//! on the same pattern), solve.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef, CholeskySymbolicParams,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

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
        self.analysis = None;
        self.factor = None;
        if pattern.nrows() != pattern.ncols() {
            return Err(SolveError::Mismatch {
                reason: format!(
                    "the matrix is {} x {}, not square",
                    pattern.nrows(),
                    pattern.ncols()
                ),
            });
        }
        // The natural order is passed as an explicit identity permutation: faer's `Identity`
        // ordering skips the symmetric permutation step that selects the `Side::Lower`
        // triangle of a full-storage matrix.
        let identity: Vec<usize> = (0..pattern.nrows()).collect();
        let ordering = match self.settings.ordering {
            Ordering::Amd => SymmetricOrdering::Amd,
            Ordering::Natural => SymmetricOrdering::Custom(PermRef::new_checked(
                &identity,
                &identity,
                pattern.nrows(),
            )),
        };
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            ordering,
            CholeskySymbolicParams::default(),
        )
        .map_err(backend)?;
        self.analysis = Some(Analysis {
            symbolic,
            n: pattern.nrows(),
            nnz: pattern.row_idx().len(),
            fingerprint: fingerprint(pattern),
        });
        Ok(())
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
