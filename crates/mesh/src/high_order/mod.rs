//! [`HighOrderQuadMesh`]: curved Lagrange quads of order N (equidistant
//! nodes), every node classified on a model entity — the output of the coarse
//! method (`quadrille mesh --method coarse`), one element per layout block.
//!
//! One stage per module: `ordering` (tensor order ↔ Gmsh's and VTK's node
//! orders), `jacobian` (Lagrange basis, det J, the per-element judge),
//! `tessellate` (linear views for pictures). The files are written by
//! [`crate::msh::write_high_order_msh`] and [`crate::vtu::write_high_order_vtu`]
//! and read by [`crate::msh::read_high_order_msh`].

mod jacobian;
mod ordering;
mod stats;
mod tessellate;

pub use jacobian::{gauss_legendre, lagrange_basis, ElementJacobian};
pub use ordering::{
    gmsh_line_ordering, gmsh_line_type, gmsh_quad_ordering, gmsh_quad_type, order_of_gmsh_line,
    order_of_gmsh_quad, vtk_quad_ordering, VTK_LAGRANGE_QUADRILATERAL,
};
pub use stats::HighOrderStats;
pub use tessellate::Tessellation;

use crate::quadmesh::NodeClass;
use geometry::{CornerId, CurveId, FaceId, Vec3};

/// Why a high-order mesh (or an order, or a request on it) was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HighOrderError {
    /// The order is outside `1..=MAX_ORDER`.
    #[error("order {0} is not supported (orders 1 to {MAX_ORDER})")]
    BadOrder(usize),
    /// An array has the wrong length for the others.
    #[error("{what}: {got} values where {want} are expected")]
    Length {
        /// The array.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The length the other arrays call for.
        want: usize,
    },
    /// An element, curve edge or corner refers to a node that does not exist.
    #[error("{what} {index} refers to node {node}, beyond the {nodes} nodes")]
    MissingNode {
        /// `element`, `curve edge` or `corner node`.
        what: &'static str,
        /// Which one.
        index: usize,
        /// The node index it holds.
        node: u32,
        /// Number of nodes.
        nodes: usize,
    },
    /// A node has a NaN or infinite coordinate.
    #[error("node {0} has a non-finite coordinate")]
    NonFinite(usize),
    /// More nodes than 32-bit node indices can address.
    #[error("{0} nodes is more than 32-bit node indices address")]
    TooManyNodes(usize),
    /// An element index beyond the mesh.
    #[error("element {index} does not exist (the mesh has {count})")]
    NoSuchElement {
        /// The index asked for.
        index: usize,
        /// Number of elements.
        count: usize,
    },
    /// A reference point outside the reference square, or not finite.
    #[error("reference point ({0}, {1}) is outside [0, 1]²")]
    BadReferencePoint(f64, f64),
    /// A tessellation of 0 or more than [`MAX_SUBDIVISION`] steps per element side.
    #[error("subdivision {0} is not supported (1 to {MAX_SUBDIVISION} steps per element side)")]
    BadSubdivision(usize),
}

/// Most steps per element side that [`HighOrderQuadMesh::tessellate`] takes.
pub const MAX_SUBDIVISION: usize = 64;

