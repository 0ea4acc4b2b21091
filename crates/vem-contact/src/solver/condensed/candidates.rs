//! The iterative interface's QP on its **candidate nodes**: the nodes that carry a force or may
//! come to carry one. Where they are few (a Hertz-like contact zone on a large face, the
//! later steps of a Coulomb fixed point), the Schur complement on their rows,
//! `H_CC = B_C K^-1 B_C'`, costs one block solve per body (the factor read once for all of
//! its columns, [`CholeskySolver::solve_many_on_support`](vem_elastic::CholeskySolver::solve_many_on_support)),
//! far less than the conjugate gradient products an iteration would take, and the QP on them
//! is the dense one (`dense_qp`, exact in a few projected Newton steps).
//!
//! Every answer is checked on the whole interface with one product `H lambda`: the stopping
//! test of the iterative interface (`|g^P|_inf <= tolerance`, a length) on every row. Nodes
//! outside the candidates whose rows fail it (contact spreading beyond the candidates, a
//! friction force where none was expected) join them, and the dense QP is solved again from
//! its answer; candidates that grow beyond [`MAX_CANDIDATE_FRACTION`] of the interface or
//! [`MAX_CANDIDATE_ROWS`], or a check failed only on candidate rows, hand the problem back to
//! the iteration (MPGP, or with friction in space its projected Newton steps), from the last
//! answer. `H_CC` is kept per structure (`H` does not change along a Coulomb fixed point or a
//! load history) and only grows: a node once a candidate stays one.

use faer::Mat;
use rayon::prelude::*;

use super::super::box_qp::ReducedFactor;
use super::super::disk_qp::Disk;
use super::super::error::ContactSolverError;
use super::super::mprgp::Mprgp;
use super::super::report::WorkCounters;
use super::{backend, dense_qp, Factors, Interface, CANDIDATES_NAME};

/// The candidates' rows stay within this fraction of the interface rows; beyond it the
/// iteration is cheaper than the columns of `H_CC`.
const MAX_CANDIDATE_FRACTION: f64 = 0.25;
/// The candidates' rows stay within this many (`H_CC` and its reduced factor in memory).
const MAX_CANDIDATE_ROWS: usize = 3000;
/// Without a warm start the first candidates penetrate by more than this fraction of the
/// deepest unconstrained penetration: a Hertz-like contact zone covers about half the area
/// of the bodies' overlap (`a^2 = R delta` against `2 R delta`), and nodes beyond it join at
/// the check.
const FIRST_PENETRATION: f64 = 0.5;
/// Rounds of the dense QP and the check on the whole interface before the iteration takes
/// over.
const MAX_ROUNDS: usize = 8;
/// The columns of `H_CC` solved for in one block: at most this many, and at most what keeps
/// the block's work space (the reached rows of the factor times the columns) within
/// [`BLOCK_BYTES`]. From about 100 columns on, a block of `k` costs about `k / 15` single solves.
const BLOCK_COLUMNS: usize = 256;
/// The largest work space of a block solve, per body.
const BLOCK_BYTES: usize = 256 << 20;

/// `H_CC` on the candidate nodes, kept per structure.
#[derive(Debug)]
pub(super) struct CandidateHessian {
    /// The candidate nodes, in the order of their rows in `hessian`.
    nodes: Vec<usize>,
    /// The interface rows of `hessian`'s rows and columns (each node's normal row, then its
    /// tangential rows).
    rows: Vec<usize>,
    /// `B_C K^-1 B_C'`.
    hessian: Mat<f64>,
    /// The reduced factor of the dense QP's last Newton step.
    reduced: ReducedFactor,
}

impl Default for CandidateHessian {
    fn default() -> Self {
        Self {
            nodes: Vec::new(),
            rows: Vec::new(),
            hessian: Mat::zeros(0, 0),
            reduced: ReducedFactor::default(),
        }
    }
}

/// The outcome of [`solve_on_candidates`].
pub(super) enum CandidateOutcome {
    /// The answer, checked on the whole interface.
    Solved(Interface),
    /// The candidates do not suit the problem: the iteration goes on from these multipliers.
    Iterate(Vec<f64>),
}

/// The interface rows of the nodes: node `i` owns normal row `i` and tangential rows
/// `normal + t i .. normal + t (i + 1)` (`t` tangential rows per node, 0 without friction).
struct NodeRows {
    normal: usize,
    per_node: usize,
}

impl NodeRows {
    fn of(&self, node: usize) -> impl Iterator<Item = usize> {
        let first = self.normal + self.per_node * node;
        std::iter::once(node).chain(first..first + self.per_node)
    }

    fn node_of(&self, row: usize) -> usize {
        if row < self.normal {
            row
        } else {
            (row - self.normal) / self.per_node
        }
    }
}

