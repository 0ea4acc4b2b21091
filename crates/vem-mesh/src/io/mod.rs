//! File input and output: atomic writes; PolyMesher/mVEM text input; and with the features of
//! the same names Gmsh `.msh` 4.1 and 2.2 input (`gmsh`), VTK `.vtu` output and `.pvd`
//! collections with `.vtu`/legacy `.vtk` input (`vtu`), and SVG output (`svg`).
//!
//! Every writer goes through [`write_atomically`]: a file is written whole or not at all, so
//! an interrupted run never leaves a truncated `.vtu` that a viewer half-reads.
//!
//! ```
//! # #[cfg(all(feature = "generators", feature = "vtu", feature = "svg"))] {
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::io::{write_svg, write_vtu, SvgOptions, VtuData};
//!
//! let mesh = structured_quads(&Rectangle::unit_square(), 4, 4)?;
//! let dir = std::env::temp_dir().join(format!("vem-mesh-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let x: Vec<f64> = mesh.vertices().iter().map(|p| p.x).collect();
//! write_vtu(dir.join("square.vtu"), &mesh, &VtuData::new().with_point_scalars("x", x))?;
//! write_svg(dir.join("square.svg"), &mesh, &SvgOptions::default())?;
//! # std::fs::remove_dir_all(&dir).unwrap();
//! # }
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

#[cfg(feature = "gmsh")]
mod gmsh;
#[cfg(feature = "gmsh")]
mod gmsh3d;
#[cfg(feature = "gmsh")]
mod msh;
mod polymesher;
#[cfg(feature = "svg")]
mod raster;
#[cfg(feature = "svg")]
mod svg;
#[cfg(feature = "vtu")]
mod vtk;
#[cfg(feature = "vtu")]
mod vtk_read;
#[cfg(feature = "vtu")]
mod vtu;
#[cfg(feature = "vtu")]
mod vtu_polyhedral;

#[cfg(feature = "gmsh")]
pub use gmsh::{mesh_from_msh, read_gmsh, read_gmsh_bytes};
#[cfg(feature = "gmsh")]
pub use gmsh3d::{polyhedral_mesh_from_msh, read_gmsh_polyhedral, read_gmsh_polyhedral_bytes};
#[cfg(feature = "gmsh")]
pub use msh::{
    element_type_name, read_msh_bytes, MshElement, MshEntity, MshError, MshFile, MshLocation,
    MshNode, MshVersion,
};
pub use polymesher::{read_polymesher, read_polymesher_bytes};
#[cfg(feature = "svg")]
pub use svg::{
    wrap, write_svg, write_svg_layers, SvgLayer, SvgMarks, SvgOptions, EDGE_MIN_PIXELS,
    VECTOR_CELL_LIMIT,
};
#[cfg(feature = "vtu")]
pub use vtk::{
    CellType, Cells, PvdCollection, PvdDataSet, UnstructuredGrid, Values, VtkArray, VtuEncoding,
};
#[cfg(feature = "vtu")]
pub use vtk_read::{
    mesh_from_grid, read_legacy_vtk, read_legacy_vtk_bytes, read_vtk_mesh, read_vtu,
    read_vtu_bytes, GridMeshOptions,
};
#[cfg(feature = "vtu")]
pub use vtu::{write_vtu, write_vtu_with, DataArray, VtuData};
#[cfg(feature = "vtu")]
pub use vtu_polyhedral::{write_polyhedral_vtu, write_polyhedral_vtu_with};

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::MeshError;

/// Writes the file at `path` whole or not at all.
///
/// `write` receives a buffered writer on a temporary file in the same directory as `path`
/// (so that the final rename stays on one file system). When `write` succeeds the data is
/// flushed and synced to disk and the temporary file is renamed over `path`, replacing any
/// previous file atomically. When anything fails the temporary file is removed, `path` is left
/// as it was, and the error is [`MeshError::Write`] naming `path`.
///
/// Any text or binary format can use it (VTU, SVG, CSV, JSON):
///
/// ```
/// use std::io::Write;
/// let path = std::env::temp_dir().join(format!("vem-mesh-atomic-doc-{}.csv", std::process::id()));
/// vem_mesh::io::write_atomically(&path, |w| writeln!(w, "h,error\n0.5,0.01"))?;
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "h,error\n0.5,0.01\n");
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn write_atomically<F>(path: impl AsRef<Path>, write: F) -> Result<(), MeshError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let path = path.as_ref();
    let fail = |reason: String| MeshError::Write {
        path: path.to_path_buf(),
        reason,
    };
    let (temporary, file) = create_temporary(path)
        .map_err(|e| fail(format!("cannot create a temporary file beside it: {e}")))?;
    let result = write_and_sync(file, write).and_then(|()| fs::rename(&temporary, path));
    result.map_err(|e| {
        // The temporary file is ours and incomplete: remove it, whatever the failure was.
        let _ = fs::remove_file(&temporary);
        fail(e.to_string())
    })
}

/// Runs `write` on a buffered `file`, then flushes and syncs it to disk.
fn write_and_sync<F>(file: File, write: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()
}

