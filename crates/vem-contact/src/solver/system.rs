//! The algebraic contact problem: stiffness, load, constraint rows, gaps and friction bounds.
//!
//! A [`ContactSystem`] is what every [`ContactSolver`](super::ContactSolver) sees. It knows
//! nothing of meshes: the two-body layer turns the interface pairing into rows of `B_N`
//! (normal jump `[u]_nu` at each interface node) and `B_T` (tangential jump `[u]_1tau`), the
//! interpolated initial gap `g = h0_I` and the nodal friction bounds `b_i = l_i g_F(x_i)`
//! (spec section 2, nodal quadrature `j_h`).

use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};

use faer::sparse::{SparseColMat, SparseColMatRef};

/// Why a [`ConstraintRows`] or a [`ContactSystem`] was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContactSystemError {
    /// A constraint entry refers to a column (unknown) outside `0..ncols`.
    #[error("{what}: row {row} refers to column {col}, but there are only {ncols} unknowns")]
    ColumnOutOfRange {
        /// Which matrix (`"normal rows"`, `"tangential rows"`, ...).
        what: &'static str,
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
        /// Number of columns.
        ncols: usize,
    },
    /// A triplet refers to a row outside `0..nrows`.
    #[error("{what}: entry refers to row {row}, but there are only {nrows} rows")]
    RowOutOfRange {
        /// Which matrix.
        what: &'static str,
        /// The offending row index.
        row: usize,
        /// Number of rows.
        nrows: usize,
    },
    /// The CSR row pointer is not a non-decreasing sequence from 0 to the number of entries.
    #[error("{what}: malformed CSR row pointer ({reason})")]
    MalformedRowPointer {
        /// Which matrix.
        what: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A matrix or vector entry is NaN or infinite.
    #[error("{what}: entry {index} is not finite ({value})")]
    NonFinite {
        /// Which matrix or vector.
        what: &'static str,
        /// Entry index (row for vectors, position in storage for matrices).
        index: usize,
        /// The value.
        value: f64,
    },
    /// Two sizes that must agree do not.
    #[error("{what}: expected length {expected}, got {actual}")]
    DimensionMismatch {
        /// Which quantity.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Actual size.
        actual: usize,
    },
    /// The stiffness matrix is not square.
    #[error("stiffness matrix is {nrows} x {ncols}, not square")]
    StiffnessNotSquare {
        /// Rows.
        nrows: usize,
        /// Columns.
        ncols: usize,
    },
    /// The stiffness matrix is not stored in full symmetric form (entry `(row, col)` differs
    /// from entry `(col, row)` or one of them is missing).
    #[error("stiffness matrix is not symmetric: K[{row}, {col}] = {value} but K[{col}, {row}] = {transposed}")]
    StiffnessNotSymmetric {
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
        /// `K[row, col]`.
        value: f64,
        /// `K[col, row]` (0 if not stored).
        transposed: f64,
    },
    /// A diagonal entry of the stiffness is negative, so it cannot be positive semi-definite.
    #[error("stiffness matrix has a negative diagonal entry K[{dof}, {dof}] = {value}")]
    NegativeDiagonal {
        /// The unknown.
        dof: usize,
        /// The diagonal value.
        value: f64,
    },
    /// A friction bound is negative.
    #[error("friction bound b[{row}] = {value} is negative")]
    NegativeFrictionBound {
        /// Interface node (constraint row).
        row: usize,
        /// The bound.
        value: f64,
    },
}

/// A sparse block of constraint rows (`B_N` or `B_T`), stored row by row (CSR).
///
/// Row `i` is a linear form `(B x)_i = sum_k values[k] x[col_idx[k]]` over the unknowns, for
/// example the normal jump `[u]_nu = (u_1 - u_2) . nu_1` at interface node `i`. Columns within
/// a row are sorted and unique; every value is finite.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintRows {
    ncols: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