/// The interface QP (`d`, the bounds and disks as the iterative interface has them, in
/// unscaled multipliers) on the candidate nodes, or the multipliers to iterate from.
/// `carries[i]` tells whether row `i` can carry a force (its bounds are not both zero);
/// `tolerance` is the length of the stopping test.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_on_candidates(
    factors: &mut Factors,
    rows: &[(&[usize], &[f64])],
    n_dofs: usize,
    (normal_rows, per_node): (usize, usize),
    d: &[f64],
    (lower, upper, disks): (&[f64], &[f64], &[Disk]),
    carries: &[bool],
    warm: &[f64],
    tolerance: f64,
    max_iterations: usize,
    work: &mut WorkCounters,
) -> Result<CandidateOutcome, ContactSolverError> {
    let m = rows.len();
    let iterate = |lambda: &[f64]| Ok(CandidateOutcome::Iterate(lambda.to_vec()));
    if normal_rows == 0 || m != normal_rows * (1 + per_node) {
        return iterate(warm);
    }
    let layout = NodeRows {
        normal: normal_rows,
        per_node,
    };
    let limit = MAX_CANDIDATE_ROWS.min((MAX_CANDIDATE_FRACTION * m as f64) as usize);
    let Some(mut candidates) = factors
        .iterative
        .as_mut()
        .map(|s| std::mem::take(&mut s.candidates))
    else {
        return iterate(warm);
    };
    // The first candidates: the nodes whose warm start carries a force, or without one, the
    // nodes whose rows fail the test at zero force (an unconstrained penetration, a slip on a
    // row that carries); and the candidates kept.
    let mut is_candidate = vec![false; normal_rows];
    for &node in &candidates.nodes {
        is_candidate[node] = true;
    }
    let warm_carries = (0..m).any(|i| carries[i] && warm[i] != 0.0);
    let deepest = (0..normal_rows)
        .filter(|&i| carries[i])
        .fold(0.0f64, |a, i| a.max(d[i]));
    let mut joining: Vec<usize> = (0..normal_rows)
        .filter(|&node| {
            !is_candidate[node]
                && if warm_carries {
                    layout.of(node).any(|i| carries[i] && warm[i] != 0.0)
                } else {
                    layout.of(node).any(|i| {
                        carries[i]
                            && if i < normal_rows {
                                d[i] > FIRST_PENETRATION * deepest
                            } else {
                                d[i].abs() > tolerance
                            }
                    })
                }
        })
        .collect();
    let mut lambda = warm.to_vec();
    let mut iterations = 0;
    let outcome = 'rounds: {
        for _ in 0..MAX_ROUNDS {
            let joining_rows: usize = joining.len() * (1 + layout.per_node);
            if candidates.rows.len() + joining_rows > limit {
                break 'rounds Ok(CandidateOutcome::Iterate(lambda));
            }
            if !joining.is_empty() {
                if let Err(e) = candidates.extend(factors, rows, &layout, &joining, work) {
                    break 'rounds Err(e);
                }
                for &node in &joining {
                    is_candidate[node] = true;
                }
            }
            if candidates.rows.is_empty() {
                break 'rounds Ok(CandidateOutcome::Iterate(lambda));
            }
            // The dense QP on the candidates' rows, to the length `tolerance` on each row
            // (its force test scaled by the largest compliance).
            let c = &candidates.rows;
            let mut position = vec![usize::MAX; m];
            for (k, &i) in c.iter().enumerate() {
                position[i] = k;
            }
            let gather = |v: &[f64]| -> Vec<f64> { c.iter().map(|&i| v[i]).collect() };
            let local_disks: Vec<Disk> = disks
                .iter()
                .filter(|disk| is_candidate[layout.node_of(disk.first)])
                .map(|disk| Disk {
                    first: position[disk.first],
                    radius: disk.radius,
                })
                .collect();
            let largest = (0..c.len())
                .map(|k| candidates.hessian[(k, k)])
                .fold(0.0f64, f64::max);
            if !(largest > 0.0 && largest.is_finite()) {
                break 'rounds Ok(CandidateOutcome::Iterate(lambda));
            }
            let outcome = dense_qp(
                candidates.hessian.as_ref(),
                &gather(d),
                &gather(lower),
                &gather(upper),
                &local_disks,
                &gather(&lambda),
                tolerance / largest,
                max_iterations,
                &mut candidates.reduced,
            );
            iterations += outcome.iterations;
            lambda = vec![0.0; m];
            for (&i, &v) in c.iter().zip(&outcome.x) {
                lambda[i] = v;
            }
            // The check on the whole interface: one product.
            let hessian_lambda = match factors.apply_operator(rows, n_dofs, &lambda, work) {
                Ok(hessian_lambda) => hessian_lambda,
                Err(e) => break 'rounds Err(e),
            };
            let g: Vec<f64> = hessian_lambda.iter().zip(d).map(|(h, d)| h - d).collect();
            let whole = Mprgp {
                linear: d,
                lower,
                upper,
                disks,
                weights: &[],
            };
            let violations = whole.violations(&lambda, &g);
            if violations.iter().all(|&v| v <= tolerance) {
                break 'rounds Ok(CandidateOutcome::Solved(Interface {
                    lambda,
                    d: d.to_vec(),
                    iterations,
                    converged: true,
                    free_mode: false,
                    hessian_lambda: Some(hessian_lambda),
                    solver: CANDIDATES_NAME,
                }));
            }
            joining = (0..normal_rows)
                .filter(|&node| {
                    !is_candidate[node] && layout.of(node).any(|i| violations[i] > tolerance)
                })
                .collect();
            if joining.is_empty() {
                // Only candidate rows fail: round-off of the dense answer against the
                // products; the iteration finishes from here.
                break 'rounds Ok(CandidateOutcome::Iterate(lambda));
            }
        }
        Ok(CandidateOutcome::Iterate(lambda))
    };
    // Kept for the next solve of the structure, also after an error of a solve.
    if let Some(state) = factors.iterative.as_mut() {
        state.candidates = candidates;
    }
    outcome
}

