//! Global assembly: the sparsity pattern once from the mesh connectivity, element matrices in
//! parallel, values scattered straight into the compressed-column value arrays.
//!
//! Dirichlet conditions are eliminated: with the free (f) and prescribed (p) degrees of
//! freedom of a [`DofMap`], the global system `K u = f` splits into
//!
//! ```text
//! [K_ff K_fp] [u_f]   [f_f]                    K_ff u_f = f_f - K_fp u_p      (solved)
//! [K_pf K_pp] [u_p] = [f_p] + r_p     =>       r_p = K_pf u_f + K_pp u_p - f_p (reactions)
//! ```
//!
//! Three blocks are stored, each in compressed-column form with full (not triangular) storage:
//! `K_ff` (the reduced stiffness), `K_fp` (the lifting of the Dirichlet data) and `K_pp`.
//! `K_pf = K_fp^T` is not stored.
//!
//! Rigid plates (force control): the degrees of freedom a plate ties are prescribed ones for
//! the assembly, with value zero; each plate component `k` adds an unknown `w_k` with
//! `u_p = E w` on its tied degrees of freedom (`E` has a 1 per tied degree of freedom). The
//! system solved is the bordered one
//!
//! ```text
//! [ K_ff      K_fp E    ] [u_f]   [ f_f - K_fp u_p0             ]
//! [ E^T K_pf  E^T K_pp E] [ w ] = [ E^T (f_p - K_pp u_p0) + P   ]
//! ```
//!
//! (`u_p0` the ordinary prescribed values, `P` the prescribed resultants), i.e. `T^T K T` for
//! the change of unknowns `u = T v`: symmetric, positive semi-definite like `K`. Its pattern
//! is built once with the blocks; its values are refilled after each assembly.
//!
//! The pattern is built in passes over compressed arrays, in parallel over blocks of vertices:
//! the vertex adjacency from the cell-vertex incidence (count, fill, sort and deduplicate per
//! row), then the three blocks, whose columns of one vertex with one status share their rows
//! (written once, copied). Element matrices are computed in parallel, a chunk of cells at a
//! time (about 2 MiB of matrices: bounded memory, still in cache for their scatter), and
//! scattered in parallel by disjoint blocks of columns; an element's rows are located in the
//! columns of one of its vertices by one merge along the column's sorted rows, and the
//! offsets serve the vertex's other columns. Cells are visited along a Morton curve of their
//! vertex means, which keeps the scatter in cache on meshes with a random numbering (Voronoi):
//! measured 2-3x faster there. Every entry is summed in the same order whatever the number of
//! threads, so the values are reproducible bit for bit.

use std::ops::Range;

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use vem_mesh::{morton_key, BodyMesh, PointD, VectorD};

use crate::{DofMap, DofStatus, ElasticError};

/// Bytes of element matrices computed together before they are scattered: bounds the memory
/// held in element matrices independently of the mesh size, and keeps them in cache between
/// their computation and their scatter.
const CHUNK_BYTES: usize = 2 << 20;

/// The stiffness, load and Dirichlet lifting of one body, ready for a linear solver.
///
/// The pattern is built once from the mesh connectivity; values can be recomputed on the same
/// pattern (e.g. for another material) with [`crate::ElasticBody::reassemble`].
#[derive(Debug, Clone)]
pub struct AssembledSystem {
    body: String,
    n_vertices: usize,
    n_polygons: usize,
    dofs: DofMap,
    stiffness: SparseColMat<usize, f64>,
    coupling: SparseColMat<usize, f64>,
    prescribed_block: SparseColMat<usize, f64>,
    load: Vec<f64>,
    rhs: Vec<f64>,
    /// The bordered stiffness (free and plate unknowns) when the body has rigid plates.
    bordered: Option<SparseColMat<usize, f64>>,
    /// The order in which polygons are assembled: along a Morton (Z-order) curve of their
    /// vertex means, so that consecutive elements share vertices and the scatter stays in cache
    /// whatever the mesh's numbering.
    element_order: Vec<usize>,
    /// The number of elements whose matrices are computed together before they are scattered
    /// (about [`CHUNK_BYTES`] of matrices).
    chunk: usize,
}

/// `n` zeros written by every thread, a part each. `vec![0.0; n]` of a large `n` is fresh
/// memory the system maps on first access: the scatter's first `+=` would read a page (mapped
/// to the shared zero page) and then write it (a second fault, which on a multithreaded
/// process also interrupts the other cores to flush their view of the page). Written first,
/// every page faults once, the faults spread over the threads.
fn written_zeros(n: usize) -> Vec<f64> {
    let mut zeros = Vec::with_capacity(n);
    zeros.par_extend(rayon::iter::repeat_n(0.0, n));
    zeros
}

/// What one element contributes: its global degrees of freedom, matrix and load vector.
pub(crate) struct ElementContribution {
    pub(crate) dofs: Vec<usize>,
    pub(crate) matrix: DMatrix<f64>,
    pub(crate) load: Option<DVector<f64>>,
}