impl ConstraintRows {
    /// Builds `nrows x ncols` rows from `(row, col, value)` triplets; duplicates are summed.
    ///
    /// # Errors
    /// [`ContactSystemError::RowOutOfRange`], [`ContactSystemError::ColumnOutOfRange`] or
    /// [`ContactSystemError::NonFinite`] naming the offending entry.
    pub fn try_from_triplets(
        nrows: usize,
        ncols: usize,
        triplets: &[(usize, usize, f64)],
    ) -> Result<Self, ContactSystemError> {
        const WHAT: &str = "constraint triplets";
        for (k, &(row, col, value)) in triplets.iter().enumerate() {
            if row >= nrows {
                return Err(ContactSystemError::RowOutOfRange {
                    what: WHAT,
                    row,
                    nrows,
                });
            }
            if col >= ncols {
                return Err(ContactSystemError::ColumnOutOfRange {
                    what: WHAT,
                    row,
                    col,
                    ncols,
                });
            }
            if !value.is_finite() {
                return Err(ContactSystemError::NonFinite {
                    what: WHAT,
                    index: k,
                    value,
                });
            }
        }
        let mut sorted: Vec<(usize, usize, f64)> = triplets.to_vec();
        sorted.sort_by_key(|&(row, col, _)| (row, col));
        let mut row_ptr = vec![0usize; nrows + 1];
        let mut col_idx = Vec::with_capacity(sorted.len());
        let mut values: Vec<f64> = Vec::with_capacity(sorted.len());
        let mut last: Option<(usize, usize)> = None;
        for (row, col, value) in sorted {
            if last == Some((row, col)) {
                if let Some(v) = values.last_mut() {
                    *v += value;
                }
            } else {
                col_idx.push(col);
                values.push(value);
                row_ptr[row + 1] += 1;
                last = Some((row, col));
            }
        }
        for i in 0..nrows {
            row_ptr[i + 1] += row_ptr[i];
        }
        Ok(Self {
            ncols,
            row_ptr,
            col_idx,
            values,
        })
    }

    /// Builds rows from CSR arrays. Columns within a row may come in any order but must be
    /// unique.
    ///
    /// # Errors
    /// [`ContactSystemError::MalformedRowPointer`], [`ContactSystemError::ColumnOutOfRange`]
    /// (also for a repeated column), [`ContactSystemError::NonFinite`] or
    /// [`ContactSystemError::DimensionMismatch`].
    pub fn try_from_csr(
        ncols: usize,
        row_ptr: Vec<usize>,
        col_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<Self, ContactSystemError> {
        const WHAT: &str = "constraint rows (CSR)";
        if col_idx.len() != values.len() {
            return Err(ContactSystemError::DimensionMismatch {
                what: "CSR values vs column indices",
                expected: col_idx.len(),
                actual: values.len(),
            });
        }
        if row_ptr.first() != Some(&0) {
            return Err(ContactSystemError::MalformedRowPointer {
                what: WHAT,
                reason: "must start with 0",
            });
        }
        if row_ptr.windows(2).any(|w| w[0] > w[1]) {
            return Err(ContactSystemError::MalformedRowPointer {
                what: WHAT,
                reason: "must be non-decreasing",
            });
        }
        if row_ptr.last() != Some(&col_idx.len()) {
            return Err(ContactSystemError::MalformedRowPointer {
                what: WHAT,
                reason: "last entry must equal the number of stored entries",
            });
        }
        let nrows = row_ptr.len() - 1;
        let mut triplets = Vec::with_capacity(values.len());
        for row in 0..nrows {
            let range = row_ptr[row]..row_ptr[row + 1];
            let mut cols: Vec<usize> = col_idx[range.clone()].to_vec();
            cols.sort_unstable();
            if let Some(w) = cols.windows(2).find(|w| w[0] == w[1]) {
                return Err(ContactSystemError::ColumnOutOfRange {
                    what: "constraint rows (CSR, repeated column)",
                    row,
                    col: w[0],
                    ncols,
                });
            }
            for k in range {
                triplets.push((row, col_idx[k], values[k]));
            }
        }
        Self::try_from_triplets(nrows, ncols, &triplets)
    }

    /// Number of rows (interface nodes).
    pub fn nrows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Number of columns (unknowns).
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Column indices and values of row `i` (columns sorted increasingly).
    ///
    /// # Panics
    /// If `i >= self.nrows()`.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.col_idx[range.clone()], &self.values[range])
    }

    /// `(B x)_i`, the linear form of row `i` applied to `x`.
    ///
    /// # Panics
    /// If `i >= self.nrows()` or `x.len() != self.ncols()`.
    pub fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        let (cols, vals) = self.row(i);
        cols.iter().zip(vals).map(|(&c, &v)| v * x[c]).sum()
    }

    /// `B x` for all rows.
    ///
    /// # Panics
    /// If `x.len() != self.ncols()`.
    pub fn apply(&self, x: &[f64]) -> Vec<f64> {
        assert_eq!(x.len(), self.ncols, "ConstraintRows::apply: wrong length");
        (0..self.nrows()).map(|i| self.row_dot(i, x)).collect()
    }

    /// `out += B' y`.
    ///
    /// # Panics
    /// If `y.len() != self.nrows()` or `out.len() != self.ncols()`.
    pub fn add_transpose_apply(&self, y: &[f64], out: &mut [f64]) {
        assert_eq!(
            y.len(),
            self.nrows(),
            "ConstraintRows: wrong multiplier length"
        );
        assert_eq!(out.len(), self.ncols, "ConstraintRows: wrong output length");
        for (i, &yi) in y.iter().enumerate() {
            if yi == 0.0 {
                continue;
            }
            let (cols, vals) = self.row(i);
            for (&c, &v) in cols.iter().zip(vals) {
                out[c] += v * yi;
            }
        }
    }
}

