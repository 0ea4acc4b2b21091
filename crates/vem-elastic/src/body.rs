//! One elastic body: mesh, material, element, boundary conditions; assembly and solve.

use std::fmt;
use std::sync::Arc;

use nalgebra::DVector;
use vem_mesh::{Mesh, Point, Vector};
use vem_space::quadrature::GaussLegendre;
use vem_space::{edge_traction_load, ElasticityTensor, ElementSpace};

use crate::assembly::ElementContribution;
use crate::boundary::VectorField;
use crate::post::{ElementField, PartReaction, Solution};
use crate::{
    AssembledSystem, CholeskySettings, CholeskySolver, Component, Dirichlet, DofMap, ElasticError,
    LinearSolver, Material, SolveError, Traction,
};

/// A linear elastic body discretised by an [`ElementSpace`] on a polygonal mesh, with its
/// boundary conditions (by boundary-part name) and body force. Built and validated by
/// [`ElasticBody::builder`].
#[derive(Clone)]
pub struct ElasticBody {
    name: String,
    mesh: Arc<Mesh>,
    material: Material,
    tensor: ElasticityTensor,
    element: Arc<dyn ElementSpace>,
    dirichlet: Vec<Dirichlet>,
    tractions: Vec<Traction>,
    body_force: Option<VectorField>,
    traction_points: usize,
    dofs: DofMap,
}

/// Builder of an [`ElasticBody`]; [`ElasticBodyBuilder::build`] checks everything.
#[derive(Clone)]
pub struct ElasticBodyBuilder {
    name: String,
    mesh: Arc<Mesh>,
    material: Material,
    element: Arc<dyn ElementSpace>,
    dirichlet: Vec<Dirichlet>,
    tractions: Vec<Traction>,
    body_force: Option<VectorField>,
    traction_points: usize,
}

impl ElasticBodyBuilder {
    /// The default number of Gauss points per edge for tractions: 2, exact for tractions
    /// quadratic along the edge (the integrand, traction times the linear trace, is cubic).
    pub const DEFAULT_TRACTION_POINTS: usize = 2;

    /// Adds a Dirichlet condition.
    pub fn dirichlet(mut self, condition: Dirichlet) -> Self {
        self.dirichlet.push(condition);
        self
    }

    /// Clamps `part`: zero displacement in both components.
    pub fn clamp(self, part: impl Into<String>) -> Self {
        self.dirichlet(Dirichlet::fixed(part, Component::Both))
    }

    /// Adds a traction `g(x)` on `part`.
    pub fn traction(
        mut self,
        part: impl Into<String>,
        traction: impl Fn(Point) -> Vector + Send + Sync + 'static,
    ) -> Self {
        self.tractions.push(Traction::new(part, traction));
        self
    }

    /// Sets the body force `f(x)` (per unit area).
    pub fn body_force(mut self, force: impl Fn(Point) -> Vector + Send + Sync + 'static) -> Self {
        self.body_force = Some(Arc::new(force));
        self
    }

    /// Sets the number of Gauss–Legendre points per edge for tractions (exact for tractions
    /// of degree `2 points - 2` along the edge).
    pub fn traction_points(mut self, points: usize) -> Self {
        self.traction_points = points;
        self
    }

    /// Checks the material, that the element supports every polygon of the mesh
    /// ([`ElementSpace::supports`]), the quadrature setting, that every named part exists and
    /// that the Dirichlet data are finite and consistent, and builds the body.
    pub fn build(self) -> Result<ElasticBody, ElasticError> {
        let tensor = self.material.tensor()?;
        if let Some((polygon, vertices)) = self
            .mesh
            .polygons()
            .map(<[usize]>::len)
            .enumerate()
            .find(|&(_, n)| !self.element.supports(n))
        {
            return Err(ElasticError::UnsupportedPolygon {
                body: self.name,
                element: self.element.name().to_string(),
                polygon,
                vertices,
            });
        }
        GaussLegendre::try_new(self.traction_points).map_err(|e| ElasticError::InvalidSetting {
            reason: format!("traction_points = {}: {e}", self.traction_points),
        })?;
        for traction in &self.tractions {
            self.mesh
                .part(traction.part())
                .map_err(|source| ElasticError::Mesh {
                    body: self.name.clone(),
                    source,
                })?;
        }
        let dofs = DofMap::new(&self.mesh, &self.dirichlet, &self.name)?;
        Ok(ElasticBody {
            name: self.name,
            mesh: self.mesh,
            material: self.material,
            tensor,
            element: self.element,
            dirichlet: self.dirichlet,
            tractions: self.tractions,
            body_force: self.body_force,
            traction_points: self.traction_points,
            dofs,
        })
    }
}

