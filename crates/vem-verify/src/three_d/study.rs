//! Solves of the exact solutions in space on the polyhedral families, and convergence tables.

use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_elastic::{CholeskySolver, Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::{PolyhedralMesh, Vector3};
use vem_space::PolyhedralElement;

use super::norms::{body_errors_3d, nodal_interpolant_3d};
use super::{ExactSolution3d, CUBE_PARTS};
use crate::norms::ErrorNorms;
use crate::study::fitted_rate;
use crate::VerifyError;

/// The seed of the random families (perturbed hexahedra, Voronoi) in the studies.
pub const SOLID_SEED: u64 = 1;

/// One solve of an exact solution in space on one mesh, with what it measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidRun {
    /// The case ("E1-3D", ...).
    pub case: String,
    /// The mesh family.
    pub family: String,
    /// The element ("vem1", "vem1-bbar", ...).
    pub element: String,
    /// The size parameter (cells across x).
    pub n: usize,
    /// Number of cells.
    pub cells: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of unknowns of the reduced system.
    pub unknowns: usize,
    /// Mesh size `h` (largest cell diameter).
    pub h: f64,
    /// The mean cell size `(|Omega| / cells)^(1/3)`: what the rates are fitted against (the
    /// largest diameter of a random mesh is an outlier statistic that does not halve exactly
    /// when the cells are eight times as many; for the structured families the two are
    /// proportional).
    pub spacing: f64,
    /// `E_grad`, `E_0`, `E_a` and the norms of the exact solution.
    pub errors: ErrorNorms,
    /// `max_v |u_h(v) - u(v)| / max_v |u(v)|` over the vertices.
    pub nodal_error: f64,
    /// Wall-clock seconds of mesh generation, assembly, solve and measures.
    pub seconds: f64,
}