/// Tresca friction data: tangential rows `B_T`, nodal friction bounds
/// `b_i = l_i g_F(x_i) >= 0` (tributary measure times friction bound; nodal quadrature of
/// `j_h`) and the reference slip `s` from which the slip of the solve is measured: the
/// friction term is `sum_i b_i |(B_T u)_i - s_i|`. Node `i` has `t` consecutive tangential
/// rows ([`Friction::rows_per_node`]: 1 in the plane, 2 in space, the node's two tangent
/// directions), `(B_T u)_i` is the vector of them and `|.|` its Euclidean norm: in space the
/// nodal friction force lies in the disk of radius `b_i` of the tangent plane. The reference slip is zero for a problem solved from rest
/// and the tangential jump at the end of the previous load step for a step of a load history
/// (the friction functional on the increment of the tangential jump). Owns its data or borrows
/// it from a [`ContactDiscretisation`](crate::ContactDiscretisation).
#[derive(Debug, Clone, PartialEq)]
pub struct Friction<'a> {
    tangential_rows: Cow<'a, ConstraintRows>,
    bounds: Cow<'a, [f64]>,
    rows_per_node: usize,
    /// `None`: zero.
    reference_slip: Option<Cow<'a, [f64]>>,
}

impl<'a> Friction<'a> {
    /// Tangential rows (one per interface node, the same nodes and order as the normal rows)
    /// and their bounds, one per node: the plane's friction (an interval per node).
    ///
    /// # Errors
    /// [`ContactSystemError::DimensionMismatch`] if `bounds.len() != tangential_rows.nrows()`,
    /// [`ContactSystemError::NonFinite`] or [`ContactSystemError::NegativeFrictionBound`].
    pub fn try_new(
        tangential_rows: impl Into<Cow<'a, ConstraintRows>>,
        bounds: impl Into<Cow<'a, [f64]>>,
    ) -> Result<Self, ContactSystemError> {
        Self::try_with_rows_per_node(tangential_rows, bounds, 1)
    }

    /// Tangential rows, `rows_per_node` consecutive ones per interface node (the nodes in the
    /// order of the normal rows; 2 in space: the node's two orthonormal tangent directions),
    /// and one bound per node, the radius of the node's friction disk (an interval for one
    /// row per node).
    ///
    /// # Errors
    /// [`ContactSystemError::DimensionMismatch`] if `rows_per_node` is not 1 or 2 or
    /// `rows_per_node * bounds.len() != tangential_rows.nrows()`,
    /// [`ContactSystemError::NonFinite`] or [`ContactSystemError::NegativeFrictionBound`].
    pub fn try_with_rows_per_node(
        tangential_rows: impl Into<Cow<'a, ConstraintRows>>,
        bounds: impl Into<Cow<'a, [f64]>>,
        rows_per_node: usize,
    ) -> Result<Self, ContactSystemError> {
        let tangential_rows = tangential_rows.into();
        let bounds = bounds.into();
        if !(1..=2).contains(&rows_per_node) {
            return Err(ContactSystemError::DimensionMismatch {
                what: "tangential rows per node (1 or 2)",
                expected: 2,
                actual: rows_per_node,
            });
        }
        check_len(
            "tangential rows vs rows per node x friction bounds",
            rows_per_node * bounds.len(),
            tangential_rows.nrows(),
        )?;
        check_bounds(bounds.len(), &bounds)?;
        Ok(Self {
            tangential_rows,
            bounds,
            rows_per_node,
            reference_slip: None,
        })
    }

    /// The number of tangential rows of each node: 1 in the plane, 2 in space (the nodal
    /// friction force is then a vector of the tangent plane, bounded by a disk).
    pub fn rows_per_node(&self) -> usize {
        self.rows_per_node
    }

    /// The number of interface nodes (friction bounds).
    pub fn n_nodes(&self) -> usize {
        self.bounds.len()
    }

