//! Post-processing: displacements, per-element strain and stress, reactions, strain energy.

use nalgebra::{Matrix3, SMatrix};
use vem_mesh::VectorD;
use vem_space::ElasticityTensor;

use crate::material::von_mises;
use crate::{Component, Material};

/// Strain and stress of one element, from the energy projection `Pi u_h` (constant per
/// element), as three-dimensional symmetric tensors: in 2D the in-plane state completed by the
/// out-of-plane strain and stress of the material's plane reduction
/// ([`Material::strain_state`], [`Material::stress_state`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementField {
    /// The strain tensor of `Pi u_h`.
    pub strain: Matrix3<f64>,
    /// The stress tensor `C eps` (in plane strain with `sigma_zz = lambda tr(eps)`).
    pub stress: Matrix3<f64>,
    /// The von Mises stress of [`ElementField::stress`].
    pub von_mises: f64,
}

impl ElementField {
    /// The fields of the strain tensor `strain` of a body in `D` dimensions, for the tensor
    /// `tensor` of `material`.
    pub fn from_strain<const D: usize>(
        strain: &SMatrix<f64, D, D>,
        tensor: &ElasticityTensor<D>,
        material: &Material,
    ) -> Self {
        let stress = material.stress_state(tensor, strain);
        Self {
            strain: material.strain_state(strain),
            stress,
            von_mises: von_mises(&stress),
        }
    }
}

/// The reaction force of one Dirichlet condition: the force the support exerts on the body,
/// summed over the prescribed degrees of freedom the condition owns.
#[derive(Debug, Clone, PartialEq)]
pub struct PartReaction<const D: usize = 2> {
    /// The boundary part.
    pub part: String,
    /// The prescribed components.
    pub component: Component,
    /// The resultant force (zero in a component the condition does not prescribe).
    pub force: VectorD<D>,
}

/// The solution of one elastic body: full displacement (in the global numbering of the
/// body's [`DofMap`](crate::DofMap): the `D` components of vertex `v` are entries
/// `D v .. D v + D`), reactions, strain energy.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution<const D: usize = 2> {
    displacement: Vec<f64>,
    reactions: Vec<PartReaction<D>>,
    strain_energy: f64,
}

impl<const D: usize> Solution<D> {
    pub(crate) fn new(
        displacement: Vec<f64>,
        reactions: Vec<PartReaction<D>>,
        strain_energy: f64,
    ) -> Self {
        Self {
            displacement,
            reactions,
            strain_energy,
        }
    }

    /// The full displacement vector `[u_x(v0), u_y(v0), (u_z(v0),) u_x(v1), ...]`.
    pub fn displacement(&self) -> &[f64] {
        &self.displacement
    }

    /// The displacement of vertex `v`.
    pub fn vertex_displacement(&self, v: usize) -> VectorD<D> {
        VectorD::<D>::from_column_slice(&self.displacement[D * v..D * (v + 1)])
    }

    /// The displacements of all vertices.
    pub fn vertex_displacements(&self) -> Vec<VectorD<D>> {
        self.displacement
            .chunks_exact(D)
            .map(VectorD::<D>::from_column_slice)
            .collect()
    }

    /// The discrete strain energy `1/2 a_h(u_h, u_h)`.
    pub fn strain_energy(&self) -> f64 {
        self.strain_energy
    }

    /// The reactions of the Dirichlet conditions, in the order they were given.
    pub fn reactions(&self) -> &[PartReaction<D>] {
        &self.reactions
    }

    /// The total reaction on boundary part `part` (summed over the conditions on it); `None`
    /// if no Dirichlet condition names it.
    pub fn reaction(&self, part: &str) -> Option<VectorD<D>> {
        let mut found = false;
        let total = self
            .reactions
            .iter()
            .filter(|r| r.part == part)
            .inspect(|_| found = true)
            .fold(VectorD::zeros(), |acc, r| acc + r.force);
        found.then_some(total)
    }

    /// The sum of all reactions.
    pub fn total_reaction(&self) -> VectorD<D> {
        self.reactions
            .iter()
            .fold(VectorD::zeros(), |acc, r| acc + r.force)
    }
}
