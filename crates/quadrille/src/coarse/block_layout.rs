//! [`BlockLayout`]: the coarse block structure placed on the input mesh
//! (paper §IV.C) — what the layout stages (T-mesh, integer program, splitting
//! and merging) hand to the geometry stages (fine block mesh, high-order
//! extraction).

use geometry::{CurveId, FaceId};

/// One layout edge: two layout vertices joined by a path of input-mesh nodes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LayoutEdge {
    /// Its two layout vertices (indices into [`BlockLayout::vertex_node`]);
    /// distinct.
    pub ends: [u32; 2],
    /// The path on the input mesh, as input-mesh node indices from the centre
    /// of `ends[0]` to the centre of `ends[1]` (both included; ≥ 2 nodes,
    /// consecutive nodes joined by an input-mesh edge). On a CAD curve it is
    /// the run of that curve's mesh edges; otherwise it stays inside (or on
    /// the boundary of) the face of the blocks it bounds.
    pub path: Vec<u32>,
    /// The CAD curve the edge follows, if any (then every node of `path` is on
    /// that curve or one of its end corners).
    pub curve: Option<CurveId>,
}

/// One block: a four-sided patch that becomes one high-order element.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Block {
    /// Its corner layout vertices, counter-clockwise about the CAD face
    /// normal (the [`mesh::QuadMesh`] orientation); four distinct vertices.
    pub corners: [u32; 4],
    /// Its sides: side `k` goes from `corners[k]` to `corners[(k + 1) % 4]`;
    /// `(edge, reversed)` where `reversed` means the edge's `ends` run from
    /// `corners[(k + 1) % 4]` to `corners[k]`.
    pub sides: [(u32, bool); 4],
    /// The CAD face the block lies in (blocks never cross a CAD curve).
    pub face: FaceId,
}

/// The coarse layout on the input mesh: vertices at input-mesh nodes, edges
/// along input-mesh paths, blocks bounded by four edges. Conforming: every
/// edge bounds one or two blocks (one on an open boundary).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct BlockLayout {
    /// The input-mesh node at the centre of each layout vertex (§IV.C:
    /// a CAD corner if the vertex holds one, else a CAD-curve node, else any).
    pub vertex_node: Vec<u32>,
    /// The layout edges.
    pub edges: Vec<LayoutEdge>,
    /// The blocks.
    pub blocks: Vec<Block>,
}
