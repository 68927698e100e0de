//! The coarse method (coarse high-order quads paper; `quadrille mesh --method
//! coarse`): the default method's quads, a T-mesh of traces on them (§III.A),
//! an integer program over the T-mesh arc lengths (§III.B–C), the coarse block
//! layout it implies (§IV.A–C), a fine block-structured mesh (§IV.D–E) and one
//! curved Lagrange quad per block (§IV.F).
//!
//! Stages, one module each:
//! - [`connectivity`]: half-edges, stars, irregular nodes (§II, spec §2);
//! - [`traces`]: the traces and their crossings (§III.A);
//! - [`tmesh`]: arcs and patches (§III.A);
//! - [`ilp`]: the integer program and its solve (§III.B–C);
//! - [`layout`]: splitting, merging, placement (§IV.A–C), with [`centres`]
//!   (group centres with an input edge per block side; ours);
//! - [`block_layout`]: the coarse layout placed on the input mesh — the
//!   hand-over between the layout stages and the geometry stages;
//! - [`layout_check`]: the identity layout (every input quad a block, q = l)
//!   and the validity check of a layout;
//! - [`quad_loops`]: the quad loops of a layout and their widths (§IV.D);
//! - [`fine_mesh`]: the fine block-structured mesh, placed by transfinite
//!   interpolation and smoothed (§IV.D–E);
//! - [`high_order_extraction`]: one Lagrange quad of order N per block, its
//!   Jacobian checked (§IV.F);
//! - [`loop_split`]: the quad loops of elements that stay invalid split in
//!   two, and the extraction run again (issue 29; not in the paper).
//!
//! Helpers of the geometry stages: [`face_patches`] (per-face (u, v) views of
//! a mesh) and [`resample`] (equal-arc-length resampling, curve parameters,
//! transfinite interpolation).

pub(crate) mod block_layout;
pub(crate) mod centres;
pub(crate) mod connectivity;
pub(crate) mod face_patches;
pub(crate) mod fine_mesh;
pub(crate) mod high_order_extraction;
pub(crate) mod ilp;
pub(crate) mod layout;
pub(crate) mod layout_check;
pub(crate) mod loop_split;
pub(crate) mod quad_loops;
pub(crate) mod resample;
pub(crate) mod tmesh;
pub(crate) mod traces;

#[cfg(test)]
mod tests;

use crate::core::error::MeshError;
use block_layout::BlockLayout;
use connectivity::{Connectivity, NodeKind};
use ilp::{RowKind, SolveStatus};
use mesh::QuadMesh;
use std::collections::{BTreeMap, HashSet};
use std::time::Instant;

/// Rounds of "hold the failing arcs at their input length and solve again"
/// before the layout falls back to `q = l` (issue 29: 3).
pub const LAYOUT_ROUNDS: usize = 3;

/// Rounds, before those, that only keep the collapsed arcs of failing
/// vertices open (ours; [`layout::LayoutFailure::separate`]).
pub const REPAIR_ROUNDS: usize = 6;

/// Re-solves with weights linearizing the block count (5) about the last
/// answer, while the count drops ([`ilp::area_weights`]; ours).
pub const AREA_ROUNDS: usize = 4;

/// The layout stages' options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutOptions {
    /// Cone half-angle α off CAD curves, degrees (the paper: 45°); in (0, 90).
    pub alpha_degrees: f64,
    /// HiGHS time limit, seconds (0: no solve, `q = l`).
    pub ilp_time_limit: f64,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        LayoutOptions { alpha_degrees: 45.0, ilp_time_limit: 60.0 }
    }
}

