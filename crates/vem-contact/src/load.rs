//! The load and gaps of one load level, from per-condition parts (load histories) or one
//! factor for everything (load steps of the static problem).

use std::borrow::Cow;

use faer::sparse::SparseColMat;
use vem_elastic::{AssembledSystem, ElasticBody, Solution};

use crate::{ContactDiscretisation, ContactError, LoadCondition, LoadFactors};

/// What one condition contributes at factor 1.
#[derive(Debug, Clone)]
pub(crate) struct ConditionPart {
    /// Its part of the right-hand side over the body's unknowns (free values, then plates).
    rhs: Vec<f64>,
    /// Its load vector over every global degree of freedom (body force, tractions; `None` for
    /// a Dirichlet condition, which loads through the lifting only).
    load: Option<Vec<f64>>,
}

/// The parts of one body's right-hand side.
#[derive(Debug, Clone)]
pub(crate) struct BodyParts {
    body_force: Option<ConditionPart>,
    /// One per Dirichlet condition; `None` when it contributes nothing (zero values).
    dirichlet: Vec<Option<ConditionPart>>,
    tractions: Vec<ConditionPart>,
}

/// The per-condition parts of the load of every body and of the prescribed normal jumps of
/// the interface nodes: the load and gaps at any factors without assembly.
#[derive(Debug, Clone)]
pub(crate) struct LoadParts {
    bodies: Vec<BodyParts>,
    /// `(body, Dirichlet index, prescribed part of [u]_nu at every node)` of the conditions
    /// that prescribe a value at an interface node.
    lifting: Vec<(usize, usize, Vec<f64>)>,
}

/// The factor of every condition of every body, checked against the problem.
#[derive(Debug, Clone)]
pub(crate) struct LevelFactors {
    bodies: Vec<BodyFactors>,
}

#[derive(Debug, Clone)]
struct BodyFactors {
    body_force: f64,
    dirichlet: Vec<f64>,
    tractions: Vec<f64>,
}

impl LevelFactors {
    /// The factors `factors` on the conditions of `discretisation`.
    ///
    /// # Errors
    /// A factor that is not finite, a condition that does not exist (both named).
    pub(crate) fn resolve<const D: usize>(
        discretisation: &ContactDiscretisation<D>,
        factors: &LoadFactors,
    ) -> Result<Self, ContactError> {
        let bodies = discretisation.bodies();
        let invalid = |reason: String| ContactError::InvalidSetting { reason };
        if !factors.default_factor().is_finite() {
            return Err(invalid(format!(
                "load factor {} (default) is not finite",
                factors.default_factor()
            )));
        }
        for &(condition, factor) in factors.given() {
            if !factor.is_finite() {
                return Err(invalid(format!(
                    "load factor {factor} of the {condition} is not finite"
                )));
            }
            let Some(body) = bodies.get(condition.body()) else {
                return Err(invalid(format!(
                    "load factor of the {condition}: the problem has {} bodies",
                    bodies.len()
                )));
            };
            let exists = match condition {
                LoadCondition::BodyForce { .. } => true,
                LoadCondition::Dirichlet { index, .. } => index < body.dirichlet().len(),
                LoadCondition::Traction { index, .. } => index < body.tractions().len(),
            };
            if !exists {
                return Err(invalid(format!(
                    "load factor of the {condition}: body '{}' has {} Dirichlet conditions and \
                     {} tractions",
                    body.name(),
                    body.dirichlet().len(),
                    body.tractions().len()
                )));
            }
        }
        Ok(Self {
            bodies: bodies
                .iter()
                .enumerate()
                .map(|(b, body)| BodyFactors {
                    body_force: factors.factor(LoadCondition::BodyForce { body: b }),
                    dirichlet: (0..body.dirichlet().len())
                        .map(|index| factors.factor(LoadCondition::Dirichlet { body: b, index }))
                        .collect(),
                    tractions: (0..body.tractions().len())
                        .map(|index| factors.factor(LoadCondition::Traction { body: b, index }))
                        .collect(),
                })
                .collect(),
        })
    }
}

