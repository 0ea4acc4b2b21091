//! The files of `vem run` for a scene in space: one `.vtu` of polyhedra per body (VTK type 42,
//! as ParaView, VTK and meshio read it), `results.pvd` opening them all, `reactions.csv` and
//! `summary.json`. Pictures are drawn in the plane only: a scene in space writes none, and its
//! summary says so.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use vem_mesh::io::{write_atomically, write_polyhedral_vtu, DataArray, PvdCollection, VtuData};
use vem_mesh::polyhedral::quality::CellQuality;
use vem_scene::SolvedBody;

use crate::{CliError, Outcome};

/// The columns of `reactions.csv`, in order.
pub const REACTION_COLUMNS: &str = "body,part,components,rigid_plate,force_x,force_y,force_z";

/// The note of a run in space about its pictures.
pub const NO_PICTURES_IN_SPACE: &str =
    "no pictures: deformed.svg is drawn for bodies in the plane only; open results.pvd in \
     ParaView for the bodies in space";

impl Outcome {
    /// Writes the files of a scene in space into the existing folder `dir`.
    pub(crate) fn write_into_3d(&mut self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let start = Instant::now();
        let mesh_error = |path: &Path| {
            let context = path.display().to_string();
            move |source| CliError::Mesh { context, source }
        };
        let mut written = Vec::new();
        let mut collection = PvdCollection::new();
        for (part, solved) in self.bodies_3d.iter().enumerate() {
            let name = solved.body.name();
            let file = format!("{name}.vtu");
            let path = dir.join(&file);
            write_polyhedral_vtu(&path, solved.body.mesh(), &vtu_data_3d(solved))
                .map_err(mesh_error(&path))?;
            collection.add(0.0, part, name, file);
            written.push(path);
        }
        let path = dir.join("results.pvd");
        collection.write(&path).map_err(mesh_error(&path))?;
        written.push(path);
        let path = dir.join("reactions.csv");
        write_atomically(&path, |w| write_reactions_csv(w, self.summary()))
            .map_err(mesh_error(&path))?;
        written.push(path);
        if !self.summary.notes.iter().any(|n| n == NO_PICTURES_IN_SPACE) {
            self.summary.notes.push(NO_PICTURES_IN_SPACE.to_string());
        }
        let path = dir.join("summary.json");
        self.set_output_time(start.elapsed());
        let json = serde_json::to_string_pretty(&self.summary).map_err(|e| CliError::Io {
            action: "serialise",
            path: path.clone(),
            source: e.into(),
        })?;
        write_atomically(&path, |w| writeln!(w, "{json}")).map_err(mesh_error(&path))?;
        written.push(path);
        Ok(written)
    }
}

/// Point data `displacement` (3 components); cell data `stress_xx_yy_zz` and
/// `stress_yz_xz_xy` (3 components each), `von_mises`, `quality_gamma`, `star_ratio`,
/// `shortest_edge_ratio`.
fn vtu_data_3d(solved: &SolvedBody<3, CellQuality>) -> VtuData {
    let fields = &solved.fields;
    let stress = |pairs: [(usize, usize); 3]| -> Vec<f64> {
        fields
            .iter()
            .flat_map(|f| pairs.map(|(i, j)| f.stress[(i, j)]))
            .collect()
    };
    let qualities = &solved.qualities;
    VtuData::new()
        .with_point_vectors_3d("displacement", &solved.solution.vertex_displacements())
        .with_cell_data(DataArray::new(
            "stress_xx_yy_zz",
            3,
            stress([(0, 0), (1, 1), (2, 2)]),
        ))
        .with_cell_data(DataArray::new(
            "stress_yz_xz_xy",
            3,
            stress([(1, 2), (0, 2), (0, 1)]),
        ))
        .with_cell_scalars("von_mises", fields.iter().map(|f| f.von_mises).collect())
        .with_cell_scalars(
            "quality_gamma",
            qualities.iter().map(CellQuality::gamma).collect(),
        )
        .with_cell_scalars(
            "star_ratio",
            qualities.iter().map(|q| q.star_ratio).collect(),
        )
        .with_cell_scalars(
            "shortest_edge_ratio",
            qualities.iter().map(|q| q.shortest_edge_ratio).collect(),
        )
}

/// One row per Dirichlet condition or rigid plate of every body: the force the support
/// exerts on the body (the prescribed resultant for a rigid plate), by component.
fn write_reactions_csv(w: &mut dyn Write, summary: &vem_scene::RunSummary) -> std::io::Result<()> {
    writeln!(w, "{REACTION_COLUMNS}")?;
    for body in &summary.bodies {
        for r in &body.reactions {
            let force: Vec<String> = (0..3)
                .map(|i| {
                    r.force
                        .get(i)
                        .map_or_else(String::new, |f| format!("{f:e}"))
                })
                .collect();
            writeln!(
                w,
                "{},{},\"{}\",{},{}",
                body.name,
                r.part,
                r.components,
                r.rigid_plate,
                force.join(",")
            )?;
        }
    }
    Ok(())
}
