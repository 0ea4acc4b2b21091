//! Fill-reducing orderings of a symmetric sparsity pattern: approximate minimum degree (faer's
//! AMD), nested dissection (METIS), the natural order, and the choice between them by size.
//!
//! Both fill-reducing orderings work on the **compressed graph**: unknowns whose closed
//! neighbourhoods in the pattern are equal (the two displacement components of a vertex, in
//! general the components of a node) are merged into one supervariable, the graph of the
//! supervariables is ordered, and each supervariable is expanded in place. For the lowest-order
//! VEM in 2D this orders a graph with a quarter of the edges of the matrix.
//!
//! Unknowns given as *trailing* are left out of the graph and eliminated last, in the order
//! given (see [`crate::CholeskySolver::analyse_with_trailing`]).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

use crate::SolveError;

/// The fill-reducing ordering of the Cholesky factorisation.
///
/// Measured on the lowest-order VEM in 2D (quads and Voronoi meshes, see
/// `docs/benchmarks.md`): nested dissection gives the smaller factor and the fewer flops at
/// every size from 10^4 unknowns on, and the gap grows with the size (factor 6 % smaller at
/// 10^4, 20 % at 10^5, 30 % at 10^6, 34 % at 8·10^6; flops 10 %, 40 %, 55-60 %, 58 %), but
/// it takes 2-3x AMD's time to compute. In 3D (elasticity on polyhedra) nested dissection is
/// 1.4x faster than AMD from 10^4 unknowns and 3-4x at 10^5. [`Ordering::Auto`] chooses by size
/// and, below the 2D threshold, by the size of the supervariables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Ordering {
    /// [`Ordering::NestedDissection`] for at least
    /// [`Ordering::NESTED_DISSECTION_MIN_UNKNOWNS`] unknowns to order, or for at least
    /// [`Ordering::NESTED_DISSECTION_MIN_UNKNOWNS_3D`] when the unknowns come in groups of three
    /// with the same neighbours (the supervariables of an elasticity problem in space), when
    /// nested dissection is available ([`Ordering::nested_dissection_available`]);
    /// [`Ordering::Amd`] otherwise (the default).
    #[default]
    Auto,
    /// Approximate minimum degree (faer's built-in AMD) of the compressed graph.
    Amd,
    /// Nested dissection of the compressed graph by METIS (multilevel vertex separators,
    /// minimum degree on the small parts). Needs the `metis` feature (default): without it
    /// asking for it is [`SolveError::InvalidSetting`].
    NestedDissection,
    /// The natural order (no permutation; for tests and already ordered matrices).
    Natural,
}

impl Ordering {
    /// Unknowns to order from which [`Ordering::Auto`] takes nested dissection: below, AMD's
    /// analysis and one factorisation take less time (10^5 unknowns: 0.24 s against 0.43 s on
    /// quads), above, nested dissection's do (10^6: 8.3 s against 7.9 s, Voronoi 17.0 s
    /// against 15.0 s) with a third less memory for the factor (measured in
    /// `docs/benchmarks.md`).
    pub const NESTED_DISSECTION_MIN_UNKNOWNS: usize = 200_000;

    /// Unknowns to order from which [`Ordering::Auto`] takes nested dissection for a graph of
    /// three-component supervariables (elasticity in space, the mean supervariable size at
    /// least 2.5): there the separators are surfaces, AMD's fill grows much faster, and nested
    /// dissection's analysis plus one factorisation is shorter from 10^4 unknowns on (hexahedra
    /// 0.12 s against 0.17 s, Voronoi cells 0.26 against 0.36 s; at 10^5 3.9 against 13.2 s and
    /// 10.2 against 29.7 s: `docs/benchmarks.md`, "Three dimensions").
    pub const NESTED_DISSECTION_MIN_UNKNOWNS_3D: usize = 10_000;

    /// Whether [`Ordering::NestedDissection`] is compiled in (the `metis` feature).
    pub const fn nested_dissection_available() -> bool {
        cfg!(feature = "metis")
    }

    /// The ordering used for `n` unknowns to order: [`Ordering::Auto`] resolved by the size
    /// alone, the others as they are. ([`elimination_order`], which sees the graph, also applies
    /// the rule of three-component supervariables of [`Ordering::Auto`].)
    pub fn resolve(self, n: usize) -> Ordering {
        match self {
            Ordering::Auto
                if n >= Self::NESTED_DISSECTION_MIN_UNKNOWNS
                    && Self::nested_dissection_available() =>
            {
                Ordering::NestedDissection
            }
            Ordering::Auto => Ordering::Amd,
            other => other,
        }
    }
}