impl AssembledSystem {
    /// An all-zero system with the pattern of `mesh` and the split of `dofs`.
    pub(crate) fn with_pattern<const D: usize>(
        body: &str,
        mesh: &dyn BodyMesh<D>,
        dofs: DofMap,
    ) -> Self {
        // The adjacency is dropped before the values are allocated: it never lives beside a
        // whole copy of `K`.
        let (ff, fp, pp) = block_patterns(&VertexAdjacency::new(mesh), &dofs);
        let bordered = (dofs.n_plates() > 0).then(|| bordered_pattern(&ff, &fp, &dofs));
        let zeros = |p: SymbolicSparseColMat<usize>| {
            let nnz = p.row_idx().len();
            SparseColMat::new(p, written_zeros(nnz))
        };
        Self {
            body: body.to_string(),
            n_vertices: mesh.n_vertices(),
            n_polygons: mesh.n_cells(),
            load: vec![0.0; dofs.n_dofs()],
            rhs: vec![0.0; dofs.n_unknowns()],
            bordered: bordered.map(zeros),
            element_order: morton_order(mesh),
            chunk: chunk_len(mesh, dofs.components()),
            dofs,
            stiffness: zeros(ff),
            coupling: zeros(fp),
            prescribed_block: zeros(pp),
        }
    }

    /// True when this system was built for a mesh of this size and this dof split.
    pub(crate) fn matches<const D: usize>(&self, mesh: &dyn BodyMesh<D>, dofs: &DofMap) -> bool {
        self.n_vertices == mesh.n_vertices()
            && self.n_polygons == mesh.n_cells()
            && &self.dofs == dofs
    }

    /// Sets every value (matrices, load, right-hand side) to zero, keeping the pattern.
    pub(crate) fn clear_values(&mut self) {
        self.stiffness.val_mut().fill(0.0);
        self.coupling.val_mut().fill(0.0);
        self.prescribed_block.val_mut().fill(0.0);
        self.load.fill(0.0);
        self.rhs.fill(0.0);
    }

    /// Computes the contributions of all polygons with `element` (in parallel, chunk by
    /// chunk) and scatters them (in parallel over disjoint column blocks).
    pub(crate) fn scatter_elements<F>(&mut self, element: F) -> Result<(), ElasticError>
    where
        F: Fn(usize) -> Result<ElementContribution, ElasticError> + Sync,
    {
        let dofs = &self.dofs;
        let d = dofs.components();
        let mut blocks = column_blocks(
            dofs,
            &mut self.stiffness,
            &mut self.coupling,
            &mut self.prescribed_block,
            &mut self.load,
            rayon::current_num_threads(),
        );
        let statuses = dofs.statuses();
        for chunk in self.element_order.chunks(self.chunk) {
            // Each contribution with its rows, found here in parallel once rather than by
            // every column block it touches.
            let contributions: Vec<(ElementRows, ElementContribution)> = chunk
                .par_iter()
                .map(|&p| {
                    let contribution = element(p)?;
                    Ok((ElementRows::new(&contribution.dofs, statuses), contribution))
                })
                .collect::<Result<_, ElasticError>>()?;
            blocks
                .par_iter_mut()
                .for_each(|block| block.scatter(statuses, d, &contributions));
        }
        Ok(())
    }

    /// Adds `values` at the global degrees of freedom `global` of the load vector
    /// (tractions; sequential, boundary-sized).
    pub(crate) fn add_load(&mut self, global: &[usize], values: &[f64]) {
        for (&g, &v) in global.iter().zip(values) {
            self.load[g] += v;
        }
    }

    /// Forms the reduced right-hand side `f_f - K_fp u_p` from the load and the Dirichlet data
    /// and, with rigid plates, the bordered stiffness and the plate rows of the right-hand side.
    pub(crate) fn finish_rhs(&mut self) {
        let n_free = self.dofs.n_free();
        for (i, &g) in self.dofs.free_dofs().iter().enumerate() {
            self.rhs[i] = self.load[g];
        }
        let u_p = self.dofs.prescribed_values();
        matvec_add(&self.coupling, u_p, -1.0, &mut self.rhs[..n_free]);
        if self.dofs.n_plates() == 0 {
            return;
        }
        // Plate rows: E^T (f_p - K_pp u_p0) + P.
        let mut k_pp_u = vec![0.0; self.dofs.n_prescribed()];
        matvec_add(&self.prescribed_block, u_p, 1.0, &mut k_pp_u);
        let prescribed = self.dofs.prescribed_dofs();
        for (k, plate) in self.dofs.plates().iter().enumerate() {
            self.rhs[n_free + k] = plate.resultant
                + plate
                    .members
                    .iter()
                    .map(|&p| self.load[prescribed[p]] - k_pp_u[p])
                    .sum::<f64>();
        }
        if let Some(bordered) = self.bordered.as_mut() {
            fill_bordered(
                bordered,
                &self.stiffness,
                &self.coupling,
                &self.prescribed_block,
                &self.dofs,
            );
        }
    }

    /// The name of the body this system belongs to.
    pub fn body(&self) -> &str {
        &self.body
    }

    /// The free/prescribed split of the degrees of freedom.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// The matrix of the unknowns (symmetric, full storage): the reduced stiffness `K_ff`
    /// (free x free) or, with rigid plates, the bordered matrix over the free degrees of
    /// freedom and the plate translations (see the module documentation).
    pub fn stiffness(&self) -> &SparseColMat<usize, f64> {
        self.bordered.as_ref().unwrap_or(&self.stiffness)
    }

    /// The coupling block `K_fp` (free rows x prescribed columns) that lifts the Dirichlet data.
    pub fn coupling(&self) -> &SparseColMat<usize, f64> {
        &self.coupling
    }

