//! Methods: each meshing method as its recipe of stages, and the driver that
//! meshes every face and assembles the model's mesh. Imports every folder
//! below it; nothing imports it but the crate root.
//!
//! - [`baseline`]: triangulation split into quads (ours; always valid, the
//!   fallback of every other method);
//! - [`unstructured`]: the quasi-structured meshing paper's §5 on one face
//!   (frontal points, recombination, subdivision);
//! - [`quasi_structured`]: the paper's whole recipe (§3–6), and the plain
//!   unstructured method as its preset without topology stages;
//! - [`regular`]: the fully-regular paper's method (baseline, then
//!   topological regularization);
//! - [`driver`]: faces in parallel, curve refinement rounds, assembly;
//! - [`guard`]: the size guard, the quad count estimated before meshing
//!   and a run refused above [`MeshOptions::max_quads`];
//! - [`options`], [`report`]: what a method takes and gives back.
//!
//! - [`curvenet`]: quads from the closed cycles of a 3D curve network, no
//!   surface given (paper curve-network-quadrangulation; `quadrille curves`).
//!
//! - [`spline`]: untrimmed bicubic B-spline patches of an open shell (paper
//!   ricci-flow-iga-reconstruction; `quadrille spline`), the cone-free disks so far.

pub(crate) mod baseline;
pub(crate) mod coarse;
pub mod curvenet;
mod curvenet_assemble;
mod curvenet_facing;
pub mod curvenet_network;
pub mod curvenet_seams;
pub(crate) mod driver;
pub(crate) mod guard;
pub(crate) mod options;
pub(crate) mod quasi_structured;
pub(crate) mod regular;
pub(crate) mod report;
pub mod spline;
pub(crate) mod unstructured;

#[cfg(test)]
mod tests;

use std::time::{Duration, Instant};

use geometry::{CornerId, Model};
use mesh::QuadMesh;

use crate::core::error::MeshError;
use crate::core::options::resolve_size;
use crate::topology::regularize::RegularizeOptions;
use driver::{collapse_slivers, in_pool};
use options::{MeshOptions, Stages};
use report::MeshReport;

/// A meshing method: which recipe [`mesh_model_with`] runs.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshMethod {
    /// Triangulate each face in (u, v) and split every triangle into three
    /// quads ([`baseline`]): always valid, about half the vertices irregular.
    Baseline,
    /// The quasi-structured meshing paper's §5 mesh alone: cross field and
    /// size map, frontal points, recombination, subdivision, smoothing
    /// ([`quasi_structured`] with [`Stages::NONE`], the plain preset).
    Unstructured,
    /// The quasi-structured method (the default): the §5 mesh, then the
    /// topology stages of [`Stages`] ([`quasi_structured`]).
    QuasiStructured(Stages),
    /// The regular method: the baseline, then topological regularization
    /// with these options ([`regular`]).
    Regular(RegularizeOptions),
}

impl MeshMethod {
    /// [`MeshMethod::Regular`] with the default regularization on `threads`
    /// threads (`None`: rayon's pool), as the front ends ask for it.
    pub fn regular(threads: Option<usize>) -> Self {
        MeshMethod::Regular(RegularizeOptions {
            threads,
            ..Default::default()
        })
    }
}

impl Default for MeshMethod {
    /// [`MeshMethod::QuasiStructured`] with every stage.
    fn default() -> Self {
        MeshMethod::QuasiStructured(Stages::ALL)
    }
}

/// Meshes every face of `model` with the default method (quasi-structured):
/// an all-quad mesh, conforming across shared curves and seams, every node
/// on the CAD and classified on its entity, every quad counter-clockwise
/// seen from its face's oriented normal. Output is identical for any
/// `threads`.
///
/// ```
/// let model = geometry::primitives::square(1.0);
/// let opts = quadrille::MeshOptions { threads: Some(1), ..Default::default() };
/// let mesh = quadrille::mesh_model(&model, &opts).unwrap();
/// assert!(!mesh.quads.is_empty());
/// ```
pub fn mesh_model(model: &Model, opts: &MeshOptions) -> Result<QuadMesh, MeshError> {
    mesh_model_with(model, opts, MeshMethod::default()).map(|(m, _)| m)
}

