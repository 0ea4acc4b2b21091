//! Degrees of freedom: the global numbering of what the element declares
//! ([`DofLayout`]) and the split into free and prescribed (Dirichlet) degrees of freedom used
//! by elimination, plus the translations of rigid plates (force control) as extra unknowns.

use std::ops::Range;

use vem_mesh::BodyMesh;
use vem_space::DofLayout;

use crate::{Dirichlet, ElasticError};

/// The status of one global degree of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DofStatus {
    /// An unknown, with its index in the reduced (free) numbering.
    Free(usize),
    /// A Dirichlet degree of freedom, with its index in the prescribed numbering.
    Prescribed(usize),
}

/// The global numbering of the degrees of freedom and their split into free and prescribed
/// ones.
///
/// The numbering follows the element's [`DofLayout`]: the `components` values of vertex `v` are
/// the global degrees of freedom `components * v + c` ([`DofMap::vertex_dof`]); nothing outside
/// this type computes a global index.
///
/// Both numberings keep the global order: free index `i < j` implies global `free[i] < free[j]`
/// (and likewise for prescribed ones), so a contiguous global range maps to contiguous free and
/// prescribed ranges.
///
/// ```
/// use vem_elastic::{Component, Dirichlet, DofMap, DofStatus};
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// let mesh = structured_quads(&Rectangle::unit_square(), 2, 2)?;
/// let dofs = DofMap::new(&mesh, &[Dirichlet::fixed("left", Component::All)], "plate").unwrap();
/// assert_eq!(dofs.n_dofs(), 18);
/// assert_eq!(dofs.n_prescribed(), 6); // 3 vertices on the left, 2 components each
/// assert_eq!(dofs.status(dofs.vertex_dof(0, 0)), DofStatus::Prescribed(0)); // vertex 0 = (0, 0)
/// assert_eq!(dofs.status(dofs.vertex_dof(1, 0)), DofStatus::Free(0));       // (1/2, 0), x
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
///
/// # Rigid plates
///
/// The degrees of freedom tied by a rigid plate ([`Dirichlet::rigid_plate`]) are
/// [`DofStatus::Prescribed`] for the assembly (their columns go to the blocks `K_fp`, `K_pp`),
/// with value zero in [`DofMap::prescribed_values`]; each tied component of a plate is one
/// extra unknown, numbered after the free degrees of freedom: the unknowns of the system are
/// `n_free()` free values followed by `n_plates()` plate translations
/// ([`DofMap::n_unknowns`], [`DofMap::unknown_index`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    layout: DofLayout,
    status: Vec<DofStatus>,
    free: Vec<usize>,
    prescribed: Vec<usize>,
    prescribed_values: Vec<f64>,
    prescribed_owner: Vec<usize>,
    /// For each prescribed degree of freedom, the plate unknown it is tied to.
    plate_of: Vec<Option<usize>>,
    plates: Vec<PlateUnknown>,
}

/// One unknown translation of a rigid plate: a component of a [`Dirichlet::rigid_plate`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlateUnknown {
    /// The index of the condition (in the body's list of Dirichlet conditions).
    pub condition: usize,
    /// The component (0 = x, 1 = y, 2 = z).
    pub component: usize,
    /// The prescribed resultant in this component.
    pub resultant: f64,
    /// The tied degrees of freedom, in the prescribed numbering (sorted).
    pub members: Vec<usize>,
}

impl DofMap {
    /// Builds the map of an elasticity element (the `D` displacement values at every vertex)
    /// for `mesh` and the Dirichlet conditions `dirichlet`; see [`DofMap::with_layout`].
    pub fn new<const D: usize, M: BodyMesh<D> + ?Sized>(
        mesh: &M,
        dirichlet: &[Dirichlet<D>],
        body: &str,
    ) -> Result<Self, ElasticError> {
        Self::with_layout(mesh, DofLayout::vertex_values(D), dirichlet, body)
    }

