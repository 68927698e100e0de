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

/// An inverted quad of a failed face attempt: its centre and diameter (the
/// largest distance between two of its corners).
#[derive(Clone, Copy, Debug)]
pub struct FailureSpot {
    /// The mean of its four corners.
    pub at: Vec3,
    /// The largest distance between two of its corners.
    pub diameter: f64,
}

/// Why a face could not be triangulated.
#[derive(Clone, Debug)]
pub enum FaceFailure {
    /// The boundary polygon is too coarse (self-intersecting, or its quads
    /// cannot be made valid): refining these curves may help.
    RefineCurves(Vec<CurveId>, String),
    /// Quads stay inverted at `spots`, which refining the face's curves near
    /// them may repair (the driver refines locally there first, and the
    /// chord classes of `curves` as a last resort); the attempt had `quads`
    /// quads.
    InvertedAt {
        /// The curves whose boundary edges touch the inverted quads.
        curves: Vec<CurveId>,
        /// The inverted quads, in quad order.
        spots: Vec<FailureSpot>,
        /// Quads of the failed attempt (for the driver's growth bound).
        quads: usize,
        /// What went wrong, for the error message.
        reason: String,
    },
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

    /// The number of quads at each local node (0 for a node in no quad).
    pub fn valences(&self) -> Vec<usize> {
        let mut deg = vec![0usize; self.nodes.len()];
        for q in &self.quads {
            for &v in q {
                deg[v as usize] += 1;
            }
        }
        deg
    }

    /// Face-interior nodes with other than four quads (nodes in no quad are
    /// not counted).
    pub fn interior_irregular(&self) -> usize {
        let deg = self.valences();
        self.nodes
            .iter()
            .zip(&deg)
            .filter(|(n, &d)| n.node == NodeRef::Interior && d > 0 && d != 4)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 2 grid of quads on 3 × 3 nodes, the middle one interior.
    fn grid() -> QuadPatch {
        let node = |i: u32| LocalNode {
            uv: [(i % 3) as f64, (i / 3) as f64],
            node: if i == 4 {
                NodeRef::Interior
            } else {
                NodeRef::Curve(CurveId(0), i + 1)
            },
            pole: None,
        };
        QuadPatch {
            nodes: (0..9).map(node).collect(),
            pos: (0..9)
                .map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0])
                .collect(),
            quads: vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]],
            quad_tri: vec![0, 1, 2, 3],
        }
    }

    #[test]
    fn valences_count_quads_per_node_and_only_interior_nodes_are_irregular() {
        let mut p = grid();
        assert_eq!(p.valences(), vec![1, 2, 1, 2, 4, 2, 1, 2, 1]);
        assert_eq!(p.interior_irregular(), 0);
        p.quads.pop();
        assert_eq!(p.valences(), vec![1, 2, 1, 2, 3, 1, 1, 1, 0]);
        assert_eq!(p.interior_irregular(), 1);
    }

    #[test]
    fn a_quad_on_two_instances_of_one_curve_node_repeats_it() {
        let mut p = grid();
        assert!(!p.repeats_a_node(&[0, 1, 4, 3]));
        p.nodes[3].node = p.nodes[1].node;
        assert!(p.repeats_a_node(&[0, 1, 4, 3]));
        assert!(p.repeats_a_node(&[0, 1, 1, 3]));
    }

    #[test]
    fn a_pole_is_seen_from_its_neighbour_at_the_nearest_point_of_its_segment() {
        let n = LocalNode {
            uv: [0.0, 0.0],
            node: NodeRef::Corner(CornerId(0)),
            pole: Some([[0.0, 1.0], [2.0, 1.0]]),
        };
        assert_eq!(n.uv_toward([1.5, 3.0]), [1.5, 1.0]);
        assert_eq!(n.uv_toward([-4.0, 0.0]), [0.0, 1.0]);
        let plain = LocalNode { pole: None, ..n };
        assert_eq!(plain.uv_toward([1.5, 3.0]), [0.0, 0.0]);
    }
}