/// The elimination order (new position -> original unknown) of the square `pattern`: the
/// unknowns not in `trailing` in the fill-reducing order `ordering` of the pattern restricted
/// to them, then `trailing` as given. Only the entries below the diagonal are read (a pattern
/// in full symmetric storage or its lower triangle gives the same order). Returns the order and
/// the ordering used ([`Ordering::Auto`] resolved).
///
/// ```
/// use faer::sparse::SymbolicSparseColMat;
/// use vem_elastic::{elimination_order, Ordering};
/// // A path 0 - 1 - 2 (lower triangle): with 1 trailing, 0 and 2 come first.
/// let pattern = SymbolicSparseColMat::new_checked(3, 3, vec![0, 2, 4, 5], None, vec![0, 1, 1, 2, 2]);
/// let (order, used) = elimination_order(pattern.as_ref(), &[1], Ordering::Amd)?;
/// assert_eq!(order[2], 1);
/// assert_eq!(used, Ordering::Amd);
/// # Ok::<(), vem_elastic::SolveError>(())
/// ```
///
/// # Errors
/// [`SolveError::Mismatch`] for a non-square pattern, a trailing unknown out of range or
/// repeated; [`SolveError::InvalidSetting`] for nested dissection without the `metis` feature;
/// [`SolveError::Backend`] when the ordering fails (out of memory).
pub fn elimination_order(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    trailing: &[usize],
    ordering: Ordering,
) -> Result<(Vec<usize>, Ordering), SolveError> {
    let n = pattern.nrows();
    if n != pattern.ncols() {
        return Err(SolveError::Mismatch {
            reason: format!("the matrix is {} x {}, not square", n, pattern.ncols()),
        });
    }
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
    let mut used = ordering.resolve(leading.len());
    let mut order = match used {
        Ordering::Natural | Ordering::Auto => leading.clone(),
        Ordering::Amd | Ordering::NestedDissection => {
            let graph = Graph::of_leading_block(pattern, &leading, &local);
            drop(local);
            let (supervariables, quotient) = graph.compress();
            drop(graph);
            // Auto below the 2D threshold: a graph of three-component supervariables.
            let groups = supervariables.ptr.len().saturating_sub(1).max(1);
            if ordering == Ordering::Auto
                && used == Ordering::Amd
                && Ordering::nested_dissection_available()
                && leading.len() >= Ordering::NESTED_DISSECTION_MIN_UNKNOWNS_3D
                && leading.len() as f64 >= 2.5 * groups as f64
            {
                used = Ordering::NestedDissection;
            }
            let order = if used == Ordering::Amd {
                quotient.amd()?
            } else {
                quotient.nested_dissection(&supervariables)?
            };
            let mut expanded = Vec::with_capacity(leading.len());
            for s in order {
                expanded.extend(supervariables.members(s).iter().map(|&k| leading[k]));
            }
            expanded
        }
    };
    order.extend_from_slice(trailing);
    Ok((order, used))
}

/// An undirected graph without self loops in compressed-row form (both directions stored).
struct Graph {
    ptr: Vec<usize>,
    adj: Vec<usize>,
}

/// A partition of the vertices into supervariables (sets of vertices with equal closed
/// neighbourhoods).
struct Supervariables {
    ptr: Vec<usize>,
    members: Vec<usize>,
}

impl Supervariables {
    fn members(&self, s: usize) -> &[usize] {
        &self.members[self.ptr[s]..self.ptr[s + 1]]
    }
}