    /// The same friction data with the reference slip `s` (one value per tangential row): the
    /// friction term becomes `sum_i b_i |(B_T u)_i - s_i|`.
    ///
    /// # Errors
    /// [`ContactSystemError::DimensionMismatch`] if `slip.len()` is not the number of
    /// tangential rows, [`ContactSystemError::NonFinite`] for a value that is not finite.
    pub fn with_reference_slip(
        mut self,
        slip: impl Into<Cow<'a, [f64]>>,
    ) -> Result<Self, ContactSystemError> {
        let slip = slip.into();
        check_len(
            "reference slip vs tangential rows",
            self.tangential_rows.nrows(),
            slip.len(),
        )?;
        check_finite("reference slip", &slip)?;
        self.reference_slip = slip.iter().any(|&s| s != 0.0).then_some(slip);
        Ok(self)
    }

    /// The tangential rows `B_T`: `(B_T u)_i = [u]_1tau` at node `i`.
    pub fn tangential_rows(&self) -> &ConstraintRows {
        &self.tangential_rows
    }

    /// The nodal friction bounds `b_i` (one per node: the disk radius in space).
    pub fn bounds(&self) -> &[f64] {
        &self.bounds
    }

    /// The reference slip `s` (`None` when it is zero, the problem from rest).
    pub fn reference_slip(&self) -> Option<&[f64]> {
        self.reference_slip.as_deref()
    }

    /// The slips `(B_T u)_i - s_i` of the displacement `u`: the tangential jump since the
    /// reference slip.
    pub fn slip(&self, u: &[f64]) -> Vec<f64> {
        let mut slip = self.tangential_rows.apply(u);
        self.subtract_reference(&mut slip);
        slip
    }

    /// `values_i -= s_i` (nothing when the reference slip is zero).
    pub(crate) fn subtract_reference(&self, values: &mut [f64]) {
        if let Some(s) = &self.reference_slip {
            for (v, s) in values.iter_mut().zip(s.iter()) {
                *v -= s;
            }
        }
    }

    /// The reference slip as a vector, zeros when there is none.
    pub(crate) fn reference_or_zero(&self) -> Cow<'_, [f64]> {
        match &self.reference_slip {
            Some(s) => Cow::Borrowed(&s[..]),
            None => Cow::Owned(vec![0.0; self.tangential_rows.nrows()]),
        }
    }
}

fn check_bounds(nrows: usize, bounds: &[f64]) -> Result<(), ContactSystemError> {
    if bounds.len() != nrows {
        return Err(ContactSystemError::DimensionMismatch {
            what: "friction bounds vs tangential rows",
            expected: nrows,
            actual: bounds.len(),
        });
    }
    for (row, &value) in bounds.iter().enumerate() {
        if !value.is_finite() {
            return Err(ContactSystemError::NonFinite {
                what: "friction bounds",
                index: row,
                value,
            });
        }
        if value < 0.0 {
            return Err(ContactSystemError::NegativeFrictionBound { row, value });
        }
    }
    Ok(())
}

impl<'a> From<&'a ConstraintRows> for Cow<'a, ConstraintRows> {
    fn from(rows: &'a ConstraintRows) -> Self {
        Cow::Borrowed(rows)
    }
}

impl From<ConstraintRows> for Cow<'_, ConstraintRows> {
    fn from(rows: ConstraintRows) -> Self {
        Cow::Owned(rows)
    }
}

/// The identity of a contact system's structure: the sparsity patterns of `K` and of the
/// constraint rows and the values of the rows (geometry). Two systems with the same identity
/// differ at most in the values of `K`, the load, the gaps and the friction bounds, so a solver
/// may keep its symbolic work (orderings, symbolic factorisations, workspaces) from one to the
/// other. Every [`ContactSystem::try_new`] and every
/// [`ContactDiscretisation`](crate::ContactDiscretisation) draws a fresh one; systems derived
/// from a system ([`ContactSystem::with_load`], ...) or from one discretisation share it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PatternId(u64);

impl PatternId {
    /// A new identity, distinct from every other drawn in this process.
    pub fn fresh() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        Self(NEXT.fetch_add(1, AtomicOrdering::Relaxed))
    }
}

/// One diagonal block of the stiffness: a body's reduced stiffness and the first unknown of the
/// body in the combined numbering.
#[derive(Debug, Clone)]
pub struct StiffnessBlock<'a> {
    offset: usize,
    matrix: Cow<'a, SparseColMat<usize, f64>>,
    /// Its diagonal, when the owner of the matrix keeps it (a discretisation: computed once
    /// per stiffness, not once per system), and its values were checked finite there.
    checked_diagonal: Option<&'a [f64]>,
}