    /// Builds the map for the degrees of freedom `layout` declares on `mesh` and the Dirichlet
    /// conditions `dirichlet` (evaluated at the part's vertices). A degree of freedom
    /// prescribed by several conditions (a corner shared by two parts) belongs to the first
    /// one; their values must agree (to 1e-12 relative). `body` names the body in errors.
    pub fn with_layout<const D: usize, M: BodyMesh<D> + ?Sized>(
        mesh: &M,
        layout: DofLayout,
        dirichlet: &[Dirichlet<D>],
        body: &str,
    ) -> Result<Self, ElasticError> {
        if layout.vertex_components() != D {
            return Err(ElasticError::InvalidSetting {
                reason: format!(
                    "body '{body}': the element declares {} values per vertex; elasticity in {D}D \
                     needs {D}",
                    layout.vertex_components()
                ),
            });
        }
        let dof = |v: usize, c: usize| D * v + c;
        let n_dofs = D * mesh.n_vertices();
        // (owner condition, value) of every prescribed global dof.
        let mut prescribed_by: Vec<Option<(usize, f64)>> = vec![None; n_dofs];
        // The plate unknown of every tied global dof.
        let mut tied_to: Vec<Option<usize>> = vec![None; n_dofs];
        let mut plates = Vec::new();
        for (c, condition) in dirichlet.iter().enumerate() {
            if let Some(resultant) = condition.resultant() {
                let vertices =
                    mesh.part_vertices(condition.part())
                        .map_err(|source| ElasticError::Mesh {
                            body: body.to_string(),
                            source,
                        })?;
                for &k in condition.component().indices(D) {
                    if !resultant[k].is_finite() {
                        return Err(ElasticError::NonFiniteResultant {
                            body: body.to_string(),
                            part: condition.part().to_string(),
                            component: k,
                            value: resultant[k],
                        });
                    }
                    for &v in &vertices {
                        if let Some((first, _)) = prescribed_by[dof(v, k)] {
                            return Err(ElasticError::RigidPlateConflict {
                                body: body.to_string(),
                                plate: condition.part().to_string(),
                                other: dirichlet[first].part().to_string(),
                                vertex: v,
                                component: k,
                            });
                        }
                        prescribed_by[dof(v, k)] = Some((c, 0.0));
                        tied_to[dof(v, k)] = Some(plates.len());
                    }
                    plates.push(PlateUnknown {
                        condition: c,
                        component: k,
                        resultant: resultant[k],
                        members: Vec::new(),
                    });
                }
                continue;
            }
            let vertices =
                mesh.part_vertices(condition.part())
                    .map_err(|source| ElasticError::Mesh {
                        body: body.to_string(),
                        source,
                    })?;
            for v in vertices {
                let value = condition.value_at(mesh.points()[v]);
                for &k in condition.component().indices(D) {
                    let g = value[k];
                    if !g.is_finite() {
                        return Err(ElasticError::NonFiniteDirichlet {
                            body: body.to_string(),
                            part: condition.part().to_string(),
                            vertex: v,
                            value: g,
                        });
                    }
                    if tied_to[dof(v, k)].is_some() {
                        let (plate, _) = prescribed_by[dof(v, k)].unwrap_or((c, 0.0));
                        return Err(ElasticError::RigidPlateConflict {
                            body: body.to_string(),
                            plate: dirichlet[plate].part().to_string(),
                            other: condition.part().to_string(),
                            vertex: v,
                            component: k,
                        });
                    }
                    match prescribed_by[dof(v, k)] {
                        None => prescribed_by[dof(v, k)] = Some((c, g)),
                        Some((first, first_value)) => {
                            let scale = first_value.abs().max(g.abs());
                            if (first_value - g).abs() > 1e-12 * scale {
                                return Err(ElasticError::ConflictingDirichlet {
                                    body: body.to_string(),
                                    vertex: v,
                                    component: k,
                                    first: dirichlet[first].part().to_string(),
                                    first_value,
                                    second: condition.part().to_string(),
                                    second_value: g,
                                });
                            }
                        }
                    }
                }
            }
        }
        // Exact capacities: the map lives as long as the body.
        let n_prescribed = prescribed_by.iter().filter(|entry| entry.is_some()).count();
        let mut map = DofMap {
            layout,
            status: Vec::with_capacity(n_dofs),
            free: Vec::with_capacity(n_dofs - n_prescribed),
            prescribed: Vec::with_capacity(n_prescribed),
            prescribed_values: Vec::with_capacity(n_prescribed),
            prescribed_owner: Vec::with_capacity(n_prescribed),
            plate_of: Vec::with_capacity(n_prescribed),
            plates,
        };
        for (g, entry) in prescribed_by.into_iter().enumerate() {
            match entry {
                None => {
                    map.status.push(DofStatus::Free(map.free.len()));
                    map.free.push(g);
                }
                Some((owner, value)) => {
                    if let Some(plate) = tied_to[g] {
                        map.plates[plate].members.push(map.prescribed.len());
                    }
                    map.plate_of.push(tied_to[g]);
                    map.status.push(DofStatus::Prescribed(map.prescribed.len()));
                    map.prescribed.push(g);
                    map.prescribed_values.push(value);
                    map.prescribed_owner.push(owner);
                }
            }
        }
        Ok(map)
    }

    /// Number of global degrees of freedom.
    pub fn n_dofs(&self) -> usize {
        self.status.len()
    }

    /// The local degrees of freedom the element declares, which this map numbers.
    pub fn layout(&self) -> DofLayout {
        self.layout
    }

    /// The number of displacement components per vertex (the dimension).
    pub fn components(&self) -> usize {
        self.layout.vertex_components()
    }

    /// The global degree of freedom of `component` at `vertex`.
    #[inline]
    pub fn vertex_dof(&self, vertex: usize, component: usize) -> usize {
        self.components() * vertex + component
    }