/// How the data of the bodies are scaled at a level (for the load, the gaps and the
/// post-processing of the body solutions).
#[derive(Debug, Clone)]
pub(crate) enum Scaling<'a> {
    /// Every condition by the same factor.
    Uniform(f64),
    /// Each condition by its own factor.
    Factors {
        factors: LevelFactors,
        parts: &'a LoadParts,
    },
}

/// The load vector and the prescribed normal jumps of one level.
#[derive(Debug, Clone)]
pub(crate) struct LoadLevel<'a> {
    /// `f` over every unknown of the problem.
    pub(crate) load: Cow<'a, [f64]>,
    /// The prescribed part of `[u]_nu` at every interface node.
    pub(crate) lifting: Cow<'a, [f64]>,
    pub(crate) scaling: Scaling<'a>,
}

impl LoadLevel<'_> {
    /// The full displacement and the solution of body `k` from its unknowns `free`.
    pub(crate) fn body_solution<const D: usize>(
        &self,
        k: usize,
        body: &ElasticBody<D>,
        system: &AssembledSystem,
        free: &[f64],
    ) -> Result<Solution<D>, ContactError> {
        match &self.scaling {
            Scaling::Uniform(s) => {
                let displacement = system.expand_scaled(free, *s)?;
                Ok(body.solution_scaled(system, displacement, *s)?)
            }
            Scaling::Factors { factors, parts } => {
                let f = &factors.bodies[k];
                let dofs = system.dofs();
                let mut displacement = system.expand(free)?;
                for (((&g, &value), &owner), plate) in dofs
                    .prescribed_dofs()
                    .iter()
                    .zip(dofs.prescribed_values())
                    .zip(dofs.prescribed_owners())
                    .zip(dofs.plate_of_prescribed())
                {
                    if plate.is_none() {
                        displacement[g] = f.dirichlet[owner] * value;
                    }
                }
                let mut load = vec![0.0; dofs.n_dofs()];
                let body_parts = &parts.bodies[k];
                let loads = body_parts
                    .body_force
                    .iter()
                    .map(|p| (f.body_force, p))
                    .chain(f.tractions.iter().copied().zip(&body_parts.tractions));
                for (s, part) in loads {
                    if let Some(values) = &part.load {
                        axpy(s, values, &mut load);
                    }
                }
                Ok(body.solution_with_load(system, displacement, &load)?)
            }
        }
    }
}

/// `y += a x`.
fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    if a == 0.0 {
        return;
    }
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

/// `y += a M x` for a sparse `M` (column storage).
fn matvec_add(m: &SparseColMat<usize, f64>, x: &[f64], a: f64, y: &mut [f64]) {
    let (rows, values) = (m.row_idx(), m.val());
    for (j, &xj) in x.iter().enumerate() {
        if xj == 0.0 {
            continue;
        }
        for p in m.col_range(j) {
            y[rows[p]] += a * values[p] * xj;
        }
    }
}