/// Checks that `order` is in `1..=MAX_ORDER`.
pub fn check_order(order: usize) -> Result<(), HighOrderError> {
    if (1..=MAX_ORDER).contains(&order) {
        Ok(())
    } else {
        Err(HighOrderError::BadOrder(order))
    }
}

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
        [
            self.node_at(e, 0, 0),
            self.node_at(e, n, 0),
            self.node_at(e, n, n),
            self.node_at(e, 0, n),
        ]
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

    /// Checks everything the writers, the judge and the tessellation rely
    /// on: the order, matching array lengths, node references in range,
    /// finite coordinates. Returns the first problem found.
    pub fn validate(&self) -> Result<(), HighOrderError> {
        check_order(self.order)?;
        let nn = self.nodes.len();
        if nn > u32::MAX as usize {
            return Err(HighOrderError::TooManyNodes(nn));
        }
        let length = |what, got, want| {
            if got == want {
                Ok(())
            } else {
                Err(HighOrderError::Length { what, got, want })
            }
        };
        length("node_class", self.node_class.len(), nn)?;
        let k = self.nodes_per_element();
        length(
            "element_nodes",
            self.element_nodes.len(),
            self.element_face.len() * k,
        )?;
        let m = self.order + 1;
        length(
            "curve_edge_nodes",
            self.curve_edge_nodes.len(),
            self.curve_edge_curve.len() * m,
        )?;
        let lists: [(&'static str, &[u32], usize); 2] = [
            ("element", &self.element_nodes, k),
            ("curve edge", &self.curve_edge_nodes, m),
        ];
        for (what, list, per) in lists {
            if let Some(p) = list.iter().position(|&v| v as usize >= nn) {
                return Err(HighOrderError::MissingNode {
                    what,
                    index: p / per,
                    node: list[p],
                    nodes: nn,
                });
            }
        }
        if let Some(index) = self
            .corner_nodes
            .iter()
            .position(|&(v, _)| v as usize >= nn)
        {
            return Err(HighOrderError::MissingNode {
                what: "corner node",
                index,
                node: self.corner_nodes[index].0,
                nodes: nn,
            });
        }
        if let Some(i) = self
            .nodes
            .iter()
            .position(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(HighOrderError::NonFinite(i));
        }
        Ok(())
    }

    /// Element `e`'s nodes after the checks one element needs (the order,
    /// the length of `element_nodes`, the element's node references): cheap
    /// enough to run on every point query, unlike [`Self::validate`].
    pub(crate) fn checked_element(&self, e: usize) -> Result<&[u32], HighOrderError> {
        check_order(self.order)?;
        let want = self.element_face.len() * self.nodes_per_element();
        if self.element_nodes.len() != want {
            return Err(HighOrderError::Length {
                what: "element_nodes",
                got: self.element_nodes.len(),
                want,
            });
        }
        if e >= self.num_elements() {
            return Err(HighOrderError::NoSuchElement {
                index: e,
                count: self.num_elements(),
            });
        }
        let elem = self.element(e);
        let nodes = self.nodes.len();
        if let Some(&node) = elem.iter().find(|&&v| v as usize >= nodes) {
            return Err(HighOrderError::MissingNode {
                what: "element",
                index: e,
                node,
                nodes,
            });
        }
        Ok(elem)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::high_order_patch;

    #[test]
    fn validate_names_the_first_problem() {
        let good = high_order_patch(3, 2, 1, |u, v| [u, v, 0.0]);
        assert_eq!(good.validate(), Ok(()));
        let mut m = good.clone();
        m.order = 0;
        assert_eq!(m.validate(), Err(HighOrderError::BadOrder(0)));
        m.order = 11;
        assert!(m.validate().unwrap_err().to_string().contains("order 11"));
        let mut m = good.clone();
        m.element_nodes.pop();
        assert_eq!(
            m.validate(),
            Err(HighOrderError::Length {
                what: "element_nodes",
                got: 31,
                want: 32
            })
        );
        let mut m = good.clone();
        m.curve_edge_curve.pop();
        assert!(matches!(
            m.validate(),
            Err(HighOrderError::Length {
                what: "curve_edge_nodes",
                ..
            })
        ));
        let mut m = good.clone();
        m.node_class.pop();
        assert!(matches!(
            m.validate(),
            Err(HighOrderError::Length {
                what: "node_class",
                ..
            })
        ));
        let mut m = good.clone();
        m.element_nodes[16 + 5] = 999;
        assert_eq!(
            m.validate(),
            Err(HighOrderError::MissingNode {
                what: "element",
                index: 1,
                node: 999,
                nodes: 28
            })
        );
        // the per-element check finds it too, and only in that element
        assert_eq!(m.checked_element(1), m.validate().map(|_| &[][..]));
        assert_eq!(m.checked_element(0).map(<[u32]>::len), Ok(16));
        assert!(m.point_at(1, 0.5, 0.5).is_err());
        assert!(m.det_jacobian(0, 0.5, 0.5, None).unwrap() > 0.0);
        let mut m = good.clone();
        m.curve_edge_nodes[4 * 3 + 1] = 28;
        assert!(matches!(
            m.validate(),
            Err(HighOrderError::MissingNode {
                what: "curve edge",
                index: 3,
                ..
            })
        ));
        let mut m = good.clone();
        m.corner_nodes[2].0 = 40;
        assert!(matches!(
            m.validate(),
            Err(HighOrderError::MissingNode {
                what: "corner node",
                index: 2,
                ..
            })
        ));
        let mut m = good;
        m.nodes[7][2] = f64::INFINITY;
        assert_eq!(m.validate(), Err(HighOrderError::NonFinite(7)));
        assert_eq!(
            m.checked_element(2),
            Err(HighOrderError::NoSuchElement { index: 2, count: 2 })
        );
    }
}