impl ElasticBody {
    /// Starts a body named `name` (used in every error and report) on `mesh`.
    pub fn builder(
        name: impl Into<String>,
        mesh: impl Into<Arc<Mesh>>,
        material: Material,
        element: Arc<dyn ElementSpace>,
    ) -> ElasticBodyBuilder {
        ElasticBodyBuilder {
            name: name.into(),
            mesh: mesh.into(),
            material,
            element,
            dirichlet: Vec::new(),
            tractions: Vec::new(),
            body_force: None,
            traction_points: ElasticBodyBuilder::DEFAULT_TRACTION_POINTS,
        }
    }

    /// The same body (material, element, conditions) on another mesh that has the same
    /// boundary-part names, e.g. the mesh enlarged by interface node insertion. The degrees of
    /// freedom are rebuilt and everything is checked again on the new mesh (as by
    /// [`ElasticBodyBuilder::build`]: an element that does not support a polygon that gained
    /// vertices is [`ElasticError::UnsupportedPolygon`]).
    pub fn with_mesh(&self, mesh: impl Into<Arc<Mesh>>) -> Result<Self, ElasticError> {
        ElasticBodyBuilder {
            name: self.name.clone(),
            mesh: mesh.into(),
            material: self.material,
            element: Arc::clone(&self.element),
            dirichlet: self.dirichlet.clone(),
            tractions: self.tractions.clone(),
            body_force: self.body_force.clone(),
            traction_points: self.traction_points,
        }
        .build()
    }

    /// The same body with another material (same mesh, conditions and degrees of freedom:
    /// its systems can be refilled with [`ElasticBody::reassemble`]).
    pub fn with_material(&self, material: Material) -> Result<Self, ElasticError> {
        let tensor = material.tensor()?;
        Ok(Self {
            material,
            tensor,
            ..self.clone()
        })
    }

