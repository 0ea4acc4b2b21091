//! The Newton matrix `K + sum_r w_r b_r b_r' + diag(s)` of the penalty method on a fixed
//! pattern: symbolic analysis (AMD ordering) once on the pattern of
//! `K + B_N'B_N + B_T'B_T + I`, then for every Newton step only the values are refilled and
//! factorised (faer sparse Cholesky, low-level API with explicit parallelism).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::system::{ConstraintRows, ContactSystem};

/// Entries `(slot, coefficient)` of `b_r b_r'` (upper triangle) for each constraint row `r`.
#[derive(Debug, Clone)]
struct RowProducts {
    ptr: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl RowProducts {
    fn new(rows: &ConstraintRows, slot: &impl Fn(usize, usize) -> usize) -> Self {
        let mut ptr = vec![0];
        let mut entries = Vec::new();
        for r in 0..rows.nrows() {
            let (cols, vals) = rows.row(r);
            for a in 0..cols.len() {
                for b in a..cols.len() {
                    // Columns are sorted: cols[a] <= cols[b] is an upper-triangle entry.
                    entries.push((slot(cols[a], cols[b]), vals[a] * vals[b]));
                }
            }
            ptr.push(entries.len());
        }
        Self { ptr, entries }
    }

    fn add_weighted(&self, weights: &[f64], values: &mut [f64]) {
        for (r, &w) in weights.iter().enumerate() {
            if w == 0.0 {
                continue;
            }
            for &(slot, coef) in &self.entries[self.ptr[r]..self.ptr[r + 1]] {
                values[slot] += w * coef;
            }
        }
    }
}

/// Copy of the patterns the analysis was made for, to decide whether it can be reused.
#[derive(Debug, Clone, PartialEq)]
struct PatternKey {
    n: usize,
    k_pattern: Vec<(usize, usize)>,
    normal: Vec<Vec<usize>>,
    tangential: Option<Vec<Vec<usize>>>,
}

impl PatternKey {
    fn of(system: &ContactSystem) -> Self {
        let k = system.stiffness().as_ref();
        let k_pattern = (0..k.ncols())
            .flat_map(|j| k.row_idx()[k.col_range(j)].iter().map(move |&i| (i, j)))
            .collect();
        let rows = |b: &ConstraintRows| (0..b.nrows()).map(|r| b.row(r).0.to_vec()).collect();
        Self {
            n: system.n_dofs(),
            k_pattern,
            normal: rows(system.normal_rows()),
            tangential: system.friction().map(|f| rows(f.tangential_rows())),
        }
    }
}

/// Symmetric positive definite Newton matrix with a reusable symbolic Cholesky analysis.
pub(crate) struct NewtonMatrix {
    key: PatternKey,
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// `(slot, index into K's values)` for the upper-triangle entries of `K`.
    k_slots: Vec<(usize, usize)>,
    normal: RowProducts,
    tangential: Option<RowProducts>,
    diag_slots: Vec<usize>,
    values: Vec<f64>,
    factor: Vec<f64>,
    buffer: MemBuffer,
    par: Par,
}

impl std::fmt::Debug for NewtonMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NewtonMatrix")
            .field("n", &self.key.n)
            .field("pattern_nnz", &self.values.len())
            .field("factor_nnz", &self.factor.len())
            .field("par", &self.par)
            .finish_non_exhaustive()
    }
}

