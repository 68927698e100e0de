//! Overlays that show the coarse method's stages over the input mesh (for
//! `--png` pictures and the docs' figures): the T-mesh (arcs and nodes,
//! coloured as the paper's Fig. 3), the input mesh's own quad layout (Fig. 2)
//! and the block layout.

use super::block_layout::BlockLayout;
use super::connectivity::{Connectivity, NodeKind};
use super::tmesh::TMesh;
use mesh::render::{Overlay, OverlayPoint, OverlaySegment};
use mesh::QuadMesh;

/// Valence-3 nodes (the paper's blue).
const BLUE: [u8; 3] = [40, 90, 220];
/// Valence-5 nodes (red).
const RED: [u8; 3] = [220, 40, 40];
/// Other irregular nodes.
const PURPLE: [u8; 3] = [150, 60, 190];
/// CAD corners (brown).
const BROWN: [u8; 3] = [140, 90, 40];
/// T-mesh arcs.
const ARC: [u8; 3] = [230, 120, 20];
/// Layout edges.
const EDGE: [u8; 3] = [20, 20, 20];

/// The irregular nodes and corners as dots, with a legend.
fn node_dots(mesh: &QuadMesh, conn: &Connectivity, overlay: &mut Overlay) {
    for (v, k) in conn.kind.iter().enumerate() {
        let color = match *k {
            NodeKind::Regular => continue,
            NodeKind::Corner => BROWN,
            NodeKind::Irregular { valence: 3, face_interior: true } => BLUE,
            NodeKind::Irregular { valence: 5, face_interior: true } => RED,
            NodeKind::Irregular { .. } => PURPLE,
        };
        overlay.points.push(OverlayPoint { position: mesh.nodes[v], color });
    }
    overlay.legend.extend([
        (BLUE, "valence 3".to_string()),
        (RED, "valence 5".to_string()),
        (PURPLE, "other irregular".to_string()),
        (BROWN, "CAD corner".to_string()),
    ]);
}

/// Segments along a polyline of input nodes.
fn polyline(mesh: &QuadMesh, nodes: &[u32], color: [u8; 3], overlay: &mut Overlay) {
    for w in nodes.windows(2) {
        overlay.segments.push(OverlaySegment {
            a: mesh.nodes[w[0] as usize],
            b: mesh.nodes[w[1] as usize],
            color,
            normal: None,
        });
    }
}

/// The T-mesh: every arc, and the irregular nodes and corners.
pub(crate) fn tmesh_overlay(mesh: &QuadMesh, conn: &Connectivity, tm: &TMesh) -> Overlay {
    let mut overlay = Overlay { line_width: 2.5, ..Overlay::default() };
    for arc in &tm.arcs {
        polyline(mesh, &arc.nodes, ARC, &mut overlay);
    }
    node_dots(mesh, conn, &mut overlay);
    overlay
}

/// The block layout: every edge's path, and the irregular nodes and corners
/// of the input.
pub(crate) fn layout_overlay(mesh: &QuadMesh, conn: &Connectivity, layout: &BlockLayout) -> Overlay {
    let mut overlay = Overlay { line_width: 2.5, ..Overlay::default() };
    for e in &layout.edges {
        polyline(mesh, &e.path, EDGE, &mut overlay);
    }
    node_dots(mesh, conn, &mut overlay);
    overlay
}
