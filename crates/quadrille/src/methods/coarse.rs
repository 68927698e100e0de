//! The coarse method end to end (coarse high-order quads paper;
//! `quadrille mesh --method coarse`): the default method's quads (or a given
//! all-quad mesh), the block layout of [`crate::coarse`], its fine
//! block-structured mesh and one curved Lagrange quad per block. A layout
//! whose geometry fails falls back to the input's own layout (`q = l`, one
//! block per input quad: valid, conforming, nothing lost), which is reported.

use super::driver::in_pool;
use super::options::MeshOptions;
use crate::coarse::block_layout::BlockLayout;
use crate::coarse::fine_mesh::fine_mesh;
use crate::coarse::high_order_extraction::extract_high_order;
use crate::coarse::quad_loops::QuadLoops;
use crate::coarse::{coarse_layout, LayoutOptions, LayoutReport};
use crate::core::error::MeshError;
use geometry::Model;
use mesh::{HighOrderQuadMesh, NodeClass, QuadMesh};
use std::time::Instant;

/// Options of the coarse method (its size and threads come from
/// [`MeshOptions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoarseOptions {
    /// Lagrange order N of the elements, 1..=10 (the paper: 5; 1 gives the
    /// straight block layout).
    pub order: usize,
    /// The layout stages' options (α, the integer program's time limit).
    pub layout: LayoutOptions,
}

impl Default for CoarseOptions {
    fn default() -> Self {
        CoarseOptions { order: 5, layout: LayoutOptions::default() }
    }
}

/// What the coarse method makes.
#[derive(Clone, Debug)]
pub struct CoarseMesh {
    /// The input all-quad mesh (the default method's, or the given one).
    pub input: QuadMesh,
    /// The fine block-structured mesh (blocks subdivided and smoothed).
    pub fine: QuadMesh,
    /// One Lagrange quad of order N per block.
    pub high_order: HighOrderQuadMesh,
}

/// Seconds per stage (the paper's Table 1 split).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoarseTimes {
    /// The default method (0 with a given input mesh).
    pub quasi_structured: f64,
    /// Traces, T-mesh, integer program and layout (the solver included).
    pub layout: f64,
    /// Fine block mesh: subdivision and smoothing.
    pub fine_mesh: f64,
    /// High-order extraction.
    pub high_order: f64,
}

impl CoarseTimes {
    /// All stages.
    pub fn total(&self) -> f64 {
        self.quasi_structured + self.layout + self.fine_mesh + self.high_order
    }
}

/// What the coarse method did.
#[derive(Clone, Debug, PartialEq)]
pub struct CoarseReport {
    /// The layout stages' figures (Table 1, the solve).
    pub layout: LayoutReport,
    /// Seconds per stage.
    pub times: CoarseTimes,
    /// Fine-mesh quads that stayed inverted after smoothing and untangling.
    pub fine_invalid_quads: usize,
    /// Elements with det J ≤ 0 at a node after the repairs (written anyway).
    pub invalid_elements: Vec<u32>,
    /// Elements whose inner nodes were resampled from the fine grid.
    pub resampled_elements: usize,
    /// True when the coarse layout's geometry failed and the input's own
    /// layout was used.
    pub used_input_layout: bool,
    /// Lines for the user: fallbacks and repairs.
    pub geometry_notes: Vec<String>,
    /// The size guard's estimate of the default method's quad count
    /// ([`crate::MeshReport::estimated_quads`]); `None` with a given input mesh.
    pub estimated_quads: Option<u64>,
}

/// Checks that `mesh` can start the coarse method on `model`: quads only,
/// every node and quad classified on an entity of `model`, and the model
/// 2-manifold (no curve on three or more faces; the paper's limit).
pub fn check_input_mesh(mesh: &QuadMesh, model: &Model) -> Result<(), MeshError> {
    check_manifold(model)?;
    if !mesh.triangles.is_empty() {
        return Err(MeshError::Coarse(format!(
            "the input mesh has {} triangles; the coarse method needs quads only",
            mesh.triangles.len()
        )));
    }
    if mesh.quads.is_empty() {
        return Err(MeshError::Coarse("the input mesh has no quads".into()));
    }
    for (v, c) in mesh.node_class.iter().enumerate() {
        let known = match *c {
            NodeClass::Corner(k) => k.idx() < model.corners.len(),
            NodeClass::Curve(k, _) => k.idx() < model.curves.len(),
            NodeClass::Face(k, _) => k.idx() < model.faces.len(),
            NodeClass::Unclassified => false,
        };
        if !known {
            return Err(MeshError::Coarse(format!(
                "node {} is not classified on an entity of the model ({c:?})",
                v + 1
            )));
        }
    }
    if let Some(q) = mesh.quad_face.iter().position(|f| f.idx() >= model.faces.len()) {
        return Err(MeshError::Coarse(format!("quad {} is on no face of the model", q + 1)));
    }
    Ok(())
}

