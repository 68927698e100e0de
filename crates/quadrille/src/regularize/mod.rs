//! The **regular** method (Docampo-Sánchez & Haimes, "Towards Fully Regular
//! Quad Mesh Generation", AIAA 2019-1988): start from the triangle-split quad
//! mesh (about half its vertices irregular) and recover regularity with local
//! topological operations, each guarded by a geometric validity check,
//! repositioning and rollback; then redistribute the vertices so the quad
//! angles approach 90°.
//!
//! Stages (one module each):
//! - [`ops`]: swap, collapse, split with exact valence bookkeeping;
//! - [`validity`]: projected-angle / triangle-sign validity of a quad;
//! - [`reposition`]: Algorithm 1 and the local repair loop;
//! - [`driver`]: the sweep over quads, compositions and translations, rollback;
//! - [`redistribute`]: Algorithm 2 (tightening angle window).
//!
//! Faces are regularized independently (their boundary nodes never move, so
//! the mesh stays watertight), in parallel, with an output that does not depend
//! on the thread count.

pub mod driver;
pub mod ops;
pub mod redistribute;
pub mod reposition;
pub mod validity;

use geometry::{Face, FaceId, Model};
use mesh::QuadMesh;
use rayon::prelude::*;

use crate::face_quads::extract::{extract_face, quads_by_face, write_back};
use crate::face_quads::FaceQuads;

pub use driver::OpCounts;
pub use validity::AngleWindow;

/// Options of [`regularize_mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct RegularizeOptions {
    /// Angle window every operation must respect (paper: (5°, 175°)).
    pub window: AngleWindow,
    /// Window Algorithm 2 tightens toward (paper: (85°, 95°)).
    pub target: AngleWindow,
    /// Tightening step of Algorithm 2 in degrees (paper: 1°).
    pub angle_step: f64,
    /// Maximum sweeps of the operation loop per face.
    pub max_sweeps: usize,
    /// Search two-operation compositions (swap-split, double collapse, …).
    pub compositions: bool,
    /// Longest operation sequence searched at one quad: 2 covers the paper's
    /// compositions, 3 and more add translations (valence-neutral moves
    /// before a composition).
    pub max_sequence: usize,
    /// Topological trial applications allowed per sequence search at one quad.
    pub search_budget: usize,
    /// Run Algorithm 2 after the topological phase.
    pub redistribute: bool,
    /// Worker threads (`None`: rayon's global pool). The output does not depend on it.
    pub threads: Option<usize>,
}

impl Default for RegularizeOptions {
    fn default() -> Self {
        RegularizeOptions {
            window: AngleWindow::BASE,
            target: AngleWindow { min_deg: 85.0, max_deg: 95.0 },
            angle_step: 1.0,
            max_sweeps: 100,
            compositions: true,
            max_sequence: 3,
            search_budget: 600,
            redistribute: true,
            threads: None,
        }
    }
}

/// What regularization did to one face.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceReport {
    /// The face.
    pub face: FaceId,
    /// Quads before / after.
    pub quads: (usize, usize),
    /// Local vertices (seam nodes counted once per side) before / after.
    pub verts: (usize, usize),
    /// Vertices whose valence differs from the ideal one (4 inside, from the
    /// corner angle on the boundary), before / after.
    pub irregular: (usize, usize),
    /// Quads invalid for the base window, before / after.
    pub invalid: (usize, usize),
    /// Operations accepted and rejected.
    pub ops: OpCounts,
    /// Tightest angle window reached by Algorithm 2 (the base window if it did not run).
    pub window: AngleWindow,
}

/// What [`regularize_mesh`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RegularizeReport {
    /// One report per regularized face, in face order.
    pub faces: Vec<FaceReport>,
    /// Faces left untouched, with the reason (their quads could not be read as a disk-like patch).
    pub skipped: Vec<(FaceId, String)>,
}

impl RegularizeReport {
    /// Sum of the face-local irregular counts, before / after.
    pub fn irregular(&self) -> (usize, usize) {
        self.faces.iter().fold((0, 0), |a, f| (a.0 + f.irregular.0, a.1 + f.irregular.1))
    }
    /// Sum of the invalid quad counts, before / after.
    pub fn invalid(&self) -> (usize, usize) {
        self.faces.iter().fold((0, 0), |a, f| (a.0 + f.invalid.0, a.1 + f.invalid.1))
    }
    /// Operations over all faces.
    pub fn ops(&self) -> OpCounts {
        self.faces.iter().fold(OpCounts::default(), |a, f| OpCounts {
            swaps: a.swaps + f.ops.swaps,
            collapses: a.collapses + f.ops.collapses,
            splits: a.splits + f.ops.splits,
            compositions: a.compositions + f.ops.compositions,
            rejected: a.rejected + f.ops.rejected,
            sweeps: a.sweeps.max(f.ops.sweeps),
        })
    }
}