    /// The body's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The shared mesh.
    pub fn mesh_arc(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The element's elasticity tensor.
    pub fn tensor(&self) -> &ElasticityTensor {
        &self.tensor
    }

    /// The element space.
    pub fn element(&self) -> &dyn ElementSpace {
        &*self.element
    }

    /// The Dirichlet conditions, in the order given.
    pub fn dirichlet(&self) -> &[Dirichlet] {
        &self.dirichlet
    }

    /// The tractions, in the order given.
    pub fn tractions(&self) -> &[Traction] {
        &self.tractions
    }

    /// The number of Gauss points per edge for tractions.
    pub fn traction_points(&self) -> usize {
        self.traction_points
    }

    /// The split into free and prescribed degrees of freedom.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// Builds the pattern and assembles stiffness, load and Dirichlet lifting (in parallel).
    pub fn assemble(&self) -> Result<AssembledSystem, ElasticError> {
        let mut system = AssembledSystem::with_pattern(&self.name, &self.mesh, self.dofs.clone());
        self.fill(&mut system)?;
        Ok(system)
    }

    /// Recomputes the values of `system` (built by [`ElasticBody::assemble`] for this mesh and
    /// these Dirichlet conditions) on its existing pattern. If an element fails, the error is
    /// returned and the values of `system` are incomplete until the next successful call.
    pub fn reassemble(&self, system: &mut AssembledSystem) -> Result<(), ElasticError> {
        if !system.matches(&self.mesh, &self.dofs) {
            return Err(ElasticError::ForeignSystem {
                body: self.name.clone(),
            });
        }
        self.fill(system)
    }

    fn fill(&self, system: &mut AssembledSystem) -> Result<(), ElasticError> {
        system.clear_values();
        system.scatter_elements(|p| self.element_contribution(p))?;
        for traction in &self.tractions {
            let part = self
                .mesh
                .part(traction.part())
                .map_err(|source| ElasticError::Mesh {
                    body: self.name.clone(),
                    source,
                })?;
            for &e in &part.edges {
                let [a, b] = self.mesh.edge(e).vertices;
                let load = edge_traction_load(
                    self.mesh.vertex(a),
                    self.mesh.vertex(b),
                    &|x| traction.value_at(x),
                    self.traction_points,
                )
                .map_err(|source| ElasticError::Traction {
                    body: self.name.clone(),
                    part: traction.part().to_string(),
                    a,
                    b,
                    source,
                })?;
                system.add_load(&[2 * a, 2 * a + 1, 2 * b, 2 * b + 1], &load);
            }
        }
        system.finish_rhs();
        Ok(())
    }

    /// The local matrix `consistency + stabilisation` and body load of polygon `p`.
    fn element_contribution(&self, p: usize) -> Result<ElementContribution, ElasticError> {
        let points = self.mesh.polygon_points(p);
        let element_error = |source| ElasticError::Element {
            body: self.name.clone(),
            polygon: p,
            source,
        };
        let expected = 2 * points.len();
        let size_error = |what, found| ElasticError::ElementSize {
            body: self.name.clone(),
            polygon: p,
            vertices: points.len(),
            what,
            found,
            expected,
        };
        let matrix = self
            .element
            .stiffness(&points, &self.tensor)
            .map_err(element_error)?
            .total();
        if matrix.nrows() != expected || matrix.ncols() != expected {
            return Err(size_error("a stiffness matrix", matrix.nrows()));
        }
        let load = match &self.body_force {
            Some(force) => {
                let load = self
                    .element
                    .body_load(&points, &**force)
                    .map_err(element_error)?;
                if load.len() != expected {
                    return Err(size_error("a load vector", load.len()));
                }
                Some(load)
            }
            None => None,
        };
        let dofs = self
            .mesh
            .polygon(p)
            .iter()
            .flat_map(|&v| [2 * v, 2 * v + 1])
            .collect();
        Ok(ElementContribution { dofs, matrix, load })
    }

    /// Assembles and solves with the default sparse Cholesky solver.
    pub fn solve(&self) -> Result<Solution, ElasticError> {
        self.solve_with(&mut CholeskySolver::default())
    }

    /// Assembles and solves with `solver` (analyse, factorise, solve).
    pub fn solve_with(&self, solver: &mut dyn LinearSolver) -> Result<Solution, ElasticError> {
        let system = self.assemble()?;
        self.solve_system(&system, solver)
    }

    /// Solves the assembled `system` with `solver` (analyse, factorise, solve) and
    /// post-processes: full displacement, reactions, strain energy. A non-positive-definite
    /// stiffness is [`ElasticError::SingularStiffness`] when the Dirichlet conditions leave a
    /// rigid motion free ([`ElasticBody::holds_rigid_motions`]); for a held body (badly shaped
    /// elements) it is factorised again accepting any positive pivot, and the answer is kept if
    /// it solves the system to `1e-8` relative, else [`ElasticError::IllConditioned`] names the
    /// worst element.
    pub fn solve_system(
        &self,
        system: &AssembledSystem,
        solver: &mut dyn LinearSolver,
    ) -> Result<Solution, ElasticError> {
        let u_free = if system.dofs().n_unknowns() == 0 {
            Vec::new()
        } else {
            let map = |e| ElasticError::from_solver(&self.name, e);
            solver.analyse(system.stiffness().symbolic()).map_err(map)?;
            match solver.factorise(system.stiffness().as_ref()) {
                Ok(()) => solver.solve(system.rhs()).map_err(map)?,
                Err(SolveError::NotPositiveDefinite { .. }) if self.holds_rigid_motions() => {
                    self.solve_ill_conditioned(system)?
                }
                Err(e) => return Err(map(e)),
            }
        };
        let displacement = system.expand(&u_free)?;
        self.solution(system, displacement)
    }

    /// True when the Dirichlet conditions fix the three rigid motions (rigid plates do not
    /// count: their translations are unknowns; the translations and
    /// the rotation about the centroid of the prescribed vertices): the prescribed components
    /// of the rigid motions, as columns, have rank 3 (their correlation matrix has a
    /// determinant above `1e-12`). A body that is not held has a singular stiffness whatever
    /// its mesh; a held body's stiffness is positive definite in exact arithmetic.
    pub fn holds_rigid_motions(&self) -> bool {
        let dofs = self.dofs();
        // A rigid plate (force control) holds nothing: its translation is an unknown.
        let points: Vec<(Point, usize)> = dofs
            .prescribed_dofs()
            .iter()
            .zip(dofs.plate_of_prescribed())
            .filter(|(_, plate)| plate.is_none())
            .map(|(&dof, _)| (self.mesh.vertex(dof / 2), dof % 2))
            .collect();
        if points.is_empty() {
            return false;
        }
        let n = points.len() as f64;
        let centre = points
            .iter()
            .fold(Vector::zeros(), |c, (p, _)| c + p.coords)
            / n;
        let extent = points
            .iter()
            .fold(0.0f64, |e, (p, _)| e.max((p.coords - centre).norm()));
        // Rows of the rigid motions (t_x, t_y, rotation) at each prescribed component.
        let mut gram = [[0.0f64; 3]; 3];
        for (p, component) in &points {
            let r = (p.coords - centre) / if extent > 0.0 { extent } else { 1.0 };
            let row = if *component == 0 {
                [1.0, 0.0, -r.y]
            } else {
                [0.0, 1.0, r.x]
            };
            for a in 0..3 {
                for b in 0..3 {
                    gram[a][b] += row[a] * row[b];
                }
            }
        }
        if (0..3).any(|a| gram[a][a] <= 0.0) {
            return false;
        }
        let c = |a: usize, b: usize| gram[a][b] / (gram[a][a] * gram[b][b]).sqrt();
        let det = c(0, 0) * (c(1, 1) * c(2, 2) - c(1, 2) * c(2, 1))
            - c(0, 1) * (c(1, 0) * c(2, 2) - c(1, 2) * c(2, 0))
            + c(0, 2) * (c(1, 0) * c(2, 1) - c(1, 1) * c(2, 0));
        det > 1e-12
    }

    /// A held body whose factorisation was refused for a tiny pivot (badly shaped elements):
    /// factorise again accepting any positive pivot, and keep the answer only if it solves
    /// the system to `1e-8` relative (else [`ElasticError::IllConditioned`], naming the worst
    /// element).
    fn solve_ill_conditioned(&self, system: &AssembledSystem) -> Result<Vec<f64>, ElasticError> {
        let ill = |reason: String| {
            let (element, quality) = (0..self.mesh.n_polygons())
                .map(|p| (p, self.mesh.element_quality(p)))
                .min_by(|a, b| a.1.gamma().total_cmp(&b.1.gamma()))
                .map_or((0, None), |(p, q)| (p, Some(q)));
            ElasticError::IllConditioned {
                body: self.name.clone(),
                reason,
                element,
                gamma: quality.map_or(f64::NAN, |q| q.gamma()),
                diameter: quality.map_or(f64::NAN, |q| q.diameter),
            }
        };
        let settings = CholeskySettings::builder()
            .singular_pivot_tolerance(0.0)
            .build()
            .map_err(|e| ElasticError::from_solver(&self.name, e))?;
        let mut solver = CholeskySolver::new(settings);
        let k = system.stiffness().as_ref();
        solver
            .analyse(system.stiffness().symbolic())
            .map_err(|e| ElasticError::from_solver(&self.name, e))?;
        solver
            .factorise(k)
            .map_err(|e| ill(format!("the Cholesky factorisation failed: {e}")))?;
        let u = solver
            .solve(system.rhs())
            .map_err(|e| ElasticError::from_solver(&self.name, e))?;
        // Relative residual ||K u - f|| / (|| |K||u| || + ||f||).
        let (rows, values) = (k.row_idx(), k.val());
        let mut residual: Vec<f64> = system.rhs().iter().map(|f| -f).collect();
        let mut magnitude: Vec<f64> = system.rhs().iter().map(|f| f.abs()).collect();
        for (j, &uj) in u.iter().enumerate() {
            for p in k.col_range(j) {
                residual[rows[p]] += values[p] * uj;
                magnitude[rows[p]] += (values[p] * uj).abs();
            }
        }
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let relative = inf(&residual) / inf(&magnitude).max(f64::MIN_POSITIVE);
        if relative.is_finite() && relative <= 1e-8 {
            Ok(u)
        } else {
            Err(ill(format!(
                "relative residual {relative:.1e} of the solve"
            )))
        }
    }

    /// Post-processes a full displacement vector: reactions per Dirichlet condition and the
    /// strain energy.
    pub fn solution(
        &self,
        system: &AssembledSystem,
        displacement: Vec<f64>,
    ) -> Result<Solution, ElasticError> {
        self.solution_scaled(system, displacement, 1.0)
    }

    /// [`ElasticBody::solution`] for the loads of `system` scaled by `load_factor` (a load
    /// step: the reactions balance the scaled loads).
    pub fn solution_scaled(
        &self,
        system: &AssembledSystem,
        displacement: Vec<f64>,
        load_factor: f64,
    ) -> Result<Solution, ElasticError> {
        if !system.matches(&self.mesh, &self.dofs) {
            return Err(ElasticError::ForeignSystem {
                body: self.name.clone(),
            });
        }
        let nodal = system.reactions_scaled(&displacement, load_factor)?;
        let reactions = self.gather_reactions(system, nodal);
        let strain_energy = system.strain_energy(&displacement)?;
        Ok(Solution::new(displacement, reactions, strain_energy))
    }

    /// The reaction force on each Dirichlet condition: the sum of `K u - f` over the
    /// prescribed degrees of freedom the condition owns (a degree of freedom shared by two
    /// conditions belongs to the first, see [`DofMap::new`]). With the applied loads they are
    /// in equilibrium: sum of reactions + int f + int g = 0.
    pub fn part_reactions(
        &self,
        system: &AssembledSystem,
        displacement: &[f64],
    ) -> Result<Vec<PartReaction>, ElasticError> {
        let nodal = system.reactions(displacement)?;
        Ok(self.gather_reactions(system, nodal))
    }

    fn gather_reactions(&self, system: &AssembledSystem, nodal: Vec<f64>) -> Vec<PartReaction> {
        let mut forces = vec![Vector::zeros(); self.dirichlet.len()];
        let dofs = system.dofs();
        for ((&g, &owner), r) in dofs
            .prescribed_dofs()
            .iter()
            .zip(dofs.prescribed_owners())
            .zip(nodal)
        {
            forces[owner][g % 2] += r;
        }
        self.dirichlet
            .iter()
            .zip(forces)
            .map(|(condition, force)| PartReaction {
                part: condition.part().to_string(),
                component: condition.component(),
                force,
            })
            .collect()
    }

    /// Strain, stress and von Mises stress of every element from the energy projection of
    /// the full displacement `displacement` (constant per element), computed in parallel.
    pub fn element_fields(&self, displacement: &[f64]) -> Result<Vec<ElementField>, ElasticError> {
        use rayon::prelude::*;
        if displacement.len() != self.dofs.n_dofs() {
            return Err(ElasticError::WrongLength {
                body: self.name.clone(),
                what: "displacement",
                found: displacement.len(),
                expected: self.dofs.n_dofs(),
            });
        }
        (0..self.mesh.n_polygons())
            .into_par_iter()
            .map(|p| {
                let projection = self
                    .element
                    .projection(&self.mesh.polygon_points(p))
                    .map_err(|source| ElasticError::Element {
                        body: self.name.clone(),
                        polygon: p,
                        source,
                    })?;
                let local = DVector::from_iterator(
                    2 * self.mesh.polygon(p).len(),
                    self.mesh
                        .polygon(p)
                        .iter()
                        .flat_map(|&v| [displacement[2 * v], displacement[2 * v + 1]]),
                );
                Ok(ElementField::from_strain(
                    projection.strain(&local),
                    &self.tensor,
                    &self.material,
                ))
            })
            .collect()
    }
}

impl fmt::Debug for ElasticBody {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ElasticBody")
            .field("name", &self.name)
            .field("vertices", &self.mesh.n_vertices())
            .field("polygons", &self.mesh.n_polygons())
            .field("material", &self.material)
            .field("element", &self.element.name())
            .field("dirichlet", &self.dirichlet)
            .field("tractions", &self.tractions)
            .field("body_force", &self.body_force.is_some())
            .field("traction_points", &self.traction_points)
            .finish()
    }
}

impl fmt::Debug for ElasticBodyBuilder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ElasticBodyBuilder")
            .field("name", &self.name)
            .field("element", &self.element.name())
            .field("dirichlet", &self.dirichlet)
            .field("tractions", &self.tractions)
            .finish_non_exhaustive()
    }
}