impl NewtonMatrix {
    /// Analyses the pattern of `K + B_N'B_N + B_T'B_T + I` (upper triangle).
    pub(crate) fn try_new(system: &ContactSystem, par: Par) -> Result<Self, String> {
        let n = system.n_dofs();
        let k = system.stiffness().as_ref();
        let mut pairs: Vec<(usize, usize)> = (0..n).map(|j| (j, j)).collect();
        for j in 0..n {
            pairs.extend(
                k.row_idx()[k.col_range(j)]
                    .iter()
                    .filter(|&&i| i <= j)
                    .map(|&i| (i, j)),
            );
        }
        let mut add_rows = |rows: &ConstraintRows| {
            for r in 0..rows.nrows() {
                let cols = rows.row(r).0;
                for a in 0..cols.len() {
                    pairs.extend(cols[a..].iter().map(|&cb| (cols[a], cb)));
                }
            }
        };
        add_rows(system.normal_rows());
        if let Some(fr) = system.friction() {
            add_rows(fr.tangential_rows());
        }
        pairs.sort_unstable_by_key(|&(i, j)| (j, i));
        pairs.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(_, j) in &pairs {
            col_ptr[j + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let row_idx: Vec<usize> = pairs.iter().map(|&(i, _)| i).collect();
        let slot = |i: usize, j: usize| -> usize {
            let start = col_ptr[j];
            // The pair was inserted above, so the search cannot fail.
            start + row_idx[start..col_ptr[j + 1]].partition_point(|&r| r < i)
        };
        let mut k_slots = Vec::new();
        for j in 0..n {
            let range = k.col_range(j);
            for (e, &i) in range.clone().zip(&k.row_idx()[range]) {
                if i <= j {
                    k_slots.push((slot(i, j), e));
                }
            }
        }
        let normal = RowProducts::new(system.normal_rows(), &slot);
        let tangential = system
            .friction()
            .map(|fr| RowProducts::new(fr.tangential_rows(), &slot));
        let diag_slots = (0..n).map(|j| slot(j, j)).collect();
        let nnz = row_idx.len();
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| format!("symbolic Cholesky analysis: {e:?}"))?;
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let buffer = MemBuffer::try_new(scratch).map_err(|e| format!("workspace: {e:?}"))?;
        let factor = vec![0.0; symbolic.len_val()];
        Ok(Self {
            key: PatternKey::of(system),
            pattern,
            symbolic,
            k_slots,
            normal,
            tangential,
            diag_slots,
            values: vec![0.0; nnz],
            factor,
            buffer,
            par,
        })
    }

    /// Whether the analysis was made for the patterns of `system` (and parallelism `par`).
    pub(crate) fn fits(&self, system: &ContactSystem, par: Par) -> bool {
        self.par == par && self.key == PatternKey::of(system)
    }

    /// Sets the values to `K + sum_r wn_r bn_r bn_r' + sum_r wt_r bt_r bt_r' + diag(shift)`
    /// and factorises. Returns `false` if the matrix is not numerically positive definite.
    pub(crate) fn refill_and_factorise(
        &mut self,
        system: &ContactSystem,
        normal_weights: &[f64],
        tangential_weights: &[f64],
        shift: &[f64],
    ) -> bool {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        let kval = system.stiffness().as_ref().val();
        for &(slot, e) in &self.k_slots {
            self.values[slot] += kval[e];
        }
        self.normal.add_weighted(normal_weights, &mut self.values);
        if let Some(t) = &self.tangential {
            t.add_weighted(tangential_weights, &mut self.values);
        }
        for (&slot, &s) in self.diag_slots.iter().zip(shift) {
            self.values[slot] += s;
        }
        let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        self.symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                matrix,
                Side::Upper,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.buffer),
                Default::default(),
            )
            .is_ok()
    }

    /// Solves with the last factorisation, in place.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.buffer),
        );
    }
}

/// Relative diagonal shift `delta` used when a Newton matrix is singular.
const SHIFT: f64 = 1e-10;

/// A direction along which the curvature `d'Kd` is below this fraction of `d'Dd` is taken as a
/// free (rigid) mode of `K`.
pub(crate) const FREE_MODE_CURVATURE: f64 = 1e-10;

/// Guards a Newton iteration against singular matrices: the metric
/// `D = diag(K + eps_N B_N'B_N + eps_T B_T'B_T)` (zeros, i.e. unknowns nothing touches,
/// replaced by `max D`) and the shift `delta D` used when `H` itself is not definite.
#[derive(Debug, Clone)]
pub(crate) struct SingularGuard {
    metric: Vec<f64>,
    shift: Vec<f64>,
    no_shift: Vec<f64>,
}

