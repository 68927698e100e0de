//! Reading inputs and checking outputs before any long work starts.

use std::path::Path;

use anyhow::{bail, Context, Result};
use geometry::Model;
use mesh::QuadMesh;

/// Options of the triangle-mesh import (`--feature-angle`, `--feature-edges`),
/// set once by `main` before the command runs.
static TRIMESH_OPTIONS: std::sync::OnceLock<trimesh::Options> = std::sync::OnceLock::new();

/// Sets the triangle-mesh import options from the command's arguments.
pub fn set_trimesh_options(args: &crate::ImportArgs) -> Result<()> {
    let mut opts = trimesh::Options {
        feature_angle: args.feature_angle,
        ..Default::default()
    };
    if let Some(f) = &args.feature_edges {
        opts.feature_edges = trimesh::read_feature_edges(f)?;
    }
    let _ = TRIMESH_OPTIONS.set(opts);
    Ok(())
}

/// Loads a model: a CAD file (STEP, IGES, BREP) through OpenCASCADE, or a
/// triangle mesh (STL, OBJ, PLY, MSH) through the discrete B-rep import of
/// the `trimesh` crate; the error names the file. Import warnings (repairs)
/// go to stderr.
pub fn load_model(path: &Path) -> Result<Model> {
    let ext = extension(path);
    if trimesh::Format::from_extension(&ext).is_some() {
        let opts = TRIMESH_OPTIONS.get().cloned().unwrap_or_default();
        let imp = trimesh::load(path, &opts)?;
        for w in &imp.report.warnings {
            eprintln!("warning: {}: {w}", path.display());
        }
        return Ok(imp.model);
    }
    Ok(occt::load(path)?)
}

/// Reads a mesh file (MSH 4.1 or 2.2); the error names the file.
pub fn read_mesh(path: &Path) -> Result<QuadMesh> {
    let ext = extension(path);
    if ext != "msh" {
        bail!(
            "{}: unknown mesh extension '.{ext}' (expected .msh, MSH 4.1 or 2.2)",
            path.display()
        );
    }
    Ok(mesh::msh::read_msh(path)?.mesh)
}

/// Lower-case extension of `path` ("" when none).
pub fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Checks that `path` has one of `allowed` extensions and that its folder
/// accepts a new file, so that a long run does not end on an unwritable path.
pub fn check_output(path: &Path, allowed: &[&str]) -> Result<String> {
    let ext = extension(path);
    if !allowed.contains(&ext.as_str()) {
        bail!(
            "{}: unknown output extension '.{ext}' (expected one of: .{})",
            path.display(),
            allowed.join(", .")
        );
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let probe = dir.join(format!(".quadrille-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").with_context(|| {
        format!(
            "{}: cannot write the output there (folder {})",
            path.display(),
            dir.display()
        )
    })?;
    let _ = std::fs::remove_file(&probe);
    Ok(ext)
}