/// The body of `exact` on `mesh` with `element`: the material of the case, the Dirichlet data
/// `u` on every side of the unit cube but the traction sides, `sigma n` on those, the body
/// force `f`.
pub fn solid_body(
    exact: Arc<dyn ExactSolution3d>,
    mesh: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<ElasticBody<3>, VerifyError> {
    let elastic = |source| VerifyError::Elastic {
        case: exact.name().to_string(),
        source: Box::new(source),
    };
    let lame = exact.lame();
    let material = Material::from_lame(lame.lambda(), lame.mu(), Plane::Strain).map_err(elastic)?;
    let mut builder = ElasticBody::builder_polyhedral(exact.name(), mesh, material, element);
    for (part, normal) in CUBE_PARTS {
        let normal = Vector3::from(normal);
        let exact = Arc::clone(&exact);
        builder = if exact.traction_sides().contains(&part) {
            builder.traction(part, move |x| exact.stress(x) * normal)
        } else {
            builder.dirichlet(Dirichlet::with_values(part, Component::All, move |x| {
                exact.displacement(x)
            }))
        };
    }
    let force = Arc::clone(&exact);
    builder
        .body_force(move |x| force.body_force(x))
        .build()
        .map_err(elastic)
}

/// Solves `exact` on `mesh` with `element` and measures the errors.
pub fn solve_solid(
    exact: Arc<dyn ExactSolution3d>,
    mesh: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<(ElasticBody<3>, Vec<f64>, ErrorNorms), VerifyError> {
    let elastic = |source| VerifyError::Elastic {
        case: exact.name().to_string(),
        source: Box::new(source),
    };
    let body = solid_body(Arc::clone(&exact), mesh, element)?;
    let system = body.assemble().map_err(elastic)?;
    let solution = body
        .solve_system(&system, &mut CholeskySolver::default())
        .map_err(elastic)?;
    let displacement = solution.displacement().to_vec();
    let errors = body_errors_3d(&*exact, &body, &system, &displacement)?;
    Ok((body, displacement, errors))
}

/// Generates the mesh of `family` with size `n` on the unit cube and solves `exact` on it.
pub fn run_solid(
    exact: Arc<dyn ExactSolution3d>,
    family: PolyhedralFamily,
    n: usize,
    element: Arc<dyn PolyhedralElement>,
) -> Result<SolidRun, VerifyError> {
    let start = Instant::now();
    let mesh = family
        .generate(&Cuboid::unit_cube(), n, SOLID_SEED)
        .map_err(|source| VerifyError::Mesh {
            case: exact.name().to_string(),
            body: 1,
            family: family.name().to_string(),
            n,
            source: Box::new(source),
        })?;
    let (cells, vertices, h) = (mesh.n_cells(), mesh.n_vertices(), mesh.mesh_size());
    let element_name = element.name().to_string();
    let (body, displacement, errors) = solve_solid(Arc::clone(&exact), mesh, element)?;
    let interpolant = nodal_interpolant_3d(&*exact, body.mesh());
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, f64::max);
    let difference = largest(
        &mut interpolant
            .chunks(3)
            .zip(displacement.chunks(3))
            .map(|(a, b)| Vector3::from_column_slice(a) - Vector3::from_column_slice(b))
            .map(|d| d.norm()),
    );
    let scale = largest(
        &mut interpolant
            .chunks(3)
            .map(|a| Vector3::from_column_slice(a).norm()),
    );
    Ok(SolidRun {
        case: exact.name().to_string(),
        family: family.name().to_string(),
        element: element_name,
        n,
        cells,
        vertices,
        unknowns: body.dofs().n_unknowns(),
        h,
        spacing: (1.0 / cells as f64).cbrt(),
        errors,
        nodal_error: if scale > 0.0 {
            difference / scale
        } else {
            difference
        },
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The convergence study in space: every case of `cases` on every family of `families` at
/// every size of `sizes`, with `element`, in that order (case-major). The integrator's entry
/// point for `cargo xtask convergence`; [`solid_rates`] fits the rates of its runs and
/// [`solid_markdown`] prints them.
pub fn three_d_convergence(
    cases: &[Arc<dyn ExactSolution3d>],
    families: &[PolyhedralFamily],
    sizes: &[usize],
    element: Arc<dyn PolyhedralElement>,
) -> Result<Vec<SolidRun>, VerifyError> {
    if sizes.is_empty() {
        return Err(VerifyError::InvalidSetting {
            reason: "the study in space needs at least one size".into(),
        });
    }
    let mut runs = Vec::new();
    for case in cases {
        for &family in families {
            for &n in sizes {
                runs.push(run_solid(
                    Arc::clone(case),
                    family,
                    n,
                    Arc::clone(&element),
                )?);
            }
        }
    }
    Ok(runs)
}

/// The fitted rates of one (case, family, element) series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidRates {
    /// The case.
    pub case: String,
    /// The mesh family.
    pub family: String,
    /// The element.
    pub element: String,
    /// The sizes of the series.
    pub sizes: Vec<usize>,
    /// The errors at the finest size.
    pub finest: ErrorNorms,
    /// The mesh size at the finest size.
    pub h: f64,
    /// The least-squares rate of `E_grad` against the mean cell size over the last `fit` sizes.
    pub grad_rate: Option<f64>,
    /// The rate of `E_0`.
    pub l2_rate: Option<f64>,
    /// The rate of `E_a`.
    pub energy_rate: Option<f64>,
}

/// Groups `runs` by (case, family, element), in order of first appearance, and fits each
/// series' rates against the mean cell size ([`SolidRun::spacing`]) by least squares over its
/// last `fit` sizes (at least 2).
pub fn solid_rates(runs: &[SolidRun], fit: usize) -> Vec<SolidRates> {
    let mut keys: Vec<(&str, &str, &str)> = Vec::new();
    for run in runs {
        let key = (run.case.as_str(), run.family.as_str(), run.element.as_str());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(case, family, element)| {
            let series: Vec<&SolidRun> = runs
                .iter()
                .filter(|r| r.case == case && r.family == family && r.element == element)
                .collect();
            let tail = &series[series.len().saturating_sub(fit.max(2))..];
            let h: Vec<f64> = tail.iter().map(|r| r.spacing).collect();
            let rate = |f: fn(&ErrorNorms) -> f64| {
                let e: Vec<f64> = tail.iter().map(|r| f(&r.errors)).collect();
                fitted_rate(&h, &e)
            };
            let last = series.last().expect("a series has a run");
            SolidRates {
                case: case.to_string(),
                family: family.to_string(),
                element: element.to_string(),
                sizes: series.iter().map(|r| r.n).collect(),
                finest: last.errors,
                h: last.h,
                grad_rate: rate(|e| e.grad),
                l2_rate: rate(|e| e.l2),
                energy_rate: rate(|e| e.energy),
            }
        })
        .collect()
}

/// The runs and the fitted rates as Markdown tables: one row per run, then one per series.
pub fn solid_markdown(runs: &[SolidRun], rates: &[SolidRates]) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| case | family | element | n | cells | unknowns | h | E_grad / abs1 | E_0 / abs0 | E_a | seconds |"
    );
    let _ = writeln!(out, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in runs {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {:.4} | {:.3e} | {:.3e} | {:.3e} | {:.1} |",
            r.case,
            r.family,
            r.element,
            r.n,
            r.cells,
            r.unknowns,
            r.h,
            r.errors.relative_grad(),
            r.errors.relative_l2(),
            r.errors.energy,
            r.seconds
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "| case | family | element | sizes | E_grad rate | E_0 rate | E_a rate | E_grad, E_0 at finest |"
    );
    let _ = writeln!(out, "|---|---|---|---|---:|---:|---:|---|");
    let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}"));
    for r in rates {
        let sizes: Vec<String> = r.sizes.iter().map(|n| n.to_string()).collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {:.3e}, {:.3e} |",
            r.case,
            r.family,
            r.element,
            sizes.join(", "),
            show(r.grad_rate),
            show(r.l2_rate),
            show(r.energy_rate),
            r.finest.grad,
            r.finest.l2
        );
    }
    out
}
