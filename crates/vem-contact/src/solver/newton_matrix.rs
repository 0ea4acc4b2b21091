//! The Newton matrix `K + sum_r w_r b_r b_r' + sum_i c_i (b_2i b_2i+1' + b_2i+1 b_2i') + diag(s)`
//! of the penalty and active-set methods on a fixed pattern (the coupling `c_i` of a node's two
//! tangential rows in space: with the rows' weights, the 2x2 block `W_i` of the node, e.g. the
//! tangent of the radial return onto its friction disk): the lower triangle of
//! `K + B_N'B_N + B_T'B_T + I` (in space with the products of each node's two tangential rows)
//! is analysed once per
//! structure, in the order made of every stiffness block's interior order followed by all
//! interface unknowns (the blocks' orders are shared with the condensed solver, see
//! [`super::shared`]); the pattern and its analysis are shared by the penalty and active-set
//! solvers of one structure. For every Newton step only the values are refilled and factorised
//! ([`CholeskySolver`] through [`LinearSolver`]).

use std::sync::Arc;
use std::time::Instant;

use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{MatMut, Par};
use vem_elastic::{CholeskySettings, CholeskySolver, LinearSolver, Ordering, SolveError};

use super::report::WorkCounters;
use super::shared::{self, BlockOrder, CoupledKey};
use super::system::{ConstraintRows, ContactSystem};

