//! The regular method (Docampo-Sánchez & Haimes, "Towards Fully Regular
//! Quad Mesh Generation", the fully-regular paper): the baseline mesh of
//! every face (about half its vertices irregular), then topological
//! regularization face by face ([`crate::topology::regularize`]: swaps,
//! collapses and splits toward valence 4, quads kept within the angle window).
//!
//! Where the baseline cannot mesh a face (a curve far shorter than the size
//! beside a hole, boundary points that meet in (u, v): 3 of the 50 industrial
//! corpus parts), the input is the default method's mesh of the model with its
//! sliver curves collapsed ([`input_fallback`]), regularized the same way.

use geometry::Model;
use mesh::QuadMesh;

use crate::core::error::MeshError;
use crate::methods::baseline::mesh_baseline;
use crate::methods::driver::{collapse_slivers, in_pool};
use crate::methods::options::{MeshOptions, Stages};
use crate::methods::quasi_structured::mesh_quasi_structured;
use crate::methods::report::{timed, MeshReport};
use crate::topology::regularize::{regularize_mesh_with_progress, RegularizeOptions};

/// The regular method at target size `h`: [`mesh_baseline`] on `opts.threads`
/// threads (or, when it fails on a face, [`input_fallback`]), then
/// [`regularize_mesh_with_progress`] with `ropts` (its own thread count),
/// reporting to `opts.regularize_progress`.
pub(crate) fn mesh_regular(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    ropts: &RegularizeOptions,
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let collapsed;
    let (model, mut mesh, mut report) =
        match in_pool(opts.threads, || mesh_baseline(model, h, opts, &[])) {
            Ok((mesh, report)) => (model, mesh, report),
            Err(MeshError::Face { face, reason }) => {
                tracing::warn!(
                    "regular method: the baseline could not mesh face {} ({reason}); \
                     regularizing the default method's mesh instead",
                    face.0 + 1
                );
                collapsed = collapse_slivers(model);
                let (m, slivers) = match &collapsed {
                    Some((copy, list)) => (copy, list.as_slice()),
                    None => (model, &[][..]),
                };
                let (mesh, mut report) = input_fallback(m, h, opts, slivers)?;
                report.slivers = slivers.iter().map(|c| (c.curve, c.length)).collect();
                (m, mesh, report)
            }
            Err(e) => return Err(e),
        };
    let rep = timed(&mut report.times.regularize, "regularize", || {
        regularize_mesh_with_progress(model, &mut mesh, ropts, opts.regularize_progress.as_ref())
    })
    .map_err(|e| MeshError::Regularize(e.to_string()))?;
    report.regularize = Some(rep);
    Ok((mesh, report))
}

/// The regular method's input where the baseline fails: the default
/// method (patterns, the field-guided front, defects, cavities, regular pass)
/// on `model` (already with its `slivers` collapsed), which falls back on the
/// baseline only face by face.
pub(crate) fn input_fallback(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    slivers: &[geometry::slivers::Collapsed],
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let merged: Vec<geometry::CornerId> = slivers
        .iter()
        .filter(|c| c.removed != c.kept)
        .map(|c| c.removed)
        .collect();
    in_pool(opts.threads, || {
        mesh_quasi_structured(model, h, opts, Stages::ALL, &merged)
    })
}