    /// The global degrees of freedom of every component at `vertex`.
    #[inline]
    pub fn vertex_dofs(&self, vertex: usize) -> Range<usize> {
        let d = self.components();
        d * vertex..d * (vertex + 1)
    }

    /// The vertex and component of the global degree of freedom `dof`.
    #[inline]
    pub fn vertex_of(&self, dof: usize) -> (usize, usize) {
        (dof / self.components(), dof % self.components())
    }

    /// Appends the global degrees of freedom of a cell with vertices `cell_vertices`, in the
    /// element's local order, to `out`.
    pub fn cell_dofs(&self, cell_vertices: &[usize], out: &mut Vec<usize>) {
        out.extend(self.cell_dof_iter(cell_vertices));
    }

    /// The global degrees of freedom of a cell with vertices `cell_vertices`, in the element's
    /// local order ([`DofMap::cell_dofs`] without a buffer).
    pub fn cell_dof_iter<'a>(
        &'a self,
        cell_vertices: &'a [usize],
    ) -> impl Iterator<Item = usize> + 'a {
        cell_vertices.iter().flat_map(|&v| self.vertex_dofs(v))
    }

    /// Number of free degrees of freedom (the size of the reduced system).
    pub fn n_free(&self) -> usize {
        self.free.len()
    }

    /// Number of rigid-plate unknowns (one per tied component of each rigid plate).
    pub fn n_plates(&self) -> usize {
        self.plates.len()
    }

    /// Number of unknowns of the system: the free degrees of freedom followed by the
    /// rigid-plate translations, `n_free() + n_plates()`.
    pub fn n_unknowns(&self) -> usize {
        self.free.len() + self.plates.len()
    }

    /// The rigid-plate unknowns; plate `k` is unknown `n_free() + k`.
    pub fn plates(&self) -> &[PlateUnknown] {
        &self.plates
    }

    /// For each prescribed degree of freedom (prescribed numbering), the plate it is tied to.
    pub fn plate_of_prescribed(&self) -> &[Option<usize>] {
        &self.plate_of
    }

    /// The index among the unknowns of global `dof`: its free index, or `n_free() + k` for a
    /// degree of freedom tied to plate `k`; `None` for a prescribed value.
    pub fn unknown_index(&self, dof: usize) -> Option<usize> {
        match self.status[dof] {
            DofStatus::Free(i) => Some(i),
            DofStatus::Prescribed(j) => self.plate_of[j].map(|k| self.free.len() + k),
        }
    }

    /// Number of prescribed degrees of freedom (rigid-plate ones included).
    pub fn n_prescribed(&self) -> usize {
        self.prescribed.len()
    }

    /// The status of global degree of freedom `dof`.
    pub fn status(&self, dof: usize) -> DofStatus {
        self.status[dof]
    }

    /// The statuses of all global degrees of freedom.
    pub fn statuses(&self) -> &[DofStatus] {
        &self.status
    }

    /// The free index of global `dof`, if it is free.
    pub fn free_index(&self, dof: usize) -> Option<usize> {
        match self.status[dof] {
            DofStatus::Free(i) => Some(i),
            DofStatus::Prescribed(_) => None,
        }
    }

    /// The global degrees of freedom of the free numbering (free index -> global).
    pub fn free_dofs(&self) -> &[usize] {
        &self.free
    }

    /// The global degrees of freedom of the prescribed numbering (prescribed index -> global).
    pub fn prescribed_dofs(&self) -> &[usize] {
        &self.prescribed
    }

    /// The prescribed values `u_p`, in the prescribed numbering.
    pub fn prescribed_values(&self) -> &[f64] {
        &self.prescribed_values
    }

    /// For each prescribed degree of freedom, the index (in the body's list) of the Dirichlet
    /// condition that owns it.
    pub fn prescribed_owners(&self) -> &[usize] {
        &self.prescribed_owner
    }

    /// The number of free (and of prescribed) degrees of freedom with a global index below
    /// `dof`: where a global range starts in the two numberings.
    pub(crate) fn split_point(&self, dof: usize) -> (usize, usize) {
        let free = self.free.partition_point(|&g| g < dof);
        (free, dof - free)
    }

    /// The full displacement vector from the unknowns `u` (free values, then plate
    /// translations): free entries from `u`, tied entries from their plate's translation,
    /// prescribed entries from the Dirichlet data. Panics if the length is wrong; see
    /// [`crate::AssembledSystem::expand`] for the checked version.
    pub(crate) fn expand_unchecked(&self, u: &[f64]) -> Vec<f64> {
        let n_free = self.free.len();
        self.status
            .iter()
            .map(|s| match *s {
                DofStatus::Free(i) => u[i],
                DofStatus::Prescribed(j) => match self.plate_of[j] {
                    Some(k) => u[n_free + k],
                    None => self.prescribed_values[j],
                },
            })
            .collect()
    }
}