/// The layout stages' figures (the paper's Table 1 columns and the solve).
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutReport {
    /// Input quads (#Faces).
    pub input_quads: usize,
    /// Patches of the input mesh's quad layout (#P_init).
    pub initial_patches: usize,
    /// Irregular input nodes (#Irr; CAD corners not counted).
    pub irregular_nodes: usize,
    /// T-mesh arcs and patches.
    pub arcs: usize,
    /// T-mesh patches (grid and frozen).
    pub tmesh_patches: usize,
    /// Frozen T-mesh patches (not four-cornered grids).
    pub frozen_patches: usize,
    /// Integer variables (#Vars).
    pub variables: usize,
    /// Rows by kind: consistency, validity, geometric, curve.
    pub rows: BTreeMap<String, usize>,
    /// "optimal", "time limit", or "input lengths: <why>".
    pub ilp_status: String,
    /// Seconds in HiGHS (all rounds).
    pub ilp_seconds: f64,
    /// Blocks predicted by Eq. (5) at the answer.
    pub predicted_blocks: usize,
    /// Blocks of the layout (#P_final).
    pub blocks: usize,
    /// Solve rounds (1 when the first layout passed its checks).
    pub rounds: usize,
    /// Why earlier rounds' layouts were refused.
    pub refused: Vec<String>,
    /// Per solve round: (blocks Eq. (5) predicts, problems the placement
    /// found; 0 for the round that placed).
    pub round_figures: Vec<(usize, usize)>,
    /// The first round's problems by cause ([`layout::LayoutFailure::causes`]).
    pub first_round_causes: BTreeMap<String, usize>,
    /// Seconds for the traces, T-mesh, program and layout (solver excluded).
    pub layout_seconds: f64,
}