/// [`mesh_model`] with a choice of method; also reports what each stage did
/// (faces by pattern, faces that fell back to the baseline, stage times).
/// Output is identical for any `threads`.
///
/// ```
/// use quadrille::{mesh_model_with, MeshMethod, MeshOptions, Stages};
/// let model = geometry::primitives::square(1.0);
/// let opts = MeshOptions { threads: Some(1), ..Default::default() };
/// let (mesh, report) = mesh_model_with(&model, &opts, MeshMethod::Unstructured).unwrap();
/// assert!(!mesh.quads.is_empty());
/// // no topology stage ran: no face by a pattern, no cavity
/// assert!(report.patterns.is_empty() && report.cavities.replaced == [0; 4]);
/// let no_cavities = MeshMethod::QuasiStructured(Stages { cavities: false, ..Stages::ALL });
/// assert!(mesh_model_with(&model, &opts, no_cavities).is_ok());
/// ```
pub fn mesh_model_with(
    model: &Model,
    opts: &MeshOptions,
    method: MeshMethod,
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let started = Instant::now();
    model.validate()?;
    if model.faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    let h = resolve_size(model, opts.size)?;
    let collapsed = meshed_model(model, &method);
    let (model, slivers) = match &collapsed {
        Some((copy, list)) => (copy, list.as_slice()),
        None => (model, &[][..]),
    };
    // the size guard, before any curve is sampled at size h
    let mut estimate_time = Duration::ZERO;
    let estimated = report::timed(&mut estimate_time, "estimate", || {
        in_pool(opts.threads, || guard::check(model, h, opts, &method))
    })?;
    let merged: Vec<CornerId> = slivers
        .iter()
        .filter(|c| c.removed != c.kept)
        .map(|c| c.removed)
        .collect();
    let merged = merged.as_slice();
    let mut out = match &method {
        MeshMethod::Baseline => in_pool(opts.threads, || {
            baseline::mesh_baseline(model, h, opts, merged)
        }),
        MeshMethod::Unstructured => in_pool(opts.threads, || {
            quasi_structured::mesh_quasi_structured(model, h, opts, Stages::NONE, merged)
        }),
        MeshMethod::QuasiStructured(stages) => in_pool(opts.threads, || {
            quasi_structured::mesh_quasi_structured(model, h, opts, *stages, merged)
        }),
        MeshMethod::Regular(ropts) => regular::mesh_regular(model, h, opts, ropts),
    }?;
    out.1.times.estimate = estimate_time;
    out.1.estimated_quads = estimated;
    out.1.times.total = started.elapsed();
    // (the regular method collapses slivers itself when its baseline fails)
    if collapsed.is_some() {
        out.1.slivers = slivers.iter().map(|c| (c.curve, c.length)).collect();
    }
    Ok(out)
}

/// The model `method` meshes: the field-guided methods mesh sliver curves
/// as points (their corners one node; ids kept), a copy with the list of
/// curves collapsed; the baseline, the regular method's input, meshes the
/// model as it is (`None`).
fn meshed_model(
    model: &Model,
    method: &MeshMethod,
) -> Option<(Model, Vec<geometry::slivers::Collapsed>)> {
    match method {
        MeshMethod::Unstructured | MeshMethod::QuasiStructured(_) => collapse_slivers(model),
        MeshMethod::Baseline | MeshMethod::Regular(_) => None,
    }
}

/// The quad count `method` is estimated to make on `model` with `opts`,
/// without meshing: what the size guard of [`mesh_model_with`] compares
/// with [`MeshOptions::max_quads`] (and reports as
/// [`MeshReport::estimated_quads`]). Cheap at any size: the size map is
/// integrated on a background no finer than the default size's
/// ([`crate::field::size_integral`]); within 30 % of the default method's
/// count on the bundled models at the default size.
///
/// ```
/// use quadrille::{estimate_quads, MeshMethod, MeshOptions, Size};
/// let model = geometry::primitives::square(1.0);
/// let at = |h| MeshOptions { size: Size::Absolute(h), ..Default::default() };
/// let coarse = estimate_quads(&model, &at(0.1), &MeshMethod::default()).unwrap();
/// let fine = estimate_quads(&model, &at(1e-4), &MeshMethod::default()).unwrap();
/// // about area / h² quads: a thousand times finer, a million times more
/// let ratio = fine as f64 / coarse as f64;
/// assert!(ratio > 0.5e6 && ratio < 2e6, "{ratio}");
/// ```
pub fn estimate_quads(
    model: &Model,
    opts: &MeshOptions,
    method: &MeshMethod,
) -> Result<u64, MeshError> {
    model.validate()?;
    if model.faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    let h = resolve_size(model, opts.size)?;
    let collapsed = meshed_model(model, method);
    let model = collapsed.as_ref().map_or(model, |(m, _)| m);
    in_pool(opts.threads, || {
        guard::estimate_at(model, h, opts, method).map(|n| n.round() as u64)
    })
}

pub use baseline::mesh_face;
pub use guard::{BYTES_PER_QUAD, DEFAULT_MAX_QUADS};
