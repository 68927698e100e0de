//! Regularization of a whole mesh: every face in parallel ([`regularize_mesh`]),
//! written back into the mesh, with a strict second chance and then the input
//! for a face that comes out with more quads inverted against the CAD
//! normals; the mesh-level report and error.

use geometry::{FaceId, Model};
use mesh::QuadMesh;
use rayon::prelude::*;

use crate::core::face_quads::extract::{extract_face, quads_by_face, write_back};
use crate::core::face_quads::FaceQuads;

use super::{regularize_face, FaceReport, OpCounts, RegularizeOptions};

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
        self.faces
            .iter()
            .fold((0, 0), |a, f| (a.0 + f.irregular.0, a.1 + f.irregular.1))
    }
    /// Sum of the invalid quad counts, before / after.
    pub fn invalid(&self) -> (usize, usize) {
        self.faces
            .iter()
            .fold((0, 0), |a, f| (a.0 + f.invalid.0, a.1 + f.invalid.1))
    }
    /// Operations over all faces.
    pub fn ops(&self) -> OpCounts {
        self.faces
            .iter()
            .fold(OpCounts::default(), |a, f| OpCounts {
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

/// Number of quads of each face (indexed by face id) with a corner SICN < 0
/// against the CAD normals, as [`mesh::stats::MeshStats`] counts "inverted".
fn inverted_by_face(model: &Model, mesh: &QuadMesh) -> Vec<usize> {
    let mut out = vec![0; model.faces.len()];
    if mesh.quad_face.len() != mesh.quads.len() {
        return out;
    }
    let sicn = mesh::stats::quad_acceptance_sicn_values(mesh, Some(model));
    for (s, f) in sicn.iter().zip(&mesh.quad_face) {
        if *s < 0.0 {
            if let Some(c) = out.get_mut(f.idx()) {
                *c += 1;
            }
        }
    }
    out
}

/// Regularizes every face of `mesh` (a quad mesh of `model` whose nodes are
/// classified on it, such as [`crate::mesh_model`]'s output) and rewrites
/// `mesh` with the result. Boundary nodes keep their index, position and
/// classification bit-for-bit. Faces whose quads cannot be read (non-manifold,
/// missing (u, v)) are left as they are and listed in the report.
pub fn regularize_mesh(
    model: &Model,
    mesh: &mut QuadMesh,
    opts: &RegularizeOptions,
) -> Result<RegularizeReport, RegularizeError> {
    regularize_mesh_with_progress(model, mesh, opts, None)
}

/// [`regularize_mesh`], calling `progress(faces done, faces with quads)` as
/// each face's regularization finishes (from worker threads, in no
/// particular order): the stage takes seconds on CAD models with dozens of
/// faces, far longer than the baseline mesh it starts from.
pub fn regularize_mesh_with_progress(
    model: &Model,
    mesh: &mut QuadMesh,
    opts: &RegularizeOptions,
    progress: Option<&crate::core::options::ProgressFn>,
) -> Result<RegularizeReport, RegularizeError> {
    if mesh.quad_face.len() != mesh.quads.len() {
        return Err(RegularizeError::Inconsistent(format!(
            "{} quads but {} quad faces",
            mesh.quads.len(),
            mesh.quad_face.len()
        )));
    }
    if mesh.node_class.len() != mesh.nodes.len() {
        return Err(RegularizeError::Inconsistent(format!(
            "{} nodes but {} node classes",
            mesh.nodes.len(),
            mesh.node_class.len()
        )));
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let work = || -> Vec<(FaceId, Result<(FaceQuads, FaceReport), String>)> {
        let faces = quads_by_face(mesh);
        let total = faces.len();
        faces
            .into_par_iter()
            .map(|(fid, qids)| {
                let res = extract_face(model, mesh, fid, &qids)
                    .map_err(|e| e.to_string())
                    .map(|mut fq| {
                        let rep = regularize_face(&model.faces[fid.idx()], fid, &mut fq, opts);
                        (fq, rep)
                    });
                if let Some(p) = progress {
                    p(
                        done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                        total,
                    );
                }
                (fid, res)
            })
            .collect()
    };
    let results = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| RegularizeError::Threads {
                threads: n,
                reason: e.to_string(),
            })?
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
    // mesh validity is a hard requirement: a face that comes out with more
    // quads inverted against the CAD normals than it went in keeps its input
    let inverted_before = inverted_by_face(model, mesh);
    let mut refs: Vec<(FaceId, &FaceQuads)> = edited.iter().map(|(f, q)| (*f, q)).collect();
    let mut out = write_back(mesh, &refs);
    let inverted_after = inverted_by_face(model, &out);
    let worse: Vec<FaceId> = refs
        .iter()
        .map(|r| r.0)
        .filter(|f| inverted_after.get(f.idx()) > inverted_before.get(f.idx()))
        .collect();
    let mut worse_still = worse.clone();
    if !worse.is_empty() {
        // second chance in strict mode (no edit may leave an invalid quad), then the input
        let strict = RegularizeOptions {
            strict_validity: true,
            ..opts.clone()
        };
        let mut retried: Vec<(FaceId, FaceQuads, FaceReport)> = Vec::new();
        for &fid in &worse {
            let qids: Vec<usize> = (0..mesh.quads.len())
                .filter(|&q| mesh.quad_face[q] == fid)
                .collect();
            if let Ok(mut fq) = extract_face(model, mesh, fid, &qids) {
                let rep = regularize_face(&model.faces[fid.idx()], fid, &mut fq, &strict);
                retried.push((fid, fq, rep));
            }
        }
        refs.retain(|r| !worse.contains(&r.0));
        refs.extend(retried.iter().map(|(f, q, _)| (*f, q)));
        refs.sort_by_key(|r| r.0);
        out = write_back(mesh, &refs);
        let inverted_retry = inverted_by_face(model, &out);
        worse_still = worse
            .iter()
            .copied()
            .filter(|f| inverted_retry.get(f.idx()) > inverted_before.get(f.idx()))
            .collect();
        for (fid, _, rep) in &retried {
            if !worse_still.contains(fid) {
                if let Some(r) = report.faces.iter_mut().find(|r| r.face == *fid) {
                    *r = rep.clone();
                }
            }
        }
        if !worse_still.is_empty() {
            refs.retain(|r| !worse_still.contains(&r.0));
            out = write_back(mesh, &refs);
        }
    }
    for rep in report
        .faces
        .iter_mut()
        .filter(|r| worse_still.contains(&r.face))
    {
        rep.reverted = true;
        rep.quads.1 = rep.quads.0;
        rep.verts.1 = rep.verts.0;
        rep.irregular.1 = rep.irregular.0;
        rep.invalid.1 = rep.invalid.0;
    }
    *mesh = out;
    Ok(report)
}