impl Graph {
    /// The graph of the pattern restricted to `leading` (renumbered by `local`), from the
    /// entries below the diagonal.
    fn of_leading_block(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        leading: &[usize],
        local: &[usize],
    ) -> Self {
        let m = leading.len();
        let is_leading = |i: usize| local[i] != usize::MAX;
        let mut degree = vec![0usize; m + 1];
        for (kj, &j) in leading.iter().enumerate() {
            for &i in pattern.row_idx_of_col_raw(j) {
                if i > j && is_leading(i) {
                    degree[kj + 1] += 1;
                    degree[local[i] + 1] += 1;
                }
            }
        }
        for k in 0..m {
            degree[k + 1] += degree[k];
        }
        let ptr = degree;
        let mut next = ptr.clone();
        let mut adj = vec![0usize; ptr[m]];
        for (kj, &j) in leading.iter().enumerate() {
            for &i in pattern.row_idx_of_col_raw(j) {
                if i > j && is_leading(i) {
                    let ki = local[i];
                    adj[next[kj]] = ki;
                    next[kj] += 1;
                    adj[next[ki]] = kj;
                    next[ki] += 1;
                }
            }
        }
        let mut graph = Self { ptr, adj };
        graph.sort_and_dedup();
        graph
    }

    fn n(&self) -> usize {
        self.ptr.len() - 1
    }

    fn neighbours(&self, v: usize) -> &[usize] {
        &self.adj[self.ptr[v]..self.ptr[v + 1]]
    }

    /// Sorts every adjacency list and removes repeats (an unsorted or duplicated pattern).
    fn sort_and_dedup(&mut self) {
        let mut write = 0;
        let mut start = 0;
        for v in 0..self.n() {
            let end = self.ptr[v + 1];
            self.adj[start..end].sort_unstable();
            let first = write;
            for k in start..end {
                let x = self.adj[k];
                if write == first || self.adj[write - 1] != x {
                    self.adj[write] = x;
                    write += 1;
                }
            }
            start = end;
            self.ptr[v + 1] = write;
        }
        self.adj.truncate(write);
        self.adj.shrink_to_fit();
    }

    /// The supervariables (vertices with equal closed neighbourhoods, found by hashing and
    /// checked entry by entry) and the graph between them.
    fn compress(&self) -> (Supervariables, Graph) {
        let n = self.n();
        // Closed neighbourhood {v} + N(v): a hash independent of the order.
        let hash = |v: usize| -> u64 {
            let mix =
                |x: usize| (x as u64 ^ 0x9e37_79b9_7f4a_7c15).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            self.neighbours(v)
                .iter()
                .fold(mix(v), |h, &w| h.wrapping_add(mix(w)))
        };
        let same = |a: usize, b: usize| -> bool {
            let (na, nb) = (self.neighbours(a), self.neighbours(b));
            if na.len() != nb.len() {
                return false;
            }
            // Closed neighbourhoods equal <=> N(a) - {b} == N(b) - {a} and a ~ b.
            if na.binary_search(&b).is_err() {
                return false;
            }
            let mut ia = na.iter().filter(|&&x| x != b);
            let mut ib = nb.iter().filter(|&&x| x != a);
            loop {
                match (ia.next(), ib.next()) {
                    (None, None) => return true,
                    (Some(x), Some(y)) if x == y => {}
                    _ => return false,
                }
            }
        };
        let mut keyed: Vec<(u64, usize, usize)> = (0..n)
            .map(|v| (hash(v), self.neighbours(v).len(), v))
            .collect();
        keyed.sort_unstable();
        const NONE: usize = usize::MAX;
        let mut representative = vec![NONE; n];
        let mut group_start = 0;
        while group_start < n {
            let mut group_end = group_start + 1;
            while group_end < n
                && keyed[group_end].0 == keyed[group_start].0
                && keyed[group_end].1 == keyed[group_start].1
            {
                group_end += 1;
            }
            // Within a group of equal keys, match every vertex with the first equal one.
            for a in group_start..group_end {
                let va = keyed[a].2;
                if representative[va] != NONE {
                    continue;
                }
                representative[va] = va;
                for item in &keyed[a + 1..group_end] {
                    let vb = item.2;
                    if representative[vb] == NONE && same(va, vb) {
                        representative[vb] = va;
                    }
                }
            }
            group_start = group_end;
        }
        // Number the supervariables by their smallest member (the representative found first
        // in vertex order), members in increasing order.
        let mut index = vec![NONE; n];
        let mut count = 0;
        for &r in &representative {
            if index[r] == NONE {
                index[r] = count;
                count += 1;
            }
        }
        let mut ptr = vec![0usize; count + 1];
        for &r in &representative {
            ptr[index[r] + 1] += 1;
        }
        for s in 0..count {
            ptr[s + 1] += ptr[s];
        }
        let mut next = ptr.clone();
        let mut members = vec![0usize; n];
        let mut supervariable_of = vec![0usize; n];
        for v in 0..n {
            let s = index[representative[v]];
            members[next[s]] = v;
            next[s] += 1;
            supervariable_of[v] = s;
        }
        let supervariables = Supervariables { ptr, members };
        // The quotient graph from each supervariable's first member.
        let mut qptr = Vec::with_capacity(count + 1);
        let mut qadj = Vec::new();
        qptr.push(0);
        for s in 0..count {
            let v = supervariables.members(s)[0];
            let start = qadj.len();
            qadj.extend(
                self.neighbours(v)
                    .iter()
                    .map(|&w| supervariable_of[w])
                    .filter(|&t| t != s),
            );
            qadj[start..].sort_unstable();
            let mut write = start;
            for k in start..qadj.len() {
                if write == start || qadj[write - 1] != qadj[k] {
                    qadj[write] = qadj[k];
                    write += 1;
                }
            }
            qadj.truncate(write);
            qptr.push(qadj.len());
        }
        (
            supervariables,
            Graph {
                ptr: qptr,
                adj: qadj,
            },
        )
    }