impl StiffnessBlock<'_> {
    /// First unknown of the block.
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// The block (full symmetric storage).
    pub fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.matrix.as_ref().as_ref()
    }
}

/// The discrete contact problem (P1^h, or P2^h with nodal friction quadrature):
///
/// ```text
/// frictionless:  min 1/2 u'Ku - f'u                                s.t.  B_N u <= g
/// Tresca:        min 1/2 u'Ku - f'u + sum_i b_i |(B_T u)_i - s_i|   s.t.  B_N u <= g
/// ```
///
/// with the reference slip `s` of [`Friction`] (zero from rest); in space `(B_T u)_i` is the
/// node's tangential jump, a vector of its tangent plane, and `|.|` the Euclidean norm.
///
/// `K` is symmetric positive semi-definite, block diagonal (one block per body, full symmetric
/// storage); a singular `K` is allowed when the constraints (or friction) hold the rigid modes.
/// A system owns its data ([`ContactSystem::try_new`]) or borrows what does not change from a
/// [`ContactDiscretisation`](crate::ContactDiscretisation) (stiffness blocks, rows), so a
/// Coulomb fixed point or a load step copies no matrix. Its [`PatternId`] tells solvers what
/// symbolic work they may keep.
#[derive(Debug, Clone)]
pub struct ContactSystem<'a> {
    pattern: PatternId,
    stiffness_version: u64,
    n: usize,
    blocks: Vec<StiffnessBlock<'a>>,
    load: Cow<'a, [f64]>,
    normal_rows: Cow<'a, ConstraintRows>,
    gap: Cow<'a, [f64]>,
    friction: Option<Friction<'a>>,
}

impl ContactSystem<'static> {
    /// Validates and assembles the problem from owned data (one stiffness block); the system
    /// gets a fresh [`PatternId`].
    ///
    /// # Errors
    /// A [`ContactSystemError`] naming the inconsistent quantity: non-square, non-symmetric
    /// (relative tolerance `1e-12` of the largest entry) or non-finite stiffness, a negative
    /// diagonal entry, wrong vector lengths, non-finite load or gap, rows whose column count
    /// differs from the number of unknowns, tangential rows that do not pair one-to-one with
    /// the normal rows.
    pub fn try_new(
        stiffness: SparseColMat<usize, f64>,
        load: Vec<f64>,
        normal_rows: ConstraintRows,
        gap: Vec<f64>,
        friction: Option<Friction<'static>>,
    ) -> Result<Self, ContactSystemError> {
        let (nrows, ncols) = (stiffness.nrows(), stiffness.ncols());
        if nrows != ncols {
            return Err(ContactSystemError::StiffnessNotSquare { nrows, ncols });
        }
        check_stiffness(stiffness.as_ref())?;
        Self::try_from_parts(
            PatternId::fresh(),
            0,
            vec![StiffnessBlock {
                offset: 0,
                matrix: Cow::Owned(stiffness),
                checked_diagonal: None,
            }],
            Cow::Owned(load),
            Cow::Owned(normal_rows),
            Cow::Owned(gap),
            friction,
        )
    }
}

