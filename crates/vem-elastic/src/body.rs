//! One elastic body: mesh, material, element, boundary conditions; assembly and solve, in two
//! or three dimensions.

use std::fmt;
use std::sync::Arc;

use nalgebra::DVector;
use vem_mesh::{BodyMesh, Mesh, PointD, VectorD};
use vem_space::quadrature::GaussLegendre;
use vem_space::{ElasticityTensor, ElementSpace, LocalStiffness, MeshElement, PlanarElement};

use crate::assembly::ElementContribution;
use crate::boundary::VectorField;
use crate::post::{ElementField, PartReaction, Solution};
use crate::{
    AssembledSystem, CholeskySettings, CholeskySolver, Component, Dirichlet, DofMap, ElasticError,
    LinearSolver, Material, SolveError, Traction,
};

/// A linear elastic body in `R^D` (`D = 2` by default) discretised by an element
/// ([`MeshElement`]) on a mesh ([`BodyMesh`]), with its boundary conditions (by boundary-part
/// name) and body force. Built and validated by [`ElasticBody::builder`] (2D, from a polygonal
/// [`Mesh`] and an [`ElementSpace`]) or [`ElasticBody::builder_on`] (any dimension).
#[derive(Clone)]
pub struct ElasticBody<const D: usize = 2> {
    name: String,
    mesh: Arc<dyn BodyMesh<D>>,
    material: Material,
    tensor: ElasticityTensor<D>,
    element: Arc<dyn MeshElement<D>>,
    dirichlet: Vec<Dirichlet<D>>,
    tractions: Vec<Traction<D>>,
    body_force: Option<VectorField<D>>,
    traction_points: usize,
    dofs: DofMap,
}

/// Builder of an [`ElasticBody`]; [`ElasticBodyBuilder::build`] checks everything.
#[derive(Clone)]
pub struct ElasticBodyBuilder<const D: usize = 2> {
    name: String,
    mesh: Arc<dyn BodyMesh<D>>,
    material: Material,
    element: Arc<dyn MeshElement<D>>,
    dirichlet: Vec<Dirichlet<D>>,
    tractions: Vec<Traction<D>>,
    body_force: Option<VectorField<D>>,
    traction_points: usize,
}

impl<const D: usize> ElasticBodyBuilder<D> {
    /// The default number of Gauss points per facet direction for tractions: 2, exact for
    /// tractions quadratic along an edge (the integrand, traction times the linear trace, is
    /// cubic).
    pub const DEFAULT_TRACTION_POINTS: usize = 2;

    /// Adds a Dirichlet condition.
    pub fn dirichlet(mut self, condition: Dirichlet<D>) -> Self {
        self.dirichlet.push(condition);
        self
    }

    /// Clamps `part`: zero displacement in every component.
    pub fn clamp(self, part: impl Into<String>) -> Self {
        self.dirichlet(Dirichlet::fixed(part, Component::All))
    }

    /// Adds a traction `g(x)` on `part`.
    pub fn traction(
        mut self,
        part: impl Into<String>,
        traction: impl Fn(PointD<D>) -> VectorD<D> + Send + Sync + 'static,
    ) -> Self {
        self.tractions.push(Traction::field(part, traction));
        self
    }

    /// Adds a traction condition (e.g. a normal pressure, [`Traction::try_normal_pressure`]).
    pub fn traction_condition(mut self, traction: Traction<D>) -> Self {
        self.tractions.push(traction);
        self
    }

    /// Sets the body force `f(x)` (per unit area in 2D, per unit volume in 3D).
    pub fn body_force(
        mut self,
        force: impl Fn(PointD<D>) -> VectorD<D> + Send + Sync + 'static,
    ) -> Self {
        self.body_force = Some(Arc::new(force));
        self
    }

    /// Sets the number of Gauss–Legendre points per facet direction for tractions (exact for
    /// tractions of degree `2 points - 2` along an edge).
    pub fn traction_points(mut self, points: usize) -> Self {
        self.traction_points = points;
        self
    }