    /// AMD order of the vertices (faer).
    fn amd(&self) -> Result<Vec<usize>, SolveError> {
        let n = self.n();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &self.ptr, None, &self.adj);
        let (mut forward, mut inverse) = (vec![0usize; n], vec![0usize; n]);
        let mut scratch = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(
            n,
            self.adj.len(),
        ))
        .map_err(|_| backend("out of memory for the ordering workspace"))?;
        amd::order_maybe_unsorted(
            &mut forward,
            &mut inverse,
            pattern,
            amd::Control::default(),
            MemStack::new(&mut scratch),
        )
        .map_err(backend)?;
        Ok(forward)
    }

    /// Nested dissection order of the vertices (METIS `NodeND`, vertex weights the
    /// supervariable sizes, default options: deterministic).
    #[cfg(feature = "metis")]
    fn nested_dissection(&self, supervariables: &Supervariables) -> Result<Vec<usize>, SolveError> {
        use metis_sys::idx_t;
        let n = self.n();
        if n <= 2 {
            return Ok((0..n).collect());
        }
        let too_large = || backend("the graph is too large for METIS' 32-bit indices");
        let to_idx = |x: usize| idx_t::try_from(x).map_err(|_| too_large());
        let mut nvtxs = to_idx(n)?;
        let mut xadj = self
            .ptr
            .iter()
            .map(|&x| to_idx(x))
            .collect::<Result<Vec<_>, _>>()?;
        let mut adjncy = self
            .adj
            .iter()
            .map(|&x| to_idx(x))
            .collect::<Result<Vec<_>, _>>()?;
        let mut vwgt = (0..n)
            .map(|s| to_idx(supervariables.members(s).len()))
            .collect::<Result<Vec<_>, _>>()?;
        let mut perm = vec![0 as idx_t; n];
        let mut iperm = vec![0 as idx_t; n];
        // SAFETY: the arrays have the lengths METIS_NodeND reads (n + 1, xadj[n], n, n, n), the
        // adjacency is symmetric, without self loops, with indices in 0..n; a null options
        // pointer selects the defaults.
        let status = unsafe {
            metis_sys::METIS_NodeND(
                &mut nvtxs,
                xadj.as_mut_ptr(),
                adjncy.as_mut_ptr(),
                vwgt.as_mut_ptr(),
                std::ptr::null_mut(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
            )
        };
        if status != metis_sys::rstatus_et_METIS_OK {
            return Err(backend(format!("METIS_NodeND failed (status {status})")));
        }
        // perm[new] = old.
        perm.into_iter()
            .map(|p| usize::try_from(p).map_err(|_| backend("METIS returned a negative index")))
            .collect()
    }

    #[cfg(not(feature = "metis"))]
    fn nested_dissection(&self, _: &Supervariables) -> Result<Vec<usize>, SolveError> {
        Err(SolveError::InvalidSetting {
            reason: "nested dissection needs vem-elastic's `metis` feature".to_string(),
        })
    }
}

