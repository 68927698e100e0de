//! [`HighOrderQuadMesh`]: curved Lagrange quads of order N (equidistant
//! nodes), every node classified on a model entity — the output of the coarse
//! method (`quadrille mesh --method coarse`), one element per layout block.

use crate::quadmesh::NodeClass;
use geometry::{CornerId, CurveId, FaceId, Vec3};

/// Largest supported Lagrange order (MSH element types exist up to 10).
pub const MAX_ORDER: usize = 10;

/// A surface mesh of Lagrange quads of one order N (1..=[`MAX_ORDER`]).
///
/// Element nodes are stored in *tensor order*: node `(i, j)`, `i, j ∈ 0..=N`,
/// at index `i + (N + 1) · j` of the element's slice; `(i, j)` is at
/// reference coordinates `(ξ, η) = (i / N, j / N)` (equidistant). Corner 0 is
/// `(0, 0)`, 1 is `(N, 0)`, 2 is `(N, N)`, 3 is `(0, N)`, counter-clockwise
/// about the CAD face normal as in [`crate::QuadMesh`]. The file writers map
/// this order to Gmsh's and VTK's own.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HighOrderQuadMesh {
    /// The Lagrange order N.
    pub order: usize,
    /// Node positions.
    pub nodes: Vec<Vec3>,
    /// Classification of each node (same length as `nodes`).
    pub node_class: Vec<NodeClass>,
    /// Element nodes, `(N + 1)²` per element in tensor order.
    pub element_nodes: Vec<u32>,
    /// The CAD face of each element.
    pub element_face: Vec<FaceId>,
    /// Element edges on CAD curves: `N + 1` nodes each, from one end to the
    /// other, stored flat (`(N + 1)` per edge), with the curve of each edge in
    /// `curve_edge_curve`.
    pub curve_edge_nodes: Vec<u32>,
    /// The CAD curve of each curve edge.
    pub curve_edge_curve: Vec<CurveId>,
    /// Nodes on CAD corners, each with its corner.
    pub corner_nodes: Vec<(u32, CornerId)>,
}

impl HighOrderQuadMesh {
    /// Nodes per element: `(N + 1)²`.
    pub fn nodes_per_element(&self) -> usize {
        (self.order + 1) * (self.order + 1)
    }

    /// Number of elements.
    pub fn num_elements(&self) -> usize {
        self.element_face.len()
    }

    /// The nodes of element `e` in tensor order.
    pub fn element(&self, e: usize) -> &[u32] {
        let k = self.nodes_per_element();
        &self.element_nodes[e * k..(e + 1) * k]
    }

    /// The node of element `e` at tensor position `(i, j)`.
    pub fn node_at(&self, e: usize, i: usize, j: usize) -> u32 {
        self.element(e)[i + (self.order + 1) * j]
    }

    /// The four corner nodes of element `e`, counter-clockwise.
    pub fn corners(&self, e: usize) -> [u32; 4] {
        let n = self.order;
        [self.node_at(e, 0, 0), self.node_at(e, n, 0), self.node_at(e, n, n), self.node_at(e, 0, n)]
    }

    /// Number of curve edges.
    pub fn num_curve_edges(&self) -> usize {
        self.curve_edge_curve.len()
    }

    /// The `N + 1` nodes of curve edge `k`, end to end.
    pub fn curve_edge(&self, k: usize) -> &[u32] {
        let m = self.order + 1;
        &self.curve_edge_nodes[k * m..(k + 1) * m]
    }
}