impl LoadParts {
    /// The parts of every body of `discretisation` and the per-condition prescribed normal
    /// jumps (`lifting`: from [`ContactDiscretisation`]'s rows).
    pub(crate) fn new<const D: usize>(
        bodies: &[ElasticBody<D>],
        systems: &[std::sync::Arc<AssembledSystem>],
        lifting: Vec<(usize, usize, Vec<f64>)>,
    ) -> Result<Self, ContactError> {
        let mut parts = Vec::with_capacity(bodies.len());
        for (body, system) in bodies.iter().zip(systems) {
            let dofs = system.dofs();
            let (n_free, n_unknowns) = (dofs.n_free(), dofs.n_unknowns());
            // The right-hand side of a load vector over every global dof: its free values,
            // and the sum over the members of each plate.
            let rhs_of = |load: &[f64]| {
                let mut rhs = vec![0.0; n_unknowns];
                for (i, &g) in dofs.free_dofs().iter().enumerate() {
                    rhs[i] = load[g];
                }
                let prescribed = dofs.prescribed_dofs();
                for (k, plate) in dofs.plates().iter().enumerate() {
                    rhs[n_free + k] = plate.members.iter().map(|&p| load[prescribed[p]]).sum();
                }
                rhs
            };
            let mut tractions = Vec::with_capacity(body.tractions().len());
            for index in 0..body.tractions().len() {
                let load = body.traction_load(index)?;
                tractions.push(ConditionPart {
                    rhs: rhs_of(&load),
                    load: Some(load),
                });
            }
            let body_force = body.has_body_force().then(|| {
                // The assembled load less the tractions'.
                let mut load = system.load().to_vec();
                for t in &tractions {
                    axpy(-1.0, t.load.as_deref().unwrap_or(&[]), &mut load);
                }
                ConditionPart {
                    rhs: rhs_of(&load),
                    load: Some(load),
                }
            });
            let mut dirichlet: Vec<Option<ConditionPart>> = vec![None; body.dirichlet().len()];
            let values = dofs.prescribed_values();
            for (c, part) in dirichlet.iter_mut().enumerate() {
                // The lifting -K_fp u_p^c (and -E' K_pp u_p^c on plate rows) of the prescribed
                // values the condition owns; the resultant of a plate on its own rows.
                let owned: Vec<f64> = values
                    .iter()
                    .zip(dofs.prescribed_owners())
                    .map(|(&v, &owner)| if owner == c { v } else { 0.0 })
                    .collect();
                let mut rhs = vec![0.0; n_unknowns];
                let mut nonzero = false;
                if owned.iter().any(|&v| v != 0.0) {
                    matvec_add(system.coupling(), &owned, -1.0, &mut rhs[..n_free]);
                    if dofs.n_plates() > 0 {
                        let mut k_pp_u = vec![0.0; dofs.n_prescribed()];
                        matvec_add(system.prescribed_block(), &owned, 1.0, &mut k_pp_u);
                        for (k, plate) in dofs.plates().iter().enumerate() {
                            rhs[n_free + k] -=
                                plate.members.iter().map(|&p| k_pp_u[p]).sum::<f64>();
                        }
                    }
                    nonzero = true;
                }
                for (k, plate) in dofs.plates().iter().enumerate() {
                    if plate.condition == c && plate.resultant != 0.0 {
                        rhs[n_free + k] += plate.resultant;
                        nonzero = true;
                    }
                }
                if nonzero {
                    *part = Some(ConditionPart { rhs, load: None });
                }
            }
            parts.push(BodyParts {
                body_force,
                dirichlet,
                tractions,
            });
        }
        Ok(Self {
            bodies: parts,
            lifting,
        })
    }

    /// The level of the factors `factors`: `f = sum_c s_c f_c` over the bodies (at `offsets`)
    /// and the prescribed normal jumps `sum_c s_c [u_D,c]_nu`.
    pub(crate) fn level<const D: usize>(
        &self,
        discretisation: &ContactDiscretisation<D>,
        factors: LevelFactors,
    ) -> LoadLevel<'_> {
        let offsets = discretisation.offsets();
        let mut load = vec![0.0; discretisation.n_dofs()];
        for (k, (parts, f)) in self.bodies.iter().zip(&factors.bodies).enumerate() {
            let y = &mut load[offsets[k]..offsets[k + 1]];
            if let Some(p) = &parts.body_force {
                axpy(f.body_force, &p.rhs, y);
            }
            for (p, &s) in parts.tractions.iter().zip(&f.tractions) {
                axpy(s, &p.rhs, y);
            }
            for (p, &s) in parts.dirichlet.iter().zip(&f.dirichlet) {
                if let Some(p) = p {
                    axpy(s, &p.rhs, y);
                }
            }
        }
        let mut lifting = vec![0.0; discretisation.nodes().len()];
        for (body, index, values) in &self.lifting {
            axpy(
                factors.bodies[*body].dirichlet[*index],
                values,
                &mut lifting,
            );
        }
        LoadLevel {
            load: Cow::Owned(load),
            lifting: Cow::Owned(lifting),
            scaling: Scaling::Factors {
                factors,
                parts: self,
            },
        }
    }
}