    /// The prescribed block `K_pp` (prescribed x prescribed).
    pub fn prescribed_block(&self) -> &SparseColMat<usize, f64> {
        &self.prescribed_block
    }

    /// The full load vector `f` (body force and tractions, every global degree of freedom).
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The reduced right-hand side `f_f - K_fp u_p` (followed, with rigid plates, by the plate
    /// rows `E^T (f_p - K_pp u_p) + P`).
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }

    /// The full displacement vector (global numbering) from the unknowns `u_free` (the free
    /// values, then the rigid-plate translations: [`DofMap::n_unknowns`] values).
    pub fn expand(&self, u_free: &[f64]) -> Result<Vec<f64>, ElasticError> {
        self.expand_scaled(u_free, 1.0)
    }

    /// The full displacement vector from the unknowns `u_free` with the prescribed values
    /// scaled by `load_factor` (a load step: Dirichlet data scaled with the loads; the plate
    /// translations are unknowns and are not scaled).
    pub fn expand_scaled(
        &self,
        u_free: &[f64],
        load_factor: f64,
    ) -> Result<Vec<f64>, ElasticError> {
        self.check_length("u_free", u_free, self.dofs.n_unknowns())?;
        let mut full = self.dofs.expand_unchecked(u_free);
        if load_factor != 1.0 {
            let plate_of = self.dofs.plate_of_prescribed();
            for (&g, plate) in self.dofs.prescribed_dofs().iter().zip(plate_of) {
                if plate.is_none() {
                    full[g] *= load_factor;
                }
            }
        }
        Ok(full)
    }

    /// The unknowns of a full displacement vector: the free values, then the rigid-plate
    /// translations (read at the first degree of freedom each plate ties).
    pub fn restrict(&self, displacement: &[f64]) -> Result<Vec<f64>, ElasticError> {
        self.check_length("displacement", displacement, self.dofs.n_dofs())?;
        let prescribed = self.dofs.prescribed_dofs();
        Ok(self
            .dofs
            .free_dofs()
            .iter()
            .map(|&g| displacement[g])
            .chain(self.dofs.plates().iter().map(|plate| {
                plate
                    .members
                    .first()
                    .map_or(0.0, |&p| displacement[prescribed[p]])
            }))
            .collect())
    }

    /// The free values of a full displacement vector (without the plate translations).
    fn free_values(&self, displacement: &[f64]) -> Vec<f64> {
        self.dofs
            .free_dofs()
            .iter()
            .map(|&g| displacement[g])
            .collect()
    }

    /// The reaction forces `r_p = K_pf u_f + K_pp u_p - f_p` at the prescribed degrees of
    /// freedom (prescribed numbering) for the full displacement `displacement`: the force the
    /// support exerts on the body.
    pub fn reactions(&self, displacement: &[f64]) -> Result<Vec<f64>, ElasticError> {
        self.reactions_scaled(displacement, 1.0)
    }

    /// The reactions `r_p = K_pf u_f + K_pp u_p - s f_p` for the loads scaled by
    /// `load_factor = s` (a load step).
    pub fn reactions_scaled(
        &self,
        displacement: &[f64],
        load_factor: f64,
    ) -> Result<Vec<f64>, ElasticError> {
        self.check_length("displacement", displacement, self.dofs.n_dofs())?;
        let u_f = self.free_values(displacement);
        let u_p: Vec<f64> = self
            .dofs
            .prescribed_dofs()
            .iter()
            .map(|&g| displacement[g])
            .collect();
        let mut reactions: Vec<f64> = self
            .dofs
            .prescribed_dofs()
            .iter()
            .map(|&g| -load_factor * self.load[g])
            .collect();
        transpose_matvec_add(&self.coupling, &u_f, &mut reactions);
        matvec_add(&self.prescribed_block, &u_p, 1.0, &mut reactions);
        Ok(reactions)
    }

    /// The reactions `r_p = K_pf u_f + K_pp u_p - f_p` for the load vector `load` (every global
    /// degree of freedom) in place of the assembled one.
    pub fn reactions_with_load(
        &self,
        displacement: &[f64],
        load: &[f64],
    ) -> Result<Vec<f64>, ElasticError> {
        self.check_length("load", load, self.dofs.n_dofs())?;
        let mut reactions = self.reactions_scaled(displacement, 0.0)?;
        for (r, &g) in reactions.iter_mut().zip(self.dofs.prescribed_dofs()) {
            *r -= load[g];
        }
        Ok(reactions)
    }

    /// The discrete strain energy `1/2 u^T K u = 1/2 a_h(u, u)` of the full displacement.
    pub fn strain_energy(&self, displacement: &[f64]) -> Result<f64, ElasticError> {
        self.check_length("displacement", displacement, self.dofs.n_dofs())?;
        let u_f = self.free_values(displacement);
        let u_p: Vec<f64> = self
            .dofs
            .prescribed_dofs()
            .iter()
            .map(|&g| displacement[g])
            .collect();
        // K u restricted to the free rows: K_ff u_f + K_fp u_p; to the prescribed rows:
        // K_pf u_f + K_pp u_p.
        let mut k_u_f = vec![0.0; u_f.len()];
        matvec_add(&self.stiffness, &u_f, 1.0, &mut k_u_f);
        matvec_add(&self.coupling, &u_p, 1.0, &mut k_u_f);
        let mut k_u_p = vec![0.0; u_p.len()];
        transpose_matvec_add(&self.coupling, &u_f, &mut k_u_p);
        matvec_add(&self.prescribed_block, &u_p, 1.0, &mut k_u_p);
        Ok(0.5 * (dot(&u_f, &k_u_f) + dot(&u_p, &k_u_p)))
    }