/// Refuses a model with a curve on three or more faces, naming it.
fn check_manifold(model: &Model) -> Result<(), MeshError> {
    for (c, faces) in model.curve_faces().iter().enumerate() {
        if faces.len() >= 3 {
            return Err(MeshError::Coarse(format!(
                "curve {} is on {} faces; the coarse method needs each curve on at most two \
                 (a 2-manifold model)",
                c + 1,
                faces.len()
            )));
        }
    }
    Ok(())
}

/// The coarse method on `model`: from `input` when given (checked by
/// [`check_input_mesh`]), else from the default method's mesh at
/// `mesh_opts`' size. Output identical for any thread count unless the
/// integer program hit its time limit (reported).
pub fn mesh_coarse(
    model: &Model,
    mesh_opts: &MeshOptions,
    opts: &CoarseOptions,
    input: Option<QuadMesh>,
) -> Result<(CoarseMesh, CoarseReport), MeshError> {
    if !(1..=mesh::high_order::MAX_ORDER).contains(&opts.order) {
        return Err(MeshError::Coarse(format!(
            "--order {} is out of range: it must be 1 to {}",
            opts.order,
            mesh::high_order::MAX_ORDER
        )));
    }
    check_manifold(model)?;
    let mut times = CoarseTimes::default();
    let started = Instant::now();
    let mut estimated_quads = None;
    let input = match input {
        Some(m) => {
            check_input_mesh(&m, model)?;
            m
        }
        None => {
            // without ring grids ([`MeshOptions::ring_grids`])
            let no_rings = MeshOptions { ring_grids: false, ..mesh_opts.clone() };
            let (m, r) = super::mesh_model_with(model, &no_rings, super::MeshMethod::default())?;
            times.quasi_structured = started.elapsed().as_secs_f64();
            estimated_quads = Some(r.estimated_quads);
            m
        }
    };
    let t = Instant::now();
    let (layout, layout_report) = coarse_layout(&input, &opts.layout)?;
    times.layout = t.elapsed().as_secs_f64();
    let mut notes = Vec::new();
    let (geometry, used_input_layout) = in_pool(mesh_opts.threads, || {
        let first = geometry_stages(model, &input, &layout, opts.order, &mut times);
        match first {
            Ok(g) => Ok((g, false)),
            Err(why) => {
                notes.push(format!(
                    "the coarse layout's geometry failed ({why}); the input's own layout is used (one block per quad)"
                ));
                let identity = BlockLayout::identity(&input);
                geometry_stages(model, &input, &identity, opts.order, &mut times)
                    .map(|g| (g, true))
                    .map_err(|e| MeshError::Coarse(format!("the input's own layout failed too: {e}")))
            }
        }
    })?;
    let (fine, fine_invalid_quads, high_order, ho) = geometry;
    if !ho.invalid_elements.is_empty() {
        notes.push(format!(
            "{} elements keep det J <= 0 at a node after the repairs: {:?}",
            ho.invalid_elements.len(),
            ho.invalid_elements.iter().take(20).map(|e| e + 1).collect::<Vec<_>>()
        ));
    }
    let mut layout_report = layout_report;
    if used_input_layout {
        layout_report.blocks = high_order.num_elements();
    }
    let report = CoarseReport {
        layout: layout_report,
        times,
        fine_invalid_quads,
        invalid_elements: ho.invalid_elements.clone(),
        resampled_elements: ho.resampled.len(),
        used_input_layout,
        geometry_notes: notes,
        estimated_quads,
    };
    Ok((CoarseMesh { input, fine, high_order }, report))
}

/// The geometry stages' output: fine mesh, its inverted quads, the
/// high-order mesh and its report.
type Geometry = (QuadMesh, usize, HighOrderQuadMesh, crate::coarse::high_order_extraction::HighOrderReport);

/// Fine block mesh, then high-order extraction.
fn geometry_stages(
    model: &Model,
    input: &QuadMesh,
    layout: &BlockLayout,
    order: usize,
    times: &mut CoarseTimes,
) -> Result<Geometry, String> {
    let t = Instant::now();
    let loops = QuadLoops::of(layout);
    let (fine, fine_report) = fine_mesh(model, input, layout, &loops)?;
    times.fine_mesh += t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (high_order, report) = extract_high_order(model, layout, &fine, order)?;
    times.high_order += t.elapsed().as_secs_f64();
    Ok((fine.mesh, fine_report.invalid_quads, high_order, report))
}
