//! Linear elasticity of one body in `R^D` (`D = 2` or 3, written once for both; `D = 2` is the
//! default of every generic type) with the lowest-order virtual element method: materials,
//! boundary conditions by part name, parallel assembly on a fixed sparsity pattern, Dirichlet
//! conditions by elimination, sparse Cholesky solve, post-processing.
//!
//! The discrete problem (spec sections 1–2): find `u_h` in `V_h` with `u_h = g` on `Gamma_D`
//! and `a_h(u_h, v) = l_h(v)` for every `v` in `V_h` vanishing on `Gamma_D`, where
//! `a_h = sum_T a_T^h` (consistency + stabilisation, from the element's
//! [`vem_space::MeshElement`]; in 2D every [`vem_space::ElementSpace`]) and
//! `l_h(v) = sum_T l_T^h(v) + int_{Gamma_N} g . v ds`.
//!
//! - Degrees of freedom: [`DofMap`] numbers what the element declares
//!   ([`vem_space::DofLayout`]: the `D` displacement values at each vertex) and splits them
//!   into free and prescribed ones; nothing else computes a global index.
//! - Assembly ([`ElasticBody::assemble`] -> [`AssembledSystem`]): the pattern of the reduced
//!   stiffness `K_ff`, of the lifting block `K_fp` and of `K_pp` is built once from the mesh
//!   connectivity; element matrices are computed in parallel (rayon) in chunks and their values
//!   scattered straight into the compressed-column value arrays (no dense matrix, no triplets).
//!   The reduced system is `K_ff u_f = f_f - K_fp u_p`.
//! - Force control ([`Dirichlet::rigid_plate`]): a part moved as one rigid translation per tied
//!   component with a prescribed resultant; each translation is one extra unknown after the
//!   free degrees of freedom ([`DofMap::n_unknowns`]) and the matrix of the unknowns is the
//!   bordered `T^T K T` (pattern built once, values refilled with the blocks).
//! - Solve: behind the [`LinearSolver`] trait (analyse a pattern once, optionally with
//!   unknowns eliminated last, factorise values as often as needed, solve, read the trailing
//!   factor); [`CholeskySolver`] is faer's sparse Cholesky, ordered by AMD or nested
//!   dissection ([`Ordering`]), its analysis and factor shareable between solvers. A
//!   stiffness that is not positive definite is reported as
//!   [`ElasticError::SingularStiffness`] when the Dirichlet conditions leave a rigid motion
//!   free ([`ElasticBody::holds_rigid_motions`]); a held body with badly shaped elements is
//!   solved if it can be to `1e-8`, else [`ElasticError::IllConditioned`] names the worst
//!   element.
//! - Bodies in space: [`ElasticBody::builder_polyhedral`] on a `vem_mesh::PolyhedralMesh` with a
//!   `vem_space::PolyhedralElement` (parts are sets of boundary faces; tractions are integrated
//!   over the faces against the element's trace); [`Material::isotropic`] and
//!   [`Material::general_3d`] are the laws of a body in space.
//! - Post-processing ([`Solution`], [`ElasticBody::element_fields`]): displacements, strain and
//!   stress of `Pi u_h` per element, von Mises stress (plane strain includes
//!   `sigma_zz = lambda tr eps`), strain energy `1/2 u^T K u`, reactions per Dirichlet part.
//!
//! # Example: a cantilever
//!
//! A beam of length `L = 8` and depth `H = 1` (plane stress, `E = 1000`, `nu = 0.25`) is
//! clamped on the left and carries a downward shear traction of resultant `P = 1` on the
//! right. Timoshenko's beam theory gives the tip deflection
//! `P L^3 / (3 E I) + P L / (kappa G A)` with `I = H^3 / 12`, `A = H`, `kappa = 5/6`.
//!
//! ```
//! use std::sync::Arc;
//! use vem_elastic::{ElasticBody, Material, Plane};
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::{Point, Vector};
//! use vem_space::LowestOrderVem;
//!
//! let (length, depth, e, nu, load) = (8.0, 1.0, 1000.0, 0.25, 1.0);
//! let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(length, depth));
//! let mesh = structured_quads(&rect, 48, 6)?;
//! let body = ElasticBody::builder(
//!     "cantilever",
//!     mesh,
//!     Material::from_young_poisson(e, nu, Plane::Stress)?,
//!     Arc::new(LowestOrderVem::default()),
//! )
//! .clamp("left")
//! .traction("right", move |_| Vector::new(0.0, -load / depth))
//! .build()?;
//! let solution = body.solve()?;
//!
//! // Deflection of the mid-depth point of the loaded end.
//! let tip = body
//!     .mesh()
//!     .part_vertices("right")?
//!     .into_iter()
//!     .find(|&v| (body.mesh().vertex(v).y - 0.5 * depth).abs() < 1e-12)
//!     .unwrap();
//! let deflection = -solution.vertex_displacement(tip).y;
//! let inertia = depth.powi(3) / 12.0;
//! let shear_modulus = e / (2.0 * (1.0 + nu));
//! let timoshenko = load * length.powi(3) / (3.0 * e * inertia)
//!     + load * length / (5.0 / 6.0 * shear_modulus * depth);
//! assert!((deflection / timoshenko - 1.0).abs() < 0.03, "{deflection} vs {timoshenko}");
//!
//! // The clamp carries the load: reaction + applied traction = 0.
//! let reaction = solution.reaction("left").unwrap();
//! assert!((reaction.y - load).abs() < 1e-9 && reaction.x.abs() < 1e-9);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

mod assembly;
mod body;
mod boundary;
mod dofs;
mod error;
pub mod estimate;
mod material;
mod memory;
mod ordering;
mod post;
mod solid;
mod solver;

pub use assembly::AssembledSystem;
pub use body::{ElasticBody, ElasticBodyBuilder};
pub use boundary::{Component, Dirichlet, Traction, VectorField};
pub use dofs::{DofMap, DofStatus, PlateUnknown};
pub use error::{ElasticError, SolveError};
pub use estimate::{CellIndicator, ElasticEstimate};
pub use material::{von_mises, Material, Plane};
pub use memory::release_free_memory;
pub use ordering::elimination_order;
pub use post::{ElementField, PartReaction, Solution};
pub use solver::{
    CholeskyAnalysis, CholeskyFactor, CholeskySettings, CholeskySettingsBuilder, CholeskySolver,
    FactorStatistics, FactorisationParallelism, LinearSolver, Ordering, SolveSupport,
};
#[cfg(feature = "testkit")]
pub mod testkit;