/// Why [`regularize_mesh`] failed (faces that cannot be read are skipped, not errors).
#[derive(Debug, thiserror::Error)]
pub enum RegularizeError {
    /// The mesh arrays do not match (quads vs their faces, nodes vs classes).
    #[error("inconsistent mesh: {0}")]
    Inconsistent(String),
    /// The thread pool could not be created.
    #[error("could not start a pool of {threads} threads: {reason}")]
    Threads {
        /// Requested thread count.
        threads: usize,
        /// The pool builder's message.
        reason: String,
    },
}

/// Regularizes one face in place: initial repair of invalid quads, the
/// operation loop, then (optionally) Algorithm 2. Fixed vertices are never
/// moved or removed.
pub fn regularize_face(face: &Face, fid: FaceId, fq: &mut FaceQuads, opts: &RegularizeOptions) -> FaceReport {
    let before = (fq.num_quads(), fq.num_verts(), fq.irregular_count());
    let mut r = driver::Regularizer::new(face, fq);
    r.compositions = opts.compositions;
    r.max_ops = opts.max_sequence;
    r.budget = opts.search_budget;
    let invalid_before = r.invalid_count();
    r.initial_repair();
    r.run(opts.max_sweeps);
    let ops = r.counts;
    let invalid_mid = r.invalid_count();
    let window = if opts.redistribute && invalid_mid == 0 {
        redistribute::redistribute(fq, face, opts.window, opts.target, opts.angle_step)
    } else {
        opts.window
    };
    let invalid_after = fq.live_quads().filter(|&q| !validity::quad_valid(fq, face, q, opts.window)).count();
    FaceReport {
        face: fid,
        quads: (before.0, fq.num_quads()),
        verts: (before.1, fq.num_verts()),
        irregular: (before.2, fq.irregular_count()),
        invalid: (invalid_before, invalid_after),
        ops,
        window,
    }
}

/// Regularizes every face of `mesh` (a quad mesh of `model` whose nodes are
/// classified on it, such as [`crate::mesh_model`]'s output) and rewrites
/// `mesh` with the result. Boundary nodes keep their index, position and
/// classification bit-for-bit. Faces whose quads cannot be read (non-manifold,
/// missing (u, v)) are left as they are and listed in the report.
pub fn regularize_mesh(model: &Model, mesh: &mut QuadMesh, opts: &RegularizeOptions) -> Result<RegularizeReport, RegularizeError> {
    if mesh.quad_face.len() != mesh.quads.len() {
        return Err(RegularizeError::Inconsistent(format!("{} quads but {} quad faces", mesh.quads.len(), mesh.quad_face.len())));
    }
    if mesh.node_class.len() != mesh.nodes.len() {
        return Err(RegularizeError::Inconsistent(format!("{} nodes but {} node classes", mesh.nodes.len(), mesh.node_class.len())));
    }
    let work = || -> Vec<(FaceId, Result<(FaceQuads, FaceReport), String>)> {
        quads_by_face(mesh)
            .into_par_iter()
            .map(|(fid, qids)| {
                let res = extract_face(model, mesh, fid, &qids).map_err(|e| e.to_string()).map(|mut fq| {
                    let rep = regularize_face(&model.faces[fid.idx()], fid, &mut fq, opts);
                    (fq, rep)
                });
                (fid, res)
            })
            .collect()
    };
    let results = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| RegularizeError::Threads { threads: n, reason: e.to_string() })?
            .install(work),
        None => work(),
    };
    let mut report = RegularizeReport::default();
    let mut edited: Vec<(FaceId, FaceQuads)> = Vec::new();
    for (fid, r) in results {
        match r {
            Ok((fq, rep)) => {
                report.faces.push(rep);
                edited.push((fid, fq));
            }
            Err(e) => report.skipped.push((fid, e)),
        }
    }
    let refs: Vec<(FaceId, &FaceQuads)> = edited.iter().map(|(f, q)| (*f, q)).collect();
    *mesh = write_back(mesh, &refs);
    Ok(report)
}

#[cfg(test)]
mod tests;
