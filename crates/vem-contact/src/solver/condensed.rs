//! The condensed solver: contact at the cost of one factorisation of the stiffness.
//!
//! Every contact row touches only the **interface unknowns** `G` of each body (the unknowns of
//! the nodes that carry a normal or tangential row); call the others `I`. Each body's stiffness
//! is factorised once with its interface unknowns eliminated last
//! ([`CholeskySolver::analyse_with_trailing`]), so that the trailing block of the factor is the
//! Cholesky factor `L_GG` of the interface Schur complement `S = K_GG - K_GI K_II^-1 K_IG`, and
//! `(K^-1)_GG = S^-1`. With `B = [B_N; B_T]` and `u0 = K^-1 f`, the displacement for given
//! multipliers is `u = u0 - K^-1 B' lambda`, and the contact problem becomes its dual, a small
//! dense **bound-constrained** QP in the multipliers:
//!
//! ```text
//! minimise 1/2 lambda' H lambda - d' lambda,   H = B S^-1 B' = W'W,  W = L_GG^-1 B_G',
//!                                               d = B u0 - [g; 0],
//! subject to  lambda_N >= 0,  -b <= lambda_T <= b.
//! ```
//!
//! Tresca friction is a box constraint in the dual; a Coulomb fixed point changes only the
//! box, and a load step only `d`. The QP is solved by projected Newton steps with an Armijo
//! search (globally convergent; it cannot cycle, unlike a plain primal-dual active set), then
//! `u` follows from one more solve. Per structure (the [`PatternId`] and the stiffness values)
//! the solver keeps the factorisations and `H`; per solve it does two triangular solve pairs
//! per body and dense interface work. The multipliers of the last solve start the next one.
//!
//! A body whose stiffness is singular (held only by contact or friction) has no Cholesky
//! factor; the solver then hands the system to the [`ActiveSetSolver`], whose shifted
//! factorisation and free-mode test handle it, and its report says so.

use std::time::Instant;

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, Par};
use vem_elastic::{CholeskySettings, CholeskySolver, LinearSolver, SolveError};

use super::active_set::ActiveSetSolver;
use super::box_qp::BoxQp;
use super::error::{ContactSolverError, SettingsError};
use super::report::{KktResiduals, SolveReport, SolveStatus, WorkCounters};
use super::system::{ContactSystem, PatternId};
use super::{ContactSolution, ContactSolver};

const NAME: &str = "condensed (interface Schur complement)";

/// Settings of [`CondensedSolver`]; build them with [`CondensedSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CondensedSettings {
    tolerance: f64,
    max_iterations: usize,
    cholesky: CholeskySettings,
}

impl Default for CondensedSettings {
    /// Relative tolerance `1e-12` on the projected gradient of the interface problem, at most
    /// 200 projected Newton steps, the default sparse Cholesky settings.
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            max_iterations: 200,
            cholesky: CholeskySettings::default(),
        }
    }
}

impl CondensedSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> CondensedSettingsBuilder {
        CondensedSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Tolerance on the projected gradient of the interface problem, a force, relative to
    /// `max_i |d_i| / H_ii` (the force that would close the largest unconstrained penetration
    /// alone).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Limit on the projected Newton steps.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Settings of the sparse Cholesky factorisation of each body.
    pub fn cholesky(&self) -> &CholeskySettings {
        &self.cholesky
    }
}

/// Builder of [`CondensedSettings`]; values are checked by
/// [`CondensedSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct CondensedSettingsBuilder {
    settings: CondensedSettings,
}