/// The coarse block layout of the all-quad `mesh` (§III–§IV.C).
pub(crate) fn coarse_layout(
    mesh: &QuadMesh,
    opts: &LayoutOptions,
) -> Result<(BlockLayout, LayoutReport), MeshError> {
    if !(opts.alpha_degrees > 0.0 && opts.alpha_degrees < 90.0) {
        return Err(MeshError::Coarse(format!(
            "--alpha {} is out of range: it must be in (0°, 90°)",
            opts.alpha_degrees
        )));
    }
    let started = Instant::now();
    let conn = Connectivity::new(mesh)?;
    let alpha = opts.alpha_degrees.to_radians();
    let traces = traces::draw_traces(mesh, &conn, alpha, true);
    let tm = tmesh::build_tmesh(mesh, &conn, &traces);
    let initial_patches = {
        let full = traces::draw_traces(mesh, &conn, alpha, false);
        tmesh::build_tmesh(mesh, &conn, &full).patches.len()
    };
    let mut report = LayoutReport {
        input_quads: mesh.quads.len(),
        initial_patches,
        irregular_nodes: conn.kind.iter().filter(|k| matches!(k, NodeKind::Irregular { .. })).count(),
        arcs: tm.arcs.len(),
        tmesh_patches: tm.patches.len(),
        frozen_patches: tm.patches.iter().filter(|p| p.shape == tmesh::PatchShape::Frozen).count(),
        variables: 0,
        rows: BTreeMap::new(),
        ilp_status: String::new(),
        ilp_seconds: 0.0,
        predicted_blocks: 0,
        blocks: 0,
        rounds: 0,
        refused: Vec::new(),
        round_figures: Vec::new(),
        first_round_causes: BTreeMap::new(),
        layout_seconds: 0.0,
    };
    let mut fixed: HashSet<u32> = HashSet::new();
    let mut kept_open: HashSet<u32> = HashSet::new();
    let mut hold_rounds = 0;
    let identity: Vec<u32> = tm.arcs.iter().map(|a| a.len()).collect();
    let mut result = None;
    let last = REPAIR_ROUNDS + LAYOUT_ROUNDS;
    for round in 0..=last {
        let prog = ilp::build_program(mesh, &conn, &traces, &tm, alpha.tan(), &fixed, &kept_open);
        let (q, solve) = if round < last && hold_rounds < LAYOUT_ROUNDS {
            let (mut qv, mut solve) = ilp::solve(&prog, opts.ilp_time_limit);
            if solve.status == SolveStatus::Optimal {
                let mut blocks = predicted_blocks(&tm, &prog.arc_lengths(&qv));
                for _ in 0..AREA_ROUNDS {
                    let w = ilp::area_weights(&prog, &tm, &prog.arc_lengths(&qv));
                    let (q2, s2) = ilp::solve_weighted(&prog, &w, &qv, opts.ilp_time_limit);
                    solve.seconds += s2.seconds;
                    let b2 = predicted_blocks(&tm, &prog.arc_lengths(&q2));
                    if s2.status != SolveStatus::Optimal || b2 >= blocks {
                        break;
                    }
                    (qv, blocks) = (q2, b2);
                }
            }
            (prog.arc_lengths(&qv), solve)
        } else {
            let why = format!("{LAYOUT_ROUNDS} rounds of refused layouts");
            (identity.clone(), ilp::SolveReport { status: SolveStatus::Identity(why), seconds: 0.0 })
        };
        if round == 0 {
            report.variables = prog.num_vars();
            report.rows = prog.row_counts().into_iter().map(|(k, n)| (row_name(k).to_string(), n)).collect();
        }
        report.ilp_seconds += solve.seconds;
        report.ilp_status = match &solve.status {
            SolveStatus::Optimal => "optimal".to_string(),
            SolveStatus::TimeLimit => "time limit".to_string(),
            SolveStatus::Identity(why) => format!("input lengths: {why}"),
        };
        report.rounds = round + 1;
        report.predicted_blocks = predicted_blocks(&tm, &q);
        let identity_now = matches!(solve.status, SolveStatus::Identity(_));
        match layout::build_layout(mesh, &conn, &tm, &q) {
            Ok(l) => {
                report.round_figures.push((report.predicted_blocks, 0));
                result = Some(l);
                break;
            }
            Err(f) => {
                tracing::info!(
                    "coarse: layout of round {} ({} blocks predicted) refused, {} problems {:?}: {}",
                    round + 1,
                    report.predicted_blocks,
                    f.reasons.len(),
                    f.causes,
                    f.reasons.join("; ")
                );
                report.round_figures.push((report.predicted_blocks, f.reasons.len()));
                if round == 0 {
                    report.first_round_causes = f.causes.iter().map(|(k, &n)| (k.to_string(), n)).collect();
                }
                report.refused.extend(f.reasons.into_iter().take(5));
                if identity_now {
                    return Err(MeshError::Coarse(
                        "the layout of the input lengths failed its checks (a bug)".into(),
                    ));
                }
                if f.separate.is_empty() || hold_rounds > 0 || round >= REPAIR_ROUNDS {
                    fixed.extend(f.arcs);
                    hold_rounds += 1;
                } else {
                    kept_open.extend(f.separate);
                }
            }
        }
    }
    let layout = result.ok_or_else(|| MeshError::Coarse("no layout".into()))?;
    report.blocks = layout.blocks.len();
    report.layout_seconds = started.elapsed().as_secs_f64() - report.ilp_seconds;
    Ok((layout, report))
}

/// Eq. (5): `Σ Q1 · Q2` over grid patches, plus the quads of frozen ones.
fn predicted_blocks(tm: &tmesh::TMesh, q: &[u32]) -> usize {
    tm.patches
        .iter()
        .map(|p| match &p.shape {
            tmesh::PatchShape::Grid { sides, .. } => {
                let s = |k: usize| sides[k].iter().map(|&(a, _)| q[a as usize] as usize).sum::<usize>();
                s(0) * s(1)
            }
            tmesh::PatchShape::Frozen => p.quads.len(),
        })
        .sum()
}

/// The report's name of a row kind.
fn row_name(k: RowKind) -> &'static str {
    match k {
        RowKind::Consistency => "consistency",
        RowKind::Validity => "validity",
        RowKind::Geometric => "geometric",
        RowKind::Curve => "curve",
        RowKind::Repair => "repair",
    }
}