impl<'a> ContactSystem<'a> {
    /// A system from borrowed stiffness blocks `(offset, block)` whose symmetry the caller
    /// guarantees (assembled stiffnesses); sizes and finiteness are checked.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn try_from_parts(
        pattern: PatternId,
        stiffness_version: u64,
        blocks: Vec<StiffnessBlock<'a>>,
        load: Cow<'a, [f64]>,
        normal_rows: Cow<'a, ConstraintRows>,
        gap: Cow<'a, [f64]>,
        friction: Option<Friction<'a>>,
    ) -> Result<Self, ContactSystemError> {
        let mut n = 0;
        for block in &blocks {
            let m = block.matrix();
            if m.nrows() != m.ncols() {
                return Err(ContactSystemError::StiffnessNotSquare {
                    nrows: m.nrows(),
                    ncols: m.ncols(),
                });
            }
            check_len("stiffness block offset", n, block.offset)?;
            if block.checked_diagonal.is_none() {
                check_finite("stiffness values", m.val())?;
            }
            n += m.ncols();
        }
        check_len("load", n, load.len())?;
        check_finite("load", &load)?;
        check_len("normal rows: columns", n, normal_rows.ncols())?;
        check_len("gap vs normal rows", normal_rows.nrows(), gap.len())?;
        check_finite("gap", &gap)?;
        if let Some(fr) = &friction {
            check_len("tangential rows: columns", n, fr.tangential_rows.ncols())?;
            check_len(
                "friction bounds (one per node) vs normal rows",
                normal_rows.nrows(),
                fr.n_nodes(),
            )?;
        }
        Ok(Self {
            pattern,
            stiffness_version,
            n,
            blocks,
            load,
            normal_rows,
            gap,
            friction,
        })
    }

    /// The same structure with another load `f` (same [`PatternId`]).
    ///
    /// # Errors
    /// A load of the wrong length or with a non-finite entry.
    pub fn with_load(mut self, load: Vec<f64>) -> Result<Self, ContactSystemError> {
        check_len("load", self.n, load.len())?;
        check_finite("load", &load)?;
        self.load = Cow::Owned(load);
        Ok(self)
    }

    /// The same structure with other gaps `g` (same [`PatternId`]).
    ///
    /// # Errors
    /// Gaps of the wrong length or with a non-finite entry.
    pub fn with_gap(mut self, gap: Vec<f64>) -> Result<Self, ContactSystemError> {
        check_len("gap vs normal rows", self.normal_rows.nrows(), gap.len())?;
        check_finite("gap", &gap)?;
        self.gap = Cow::Owned(gap);
        Ok(self)
    }

    /// The same structure with other friction bounds `b` (same [`PatternId`]).
    ///
    /// # Errors
    /// A frictionless system, bounds of the wrong length, negative or not finite.
    pub fn with_friction_bounds(mut self, bounds: Vec<f64>) -> Result<Self, ContactSystemError> {
        let Some(friction) = &mut self.friction else {
            return Err(ContactSystemError::DimensionMismatch {
                what: "friction bounds of a frictionless system",
                expected: 0,
                actual: bounds.len(),
            });
        };
        check_bounds(friction.n_nodes(), &bounds)?;
        friction.bounds = Cow::Owned(bounds);
        Ok(self)
    }

    /// The identity of the structure (see [`PatternId`]).
    pub fn pattern(&self) -> PatternId {
        self.pattern
    }

    /// A number that changes whenever the values of `K` change under the same [`PatternId`]
    /// (a refilled discretisation).
    pub fn stiffness_version(&self) -> u64 {
        self.stiffness_version
    }

    /// Number of unknowns `n`.
    pub fn n_dofs(&self) -> usize {
        self.n
    }

    /// Number of contact constraints `m` (interface nodes).
    pub fn n_constraints(&self) -> usize {
        self.gap.len()
    }

    /// The diagonal blocks of `K` (one per body, full symmetric storage).
    pub fn stiffness_blocks(&self) -> &[StiffnessBlock<'a>] {
        &self.blocks
    }

    /// Every stored entry `(row, column, value)` of `K` in the combined numbering, column by
    /// column.
    pub fn stiffness_entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.blocks.iter().flat_map(|block| {
            let k = block.matrix();
            let offset = block.offset;
            (0..k.ncols()).flat_map(move |j| {
                let range = k.col_range(j);
                k.row_idx()[range.clone()]
                    .iter()
                    .zip(&k.val()[range])
                    .map(move |(&i, &v)| (i + offset, j + offset, v))
            })
        })
    }

    /// The load `f`.
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The normal rows `B_N`: `(B_N u)_i = [u]_nu` at interface node `i`.
    pub fn normal_rows(&self) -> &ConstraintRows {
        &self.normal_rows
    }

    /// The gaps `g`: the constraint is `B_N u <= g`.
    pub fn gap(&self) -> &[f64] {
        &self.gap
    }

    /// The length of a tangential force vector of this system: the number of tangential rows
    /// (`D - 1` per node), or `m` (zeros) for a frictionless system.
    pub fn n_tangential(&self) -> usize {
        self.friction
            .as_ref()
            .map_or(self.gap.len(), |f| f.tangential_rows.nrows())
    }

    /// Tresca friction data, `None` for frictionless contact.
    pub fn friction(&self) -> Option<&Friction<'a>> {
        self.friction.as_ref()
    }

    /// `K x` (uses the full symmetric storage).
    ///
    /// # Panics
    /// If `x.len() != self.n_dofs()`.
    pub fn stiffness_apply(&self, x: &[f64]) -> Vec<f64> {
        assert_eq!(
            x.len(),
            self.n,
            "ContactSystem::stiffness_apply: wrong length"
        );
        let mut y = vec![0.0; self.n];
        self.stiffness_apply_with(x, &mut y, |v| v);
        y
    }

    /// `y += g(K) x` entry by entry (`g(v) = |v|` gives `|K| x`): the hot loop of the Newton
    /// solvers, over plain slices block by block.
    /// `(K x, |K||x|)` in one pass over `K`.
    pub(crate) fn stiffness_apply_and_magnitude(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (mut y, mut magnitude) = (vec![0.0; self.n], vec![0.0; self.n]);
        for block in &self.blocks {
            let k = block.matrix();
            let (rows, values) = (k.row_idx(), k.val());
            let (x, y, magnitude) = (
                &x[block.offset..],
                &mut y[block.offset..],
                &mut magnitude[block.offset..],
            );
            for (j, &xj) in x.iter().take(k.ncols()).enumerate() {
                if xj == 0.0 {
                    continue;
                }
                let abs_xj = xj.abs();
                for p in k.col_range(j) {
                    let (i, v) = (rows[p], values[p]);
                    y[i] += v * xj;
                    magnitude[i] += v.abs() * abs_xj;
                }
            }
        }
        (y, magnitude)
    }

    pub(crate) fn stiffness_apply_with(&self, x: &[f64], y: &mut [f64], g: impl Fn(f64) -> f64) {
        for block in &self.blocks {
            let k = block.matrix();
            let (rows, values) = (k.row_idx(), k.val());
            let (x, y) = (&x[block.offset..], &mut y[block.offset..]);
            for (j, &xj) in x.iter().take(k.ncols()).enumerate() {
                if xj == 0.0 {
                    continue;
                }
                for p in k.col_range(j) {
                    y[rows[p]] += g(values[p]) * xj;
                }
            }
        }
    }

    /// The diagonal of `K` (duplicates of unsorted storage summed).
    pub fn stiffness_diagonal(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.n];
        for block in &self.blocks {
            let range = block.offset..block.offset + block.matrix().ncols();
            match block.checked_diagonal {
                Some(diagonal) => d[range].copy_from_slice(diagonal),
                None => d[range].copy_from_slice(&matrix_diagonal(block.matrix())),
            }
        }
        d
    }

    /// Largest diagonal entry of `K` over the unknowns that appear in a normal or tangential
    /// row (the "constrained DOFs"); 0 if there are none.
    pub fn max_constrained_diagonal(&self) -> f64 {
        self.constrained_diagonals()
            .into_iter()
            .fold(0.0f64, f64::max)
    }

    /// The constrained stiffness of the softest body: the smallest, over the stiffness blocks
    /// with a constrained unknown, of the block's largest constrained diagonal entry of `K`
    /// (0 if no unknown is constrained). A contact row is as stiff as the softer of the two
    /// bodies it joins: penalties and augmentations relative to this keep a stiffness
    /// contrast out of the round-off regime.
    pub fn softest_constrained_diagonal(&self) -> f64 {
        let softest = self
            .constrained_diagonals()
            .into_iter()
            .filter(|&d| d > 0.0)
            .fold(f64::INFINITY, f64::min);
        if softest.is_finite() {
            softest
        } else {
            0.0
        }
    }

    /// The largest constrained diagonal entry of every stiffness block (0 for a block without
    /// a constrained unknown).
    fn constrained_diagonals(&self) -> Vec<f64> {
        let mut constrained = vec![false; self.n_dofs()];
        let mut mark = |rows: &ConstraintRows| {
            for i in 0..rows.nrows() {
                for &c in rows.row(i).0 {
                    constrained[c] = true;
                }
            }
        };
        mark(&self.normal_rows);
        if let Some(fr) = &self.friction {
            mark(&fr.tangential_rows);
        }
        let diagonal = self.stiffness_diagonal();
        self.blocks
            .iter()
            .map(|block| {
                let range = block.offset..block.offset + block.matrix().ncols();
                range
                    .filter(|&j| constrained[j])
                    .fold(0.0f64, |max, j| max.max(diagonal[j]))
            })
            .collect()
    }
}