/// Entries `(slot, coefficient)` of `b_r b_r'` (lower triangle) for each constraint row `r`.
#[derive(Debug, Clone)]
struct RowProducts {
    ptr: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

/// Entries `(slot, coefficient)` of `b_2i b_2i+1' + b_2i+1 b_2i'` (lower triangle) for each
/// node `i` with two tangential rows.
#[derive(Debug, Clone)]
struct PairProducts {
    ptr: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl PairProducts {
    fn new(rows: &ConstraintRows, slot: &impl Fn(usize, usize) -> usize) -> Self {
        let mut ptr = vec![0];
        let mut entries = Vec::new();
        for node in 0..rows.nrows() / 2 {
            let (c1, v1) = rows.row(2 * node);
            let (c2, v2) = rows.row(2 * node + 1);
            for (&a, &va) in c1.iter().zip(v1) {
                for (&b, &vb) in c2.iter().zip(v2) {
                    // `va vb` lands on (a, b) and (b, a): once in the lower triangle, twice
                    // on the diagonal.
                    let coef = if a == b { 2.0 * va * vb } else { va * vb };
                    entries.push((slot(a.max(b), a.min(b)), coef));
                }
            }
            ptr.push(entries.len());
        }
        Self { ptr, entries }
    }

    fn add_weighted(&self, weights: &[f64], values: &mut [f64]) {
        for (i, &w) in weights.iter().enumerate() {
            if w == 0.0 {
                continue;
            }
            for &(slot, coef) in &self.entries[self.ptr[i]..self.ptr[i + 1]] {
                values[slot] += w * coef;
            }
        }
    }
}

impl RowProducts {
    fn new(rows: &ConstraintRows, slot: &impl Fn(usize, usize) -> usize) -> Self {
        let mut ptr = vec![0];
        let mut entries = Vec::new();
        for r in 0..rows.nrows() {
            let (cols, vals) = rows.row(r);
            for a in 0..cols.len() {
                for b in a..cols.len() {
                    // Columns are sorted: cols[b] >= cols[a] is a lower-triangle entry.
                    entries.push((slot(cols[b], cols[a]), vals[a] * vals[b]));
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

/// The pattern of the Newton matrices of one structure and its symbolic analysis: the lower
/// triangle of `K + B_N'B_N + B_T'B_T + I`, each column holding first the lower entries of
/// `K` in the stiffness' own storage order (refilled by a plain copy), then the entries only
/// the contact rows or the diagonal add.
#[derive(Debug)]
pub(crate) struct CoupledPattern {
    n: usize,
    pattern: SymbolicSparseColMat<usize>,
    /// For a stiffness that repeats entries (unsorted storage, summed): the slot of every
    /// lower entry of `K` in column order. `None` when the lower entries of each column of
    /// `K` are the head of the column, in order.
    k_slots: Option<Vec<usize>>,
    normal: RowProducts,
    tangential: Option<RowProducts>,
    /// In space: the products of each node's two tangential rows.
    pairs: Option<PairProducts>,
    diag_slots: Vec<usize>,
    analysis: Arc<vem_elastic::CholeskyAnalysis>,
    /// The blocks' orders the analysis was made on (held, so that other solvers of the
    /// structure find them).
    _orders: Vec<Arc<BlockOrder>>,
}

impl CoupledPattern {
    fn new(system: &ContactSystem<'_>, ordering: Ordering) -> Result<Self, SolveError> {
        let n = system.n_dofs();
        let interfaces = shared::interfaces(system);
        let blocks = system.stiffness_blocks();
        let orders = blocks
            .iter()
            .enumerate()
            .map(|(b, _)| shared::order_of_block(system, b, &interfaces[b], ordering))
            .collect::<Result<Vec<_>, _>>()?;
        // Every block's interior, then every block's interface.
        let mut order = Vec::with_capacity(n);
        for (block, o) in blocks.iter().zip(&orders) {
            let interior = o.order.len() - o.interface.len();
            order.extend(o.order[..interior].iter().map(|&i| i + block.offset()));
        }
        let n_interface = n - order.len();
        for (block, o) in blocks.iter().zip(&orders) {
            let interior = o.order.len() - o.interface.len();
            order.extend(o.order[interior..].iter().map(|&i| i + block.offset()));
        }
        // The entries the rows add, by column (lower triangle), and the diagonal.
        let mut extra: Vec<(usize, usize)> = (0..n).map(|j| (j, j)).collect();
        let mut add_rows = |rows: &ConstraintRows| {
            for r in 0..rows.nrows() {
                let cols = rows.row(r).0;
                for a in 0..cols.len() {
                    extra.extend(cols[a..].iter().map(|&cb| (cols[a], cb)));
                }
            }
        };
        add_rows(system.normal_rows());
        let paired = system.friction().filter(|fr| fr.rows_per_node() == 2);
        if let Some(fr) = system.friction() {
            add_rows(fr.tangential_rows());
        }
        if let Some(fr) = paired {
            let rows = fr.tangential_rows();
            for node in 0..rows.nrows() / 2 {
                let c1 = rows.row(2 * node).0;
                let c2 = rows.row(2 * node + 1).0;
                for &a in c1 {
                    extra.extend(c2.iter().map(|&b| (a.min(b), a.max(b))));
                }
            }
        }
        extra.sort_unstable();
        extra.dedup();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut k_slots = Vec::new();
        let mut repeats = false;
        let mut stamp = vec![usize::MAX; n];
        let mut next_extra = 0;
        col_ptr.push(0);
        for block in blocks {
            let k = block.matrix();
            let offset = block.offset();
            for jl in 0..k.ncols() {
                let j = jl + offset;
                let start = row_idx.len();
                for &il in k.row_idx_of_col_raw(jl) {
                    if il < jl {
                        continue;
                    }
                    let i = il + offset;
                    if stamp[i] != j {
                        stamp[i] = j;
                        row_idx.push(i);
                        k_slots.push(row_idx.len() - 1);
                    } else {
                        repeats = true;
                        let at = row_idx[start..].iter().position(|&r| r == i);
                        k_slots.push(start + at.expect("stamped in this column"));
                    }
                }
                while next_extra < extra.len() && extra[next_extra].0 == j {
                    let i = extra[next_extra].1;
                    if stamp[i] != j {
                        stamp[i] = j;
                        row_idx.push(i);
                    }
                    next_extra += 1;
                }
                col_ptr.push(row_idx.len());
            }
        }
        drop((extra, stamp));
        let slot = |i: usize, j: usize| -> usize {
            let start = col_ptr[j];
            // The entry was inserted above, so the search cannot fail.
            start
                + row_idx[start..col_ptr[j + 1]]
                    .iter()
                    .position(|&r| r == i)
                    .expect("every coupled entry is in the pattern")
        };
        let normal = RowProducts::new(system.normal_rows(), &slot);
        let tangential = system
            .friction()
            .map(|fr| RowProducts::new(fr.tangential_rows(), &slot));
        let pairs = paired.map(|fr| PairProducts::new(fr.tangential_rows(), &slot));
        let diag_slots = (0..n).map(|j| slot(j, j)).collect();
        let pattern = SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx);
        let mut cholesky = CholeskySolver::new(newton_settings(ordering, Par::Seq)?);
        cholesky.analyse_with_order(pattern.as_ref(), &order, n_interface)?;
        let analysis = cholesky.shared_analysis().expect("analysed above");
        Ok(Self {
            n,
            pattern,
            k_slots: repeats.then_some(k_slots),
            normal,
            tangential,
            pairs,
            diag_slots,
            analysis,
            _orders: orders,
        })
    }
}

/// The Cholesky settings of a Newton matrix: the solver's parallelism for factorisations and
/// solves, and any positive pivot accepted (a matrix the factorisation accepts is used; the
/// guard below shifts those it refuses).
fn newton_settings(ordering: Ordering, par: Par) -> Result<CholeskySettings, SolveError> {
    CholeskySettings::builder()
        .ordering(ordering)
        .factorisation_parallelism(par)
        .solve_parallelism(par)
        .singular_pivot_tolerance(0.0)
        .build()
}

/// Symmetric positive definite Newton matrix on the shared pattern of its structure
/// ([`CoupledPattern`]), with its own values and factor.
pub(crate) struct NewtonMatrix {
    key: CoupledKey,
    par: Par,
    coupled: Arc<CoupledPattern>,
    values: Vec<f64>,
    cholesky: CholeskySolver,
    work: WorkCounters,
}

impl std::fmt::Debug for NewtonMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NewtonMatrix")
            .field("n", &self.coupled.n)
            .field("pattern_nnz", &self.values.len())
            .field("factor_nnz", &self.coupled.analysis.factor_entries())
            .field("par", &self.par)
            .finish_non_exhaustive()
    }
}

impl NewtonMatrix {
    /// The matrix of `system`'s structure: its pattern and analysis shared with the other
    /// solvers of the structure, or made here (counted as one symbolic analysis).
    pub(crate) fn try_new(system: &ContactSystem<'_>, par: Par) -> Result<Self, String> {
        let start = Instant::now();
        let ordering = Ordering::default();
        let key = CoupledKey {
            pattern: system.pattern(),
            has_friction: system.friction().is_some(),
            ordering,
        };
        let (coupled, made) =
            shared::coupled_pattern(key, || CoupledPattern::new(system, ordering))
                .map_err(|e| format!("symbolic Cholesky analysis: {e}"))?;
        let settings = newton_settings(ordering, par).map_err(|e| e.to_string())?;
        let cholesky = CholeskySolver::from_analysis(settings, Arc::clone(&coupled.analysis));
        let mut work = WorkCounters::default();
        if made {
            work.symbolic_analyses = 1;
            work.times.symbolic = start.elapsed();
        }
        Ok(Self {
            key,
            par,
            values: vec![0.0; coupled.pattern.row_idx().len()],
            coupled,
            cholesky,
            work,
        })
    }

    /// The matrix kept in `slot` if it was made for the structure of `system` (and
    /// parallelism `par`), else a new one.
    pub(crate) fn reuse_or_analyse<'m>(
        slot: &'m mut Option<NewtonMatrix>,
        system: &ContactSystem<'_>,
        par: Par,
    ) -> Result<&'m mut NewtonMatrix, String> {
        let fits = slot.as_ref().is_some_and(|m| {
            m.par == par
                && m.key.pattern == system.pattern()
                && m.key.has_friction == system.friction().is_some()
        });
        if !fits {
            // The old matrix's values and factor go before the new ones are made.
            *slot = None;
            *slot = Some(Self::try_new(system, par)?);
        }
        Ok(slot.as_mut().expect("filled above"))
    }