    /// Checks the material, that the element supports every cell of the mesh
    /// ([`MeshElement::supports`]), the quadrature setting, that every named part exists and
    /// that the Dirichlet data are finite and consistent, and builds the body.
    pub fn build(self) -> Result<ElasticBody<D>, ElasticError> {
        let tensor = self.material.elasticity_tensor::<D>()?;
        if let Some(cell) =
            (0..self.mesh.n_cells()).find(|&c| !self.element.supports(&*self.mesh, c))
        {
            return Err(ElasticError::UnsupportedPolygon {
                body: self.name,
                element: self.element.name().to_string(),
                polygon: cell,
                vertices: self.mesh.cell_vertices(cell).len(),
            });
        }
        GaussLegendre::try_new(self.traction_points).map_err(|e| ElasticError::InvalidSetting {
            reason: format!("traction_points = {}: {e}", self.traction_points),
        })?;
        for traction in &self.tractions {
            self.mesh
                .part_facets(traction.part())
                .map_err(|source| ElasticError::Mesh {
                    body: self.name.clone(),
                    source,
                })?;
        }
        let dofs = DofMap::with_layout(
            &*self.mesh,
            self.element.dof_layout(),
            &self.dirichlet,
            &self.name,
        )?;
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

impl ElasticBody<2> {
    /// Starts a planar body named `name` (used in every error and report) on the polygonal
    /// mesh `mesh`, discretised by the element `element`.
    pub fn builder(
        name: impl Into<String>,
        mesh: impl Into<Arc<Mesh>>,
        material: Material,
        element: Arc<dyn ElementSpace>,
    ) -> ElasticBodyBuilder<2> {
        let mesh: Arc<Mesh> = mesh.into();
        Self::builder_on(name, mesh, material, Arc::new(PlanarElement::new(element)))
    }

    /// The polygonal mesh.
    pub fn mesh(&self) -> &Mesh {
        self.mesh
            .as_planar()
            .expect("vem_mesh::Mesh is the only planar BodyMesh")
    }

    /// The same body (material, element, conditions) on another polygonal mesh that has the
    /// same boundary-part names, e.g. the mesh enlarged by interface node insertion. The degrees
    /// of freedom are rebuilt and everything is checked again on the new mesh (as by
    /// [`ElasticBodyBuilder::build`]: an element that does not support a polygon that gained
    /// vertices is [`ElasticError::UnsupportedPolygon`]).
    pub fn with_mesh(&self, mesh: impl Into<Arc<Mesh>>) -> Result<Self, ElasticError> {
        let mesh: Arc<Mesh> = mesh.into();
        self.on_mesh(mesh)
    }
}

impl<const D: usize> ElasticBody<D> {
    /// Starts a body named `name` on `mesh` in any dimension, discretised by `element`.
    pub fn builder_on(
        name: impl Into<String>,
        mesh: Arc<dyn BodyMesh<D>>,
        material: Material,
        element: Arc<dyn MeshElement<D>>,
    ) -> ElasticBodyBuilder<D> {
        ElasticBodyBuilder {
            name: name.into(),
            mesh,
            material,
            element,
            dirichlet: Vec::new(),
            tractions: Vec::new(),
            body_force: None,
            traction_points: ElasticBodyBuilder::<D>::DEFAULT_TRACTION_POINTS,
        }
    }

    /// The same body (material, element, conditions) on another mesh with the same part names
    /// (see [`ElasticBody::with_mesh`]).
    pub fn on_mesh(&self, mesh: Arc<dyn BodyMesh<D>>) -> Result<Self, ElasticError> {
        ElasticBodyBuilder {
            name: self.name.clone(),
            mesh,
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
        let tensor = material.elasticity_tensor::<D>()?;
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

    /// The mesh, as the layers above see it in any dimension.
    pub fn body_mesh(&self) -> &dyn BodyMesh<D> {
        &*self.mesh
    }

    /// The shared mesh.
    pub fn mesh_arc(&self) -> &Arc<dyn BodyMesh<D>> {
        &self.mesh
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The element's elasticity tensor.
    pub fn tensor(&self) -> &ElasticityTensor<D> {
        &self.tensor
    }

    /// The element.
    pub fn element(&self) -> &dyn MeshElement<D> {
        &*self.element
    }

    /// The Dirichlet conditions, in the order given.
    pub fn dirichlet(&self) -> &[Dirichlet<D>] {
        &self.dirichlet
    }

    /// The tractions, in the order given.
    pub fn tractions(&self) -> &[Traction<D>] {
        &self.tractions
    }

    /// The number of Gauss points per facet direction for tractions.
    pub fn traction_points(&self) -> usize {
        self.traction_points
    }

    /// The numbering of the degrees of freedom and their split into free and prescribed ones.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// Builds the pattern and assembles stiffness, load and Dirichlet lifting (in parallel).
    pub fn assemble(&self) -> Result<AssembledSystem, ElasticError> {
        // A new system's values are zero: they are first written by the scatter, in parallel.
        let mut system = AssembledSystem::with_pattern(&self.name, &*self.mesh, self.dofs.clone());
        self.fill(&mut system)?;
        Ok(system)
    }

    /// Recomputes the values of `system` (built by [`ElasticBody::assemble`] for this mesh and
    /// these Dirichlet conditions) on its existing pattern. If an element fails, the error is
    /// returned and the values of `system` are incomplete until the next successful call.
    pub fn reassemble(&self, system: &mut AssembledSystem) -> Result<(), ElasticError> {
        if !system.matches(&*self.mesh, &self.dofs) {
            return Err(ElasticError::ForeignSystem {
                body: self.name.clone(),
            });
        }
        system.clear_values();
        self.fill(system)
    }

    /// Adds every contribution to the values of `system` (zero on entry).
    fn fill(&self, system: &mut AssembledSystem) -> Result<(), ElasticError> {
        system.scatter_elements(|c| self.element_contribution(c))?;
        for traction in &self.tractions {
            self.for_traction_facets(traction, |dofs, load| system.add_load(dofs, load))?;
        }
        system.finish_rhs();
        Ok(())
    }

    /// Calls `add(global dofs, load)` with the load of `traction` on each facet of its part.
    fn for_traction_facets(
        &self,
        traction: &Traction<D>,
        mut add: impl FnMut(&[usize], &[f64]),
    ) -> Result<(), ElasticError> {
        let points = self.mesh.points();
        let mut facet_dofs = Vec::new();
        let facets =
            self.mesh
                .part_facets(traction.part())
                .map_err(|source| ElasticError::Mesh {
                    body: self.name.clone(),
                    source,
                })?;
        for facet in facets {
            let corners: Vec<PointD<D>> = facet.iter().map(|&v| points[v]).collect();
            let load = self
                .element
                .facet_load(&corners, &|x| traction.value_at(x), self.traction_points)
                .map_err(|source| ElasticError::Traction {
                    body: self.name.clone(),
                    part: traction.part().to_string(),
                    facet: facet.to_vec(),
                    source,
                })?;
            facet_dofs.clear();
            self.dofs.cell_dofs(facet, &mut facet_dofs);
            add(&facet_dofs, load.as_slice());
        }
        Ok(())
    }

    /// The load vector (every global degree of freedom) of the traction `index` of
    /// [`ElasticBody::tractions`] alone: the assembled load is the body force's plus the sum of
    /// these (load histories scale each condition by its own factor).
    ///
    /// # Errors
    /// An index out of range, a part that does not exist, an element failure.
    pub fn traction_load(&self, index: usize) -> Result<Vec<f64>, ElasticError> {
        let traction = self
            .tractions
            .get(index)
            .ok_or_else(|| ElasticError::InvalidSetting {
                reason: format!(
                    "body '{}': traction index {index}, the body has {} tractions",
                    self.name,
                    self.tractions.len()
                ),
            })?;
        let mut load = vec![0.0; self.dofs.n_dofs()];
        self.for_traction_facets(traction, |dofs, values| {
            for (&g, &v) in dofs.iter().zip(values) {
                load[g] += v;
            }
        })?;
        Ok(load)
    }

    /// The body force `f(x)`, if the body carries one.
    pub fn body_force(&self) -> Option<&VectorField<D>> {
        self.body_force.as_ref()
    }

    /// True when the body carries a body force.
    pub fn has_body_force(&self) -> bool {
        self.body_force.is_some()
    }

    /// The local matrix `consistency + stabilisation` and body load of cell `c`.
    fn element_contribution(&self, c: usize) -> Result<ElementContribution, ElasticError> {
        let element_error = |source| ElasticError::Element {
            body: self.name.clone(),
            polygon: c,
            source,
        };
        let vertices = self.mesh.cell_vertices(c);
        let expected = self.dofs.layout().cell_dofs(vertices.len());
        let size_error = |what, found| ElasticError::ElementSize {
            body: self.name.clone(),
            polygon: c,
            vertices: vertices.len(),
            what,
            found,
            expected,
        };
        // consistency + stabilisation (`LocalStiffness::total`), summed in place.
        let LocalStiffness {
            consistency: mut matrix,
            stabilisation,
        } = self
            .element
            .stiffness(&*self.mesh, c, &self.tensor)
            .map_err(element_error)?;
        if matrix.shape() != stabilisation.shape() {
            return Err(size_error("a stabilisation", stabilisation.nrows()));
        }
        matrix += &stabilisation;
        if matrix.nrows() != expected || matrix.ncols() != expected {
            return Err(size_error("a stiffness matrix", matrix.nrows()));
        }
        let load = match &self.body_force {
            Some(force) => {
                let load = self
                    .element
                    .body_load(&*self.mesh, c, &**force)
                    .map_err(element_error)?;
                if load.len() != expected {
                    return Err(size_error("a load vector", load.len()));
                }
                Some(load)
            }
            None => None,
        };
        let mut dofs = Vec::with_capacity(expected);
        self.dofs.cell_dofs(vertices, &mut dofs);
        Ok(ElementContribution { dofs, matrix, load })
    }

    /// Assembles and solves with the default sparse Cholesky solver.
    pub fn solve(&self) -> Result<Solution<D>, ElasticError> {
        self.solve_with(&mut CholeskySolver::default())
    }

    /// Assembles and solves with `solver` (analyse, factorise, solve).
    pub fn solve_with(&self, solver: &mut dyn LinearSolver) -> Result<Solution<D>, ElasticError> {
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
    ) -> Result<Solution<D>, ElasticError> {
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

    /// True when the Dirichlet conditions fix every rigid motion (`D` translations and
    /// `D (D - 1) / 2` rotations about the centroid of the prescribed vertices; rigid plates do
    /// not count: their translations are unknowns): the prescribed components of the rigid
    /// motions, as columns, have full rank (their correlation matrix has a determinant above
    /// `1e-12`). A body that is not held has a singular stiffness whatever its mesh; a held
    /// body's stiffness is positive definite in exact arithmetic.
    pub fn holds_rigid_motions(&self) -> bool {
        let dofs = self.dofs();
        let points = self.mesh.points();
        // A rigid plate (force control) holds nothing: its translation is an unknown.
        let held: Vec<(PointD<D>, usize)> = dofs
            .prescribed_dofs()
            .iter()
            .zip(dofs.plate_of_prescribed())
            .filter(|(_, plate)| plate.is_none())
            .map(|(&dof, _)| {
                let (vertex, component) = dofs.vertex_of(dof);
                (points[vertex], component)
            })
            .collect();
        if held.is_empty() {
            return false;
        }
        let n = held.len() as f64;
        let centre = held
            .iter()
            .fold(VectorD::<D>::zeros(), |c, (p, _)| c + p.coords)
            / n;
        let extent = held
            .iter()
            .fold(0.0f64, |e, (p, _)| e.max((p.coords - centre).norm()));
        let scale = if extent > 0.0 { extent } else { 1.0 };
        // The rigid motions: D translations, then the rotations in the planes (a, b), a < b,
        // whose component c at r is r_a delta_cb - r_b delta_ca.
        let rotations: Vec<(usize, usize)> = (0..D)
            .flat_map(|a| (a + 1..D).map(move |b| (a, b)))
            .collect();
        let modes = D + rotations.len();
        let mut gram = nalgebra::DMatrix::<f64>::zeros(modes, modes);
        let mut row = vec![0.0; modes];
        for (p, component) in &held {
            let r = (p.coords - centre) / scale;
            row.iter_mut().for_each(|x| *x = 0.0);
            row[*component] = 1.0;
            for (k, &(a, b)) in rotations.iter().enumerate() {
                row[D + k] = if *component == b {
                    r[a]
                } else if *component == a {
                    -r[b]
                } else {
                    0.0
                };
            }
            for a in 0..modes {
                for b in 0..modes {
                    gram[(a, b)] += row[a] * row[b];
                }
            }
        }
        if (0..modes).any(|a| gram[(a, a)] <= 0.0) {
            return false;
        }
        let correlation = nalgebra::DMatrix::from_fn(modes, modes, |a, b| {
            gram[(a, b)] / (gram[(a, a)] * gram[(b, b)]).sqrt()
        });
        correlation.determinant() > 1e-12
    }

    /// A held body whose factorisation was refused for a tiny pivot (badly shaped elements):
    /// factorise again accepting any positive pivot, and keep the answer only if it solves
    /// the system to `1e-8` relative (else [`ElasticError::IllConditioned`], naming the worst
    /// element).
    fn solve_ill_conditioned(&self, system: &AssembledSystem) -> Result<Vec<f64>, ElasticError> {
        let ill = |reason: String| {
            let (element, quality) = (0..self.mesh.n_cells())
                .map(|c| (c, self.mesh.cell_quality(c)))
                .min_by(|a, b| a.1.gamma().total_cmp(&b.1.gamma()))
                .map_or((0, None), |(c, q)| (c, Some(q)));
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
    ) -> Result<Solution<D>, ElasticError> {
        self.solution_scaled(system, displacement, 1.0)
    }

    /// [`ElasticBody::solution`] for the loads of `system` scaled by `load_factor` (a load
    /// step: the reactions balance the scaled loads).
    pub fn solution_scaled(
        &self,
        system: &AssembledSystem,
        displacement: Vec<f64>,
        load_factor: f64,
    ) -> Result<Solution<D>, ElasticError> {
        if !system.matches(&*self.mesh, &self.dofs) {
            return Err(ElasticError::ForeignSystem {
                body: self.name.clone(),
            });
        }
        let nodal = system.reactions_scaled(&displacement, load_factor)?;
        let reactions = self.gather_reactions(system, nodal);
        let strain_energy = system.strain_energy(&displacement)?;
        Ok(Solution::new(displacement, reactions, strain_energy))
    }

    /// [`ElasticBody::solution`] with the load vector `load` (every global degree of freedom)
    /// in place of the assembled one: the reactions balance `load` (a step of a load history
    /// whose body force and tractions carry different factors).
    ///
    /// # Errors
    /// A system of another body, vectors of the wrong length.
    pub fn solution_with_load(
        &self,
        system: &AssembledSystem,
        displacement: Vec<f64>,
        load: &[f64],
    ) -> Result<Solution<D>, ElasticError> {
        if !system.matches(&*self.mesh, &self.dofs) {
            return Err(ElasticError::ForeignSystem {
                body: self.name.clone(),
            });
        }
        let nodal = system.reactions_with_load(&displacement, load)?;
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
    ) -> Result<Vec<PartReaction<D>>, ElasticError> {
        let nodal = system.reactions(displacement)?;
        Ok(self.gather_reactions(system, nodal))
    }

    fn gather_reactions(&self, system: &AssembledSystem, nodal: Vec<f64>) -> Vec<PartReaction<D>> {
        let mut forces = vec![VectorD::<D>::zeros(); self.dirichlet.len()];
        let dofs = system.dofs();
        for ((&g, &owner), r) in dofs
            .prescribed_dofs()
            .iter()
            .zip(dofs.prescribed_owners())
            .zip(nodal)
        {
            forces[owner][dofs.vertex_of(g).1] += r;
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

    /// The local degrees of freedom of cell `c` taken from the full displacement `displacement`.
    pub fn local_values(&self, c: usize, displacement: &[f64]) -> DVector<f64> {
        // One allocation per cell (the values'), not three: the estimate and the element
        // fields call this for every cell.
        let vertices = self.mesh.cell_vertices(c);
        let mut values = Vec::with_capacity(self.dofs.components() * vertices.len());
        values.extend(self.dofs.cell_dof_iter(vertices).map(|g| displacement[g]));
        DVector::from_vec(values)
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
        (0..self.mesh.n_cells())
            .into_par_iter()
            .map(|c| {
                let local = self.local_values(c, displacement);
                let strain = self
                    .element
                    .strain(&*self.mesh, c, &local)
                    .map_err(|source| ElasticError::Element {
                        body: self.name.clone(),
                        polygon: c,
                        source,
                    })?;
                Ok(ElementField::from_strain(
                    &strain,
                    &self.tensor,
                    &self.material,
                ))
            })
            .collect()
    }
}

impl<const D: usize> fmt::Debug for ElasticBody<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ElasticBody")
            .field("name", &self.name)
            .field("vertices", &self.mesh.n_vertices())
            .field("cells", &self.mesh.n_cells())
            .field("material", &self.material)
            .field("element", &self.element.name())
            .field("dirichlet", &self.dirichlet)
            .field("tractions", &self.tractions)
            .field("body_force", &self.body_force.is_some())
            .field("traction_points", &self.traction_points)
            .finish()
    }
}

impl<const D: usize> fmt::Debug for ElasticBodyBuilder<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ElasticBodyBuilder")
            .field("name", &self.name)
            .field("element", &self.element.name())
            .field("dirichlet", &self.dirichlet)
            .field("tractions", &self.tractions)
            .finish_non_exhaustive()
    }
}