impl SingularGuard {
    pub(crate) fn new(system: &ContactSystem, eps_n: f64, eps_t: f64) -> Self {
        let mut d = system.stiffness_diagonal();
        let mut add = |rows: &ConstraintRows, eps: f64| {
            for r in 0..rows.nrows() {
                let (cols, vals) = rows.row(r);
                for (&c, &v) in cols.iter().zip(vals) {
                    d[c] += eps * v * v;
                }
            }
        };
        add(system.normal_rows(), eps_n);
        if let Some(f) = system.friction() {
            add(f.tangential_rows(), eps_t);
        }
        let max = d.iter().fold(0.0f64, |a, &x| a.max(x));
        let floor = if max > 0.0 { max } else { 1.0 };
        let metric: Vec<f64> = d.iter().map(|&x| if x > 0.0 { x } else { floor }).collect();
        let shift = metric.iter().map(|&x| SHIFT * x).collect();
        let no_shift = vec![0.0; metric.len()];
        Self {
            metric,
            shift,
            no_shift,
        }
    }

    /// `d'Dd`.
    pub(crate) fn size(&self, d: &[f64]) -> f64 {
        d.iter().zip(&self.metric).map(|(x, w)| w * x * x).sum()
    }

    /// Factorises `K + sum wn bn bn' + sum wt bt bt'`, or, if that is not definite, the same
    /// plus `delta D`. Returns the number of factorisations done and whether the shift was
    /// needed, or `None` if even the shifted matrix is not definite (`K` indefinite).
    pub(crate) fn factorise(
        &self,
        matrix: &mut NewtonMatrix,
        system: &ContactSystem,
        normal_weights: &[f64],
        tangential_weights: &[f64],
    ) -> Option<(usize, bool)> {
        if matrix.refill_and_factorise(system, normal_weights, tangential_weights, &self.no_shift) {
            Some((1, false))
        } else if matrix.refill_and_factorise(
            system,
            normal_weights,
            tangential_weights,
            &self.shift,
        ) {
            Some((2, true))
        } else {
            None
        }
    }

    /// After a shifted factorisation, purifies the free mode that dominates `d` by one inverse
    /// iteration and returns it (or its opposite) if the energy decreases without bound along
    /// it: `K mode = 0` (relative to `D`), `B_N mode <= 0` (no penetration grows) and load
    /// along it larger than the friction capacity `sum_i b_i |(B_T mode)_i|`.
    pub(crate) fn free_mode(
        &self,
        matrix: &mut NewtonMatrix,
        system: &ContactSystem,
        d: &[f64],
    ) -> Option<Vec<f64>> {
        let mut mode: Vec<f64> = d.iter().zip(&self.metric).map(|(x, w)| w * x).collect();
        matrix.solve_in_place(&mut mode);
        let km = system.stiffness_apply(&mode);
        let curvature: f64 = mode.iter().zip(&km).map(|(a, b)| a * b).sum();
        let size = self.size(&mode);
        if size <= 0.0 || size.is_nan() || curvature > FREE_MODE_CURVATURE * size {
            return None;
        }
        let e = system.normal_rows().apply(&mode);
        let tol = 1e-8 * mode.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let capacity: f64 = system.friction().map_or(0.0, |f| {
            f.tangential_rows()
                .apply(&mode)
                .iter()
                .zip(f.bounds())
                .map(|(w, b)| b * w.abs())
                .sum()
        });
        let load: f64 = system.load().iter().zip(&mode).map(|(f, x)| f * x).sum();
        for sign in [1.0, -1.0] {
            if e.iter().all(|&ei| sign * ei <= tol) && sign * load > capacity {
                return Some(mode.iter().map(|x| sign * x).collect());
            }
        }
        None
    }
}