    /// The work counted since the last call (symbolic analysis, factorisations, solves).
    pub(crate) fn take_work(&mut self) -> WorkCounters {
        std::mem::take(&mut self.work)
    }

    /// Sets the values to
    /// `K + sum_r wn_r bn_r bn_r' + sum_r wt_r bt_r bt_r' + sum_i c_i (bt_2i bt_2i+1' + bt_2i+1 bt_2i') + diag(shift)`
    /// (`c = tangential_coupling`, one per node in space, or empty) and factorises. Returns
    /// `false` if the matrix is not numerically positive definite.
    pub(crate) fn refill_and_factorise(
        &mut self,
        system: &ContactSystem<'_>,
        normal_weights: &[f64],
        tangential_weights: &[f64],
        tangential_coupling: &[f64],
        shift: &[f64],
    ) -> bool {
        let start = Instant::now();
        let coupled = &self.coupled;
        let col_ptr = coupled.pattern.col_ptr();
        self.values.iter_mut().for_each(|v| *v = 0.0);
        // The lower entries of K, at the head of every column in K's storage order (or where
        // `k_slots` puts them).
        let mut j = 0;
        let mut entry = 0;
        for block in system.stiffness_blocks() {
            let k = block.matrix();
            for jl in 0..k.ncols() {
                let mut slot = col_ptr[j];
                let rows = k.row_idx_of_col_raw(jl);
                for (&il, &v) in rows.iter().zip(k.val_of_col(jl)) {
                    if il >= jl {
                        let at = coupled.k_slots.as_ref().map_or(slot, |s| s[entry]);
                        self.values[at] += v;
                        slot += 1;
                        entry += 1;
                    }
                }
                j += 1;
            }
        }
        coupled
            .normal
            .add_weighted(normal_weights, &mut self.values);
        if let Some(t) = &coupled.tangential {
            t.add_weighted(tangential_weights, &mut self.values);
        }
        if let Some(p) = &coupled.pairs {
            p.add_weighted(tangential_coupling, &mut self.values);
        }
        for (&slot, &s) in coupled.diag_slots.iter().zip(shift) {
            self.values[slot] += s;
        }
        let matrix = SparseColMatRef::new(coupled.pattern.as_ref(), &self.values);
        let ok = self.cholesky.factorise(matrix).is_ok();
        self.work.numeric_factorisations += 1;
        self.work.times.numeric += start.elapsed();
        ok
    }

    /// Solves with the last factorisation, in place (NaN if the last factorisation failed).
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let start = Instant::now();
        let n = rhs.len();
        if self
            .cholesky
            .solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1))
            .is_err()
        {
            rhs.fill(f64::NAN);
        }
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

    /// Factorises `K + sum wn bn bn' + sum wt bt bt'` (plus the couplings of the nodes' two
    /// tangential rows, see [`NewtonMatrix::refill_and_factorise`]), or, if that is not
    /// definite, the same plus `delta D`. Returns whether the shift was needed (the factorisations are counted in
    /// the matrix's work), or `None` if even the shifted matrix is not definite (`K`
    /// indefinite).
    pub(crate) fn factorise(
        &self,
        matrix: &mut NewtonMatrix,
        system: &ContactSystem<'_>,
        normal_weights: &[f64],
        tangential_weights: &[f64],
        tangential_coupling: &[f64],
    ) -> Option<bool> {
        if matrix.refill_and_factorise(
            system,
            normal_weights,
            tangential_weights,
            tangential_coupling,
            &self.no_shift,
        ) {
            Some(false)
        } else if matrix.refill_and_factorise(
            system,
            normal_weights,
            tangential_weights,
            tangential_coupling,
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