impl CandidateHessian {
    /// Adds the nodes `joining` (not candidates yet): the columns of their rows by one block
    /// solve per body, on the support of every candidate's unknowns in that body.
    fn extend(
        &mut self,
        factors: &Factors,
        rows: &[(&[usize], &[f64])],
        layout: &NodeRows,
        joining: &[usize],
        work: &mut WorkCounters,
    ) -> Result<(), ContactSolverError> {
        let new_rows: Vec<usize> = joining.iter().flat_map(|&node| layout.of(node)).collect();
        let all_rows: Vec<usize> = self.rows.iter().chain(&new_rows).copied().collect();
        let (old, added, total) = (self.rows.len(), new_rows.len(), all_rows.len());
        // Per body, `B_all K^-1 B_new'`, the bodies in parallel.
        let start = std::time::Instant::now();
        let parts = factors
            .bodies
            .par_iter()
            .map(|body| -> Result<(Mat<f64>, usize), ContactSolverError> {
                let local = |c: usize| c.checked_sub(body.offset).filter(|&c| c < body.n);
                let mut unknowns: Vec<usize> = all_rows
                    .iter()
                    .flat_map(|&r| rows[r].0.iter().filter_map(|&c| local(c)))
                    .collect();
                unknowns.sort_unstable();
                unknowns.dedup();
                let mut columns = Mat::<f64>::zeros(total, added);
                if unknowns.is_empty() {
                    return Ok((columns, 0));
                }
                let at = |c: usize| unknowns.binary_search(&c).expect("a support unknown");
                let support = body.cholesky.support(&unknowns).map_err(backend)?;
                let per_block =
                    (BLOCK_BYTES / (8 * support.reached_rows().max(1))).clamp(1, BLOCK_COLUMNS);
                for first in (0..added).step_by(per_block) {
                    let width = per_block.min(added - first);
                    let mut block = Mat::<f64>::zeros(unknowns.len(), width);
                    for j in 0..width {
                        let (cols, values) = rows[new_rows[first + j]];
                        for (&c, &v) in cols.iter().zip(values) {
                            if let Some(c) = local(c) {
                                block[(at(c), j)] += v;
                            }
                        }
                    }
                    body.cholesky
                        .solve_many_on_support(&support, block.as_mut())
                        .map_err(backend)?;
                    for (i, &r) in all_rows.iter().enumerate() {
                        let (cols, values) = rows[r];
                        for (&c, &v) in cols.iter().zip(values) {
                            if let Some(c) = local(c) {
                                let p = at(c);
                                for j in 0..width {
                                    columns[(i, first + j)] += v * block[(p, j)];
                                }
                            }
                        }
                    }
                }
                Ok((columns, added.div_ceil(per_block)))
            })
            .collect::<Result<Vec<_>, _>>()?;
        work.triangular_solves += parts.iter().map(|(_, blocks)| blocks).sum::<usize>();
        work.times.solves += start.elapsed();
        let mut columns = Mat::<f64>::zeros(total, added);
        for (part, _) in parts {
            columns += part;
        }
        // The new matrix: the old block, the new columns and their transposes (symmetrised
        // on the new block).
        let mut hessian = Mat::<f64>::zeros(total, total);
        hessian
            .as_mut()
            .submatrix_mut(0, 0, old, old)
            .copy_from(self.hessian.as_ref());
        for j in 0..added {
            for i in 0..total {
                let v = if i >= old {
                    0.5 * (columns[(i, j)] + columns[(old + j, i - old)])
                } else {
                    columns[(i, j)]
                };
                hessian[(i, old + j)] = v;
                hessian[(old + j, i)] = v;
            }
        }
        self.hessian = hessian;
        self.rows = all_rows;
        // The disk QP names a kept factor's columns by the problem's size, which changed.
        self.reduced = ReducedFactor::default();
        self.nodes.extend_from_slice(joining);
        Ok(())
    }
}