    fn check_length(
        &self,
        what: &'static str,
        v: &[f64],
        expected: usize,
    ) -> Result<(), ElasticError> {
        if v.len() == expected {
            Ok(())
        } else {
            Err(ElasticError::WrongLength {
                body: self.body.clone(),
                what,
                found: v.len(),
                expected,
            })
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `y += alpha A x` for a compressed-column `A`.
fn matvec_add(a: &SparseColMat<usize, f64>, x: &[f64], alpha: f64, y: &mut [f64]) {
    let (symbolic, values) = a.parts();
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
    for (j, &xj) in x.iter().enumerate() {
        let scaled = alpha * xj;
        if scaled == 0.0 {
            continue;
        }
        for k in col_ptr[j]..col_ptr[j + 1] {
            y[row_idx[k]] += values[k] * scaled;
        }
    }
}

/// `y += A^T x` for a compressed-column `A`.
fn transpose_matvec_add(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let (symbolic, values) = a.parts();
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
    for (j, yj) in y.iter_mut().enumerate() {
        *yj += (col_ptr[j]..col_ptr[j + 1])
            .map(|k| values[k] * x[row_idx[k]])
            .sum::<f64>();
    }
}

/// The cells sorted along the Morton (Z-order) curve of the mesh's bounding box by their
/// vertex means ([`morton_key`]; ties keep the mesh order).
fn morton_order<const D: usize>(mesh: &dyn BodyMesh<D>) -> Vec<usize> {
    let points = mesh.points();
    let Some(&first) = points.first() else {
        return Vec::new();
    };
    let (mut min, mut max) = (first, first);
    for x in points {
        min = min.inf(x);
        max = max.sup(x);
    }
    let extent = (max - min).map(|e| if e > 0.0 { e } else { 1.0 });
    let mut keyed: Vec<(u64, usize)> = (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| {
            let vertices = mesh.cell_vertices(c);
            let sum = vertices
                .iter()
                .fold(VectorD::<D>::zeros(), |acc, &v| acc + points[v].coords);
            let mean = PointD::from(sum / vertices.len().max(1) as f64);
            (morton_key(&mean, &min, &extent), c)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, c)| c).collect()
}

/// The number of elements of `mesh` whose matrices (of `d` values per vertex) take about
/// [`CHUNK_BYTES`], between 256 and 8192.
fn chunk_len<const D: usize>(mesh: &dyn BodyMesh<D>, d: usize) -> usize {
    let cells = mesh.n_cells().max(1);
    let vertices: usize = (0..mesh.n_cells())
        .map(|c| mesh.cell_vertices(c).len())
        .sum();
    let local = (d * vertices).div_ceil(cells).max(1);
    (CHUNK_BYTES / (8 * local * local)).clamp(256, 8192)
}

/// The vertex adjacency of a mesh in compressed form: for each vertex `v`, the sorted distinct
/// vertices that share a cell with it (itself included) are
/// `neighbours[offsets[v]..offsets[v + 1]]`.
struct VertexAdjacency {
    offsets: Vec<usize>,
    neighbours: Vec<usize>,
}

impl VertexAdjacency {
    /// Built from the cell-vertex incidence in passes over compressed arrays (no per-vertex
    /// allocation): the vertex-cell incidence (count, fill), then each vertex's candidates
    /// (the vertices of its cells, repeats included) gathered, sorted and deduplicated in
    /// place, in parallel over blocks of vertices, and the distinct ones compacted.
    fn new<const D: usize>(mesh: &dyn BodyMesh<D>) -> Self {
        let n = mesh.n_vertices();
        // Vertex -> cells incidence, and for each vertex the number of its candidates.
        let mut incidence_offsets = vec![0usize; n + 1];
        let mut candidate_offsets = vec![0usize; n + 1];
        for c in 0..mesh.n_cells() {
            let vertices = mesh.cell_vertices(c);
            for &v in vertices {
                incidence_offsets[v + 1] += 1;
                candidate_offsets[v + 1] += vertices.len();
            }
        }
        for v in 0..n {
            incidence_offsets[v + 1] += incidence_offsets[v];
            candidate_offsets[v + 1] += candidate_offsets[v];
        }
        let mut next = incidence_offsets[..n].to_vec();
        let mut incident = vec![0usize; incidence_offsets[n]];
        for c in 0..mesh.n_cells() {
            for &v in mesh.cell_vertices(c) {
                incident[next[v]] = c;
                next[v] += 1;
            }
        }
        drop(next);
        // Each vertex's candidates, sorted and deduplicated at the start of its range.
        let mut candidates = vec![0usize; candidate_offsets[n]];
        let mut distinct = vec![0usize; n];
        let blocks = vertex_blocks(n);
        let mut pieces = Vec::with_capacity(blocks.len());
        let (mut rest, mut counts) = (candidates.as_mut_slice(), distinct.as_mut_slice());
        for block in &blocks {
            let len = candidate_offsets[block.end] - candidate_offsets[block.start];
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(len);
            let (count_head, count_tail) = std::mem::take(&mut counts).split_at_mut(block.len());
            pieces.push((block.clone(), head, count_head));
            (rest, counts) = (tail, count_tail);
        }
        pieces.into_par_iter().for_each(|(block, values, counts)| {
            let base = candidate_offsets[block.start];
            for (v, count) in block.zip(counts) {
                let range = candidate_offsets[v] - base..candidate_offsets[v + 1] - base;
                let row = &mut values[range];
                let mut k = 0;
                for &c in &incident[incidence_offsets[v]..incidence_offsets[v + 1]] {
                    for &w in mesh.cell_vertices(c) {
                        row[k] = w;
                        k += 1;
                    }
                }
                row.sort_unstable();
                *count = dedup_sorted(row);
            }
        });
        drop(incident);
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0);
        let mut total = 0;
        for &count in &distinct {
            total += count;
            offsets.push(total);
        }
        let mut neighbours = Vec::with_capacity(total);
        for v in 0..n {
            let start = candidate_offsets[v];
            neighbours.extend_from_slice(&candidates[start..start + distinct[v]]);
        }
        Self {
            offsets,
            neighbours,
        }
    }

    fn n_vertices(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The sorted neighbours of `v` (itself included).
    fn of(&self, v: usize) -> &[usize] {
        &self.neighbours[self.offsets[v]..self.offsets[v + 1]]
    }
}

/// Moves the distinct values of the sorted `row` to its start and returns their number.
fn dedup_sorted(row: &mut [usize]) -> usize {
    if row.is_empty() {
        return 0;
    }
    let mut len = 1;
    for k in 1..row.len() {
        if row[k] != row[len - 1] {
            row[len] = row[k];
            len += 1;
        }
    }
    len
}

/// Contiguous blocks of the vertices `0..n` for the parallel passes: several per thread, so
/// that uneven blocks balance.
fn vertex_blocks(n: usize) -> Vec<Range<usize>> {
    let size = n.div_ceil(8 * rayon::current_num_threads()).max(1024);
    (0..n)
        .step_by(size)
        .map(|start| start..(start + size).min(n))
        .collect()
}

/// The patterns of `K_ff`, `K_fp` and `K_pp`: every degree of freedom of vertex `v` couples to
/// every degree of freedom of each neighbour `w` of `v`.
///
/// The columns of one vertex that have the same status have the same rows: the free rows of
/// `v` (the free degrees of freedom of its neighbours, sorted as the free numbering keeps the
/// global order) and its prescribed rows. The column pointers come from the counts of these
/// rows per vertex; the rows are written in parallel over blocks of vertices, each vertex's
/// lists once and copied to its other columns.
fn block_patterns(
    adjacency: &VertexAdjacency,
    dofs: &DofMap,
) -> (
    SymbolicSparseColMat<usize>,
    SymbolicSparseColMat<usize>,
    SymbolicSparseColMat<usize>,
) {
    let (n_f, n_p) = (dofs.n_free(), dofs.n_prescribed());
    let n = adjacency.n_vertices();
    let statuses = dofs.statuses();
    let free_at = |v: usize| {
        dofs.vertex_dofs(v)
            .filter(|&g| matches!(statuses[g], DofStatus::Free(_)))
            .count()
    };
    let d = dofs.components();
    // The free and prescribed degrees of freedom of every vertex, then of its neighbours.
    let free_of: Vec<usize> = (0..n).into_par_iter().map(free_at).collect();
    let rows_of: Vec<(usize, usize)> = (0..n)
        .into_par_iter()
        .map(|v| {
            let free: usize = adjacency.of(v).iter().map(|&w| free_of[w]).sum();
            (free, d * adjacency.of(v).len() - free)
        })
        .collect();
    // Column pointers of the three blocks, and where each vertex's columns start.
    let mut ff_ptr = Vec::with_capacity(n_f + 1);
    let mut fp_ptr = Vec::with_capacity(n_p + 1);
    let mut pp_ptr = Vec::with_capacity(n_p + 1);
    ff_ptr.push(0);
    fp_ptr.push(0);
    pp_ptr.push(0);
    let mut vertex_start = Vec::with_capacity(n + 1);
    let (mut ff_end, mut fp_end, mut pp_end) = (0, 0, 0);
    for (v, &(free_rows, prescribed_rows)) in rows_of.iter().enumerate() {
        vertex_start.push((ff_end, fp_end, pp_end));
        for g in dofs.vertex_dofs(v) {
            match statuses[g] {
                DofStatus::Free(_) => {
                    ff_end += free_rows;
                    ff_ptr.push(ff_end);
                }
                DofStatus::Prescribed(_) => {
                    fp_end += free_rows;
                    fp_ptr.push(fp_end);
                    pp_end += prescribed_rows;
                    pp_ptr.push(pp_end);
                }
            }
        }
    }
    vertex_start.push((ff_end, fp_end, pp_end));
    let mut ff_rows = vec![0usize; ff_end];
    let mut fp_rows = vec![0usize; fp_end];
    let mut pp_rows = vec![0usize; pp_end];
    // Hand out each block of vertices its slices of the three row arrays.
    let blocks = vertex_blocks(n);
    let mut pieces = Vec::with_capacity(blocks.len());
    let (mut ff_rest, mut fp_rest, mut pp_rest) = (
        ff_rows.as_mut_slice(),
        fp_rows.as_mut_slice(),
        pp_rows.as_mut_slice(),
    );
    for block in blocks {
        let (s, e) = (vertex_start[block.start], vertex_start[block.end]);
        let (ff, tail) = std::mem::take(&mut ff_rest).split_at_mut(e.0 - s.0);
        ff_rest = tail;
        let (fp, tail) = std::mem::take(&mut fp_rest).split_at_mut(e.1 - s.1);
        fp_rest = tail;
        let (pp, tail) = std::mem::take(&mut pp_rest).split_at_mut(e.2 - s.2);
        pp_rest = tail;
        pieces.push((block, ff, fp, pp));
    }
    pieces.into_par_iter().for_each(|(block, ff, fp, pp)| {
        let base = vertex_start[block.start];
        for v in block {
            let (free_rows, prescribed_rows) = rows_of[v];
            let (free_columns, prescribed_columns) = (free_of[v], d - free_of[v]);
            let start = vertex_start[v];
            let ff = &mut ff[start.0 - base.0..start.0 - base.0 + free_columns * free_rows];
            let fp = &mut fp[start.1 - base.1..start.1 - base.1 + prescribed_columns * free_rows];
            let pp =
                &mut pp[start.2 - base.2..start.2 - base.2 + prescribed_columns * prescribed_rows];
            // The free rows into the first column that has them, the prescribed ones likewise.
            let first_free = if free_columns > 0 {
                &mut ff[..free_rows]
            } else {
                &mut fp[..free_rows]
            };
            let (mut k, mut l) = (0, 0);
            for &w in adjacency.of(v) {
                for g in dofs.vertex_dofs(w) {
                    match statuses[g] {
                        DofStatus::Free(i) => {
                            first_free[k] = i;
                            k += 1;
                        }
                        DofStatus::Prescribed(i) => {
                            if prescribed_columns > 0 {
                                pp[l] = i;
                            }
                            l += 1;
                        }
                    }
                }
            }
            debug_assert_eq!((k, l), (free_rows, prescribed_rows));
            // Copied to the vertex's other columns.
            if free_columns > 0 {
                for c in 1..free_columns {
                    ff.copy_within(..free_rows, c * free_rows);
                }
                for c in 0..prescribed_columns {
                    fp[c * free_rows..(c + 1) * free_rows].copy_from_slice(&ff[..free_rows]);
                }
            } else {
                for c in 1..prescribed_columns {
                    fp.copy_within(..free_rows, c * free_rows);
                }
            }
            for c in 1..prescribed_columns {
                pp.copy_within(..prescribed_rows, c * prescribed_rows);
            }
        }
    });
    let finish = |n_rows, n_cols, col_ptr, row_idx| {
        SymbolicSparseColMat::new_checked(n_rows, n_cols, col_ptr, None, row_idx)
    };
    (
        finish(n_f, n_f, ff_ptr, ff_rows),
        finish(n_f, n_p, fp_ptr, fp_rows),
        finish(n_p, n_p, pp_ptr, pp_rows),
    )
}

/// The pattern of the bordered matrix `[K_ff, K_fp E; E^T K_pf, E^T K_pp E]`: column `j` of
/// `K_ff` gains row `n_f + k` where a degree of freedom tied to plate `k` couples to `j`; plate
/// column `n_f + k` holds those rows and a full plate x plate block.
fn bordered_pattern(
    ff: &SymbolicSparseColMat<usize>,
    fp: &SymbolicSparseColMat<usize>,
    dofs: &DofMap,
) -> SymbolicSparseColMat<usize> {
    let (n_f, m) = (dofs.n_free(), dofs.n_plates());
    // The free rows coupled to each plate (sorted, distinct).
    let coupled: Vec<Vec<usize>> = dofs
        .plates()
        .iter()
        .map(|plate| {
            let mut rows: Vec<usize> = plate
                .members
                .iter()
                .flat_map(|&p| fp.row_idx()[fp.col_ptr()[p]..fp.col_ptr()[p + 1]].iter())
                .copied()
                .collect();
            rows.sort_unstable();
            rows.dedup();
            rows
        })
        .collect();
    // For each free column, the plates it couples to.
    let mut plates_of_column: Vec<Vec<usize>> = vec![Vec::new(); n_f];
    for (k, rows) in coupled.iter().enumerate() {
        for &r in rows {
            plates_of_column[r].push(n_f + k);
        }
    }
    let mut builder = CscBuilder::new(n_f + m, ff.row_idx().len());
    for (j, extra) in plates_of_column.iter().enumerate() {
        builder
            .row_idx
            .extend_from_slice(&ff.row_idx()[ff.col_ptr()[j]..ff.col_ptr()[j + 1]]);
        builder.row_idx.extend_from_slice(extra);
        builder.close_column();
    }
    for rows in &coupled {
        builder.row_idx.extend_from_slice(rows);
        builder.row_idx.extend(n_f..n_f + m);
        builder.close_column();
    }
    builder.finish(n_f + m, n_f + m)
}

/// Fills the values of the bordered matrix (pattern of [`bordered_pattern`]) from the blocks.
fn fill_bordered(
    bordered: &mut SparseColMat<usize, f64>,
    ff: &SparseColMat<usize, f64>,
    fp: &SparseColMat<usize, f64>,
    pp: &SparseColMat<usize, f64>,
    dofs: &DofMap,
) {
    let (n_f, m) = (dofs.n_free(), dofs.n_plates());
    // c_k = K_fp E_k (dense over the free rows) and d = E^T K_pp E.
    let mut c = vec![vec![0.0; n_f]; m];
    let mut d = vec![vec![0.0; m]; m];
    let plate_of = dofs.plate_of_prescribed();
    let (fp_pattern, fp_values) = fp.parts();
    let (pp_pattern, pp_values) = pp.parts();
    for (k, plate) in dofs.plates().iter().enumerate() {
        for &p in &plate.members {
            for q in fp_pattern.col_ptr()[p]..fp_pattern.col_ptr()[p + 1] {
                c[k][fp_pattern.row_idx()[q]] += fp_values[q];
            }
            for q in pp_pattern.col_ptr()[p]..pp_pattern.col_ptr()[p + 1] {
                if let Some(l) = plate_of[pp_pattern.row_idx()[q]] {
                    d[l][k] += pp_values[q];
                }
            }
        }
    }
    let (ff_pattern, ff_values) = ff.parts();
    let (pattern, values) = bordered.parts_mut();
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    for j in 0..n_f + m {
        let mut q = col_ptr[j];
        if j < n_f {
            let own = ff_pattern.col_ptr()[j]..ff_pattern.col_ptr()[j + 1];
            let len = own.len();
            values[q..q + len].copy_from_slice(&ff_values[own]);
            q += len;
        }
        for position in q..col_ptr[j + 1] {
            let row = row_idx[position];
            // After K_ff's own entries a free column holds only plate rows.
            values[position] = if j < n_f {
                c[row - n_f][j]
            } else if row < n_f {
                c[j - n_f][row]
            } else {
                d[row - n_f][j - n_f]
            };
        }
    }
}

/// Compressed-column storage built column by column.
struct CscBuilder {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl CscBuilder {
    fn new(n_cols: usize, nnz_estimate: usize) -> Self {
        let mut col_ptr = Vec::with_capacity(n_cols + 1);
        col_ptr.push(0);
        Self {
            col_ptr,
            row_idx: Vec::with_capacity(nnz_estimate),
        }
    }

    fn close_column(&mut self) {
        self.col_ptr.push(self.row_idx.len());
    }

    fn finish(self, n_rows: usize, n_cols: usize) -> SymbolicSparseColMat<usize> {
        SymbolicSparseColMat::new_checked(n_rows, n_cols, self.col_ptr, None, self.row_idx)
    }
}

/// The rows of one element: `(row, local index)` of its free degrees of freedom sorted by free
/// index (the first `n_free`), then of its prescribed ones sorted by prescribed index.
pub(crate) struct ElementRows {
    rows: Vec<(usize, usize)>,
    n_free: usize,
}

impl ElementRows {
    fn new(dofs: &[usize], statuses: &[DofStatus]) -> Self {
        let mut rows = Vec::with_capacity(dofs.len());
        rows.extend(
            dofs.iter()
                .enumerate()
                .filter_map(|(a, &g)| match statuses[g] {
                    DofStatus::Free(row) => Some((row, a)),
                    DofStatus::Prescribed(_) => None,
                }),
        );
        let n_free = rows.len();
        rows.extend(
            dofs.iter()
                .enumerate()
                .filter_map(|(a, &g)| match statuses[g] {
                    DofStatus::Prescribed(row) => Some((row, a)),
                    DofStatus::Free(_) => None,
                }),
        );
        rows[..n_free].sort_unstable();
        rows[n_free..].sort_unstable();
        Self { rows, n_free }
    }
}

/// A view of the values of one block of columns of `K_ff`, `K_fp`, `K_pp` and of the load,
/// owned by one thread during the scatter.
struct ColumnBlock<'a> {
    global: Range<usize>,
    ff: BlockValues<'a>,
    fp: BlockValues<'a>,
    pp: BlockValues<'a>,
    load: &'a mut [f64],
}

/// The values of columns `first_col..` of a compressed-column matrix, with the pattern.
struct BlockValues<'a> {
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
    first_col: usize,
    values: &'a mut [f64],
}

impl BlockValues<'_> {
    /// The offsets in column `col` of the rows `rows` (sorted by row): one merge along the
    /// column's sorted row indices, which hold every element coupling by construction.
    #[inline]
    fn offsets(&self, col: usize, rows: &[(usize, usize)], offsets: &mut Vec<usize>) {
        let pattern = &self.row_idx[self.col_ptr[col]..self.col_ptr[col + 1]];
        offsets.clear();
        let mut k = 0;
        for &(row, _) in rows {
            while pattern[k] < row {
                k += 1;
            }
            debug_assert_eq!(pattern[k], row, "the pattern holds every element coupling");
            offsets.push(k);
        }
    }

    /// Adds `column[a]` at the offset `offsets[i]` of column `col` for the `i`-th `(row, a)`
    /// of `rows`.
    #[inline]
    fn add_column(
        &mut self,
        col: usize,
        rows: &[(usize, usize)],
        offsets: &[usize],
        column: &[f64],
    ) {
        let range = self.col_ptr[col]..self.col_ptr[col + 1];
        let start = range.start - self.col_ptr[self.first_col];
        let values = &mut self.values[start..start + range.len()];
        debug_assert!(rows
            .iter()
            .zip(offsets)
            .all(|(&(row, _), &k)| self.row_idx[range.start + k] == row));
        for (&(_, a), &k) in rows.iter().zip(offsets) {
            values[k] += column[a];
        }
    }
}

impl ColumnBlock<'_> {
    /// Adds the columns of every contribution that fall in this block's global range
    /// (`statuses`: those of every global degree of freedom, `d` per vertex).
    ///
    /// The columns of one vertex with the same status have the same rows (see
    /// [`block_patterns`]), and a prescribed column's free rows are those of a free column of
    /// the same vertex: the offsets of the element's rows are found once per vertex (one merge
    /// for the free rows, one for the prescribed ones) and serve its other columns.
    fn scatter(
        &mut self,
        statuses: &[DofStatus],
        d: usize,
        contributions: &[(ElementRows, ElementContribution)],
    ) {
        // The offsets of the element's free and prescribed rows in the columns of the vertex
        // they were last found for.
        let (mut free_at, mut prescribed_at) = (Vec::new(), Vec::new());
        for (rows, contribution) in contributions {
            if !contribution.dofs.iter().any(|g| self.global.contains(g)) {
                continue;
            }
            let (free, prescribed) = rows.rows.split_at(rows.n_free);
            let (mut free_vertex, mut prescribed_vertex) = (usize::MAX, usize::MAX);
            for (b, &gb) in contribution.dofs.iter().enumerate() {
                if !self.global.contains(&gb) {
                    continue;
                }
                if let Some(load) = &contribution.load {
                    self.load[gb - self.global.start] += load[b];
                }
                let column = contribution.matrix.column(b);
                let column = column.as_slice();
                let vertex = gb / d;
                match statuses[gb] {
                    DofStatus::Free(col) => {
                        if free_vertex != vertex {
                            self.ff.offsets(col, free, &mut free_at);
                            free_vertex = vertex;
                        }
                        self.ff.add_column(col, free, &free_at, column);
                    }
                    DofStatus::Prescribed(col) => {
                        if free_vertex != vertex {
                            self.fp.offsets(col, free, &mut free_at);
                            free_vertex = vertex;
                        }
                        self.fp.add_column(col, free, &free_at, column);
                        if prescribed_vertex != vertex {
                            self.pp.offsets(col, prescribed, &mut prescribed_at);
                            prescribed_vertex = vertex;
                        }
                        self.pp.add_column(col, prescribed, &prescribed_at, column);
                    }
                }
            }
        }
    }
}