fn backend(reason: impl std::fmt::Display) -> SolveError {
    SolveError::Backend {
        reason: reason.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::SymbolicSparseColMat;

    /// The full pattern of the 2D vector Laplacian of an `n x n` grid (2 unknowns per node,
    /// 9-point stencil, as Q1 elements give).
    fn grid(n: usize) -> SymbolicSparseColMat<usize> {
        let node = |i: usize, j: usize| i * n + j;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for c in 0..2 {
                    let _ = c;
                    let mut rows = Vec::new();
                    for a in i.saturating_sub(1)..(i + 2).min(n) {
                        for b in j.saturating_sub(1)..(j + 2).min(n) {
                            rows.push(2 * node(a, b));
                            rows.push(2 * node(a, b) + 1);
                        }
                    }
                    rows.sort_unstable();
                    row_idx.extend(rows);
                    col_ptr.push(row_idx.len());
                }
            }
        }
        let m = 2 * n * n;
        SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx)
    }

    /// Nonzeros of the Cholesky factor of `pattern` in the order `order` (symbolic elimination
    /// by the elimination tree's row counts, brute force on small patterns).
    fn factor_entries(pattern: &SymbolicSparseColMat<usize>, order: &[usize]) -> usize {
        let n = order.len();
        let mut position = vec![0; n];
        for (k, &o) in order.iter().enumerate() {
            position[o] = k;
        }
        let mut structure: Vec<std::collections::BTreeSet<usize>> = vec![Default::default(); n];
        for j in 0..n {
            for &i in pattern.row_idx_of_col_raw(j) {
                let (pi, pj) = (position[i], position[j]);
                if pi > pj {
                    structure[pj].insert(pi);
                }
            }
        }
        let mut total = 0;
        for k in 0..n {
            let column: Vec<usize> = structure[k].iter().copied().collect();
            total += column.len() + 1;
            if let Some(&parent) = column.first() {
                for &r in &column[1..] {
                    structure[parent].insert(r);
                }
            }
        }
        total
    }

    #[test]
    fn orders_are_permutations_with_the_trailing_unknowns_last() {
        let pattern = grid(12);
        let n = pattern.nrows();
        let trailing = [5, 0, 287, 100];
        for ordering in [
            Ordering::Amd,
            Ordering::Natural,
            Ordering::Auto,
            #[cfg(feature = "metis")]
            Ordering::NestedDissection,
        ] {
            let (order, _) = elimination_order(pattern.as_ref(), &trailing, ordering).unwrap();
            let mut seen = vec![false; n];
            for &o in &order {
                assert!(!seen[o], "{ordering:?} repeats {o}");
                seen[o] = true;
            }
            assert!(seen.iter().all(|&s| s));
            assert_eq!(&order[n - trailing.len()..], &trailing);
        }
    }

    /// The supervariables of the grid are its nodes (two unknowns each), kept together.
    #[test]
    fn the_components_of_a_node_stay_together() {
        let pattern = grid(9);
        let (order, _) = elimination_order(pattern.as_ref(), &[], Ordering::Amd).unwrap();
        for pair in order.chunks(2) {
            assert_eq!(pair[0] / 2, pair[1] / 2, "{pair:?}");
            assert_eq!(pair[0] + 1, pair[1]);
        }
    }

    /// Both fill-reducing orderings give far less fill than the natural (banded) order on a
    /// 2D grid: the factor of nested dissection grows like n log n, the band like n^1.5.
    #[test]
    fn fill_reducing_orderings_beat_the_band() {
        let pattern = grid(24);
        let natural = factor_entries(&pattern, &(0..pattern.nrows()).collect::<Vec<_>>());
        for ordering in [
            Ordering::Amd,
            #[cfg(feature = "metis")]
            Ordering::NestedDissection,
        ] {
            let (order, used) = elimination_order(pattern.as_ref(), &[], ordering).unwrap();
            assert_eq!(used, ordering);
            let fill = factor_entries(&pattern, &order);
            assert!(
                (fill as f64) < 0.8 * natural as f64,
                "{ordering:?}: {fill} vs natural {natural}"
            );
        }
    }

    #[test]
    fn auto_resolves_by_size() {
        assert_eq!(Ordering::Auto.resolve(100), Ordering::Amd);
        let large = Ordering::Auto.resolve(Ordering::NESTED_DISSECTION_MIN_UNKNOWNS);
        if Ordering::nested_dissection_available() {
            assert_eq!(large, Ordering::NestedDissection);
        } else {
            assert_eq!(large, Ordering::Amd);
        }
        assert_eq!(Ordering::Natural.resolve(10_000_000), Ordering::Natural);
    }
}
