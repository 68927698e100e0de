//! Per-face views of a [`QuadMesh`] for the geometry stages: each face's
//! quads on local nodes with a single-valued (u, v) in that face
//! ([`core::face_quads::extract_face`](crate::core::face_quads::extract::extract_face):
//! a seam node becomes one local node per side, a pole keeps its (u, v)
//! segment), as the [`QuadPatch`] the smoothing kernels work on, with the
//! mesh node of every local node and the mesh quad of every patch quad.

use geometry::{FaceId, Model};
use mesh::{NodeClass, QuadMesh};

use crate::core::face_quads::extract::{extract_face, quads_by_face};
use crate::core::patch::{LocalNode, NodeRef, QuadPatch};
use crate::core::work_queue::map_in_order;

/// One face of a mesh on local nodes.
#[derive(Clone, Debug)]
pub(crate) struct FacePatch {
    /// The face.
    pub face: FaceId,
    /// Its quads on local nodes: face-interior nodes are
    /// [`NodeRef::Interior`], corners [`NodeRef::Corner`], curve nodes
    /// `NodeRef::Curve(curve, mesh node + 1)` (the index only tells nodes
    /// apart).
    pub patch: QuadPatch,
    /// The mesh node of each local node.
    pub global: Vec<u32>,
    /// The mesh quad of each patch quad.
    pub quads: Vec<u32>,
}

/// The [`FacePatch`] of every face that has quads in `mesh`, in increasing
/// face id (faces extracted in parallel, largest first; the result does not
/// depend on the thread count). An error names the face whose quads could
/// not be given a (u, v).
pub(crate) fn face_patches(model: &Model, mesh: &QuadMesh) -> Result<Vec<FacePatch>, String> {
    let mut faces = quads_by_face(mesh);
    faces.sort_by_key(|(f, q)| (std::cmp::Reverse(q.len()), *f));
    let mut out = map_in_order(&faces, |(fid, qids)| face_patch(model, mesh, *fid, qids))
        .into_iter()
        .collect::<Result<Vec<_>, String>>()?;
    out.sort_by_key(|p| p.face);
    Ok(out)
}

/// The [`FacePatch`] of face `fid` made of the mesh quads `qids`.
fn face_patch(
    model: &Model,
    mesh: &QuadMesh,
    fid: FaceId,
    qids: &[usize],
) -> Result<FacePatch, String> {
    let fq = extract_face(model, mesh, fid, qids).map_err(|e| e.to_string())?;
    let mut global = Vec::with_capacity(fq.verts.len());
    let mut patch = QuadPatch::default();
    for (i, v) in fq.verts.iter().enumerate() {
        let g = v
            .global
            .ok_or_else(|| format!("face {}: local vertex {i} has no mesh node", fid.0 + 1))?;
        let node = match v.class {
            NodeClass::Corner(c) => NodeRef::Corner(c),
            NodeClass::Curve(c, _) => NodeRef::Curve(c, g + 1),
            _ => NodeRef::Interior,
        };
        patch.nodes.push(LocalNode {
            uv: v.uv,
            node,
            pole: v.pole,
        });
        patch.pos.push(v.xyz);
        global.push(g);
    }
    patch.quads = fq.quads.clone();
    patch.quad_tri = (0..patch.quads.len() as u32).collect();
    Ok(FacePatch {
        face: fid,
        patch,
        global,
        quads: qids.iter().map(|&q| q as u32).collect(),
    })
}

/// The local nodes at the four corners of every quad of `mesh` (indexed by
/// quad), from its face's patch in `patches`.
pub(crate) fn quad_corner_nodes(patches: &[FacePatch], quads: usize) -> Vec<[LocalNode; 4]> {
    let blank = LocalNode {
        uv: [0.0; 2],
        node: NodeRef::Interior,
        pole: None,
    };
    let mut out = vec![[blank; 4]; quads];
    for fp in patches {
        for (lq, &q) in fp.patch.quads.iter().zip(&fp.quads) {
            if let Some(slot) = out.get_mut(q as usize) {
                *slot = lq.map(|l| fp.patch.nodes[l as usize]);
            }
        }
    }
    out
}