/// Splits off the first `len` values of `values`.
fn take<'a>(values: &mut &'a mut [f64], len: usize) -> &'a mut [f64] {
    let (head, tail) = std::mem::take(values).split_at_mut(len);
    *values = tail;
    head
}

/// Splits the global degrees of freedom into about `n_blocks` contiguous ranges of similar
/// numbers of stored entries and hands out the corresponding disjoint value slices.
fn column_blocks<'a>(
    dofs: &DofMap,
    ff: &'a mut SparseColMat<usize, f64>,
    fp: &'a mut SparseColMat<usize, f64>,
    pp: &'a mut SparseColMat<usize, f64>,
    load: &'a mut [f64],
    n_blocks: usize,
) -> Vec<ColumnBlock<'a>> {
    let n_dofs = dofs.n_dofs();
    let (ff_pattern, mut ff_values) = ff.parts_mut();
    let (fp_pattern, mut fp_values) = fp.parts_mut();
    let (pp_pattern, mut pp_values) = pp.parts_mut();
    let (ff_ptr, fp_ptr, pp_ptr) = (
        ff_pattern.col_ptr(),
        fp_pattern.col_ptr(),
        pp_pattern.col_ptr(),
    );
    let total = ff_ptr[ff_ptr.len() - 1] + fp_ptr[fp_ptr.len() - 1] + pp_ptr[pp_ptr.len() - 1];
    let target = total.div_ceil(n_blocks.max(1)).max(1);
    // Stored entries before global dof g.
    let entries_before = |g: usize| {
        let (f, p) = dofs.split_point(g);
        ff_ptr[f] + fp_ptr[p] + pp_ptr[p]
    };
    let mut blocks = Vec::with_capacity(n_blocks);
    let mut load = load;
    let mut start = 0;
    while start < n_dofs {
        // The first dof at which the block holds at least `target` entries.
        let base = entries_before(start);
        let (mut lo, mut hi) = (start + 1, n_dofs);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if entries_before(mid) - base >= target {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        let end = lo;
        let (f0, p0) = dofs.split_point(start);
        let (f1, p1) = dofs.split_point(end);
        let ff_block = take(&mut ff_values, ff_ptr[f1] - ff_ptr[f0]);
        let fp_block = take(&mut fp_values, fp_ptr[p1] - fp_ptr[p0]);
        let pp_block = take(&mut pp_values, pp_ptr[p1] - pp_ptr[p0]);
        let load_block = take(&mut load, end - start);
        blocks.push(ColumnBlock {
            global: start..end,
            ff: BlockValues {
                col_ptr: ff_ptr,
                row_idx: ff_pattern.row_idx(),
                first_col: f0,
                values: ff_block,
            },
            fp: BlockValues {
                col_ptr: fp_ptr,
                row_idx: fp_pattern.row_idx(),
                first_col: p0,
                values: fp_block,
            },
            pp: BlockValues {
                col_ptr: pp_ptr,
                row_idx: pp_pattern.row_idx(),
                first_col: p0,
                values: pp_block,
            },
            load: load_block,
        });
        start = end;
    }
    blocks
}
