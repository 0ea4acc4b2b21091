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

use std::time::Instant;

use super::report::WorkCounters;
use super::system::{ConstraintRows, ContactSystem, PatternId};

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

/// Symmetric positive definite Newton matrix with a reusable symbolic Cholesky analysis, made
/// for one structure ([`PatternId`] and the presence of tangential rows).
pub(crate) struct NewtonMatrix {
    pattern_id: PatternId,
    has_friction: bool,
    n: usize,
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// For every stored entry of `K` (in the order of [`ContactSystem::stiffness_entries`]) its
    /// slot in the upper triangle, `None` for the lower triangle.
    k_slots: Vec<Option<usize>>,
    normal: RowProducts,
    tangential: Option<RowProducts>,
    diag_slots: Vec<usize>,
    values: Vec<f64>,
    factor: Vec<f64>,
    buffer: MemBuffer,
    par: Par,
    work: WorkCounters,
}

impl std::fmt::Debug for NewtonMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NewtonMatrix")
            .field("n", &self.n)
            .field("pattern_nnz", &self.values.len())
            .field("factor_nnz", &self.factor.len())
            .field("par", &self.par)
            .finish_non_exhaustive()
    }
}

impl NewtonMatrix {
    /// Analyses the pattern of `K + B_N'B_N + B_T'B_T + I` (upper triangle).
    pub(crate) fn try_new(system: &ContactSystem<'_>, par: Par) -> Result<Self, String> {
        let start = Instant::now();
        let n = system.n_dofs();
        let mut pairs: Vec<(usize, usize)> = (0..n).map(|j| (j, j)).collect();
        pairs.extend(
            system
                .stiffness_entries()
                .filter(|&(i, j, _)| i <= j)
                .map(|(i, j, _)| (i, j)),
        );
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
        let k_slots = system
            .stiffness_entries()
            .map(|(i, j, _)| (i <= j).then(|| slot(i, j)))
            .collect();
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
        .map_err(|e| format!("symbolic Cholesky analysis: {e}"))?;
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let buffer = MemBuffer::try_new(scratch).map_err(|e| format!("workspace: {e}"))?;
        let factor = vec![0.0; symbolic.len_val()];
        let mut work = WorkCounters {
            symbolic_analyses: 1,
            ..WorkCounters::default()
        };
        work.times.symbolic = start.elapsed();
        Ok(Self {
            pattern_id: system.pattern(),
            has_friction: system.friction().is_some(),
            n,
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
            work,
        })
    }

    /// The matrix kept in `slot` if it was made for the structure of `system` (and
    /// parallelism `par`), else a new analysis.
    pub(crate) fn reuse_or_analyse<'m>(
        slot: &'m mut Option<NewtonMatrix>,
        system: &ContactSystem<'_>,
        par: Par,
    ) -> Result<&'m mut NewtonMatrix, String> {
        let fits = slot.as_ref().is_some_and(|m| {
            m.par == par
                && m.pattern_id == system.pattern()
                && m.has_friction == system.friction().is_some()
        });
        if !fits {
            *slot = Some(Self::try_new(system, par)?);
        }
        Ok(slot.as_mut().expect("filled above"))
    }

    /// The work counted since the last call (symbolic analysis, factorisations, solves).
    pub(crate) fn take_work(&mut self) -> WorkCounters {
        std::mem::take(&mut self.work)
    }

    /// Sets the values to `K + sum_r wn_r bn_r bn_r' + sum_r wt_r bt_r bt_r' + diag(shift)`
    /// and factorises. Returns `false` if the matrix is not numerically positive definite.
    pub(crate) fn refill_and_factorise(
        &mut self,
        system: &ContactSystem<'_>,
        normal_weights: &[f64],
        tangential_weights: &[f64],
        shift: &[f64],
    ) -> bool {
        let start = Instant::now();
        self.values.iter_mut().for_each(|v| *v = 0.0);
        // The entries in the order of `stiffness_entries`, read from plain slices.
        let mut slots = self.k_slots.iter();
        for block in system.stiffness_blocks() {
            let k = block.matrix();
            for j in 0..k.ncols() {
                for (&v, slot) in k.val()[k.col_range(j)].iter().zip(&mut slots) {
                    if let Some(slot) = *slot {
                        self.values[slot] += v;
                    }
                }
            }
        }
        self.normal.add_weighted(normal_weights, &mut self.values);
        if let Some(t) = &self.tangential {
            t.add_weighted(tangential_weights, &mut self.values);
        }
        for (&slot, &s) in self.diag_slots.iter().zip(shift) {
            self.values[slot] += s;
        }
        let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        let ok = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                matrix,
                Side::Upper,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.buffer),
                Default::default(),
            )
            .is_ok();
        self.work.numeric_factorisations += 1;
        self.work.times.numeric += start.elapsed();
        ok
    }

    /// Solves with the last factorisation, in place.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let start = Instant::now();
        let n = rhs.len();
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.buffer),
        );
        self.work.triangular_solves += 1;
        self.work.times.solves += start.elapsed();
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
    pub(crate) fn new(system: &ContactSystem<'_>, eps_n: f64, eps_t: f64) -> Self {
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
    /// plus `delta D`. Returns whether the shift was needed (the factorisations are counted in
    /// the matrix's work), or `None` if even the shifted matrix is not definite (`K`
    /// indefinite).
    pub(crate) fn factorise(
        &self,
        matrix: &mut NewtonMatrix,
        system: &ContactSystem<'_>,
        normal_weights: &[f64],
        tangential_weights: &[f64],
    ) -> Option<bool> {
        if matrix.refill_and_factorise(system, normal_weights, tangential_weights, &self.no_shift) {
            Some(false)
        } else if matrix.refill_and_factorise(
            system,
            normal_weights,
            tangential_weights,
            &self.shift,
        ) {
            Some(true)
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
        system: &ContactSystem<'_>,
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
