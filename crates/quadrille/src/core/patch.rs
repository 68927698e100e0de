//! The quads of one face on local nodes ([`QuadPatch`]), the identity of
//! those nodes in the model's mesh ([`NodeRef`], [`LocalNode`]) and why a
//! face could not be meshed ([`FaceFailure`]): the per-face mesh every stage
//! reads and writes.

use geometry::vec3::Vec3;
use geometry::{CornerId, CurveId};

/// Where a local node lives in the global mesh, independent of global numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum NodeRef {
    /// A CAD corner.
    Corner(CornerId),
    /// Point `i` (1 ≤ i < 2n) of a curve's discretization.
    Curve(CurveId, u32),
    /// A node created inside this face.
    Interior,
}

/// A node of a face mesh in the face's parameter plane.
#[derive(Clone, Copy, Debug)]
pub struct LocalNode {
    /// Its (u, v).
    pub uv: [f64; 2],
    /// Its global identity.
    pub node: NodeRef,
    /// For a node on a degenerate curve: the (u, v) segment that all maps to it.
    pub pole: Option<[[f64; 2]; 2]>,
}

impl LocalNode {
    /// Where the node lies for [`geometry::Face::corner_normal`]: a pole, a
    /// point on a CAD curve (curve and corner nodes), or an interior point.
    pub fn corner_uv(&self) -> geometry::CornerUv {
        match (self.pole, self.node) {
            (Some(seg), _) => geometry::CornerUv::Pole(seg),
            (None, NodeRef::Interior) => geometry::CornerUv::Point(self.uv),
            (None, _) => geometry::CornerUv::Curve(self.uv),
        }
    }

    /// The node's (u, v) as seen from `other`: itself, except for a pole, which
    /// is the point of its degenerate segment nearest to `other`.
    pub fn uv_toward(&self, other: [f64; 2]) -> [f64; 2] {
        match self.pole {
            None => self.uv,
            // the nearest point of the pole's segment, as the CAD normals take it
            Some(seg) => geometry::CornerUv::Pole(seg).toward(other),
        }
    }

    /// True when both nodes are the same pole (a degenerate pair).
    pub fn same_pole(&self, other: &LocalNode) -> bool {
        self.pole.is_some() && other.pole.is_some() && self.node == other.node
    }
}

/// Why a face could not be triangulated.
#[derive(Clone, Debug)]
pub enum FaceFailure {
    /// The boundary polygon is too coarse (self-intersecting, or its quads
    /// cannot be made valid): refining these curves may help.
    RefineCurves(Vec<CurveId>, String),
    /// Nothing more can be done.
    Fatal(String),
}

/// The quads of one face, on local nodes.
#[derive(Clone, Debug, Default)]
pub struct QuadPatch {
    /// Local nodes: the triangulation's, then the new midpoints and centroids.
    pub nodes: Vec<LocalNode>,
    /// 3D position of each local node.
    pub pos: Vec<Vec3>,
    /// Quads on local node ids, counter-clockwise seen from the face normal.
    pub quads: Vec<[u32; 4]>,
    /// Index of the triangle each quad came from.
    pub quad_tri: Vec<u32>,
}

impl QuadPatch {
    /// True when quad `q` has two corners on one mesh node: the same local
    /// node twice, or two local nodes of one CAD corner or curve node (a
    /// pole's instances, a seam's two sides).
    pub fn repeats_a_node(&self, q: &[u32; 4]) -> bool {
        (0..4).any(|i| {
            (i + 1..4).any(|j| {
                let (a, b) = (&self.nodes[q[i] as usize], &self.nodes[q[j] as usize]);
                q[i] == q[j] || (a.node != NodeRef::Interior && a.node == b.node)
            })
        })
    }

    /// Face-interior nodes with other than four quads (nodes in no quad are
    /// not counted).
    pub fn interior_irregular(&self) -> usize {
        let mut deg = vec![0u32; self.nodes.len()];
        for q in &self.quads {
            for &v in q {
                deg[v as usize] += 1;
            }
        }
        self.nodes
            .iter()
            .zip(&deg)
            .filter(|(n, &d)| n.node == NodeRef::Interior && d > 0 && d != 4)
            .count()
    }
}