/// A stiffness block borrowed from an assembled system.
#[cfg(test)]
pub(crate) fn borrowed_block(
    offset: usize,
    matrix: &SparseColMat<usize, f64>,
) -> StiffnessBlock<'_> {
    StiffnessBlock {
        offset,
        matrix: Cow::Borrowed(matrix),
        checked_diagonal: None,
    }
}

/// A block borrowed from an owner that checked its values finite and keeps its diagonal
/// `diagonal`: systems made from it skip both the check and the diagonal's computation.
pub(crate) fn checked_block<'a>(
    offset: usize,
    matrix: &'a SparseColMat<usize, f64>,
    diagonal: &'a [f64],
) -> StiffnessBlock<'a> {
    debug_assert_eq!(diagonal.len(), matrix.ncols());
    StiffnessBlock {
        offset,
        matrix: Cow::Borrowed(matrix),
        checked_diagonal: Some(diagonal),
    }
}

/// The diagonal of a sparse matrix (duplicates of unsorted storage summed), by bisection in
/// columns whose rows are sorted.
pub(crate) fn matrix_diagonal(k: SparseColMatRef<'_, usize, f64>) -> Vec<f64> {
    let (rows, values) = (k.row_idx(), k.val());
    (0..k.ncols())
        .into_par_iter()
        .map(|j| {
            let range = k.col_range(j);
            let column = &rows[range.clone()];
            if column.windows(2).all(|w| w[0] < w[1]) {
                column
                    .binary_search(&j)
                    .map_or(0.0, |p| values[range.start + p])
            } else {
                column
                    .iter()
                    .zip(&values[range])
                    .filter(|(&i, _)| i == j)
                    .map(|(_, v)| v)
                    .sum()
            }
        })
        .collect()
}