impl CondensedSettingsBuilder {
    /// Relative tolerance, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Limit on the projected Newton steps, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Settings of the sparse Cholesky factorisations.
    pub fn cholesky(mut self, value: CholeskySettings) -> Self {
        self.settings.cholesky = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<CondensedSettings, SettingsError> {
        let s = self.settings;
        SettingsError::positive("tolerance", s.tolerance)?;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        Ok(s)
    }
}

/// Contact solver by condensation onto the interface: one sparse factorisation per body and
/// structure, an exact dense interface problem, one back substitution (see the module
/// documentation of `solver::condensed`). The default solver.
///
/// ```
/// use faer::sparse::{SparseColMat, Triplet};
/// use vem_contact::{ConstraintRows, ContactSolver, ContactSystem, CondensedSolver};
/// // A spring of stiffness 2 pushed by 3 against a wall at gap 1: it touches, and the wall
/// // takes 3 - 2 * 1 = 1.
/// let k = SparseColMat::try_new_from_triplets(1, 1, &[Triplet::new(0, 0, 2.0)]).unwrap();
/// let rows = ConstraintRows::try_from_triplets(1, 1, &[(0, 0, 1.0)]).unwrap();
/// let system = ContactSystem::try_new(k, vec![3.0], rows, vec![1.0], None).unwrap();
/// let solution = CondensedSolver::default().solve(&system).unwrap();
/// assert!((solution.displacement[0] - 1.0).abs() < 1e-14);
/// assert!((solution.normal_force[0] - 1.0).abs() < 1e-14);
/// ```
#[derive(Debug, Default)]
pub struct CondensedSolver {
    settings: CondensedSettings,
    structure: Option<Structure>,
    fallback: Option<ActiveSetSolver>,
}

/// What depends only on the structure and the stiffness values.
#[derive(Debug)]
struct Structure {
    pattern: PatternId,
    stiffness_version: u64,
    has_friction: bool,
    /// `None` when a body's stiffness is singular (the active-set fallback solves).
    factors: Option<Factors>,
}

#[derive(Debug)]
struct Factors {
    bodies: Vec<BodyFactor>,
    /// `H = B S^-1 B'` (rows: normal, then tangential).
    hessian: Mat<f64>,
    /// The load of the last solve and `u0 = K^-1 f` for it.
    unconstrained: Option<(Vec<f64>, Vec<f64>)>,
    /// The multipliers of the last solve (warm start).
    multipliers: Option<Vec<f64>>,
}

#[derive(Debug)]
struct BodyFactor {
    offset: usize,
    n: usize,
    cholesky: CholeskySolver,
}

impl CondensedSolver {
    /// A solver with the given settings.
    pub fn new(settings: CondensedSettings) -> Self {
        Self {
            settings,
            structure: None,
            fallback: None,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &CondensedSettings {
        &self.settings
    }
}

/// The constraint rows of a system as `(columns, values)` per row: normal rows, then
/// tangential rows.
fn all_rows<'s>(system: &'s ContactSystem<'_>) -> Vec<(&'s [usize], &'s [f64])> {
    let normal = system.normal_rows();
    let mut rows: Vec<_> = (0..normal.nrows()).map(|i| normal.row(i)).collect();
    if let Some(friction) = system.friction() {
        let t = friction.tangential_rows();
        rows.extend((0..t.nrows()).map(|i| t.row(i)));
    }
    rows
}

impl Structure {
    fn build(
        system: &ContactSystem<'_>,
        settings: &CondensedSettings,
        work: &mut WorkCounters,
    ) -> Result<Self, ContactSolverError> {
        let backend = |e: SolveError| ContactSolverError::Backend {
            solver: NAME,
            detail: e.to_string(),
        };
        let rows = all_rows(system);
        let mut bodies = Vec::new();
        let mut hessian = Mat::<f64>::zeros(rows.len(), rows.len());
        for block in system.stiffness_blocks() {
            let (offset, k) = (block.offset(), block.matrix());
            let n = k.nrows();
            // The interface unknowns of the body, local numbering, and their position in G.
            const NONE: usize = usize::MAX;
            let mut position = vec![NONE; n];
            let mut interface = Vec::new();
            for &(cols, _) in &rows {
                for &c in cols {
                    if (offset..offset + n).contains(&c) && position[c - offset] == NONE {
                        position[c - offset] = 0;
                        interface.push(c - offset);
                    }
                }
            }
            interface.sort_unstable();
            for (p, &i) in interface.iter().enumerate() {
                position[i] = p;
            }
            let mut cholesky = CholeskySolver::new(settings.cholesky);
            let start = Instant::now();
            cholesky
                .analyse_with_trailing(k.symbolic(), &interface)
                .map_err(backend)?;
            work.symbolic_analyses += 1;
            work.times.symbolic += start.elapsed();
            let start = Instant::now();
            let factorised = cholesky.factorise(k);
            work.numeric_factorisations += 1;
            work.times.numeric += start.elapsed();
            match factorised {
                Ok(()) => {}
                Err(SolveError::NotPositiveDefinite { .. }) => {
                    return Ok(Self::singular(system));
                }
                Err(e) => return Err(backend(e)),
            }
            if !interface.is_empty() {
                // W = L_GG^-1 B_G' and H += W'W.
                let mut w = Mat::<f64>::zeros(interface.len(), rows.len());
                for (r, &(cols, values)) in rows.iter().enumerate() {
                    for (&c, &v) in cols.iter().zip(values) {
                        if (offset..offset + n).contains(&c) {
                            w[(position[c - offset], r)] += v;
                        }
                    }
                }
                let l = cholesky.trailing_factor().map_err(backend)?;
                solve_lower_triangular_in_place(l.as_ref(), w.as_mut(), Par::rayon(0));
                matmul(
                    hessian.as_mut(),
                    Accum::Add,
                    w.transpose(),
                    w.as_ref(),
                    1.0,
                    Par::rayon(0),
                );
            }
            bodies.push(BodyFactor {
                offset,
                n,
                cholesky,
            });
        }
        Ok(Self {
            pattern: system.pattern(),
            stiffness_version: system.stiffness_version(),
            has_friction: system.friction().is_some(),
            factors: Some(Factors {
                bodies,
                hessian,
                unconstrained: None,
                multipliers: None,
            }),
        })
    }

    fn singular(system: &ContactSystem<'_>) -> Self {
        Self {
            pattern: system.pattern(),
            stiffness_version: system.stiffness_version(),
            has_friction: system.friction().is_some(),
            factors: None,
        }
    }

