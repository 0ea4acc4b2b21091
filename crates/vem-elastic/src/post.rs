//! Post-processing: displacements, per-element strain and stress, reactions, strain energy.

use nalgebra::Vector3;
use vem_mesh::Vector;
use vem_space::ElasticityTensor;

use crate::material::von_mises;
use crate::{Component, Material};

/// Strain and stress of one element, from the energy projection `Pi u_h` (constant per
/// element). Voigt order `[xx, yy, xy]`; the strain carries the engineering shear
/// `gamma_xy = 2 eps_xy`, the stress `sigma_xy`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementField {
    /// `[eps_xx, eps_yy, 2 eps_xy]` of `Pi u_h`.
    pub strain: Vector3<f64>,
    /// `[sigma_xx, sigma_yy, sigma_xy] = C strain`.
    pub stress: Vector3<f64>,
    /// The out-of-plane stress: `lambda (eps_xx + eps_yy)` in plane strain, zero in plane
    /// stress and for a general tensor (see [`Material::out_of_plane_stress`]).
    pub sigma_zz: f64,
    /// The von Mises stress of the three-dimensional state `(sigma_xx, sigma_yy, sigma_zz,
    /// sigma_xy)`; in plane strain it includes `sigma_zz`.
    pub von_mises: f64,
}

impl ElementField {
    /// The fields of the strain `strain` for the tensor `tensor` of `material`.
    pub fn from_strain(
        strain: Vector3<f64>,
        tensor: &ElasticityTensor,
        material: &Material,
    ) -> Self {
        let stress = tensor.voigt() * strain;
        let sigma_zz = material.out_of_plane_stress(&strain);
        Self {
            strain,
            stress,
            sigma_zz,
            von_mises: von_mises(&stress, sigma_zz),
        }
    }
}

/// The reaction force of one Dirichlet condition: the force the support exerts on the body,
/// summed over the prescribed degrees of freedom the condition owns.
#[derive(Debug, Clone, PartialEq)]
pub struct PartReaction {
    /// The boundary part.
    pub part: String,
    /// The prescribed components.
    pub component: Component,
    /// The resultant force `(R_x, R_y)` (zero in a component the condition does not prescribe).
    pub force: Vector,
}

/// The solution of one elastic body: full displacement (global numbering
/// `dof = 2 * vertex + component`), reactions, strain energy.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    displacement: Vec<f64>,
    reactions: Vec<PartReaction>,
    strain_energy: f64,
}

impl Solution {
    pub(crate) fn new(
        displacement: Vec<f64>,
        reactions: Vec<PartReaction>,
        strain_energy: f64,
    ) -> Self {
        Self {
            displacement,
            reactions,
            strain_energy,
        }
    }

    /// The full displacement vector `[u_x(v0), u_y(v0), u_x(v1), ...]`.
    pub fn displacement(&self) -> &[f64] {
        &self.displacement
    }

    /// The displacement of vertex `v`.
    pub fn vertex_displacement(&self, v: usize) -> Vector {
        Vector::new(self.displacement[2 * v], self.displacement[2 * v + 1])
    }

    /// The displacements of all vertices.
    pub fn vertex_displacements(&self) -> Vec<Vector> {
        self.displacement
            .chunks_exact(2)
            .map(|u| Vector::new(u[0], u[1]))
            .collect()
    }

    /// The discrete strain energy `1/2 a_h(u_h, u_h)`.
    pub fn strain_energy(&self) -> f64 {
        self.strain_energy
    }

    /// The reactions of the Dirichlet conditions, in the order they were given.
    pub fn reactions(&self) -> &[PartReaction] {
        &self.reactions
    }

    /// The total reaction on boundary part `part` (summed over the conditions on it); `None`
    /// if no Dirichlet condition names it.
    pub fn reaction(&self, part: &str) -> Option<Vector> {
        let mut found = false;
        let total = self
            .reactions
            .iter()
            .filter(|r| r.part == part)
            .inspect(|_| found = true)
            .fold(Vector::zeros(), |acc, r| acc + r.force);
        found.then_some(total)
    }

    /// The sum of all reactions.
    pub fn total_reaction(&self) -> Vector {
        self.reactions
            .iter()
            .fold(Vector::zeros(), |acc, r| acc + r.force)
    }
}