/// The entry `(i, j)` of a sparse matrix (`0` outside its pattern), by bisection when its
/// columns' rows are `sorted`, else by a scan that sums the copies unsorted storage may hold.
pub(crate) fn matrix_entry(
    k: SparseColMatRef<'_, usize, f64>,
    i: usize,
    j: usize,
    sorted: bool,
) -> f64 {
    let range = k.col_range(j);
    let (rows, values) = (&k.row_idx()[range.clone()], &k.val()[range]);
    if sorted {
        rows.binary_search(&i).map_or(0.0, |p| values[p])
    } else {
        // Unsorted storage may repeat an entry: sum the copies.
        rows.iter()
            .zip(values)
            .filter(|(&r, _)| r == i)
            .map(|(_, &v)| v)
            .sum()
    }
}

fn check_len(what: &'static str, expected: usize, actual: usize) -> Result<(), ContactSystemError> {
    if expected == actual {
        Ok(())
    } else {
        Err(ContactSystemError::DimensionMismatch {
            what,
            expected,
            actual,
        })
    }
}

/// `v` finite, or the error naming `what` and its first non-finite value.
pub(crate) fn check_finite(what: &'static str, v: &[f64]) -> Result<(), ContactSystemError> {
    match first_non_finite(v) {
        None => Ok(()),
        Some(index) => Err(ContactSystemError::NonFinite {
            what,
            index,
            value: v[index],
        }),
    }
}

/// The index of the first non-finite value of `values`: blocks checked on every thread
/// (without a branch per value), the first failing block searched.
fn first_non_finite(values: &[f64]) -> Option<usize> {
    const BLOCK: usize = 1 << 14;
    let block = values
        .par_chunks(BLOCK)
        .position_first(|block| block.iter().fold(false, |bad, v| bad | !v.is_finite()))?;
    let start = block * BLOCK;
    values[start..]
        .iter()
        .position(|v| !v.is_finite())
        .map(|k| start + k)
}

/// Finite entries, non-negative diagonal, symmetric pattern and values.
fn check_stiffness(k: SparseColMatRef<'_, usize, f64>) -> Result<(), ContactSystemError> {
    check_finite("stiffness values", k.val())?;
    let scale = k.val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = 1e-12 * scale;
    let sorted =
        (0..k.ncols()).all(|j| k.row_idx()[k.col_range(j)].windows(2).all(|w| w[0] < w[1]));
    let entry = |i: usize, j: usize| matrix_entry(k, i, j, sorted);
    for j in 0..k.ncols() {
        let range = k.col_range(j);
        for &i in &k.row_idx()[range] {
            let value = entry(i, j);
            if i == j {
                if value < 0.0 {
                    return Err(ContactSystemError::NegativeDiagonal { dof: j, value });
                }
            } else {
                let transposed = entry(j, i);
                if (value - transposed).abs() > tol {
                    return Err(ContactSystemError::StiffnessNotSymmetric {
                        row: i,
                        col: j,
                        value,
                        transposed,
                    });
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::first_non_finite;

    #[test]
    fn the_first_non_finite_value_is_found_in_any_block() {
        let mut values = vec![1.0; 3 * (1 << 14) + 7];
        assert_eq!(first_non_finite(&values), None);
        assert_eq!(first_non_finite(&[]), None);
        // Each new value lies before the earlier ones: it is the first.
        let last = values.len() - 1;
        for (at, bad) in [
            (last, f64::NAN),
            ((2 << 14) + 3, f64::NEG_INFINITY),
            (1 << 14, f64::INFINITY),
            (5, f64::NAN),
        ] {
            values[at] = bad;
            assert_eq!(first_non_finite(&values), Some(at));
        }
    }
}