/// Creates a new, empty temporary file in the directory of `path`, named after it.
fn create_temporary(path: &Path) -> io::Result<(PathBuf, File)> {
    loop {
        let temporary = temporary_sibling(path)?;
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
        {
            Ok(file) => return Ok((temporary, file)),
            // Left over from a crashed process with the same id: try the next name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// A fresh name `.NAME.PID.N.tmp` beside `path` (in its directory, `.` for a bare name) for a
/// temporary file or folder that is renamed onto `path` once complete: the pattern
/// [`remove_stale_temporaries`] recognises. `N` counts up within the process; a name may still
/// exist (left by a crashed process with the same id), so create it with `create_new` and ask
/// again on `AlreadyExists`.
pub fn temporary_sibling(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, "the path does not name a file")
    })?;
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(name);
    temporary_name.push(format!(
        ".{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    Ok(directory.join(temporary_name))
}

/// Removes from `directory` the temporaries that processes no longer running left behind:
/// entries named `.NAME.PID.N.tmp` (files of [`write_atomically`], or folders of the same
/// pattern) and `.NAME.PID.N.old`, whose process `PID` is not running. Returns how many
/// were removed. Where the system does not list its processes (no `/proc`) nothing is
/// removed: a temporary of a running process must not be.
pub fn remove_stale_temporaries(directory: impl AsRef<Path>) -> io::Result<usize> {
    if !Path::new("/proc/self").exists() {
        return Ok(0);
    }
    let mut removed = 0;
    for entry in fs::read_dir(directory)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(temporary_owner) else {
            continue;
        };
        if Path::new("/proc").join(pid.to_string()).exists() {
            continue;
        }
        let path = entry.path();
        let result = if entry.file_type()?.is_dir() {
            fs::remove_dir_all(&path)
        } else {
            fs::remove_file(&path)
        };
        match result {
            Ok(()) => removed += 1,
            // Removed meanwhile by another run cleaning up too.
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
    }
    Ok(removed)
}

/// The process id of a temporary's name `.NAME.PID.N.tmp` or `.NAME.PID.N.old`.
fn temporary_owner(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?;
    let rest = rest
        .strip_suffix(".tmp")
        .or_else(|| rest.strip_suffix(".old"))?;
    let mut fields = rest.rsplitn(3, '.');
    let counter = fields.next()?;
    let pid = fields.next()?;
    let stem = fields.next()?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(counter) && !stem.is_empty()).then(|| pid.parse().ok())?
}

/// Escapes the five XML special characters of `text` (attribute values and text content).
#[cfg(any(feature = "vtu", feature = "svg"))]
pub(crate) fn xml_escape(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            c => escaped.push(c),
        }
    }
    escaped
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("vem-mesh-io-{name}-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = scratch_dir("atomic");
        let path = dir.join("data.csv");
        write_atomically(&path, |w| w.write_all(b"old")).unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
        assert_eq!(
            err,
            MeshError::Write {
                path: path.clone(),
                reason: "disk on fire".into()
            }
        );
        assert_eq!(fs::read(&path).unwrap(), b"old");
        let entries: Vec<_> = fs::read_dir(&dir).unwrap().collect();
        assert_eq!(entries.len(), 1, "only data.csv may remain");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_directory_is_a_write_error_naming_the_file() {
        let path = scratch_dir("missing").join("no/such/dir/out.vtu");
        let err = write_atomically(&path, |w| w.write_all(b"x")).unwrap_err();
        match err {
            MeshError::Write { path: p, reason } => {
                assert_eq!(p, path);
                assert!(reason.contains("temporary"), "{reason}");
            }
            other => panic!("unexpected {other}"),
        }
    }

    /// Temporaries of a process that is gone are removed; those of a running process (this
    /// one) and ordinary files stay.
    #[test]
    #[cfg(target_os = "linux")]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = scratch_dir("stale");
        // Process ids above the kernel's largest (2^22) never run.
        let dead = 4_194_399;
        let own = std::process::id();
        let names = [
            format!(".a.vtu.{dead}.0.tmp"),
            format!(".out.{dead}.3.old"),
            format!(".a.vtu.{own}.0.tmp"),
            "a.vtu".to_string(),
            ".hidden.tmp".to_string(),
        ];
        for name in &names {
            fs::write(dir.join(name), b"x").unwrap();
        }
        fs::create_dir(dir.join(format!(".run.{dead}.1.tmp"))).unwrap();
        fs::write(dir.join(format!(".run.{dead}.1.tmp/a.vtu")), b"x").unwrap();
        assert_eq!(remove_stale_temporaries(&dir).unwrap(), 3);
        let mut left: Vec<String> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(
            left,
            [
                ".a.vtu.".to_string() + &format!("{own}.0.tmp"),
                ".hidden.tmp".into(),
                "a.vtu".into()
            ]
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn temporary_names_are_recognised() {
        assert_eq!(temporary_owner(".a.vtu.12.3.tmp"), Some(12));
        assert_eq!(temporary_owner(".out.7.0.old"), Some(7));
        assert_eq!(temporary_owner("a.vtu.12.3.tmp"), None);
        assert_eq!(temporary_owner(".a.x.3.tmp"), None);
        assert_eq!(temporary_owner(".12.3.tmp"), None);
    }

    #[test]
    #[cfg(any(feature = "vtu", feature = "svg"))]
    fn escapes_markup() {
        assert_eq!(
            xml_escape("a<b & \"c\">'"),
            "a&lt;b &amp; &quot;c&quot;&gt;&apos;"
        );
    }
}
