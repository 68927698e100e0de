//! [`QuadMesh`]: a surface mesh of quads (and, for readers, triangles), with
//! every node classified on a model entity and every element on a face.

use geometry::{CornerId, CurveId, FaceId, Vec3};

/// The model entity a mesh node lies on, with its parameters there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodeClass {
    /// On a CAD corner.
    Corner(CornerId),
    /// On a CAD curve, at parameter `t` (`None` when read from a file without parameters).
    Curve(CurveId, Option<f64>),
    /// Inside a CAD face, at `(u, v)` (`None` when read from a file without parameters).
    Face(FaceId, Option<[f64; 2]>),
    /// Not on any surface entity (a volume node, or a file without classification).
    Unclassified,
}

/// An all-quad (or mixed, when read from a file) surface mesh.
///
/// Orientation: each quad `[a, b, c, d]` is counter-clockwise seen from the
/// oriented normal of its face (`Face::normal`), i.e. its corner normals
/// `(x_{i+1} − x_i) × (x_{i−1} − x_i)` agree with the CAD normal when valid.
#[derive(Clone, Debug, Default)]
pub struct QuadMesh {
    /// Node positions.
    pub nodes: Vec<Vec3>,
    /// Classification of each node (same length as `nodes`).
    pub node_class: Vec<NodeClass>,
    /// Quads as 4 node indices.
    pub quads: Vec<[u32; 4]>,
    /// The CAD face of each quad (same length as `quads`).
    pub quad_face: Vec<FaceId>,
    /// Triangles (only meshes read from files or mixed meshes have them).
    pub triangles: Vec<[u32; 3]>,
    /// The CAD face of each triangle.
    pub triangle_face: Vec<FaceId>,
    /// Mesh edges lying on CAD curves, each with its curve (written as line elements).
    pub curve_edges: Vec<([u32; 2], CurveId)>,
    /// Nodes on CAD corners, each with its corner (written as point elements).
    pub corner_nodes: Vec<(u32, CornerId)>,
}

impl QuadMesh {
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
}

impl QuadMesh {
    /// Number of quads touching each node (triangles not counted).
    pub fn node_valences(&self) -> Vec<u32> {
        let mut val = vec![0u32; self.nodes.len()];
        for q in &self.quads {
            for &n in q {
                val[n as usize] += 1;
            }
        }
        val
    }

    /// True when node `n` lies strictly inside a CAD face (not on a curve or corner).
    pub fn is_face_interior(&self, n: usize) -> bool {
        matches!(self.node_class[n], NodeClass::Face(..))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn valences_count_incident_quads() {
        // 2x1 strip of quads: the two middle nodes have valence 2, the others 1.
        let mesh = QuadMesh {
            nodes: vec![[0.0; 3]; 6],
            node_class: vec![NodeClass::Unclassified; 6],
            quads: vec![[0, 1, 4, 3], [1, 2, 5, 4]],
            quad_face: vec![FaceId(0); 2],
            ..Default::default()
        };
        assert_eq!(mesh.node_valences(), vec![1, 2, 1, 1, 2, 1]);
        assert!(!mesh.is_face_interior(0));
    }
}
