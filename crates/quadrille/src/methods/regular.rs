//! The regular method (Docampo-Sánchez & Haimes, "Towards Fully Regular
//! Quad Mesh Generation", the fully-regular paper): the baseline mesh of
//! every face (about half its vertices irregular), then topological
//! regularization face by face ([`crate::topology::regularize`]: swaps,
//! collapses and splits toward valence 4, quads kept within the angle window).

use geometry::Model;
use mesh::QuadMesh;

use crate::core::error::MeshError;
use crate::methods::baseline::mesh_baseline;
use crate::methods::driver::in_pool;
use crate::methods::options::MeshOptions;
use crate::methods::report::{timed, MeshReport};
use crate::topology::regularize::{regularize_mesh_with_progress, RegularizeOptions};

/// The regular method at target size `h`: [`mesh_baseline`] on `opts.threads`
/// threads, then [`regularize_mesh_with_progress`] with `ropts` (its own
/// thread count), reporting to `opts.regularize_progress`.
pub(crate) fn mesh_regular(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    ropts: &RegularizeOptions,
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let (mut mesh, mut report) = in_pool(opts.threads, || mesh_baseline(model, h, opts, &[]))?;
    let rep = timed(&mut report.times.regularize, "regularize", || {
        regularize_mesh_with_progress(model, &mut mesh, ropts, opts.regularize_progress.as_ref())
    })
    .map_err(|e| MeshError::Regularize(e.to_string()))?;
    report.regularize = Some(rep);
    Ok((mesh, report))
}