    fn fits(&self, system: &ContactSystem<'_>) -> bool {
        self.pattern == system.pattern()
            && self.stiffness_version == system.stiffness_version()
            && self.has_friction == system.friction().is_some()
    }
}

impl Factors {
    /// `K^-1 x`, body by body.
    fn solve(&self, x: &mut [f64], work: &mut WorkCounters) -> Result<(), ContactSolverError> {
        let start = Instant::now();
        for body in &self.bodies {
            let part = &mut x[body.offset..body.offset + body.n];
            let solved = body
                .cholesky
                .solve(part)
                .map_err(|e| ContactSolverError::Backend {
                    solver: NAME,
                    detail: e.to_string(),
                })?;
            part.copy_from_slice(&solved);
            work.triangular_solves += 1;
        }
        work.times.solves += start.elapsed();
        Ok(())
    }
}

impl ContactSolver for CondensedSolver {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError> {
        let start = Instant::now();
        let mut work = WorkCounters::default();
        if !self.structure.as_ref().is_some_and(|s| s.fits(system)) {
            self.structure = None;
            self.structure = Some(Structure::build(system, &self.settings, &mut work)?);
        }
        let structure = self.structure.as_mut().expect("built above");
        let Some(factors) = structure.factors.as_mut() else {
            // A singular stiffness: the active-set solver's shifted factorisation handles it.
            let fallback = self.fallback.get_or_insert_with(ActiveSetSolver::default);
            return match fallback.solve(system) {
                Ok(mut solution) => {
                    solution.report.work += work;
                    Ok(solution)
                }
                Err(e) => Err(e),
            };
        };
        let (n, m) = (system.n_dofs(), system.n_constraints());
        let rows = all_rows(system);

        // u0 = K^-1 f (kept while the load does not change: Coulomb steps).
        let unconstrained = match factors.unconstrained.take() {
            Some((load, u0)) if load == system.load() => (load, u0),
            _ => {
                let mut u0 = system.load().to_vec();
                factors.solve(&mut u0, &mut work)?;
                (system.load().to_vec(), u0)
            }
        };
        let u0 = &unconstrained.1;

        // The interface problem.
        let mut d: Vec<f64> = rows
            .iter()
            .map(|&(cols, values)| cols.iter().zip(values).map(|(&c, v)| v * u0[c]).sum())
            .collect();
        for (di, g) in d.iter_mut().zip(system.gap()) {
            *di -= g;
        }
        let mut lower = vec![0.0; rows.len()];
        let mut upper = vec![f64::INFINITY; rows.len()];
        if let Some(friction) = system.friction() {
            for (i, &b) in friction.bounds().iter().enumerate() {
                lower[m + i] = -b;
                upper[m + i] = b;
            }
        }
        let hessian = factors.hessian.as_ref();
        let force_scale = (0..rows.len())
            .filter(|&i| hessian[(i, i)] > 0.0)
            .fold(0.0f64, |a, i| a.max(d[i].abs() / hessian[(i, i)]));
        let warm = factors
            .multipliers
            .take()
            .filter(|l| l.len() == rows.len())
            .unwrap_or_else(|| vec![0.0; rows.len()]);
        let qp = BoxQp {
            hessian,
            linear: &d,
            lower: &lower,
            upper: &upper,
        };
        let outcome = if force_scale == 0.0 {
            // No load and no gap: the forces are exactly zero.
            super::box_qp::BoxQpOutcome {
                x: vec![0.0; rows.len()],
                iterations: 0,
                converged: true,
                factorisations: 0,
            }
        } else {
            qp.solve(
                &warm,
                self.settings.tolerance * force_scale,
                self.settings.max_iterations,
            )
        };
        let lambda = outcome.x;

        // u = u0 - K^-1 B' lambda.
        let mut reaction = vec![0.0; n];
        for (&(cols, values), &l) in rows.iter().zip(&lambda) {
            if l != 0.0 {
                for (&c, v) in cols.iter().zip(values) {
                    reaction[c] += v * l;
                }
            }
        }
        factors.solve(&mut reaction, &mut work)?;
        let displacement: Vec<f64> = u0.iter().zip(&reaction).map(|(a, b)| a - b).collect();
        let normal_force = lambda[..m].to_vec();
        let tangential_force = if system.friction().is_some() {
            lambda[m..].to_vec()
        } else {
            vec![0.0; m]
        };
        factors.multipliers = Some(lambda);
        factors.unconstrained = Some(unconstrained);

        let residuals =
            KktResiduals::evaluate(system, &displacement, &normal_force, &tangential_force);
        work.times.contact_solve = start.elapsed();
        let report = SolveReport {
            solver: NAME,
            status: if outcome.converged {
                SolveStatus::Converged
            } else {
                SolveStatus::MaxIterations
            },
            iterations: outcome.iterations,
            work,
            wall_time: start.elapsed(),
            residuals,
        };
        if outcome.converged {
            Ok(ContactSolution {
                displacement,
                normal_force,
                tangential_force,
                report,
            })
        } else {
            Err(ContactSolverError::NotConverged {
                report: Box::new(report),
            })
        }
    }
}
