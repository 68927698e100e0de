//! The fine block-structured mesh (coarse paper §IV.D–E, spec §5.4–5.5):
//! every block of the layout split into a `w1 × w2` grid of quads, `w` the
//! widths of its [quad loops](crate::coarse::quad_loops), then smoothed.
//!
//! Placement: each layout edge's input path is resampled at equal arc length
//! into its loop's width (on a CAD curve at the interpolated curve
//! parameter, on the curve; elsewhere projected onto the block's face from
//! the interpolated (u, v)); each block's interior is the transfinite
//! interpolation of its four sides in the face's (u, v) (as
//! [`crate::topology::regularize::grid::structured_grid`]), by node index.
//! Edge nodes are shared by the blocks on both sides, so the mesh is
//! conforming. The (u, v) of the input nodes in each face is the one
//! [`crate::core::face_quads::extract::extract_face`] gives (seam nodes per
//! side, poles as segments); a block side sees its path through the input
//! quads on its left, so a side on a seam takes the block's side of it.
//!
//! Smoothing, face by face in parallel (faces share no movable node):
//! [`untangle`] of the poor quads TFI left, the Winslow / angle-based
//! kernels with CAD projection ([`optimize`]: Winslow on regular nodes,
//! angle-based on irregular ones, moves that lower a node's worst quad
//! refused), [`untangle`] again for the inverted quads the paper admits at
//! concave corners; then the curve nodes slide along their curves on the
//! whole mesh ([`slide_curve_nodes`]). Corners never move.

use geometry::{vec3, FaceId, Model, Vec3};
use mesh::stats::quad_sicn_values;
use mesh::{NodeClass, QuadMesh};

use crate::coarse::block_layout::BlockLayout;
use crate::coarse::face_patches::{face_patches, quad_corner_nodes};
use crate::coarse::layout_check::InputEdges;
use crate::coarse::quad_loops::QuadLoops;
use crate::coarse::resample::{
    equal_arc_samples, resampled_node, onto_face, path_params, sample_hint, side_uvs, Sample, UvSides,
};
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::queries::sharp_corners_of;
use crate::core::work_queue::map_in_order;
use crate::smoothing::curve_slide::slide_curve_nodes;
use crate::smoothing::kernels::{optimize, OptimizeOptions};
use crate::smoothing::repair::{untangle, UNTANGLE_BELOW, UNTANGLE_MAX_NODES, UNTANGLE_PASSES};

/// Sweeps of [`slide_curve_nodes`] over the fine mesh (as the default method's last pass).
pub(crate) const FINE_SLIDE_SWEEPS: usize = 10;

/// Tolerance of the projections onto a face, as a share of the model's diagonal.
pub(crate) const PROJECTION_TOLERANCE: f64 = 1e-12;

/// The fine grid of one block.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BlockGrid {
    /// `[w1, w2]`: quads along sides 0 (and 2) and 1 (and 3).
    pub size: [usize; 2],
    /// The `(w1 + 1) × (w2 + 1)` mesh nodes in tensor order: node `(i, j)`
    /// at `i + (w1 + 1) j`; `(0, 0)` is the block's corner 0, `(w1, 0)`
    /// corner 1, `(w1, w2)` corner 2, `(0, w2)` corner 3.
    pub nodes: Vec<u32>,
    /// The mesh quad of cell `(0, 0)`; cell `(i, j)` is `first_quad + i + w1 j`.
    pub first_quad: u32,
}

impl BlockGrid {
    /// The mesh node at grid position `(i, j)`.
    pub(crate) fn at(&self, i: usize, j: usize) -> u32 {
        self.nodes[i + (self.size[0] + 1) * j]
    }

    /// The mesh quad of the cell holding node `(i, j)` (the last cell along
    /// a side for the last node) and the node's position in that quad.
    pub(crate) fn cell_of(&self, i: usize, j: usize) -> (u32, usize) {
        let [w1, w2] = self.size;
        let (ci, cj) = (i.min(w1 - 1), j.min(w2 - 1));
        let k = match (i > ci, j > cj) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        (self.first_quad + (ci + w1 * cj) as u32, k)
    }
}

/// The fine block-structured mesh of a layout.
#[derive(Clone, Debug)]
pub(crate) struct FineMesh {
    /// The conforming quad mesh: layout vertex `v` is node `v`; then the
    /// nodes inside the layout edges (edge by edge), then those inside the
    /// blocks (block by block); quads block by block, each block's cells
    /// row by row.
    pub mesh: QuadMesh,
    /// The grid of each block.
    pub block_grid: Vec<BlockGrid>,
    /// The mesh nodes along each layout edge, from `ends[0]` to `ends[1]`.
    pub edge_nodes: Vec<Vec<u32>>,
}

/// What [`fine_mesh`] made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FineReport {
    /// Quads of the fine mesh.
    pub quads: usize,
    /// Nodes of the fine mesh.
    pub nodes: usize,
    /// Node moves kept by the per-face smoothing.
    pub moves: usize,
    /// Worst quad SICN (CAD normals, `mesh::stats::quad_sicn_values`).
    pub min_sicn: f64,
    /// Quads with SICN ≤ 0 (inverted or degenerate).
    pub invalid_quads: usize,
}

/// The fine mesh of `layout` on `input` (the mesh the layout lies on) with
/// the widths of `loops`, placed and smoothed (module documentation). An
/// error when the layout fails [`BlockLayout::check`] or a node cannot be
/// placed on the CAD.
#[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
pub(crate) fn fine_mesh(
    model: &Model,
    input: &QuadMesh,
    layout: &BlockLayout,
    loops: &QuadLoops,
) -> Result<(FineMesh, FineReport), String> {
    let mut fine = place(model, input, layout, loops)?;
    let moves = smooth(model, &mut fine.mesh)?;
    let sicn = quad_sicn_values(&fine.mesh, Some(model));
    let report = FineReport {
        quads: fine.mesh.quads.len(),
        nodes: fine.mesh.nodes.len(),
        moves,
        min_sicn: sicn.iter().copied().fold(f64::INFINITY, f64::min),
        invalid_quads: sicn.iter().filter(|&&s| s.is_nan() || s <= 0.0).count(),
    };
    Ok((fine, report))
}

/// The fine mesh of `layout` before smoothing: edges resampled, blocks
/// filled by transfinite interpolation in (u, v).
pub(crate) fn place(
    model: &Model,
    input: &QuadMesh,
    layout: &BlockLayout,
    loops: &QuadLoops,
) -> Result<FineMesh, String> {
    if loops.edge_loop.len() != layout.edges.len()
        || loops
            .edge_loop
            .iter()
            .any(|&l| l as usize >= loops.width.len())
    {
        return Err("the quad loops are not those of this layout".into());
    }
    if loops.width.contains(&0) {
        return Err("a quad loop has width 0".into());
    }
    let edges_in = InputEdges::of(input)?;
    layout.check_with(input, &edges_in)?;
    if let Some(b) = layout
        .blocks
        .iter()
        .find(|b| b.face.idx() >= model.faces.len())
    {
        return Err(format!(
            "a block is on face {}, not in the model",
            b.face.0 + 1
        ));
    }
    let tol = PROJECTION_TOLERANCE * model.diagonal().max(f64::MIN_POSITIVE);
    let patches = face_patches(model, input)?;
    let corners = quad_corner_nodes(&patches, input.quads.len());
    // each block side's path as seen from the block, in the edge's direction
    let blank = LocalNode {
        uv: [0.0; 2],
        node: NodeRef::Interior,
        pole: None,
    };
    let side_local: Vec<[Vec<LocalNode>; 4]> = layout
        .blocks
        .iter()
        .map(|blk| {
            [0, 1, 2, 3].map(|k| {
                let (e, rev) = blk.sides[k];
                let path = &layout.edges[e as usize].path;
                let mut out = vec![blank; path.len()];
                for s in 0..path.len() - 1 {
                    let (a, b) = (path[s], path[s + 1]);
                    let (x, y, ia, ib) = if rev {
                        (b, a, s + 1, s)
                    } else {
                        (a, b, s, s + 1)
                    };
                    if let Some(&(q, kk)) = edges_in.directed.get(&(x, y)) {
                        let c = &corners[q as usize];
                        out[ia] = c[kk as usize];
                        out[ib] = c[(kk as usize + 1) % 4];
                    }
                }
                out
            })
        })
        .collect();
    let mut mesh = QuadMesh::default();
    for &n in &layout.vertex_node {
        mesh.nodes.push(input.nodes[n as usize]);
        mesh.node_class.push(complete_params(
            model,
            input.node_class[n as usize],
            input.nodes[n as usize],
        ));
    }
    // the first block side on each edge
    let mut first_use: Vec<Option<(usize, usize)>> = vec![None; layout.edges.len()];
    for (bi, blk) in layout.blocks.iter().enumerate() {
        for (k, &(e, _)) in blk.sides.iter().enumerate() {
            first_use[e as usize].get_or_insert((bi, k));
        }
    }
    // the edges' inner nodes
    let mut resampled: Vec<Vec<Sample>> = Vec::with_capacity(layout.edges.len());
    let mut edge_nodes: Vec<Vec<u32>> = Vec::with_capacity(layout.edges.len());
    for (ei, e) in layout.edges.iter().enumerate() {
        let pts: Vec<Vec3> = e.path.iter().map(|&n| input.nodes[n as usize]).collect();
        let samples = equal_arc_samples(&pts, loops.edge_width(ei as u32));
        let params = match e.curve {
            Some(c) => Some(path_params(
                model,
                &input.node_class,
                &input.nodes,
                &e.path,
                c,
            )?),
            None => None,
        };
        let mut chain = vec![e.ends[0]];
        for s in &samples {
            let (p, class) = match (&params, e.curve) {
                (Some(t), Some(c)) => {
                    let x = t[s.seg] + s.lambda * (t[s.seg + 1] - t[s.seg]);
                    let p = model.curves[c.idx()].eval(model, x);
                    (p, NodeClass::Curve(c, Some(x)))
                }
                _ => {
                    let (bi, k) =
                        first_use[ei].ok_or_else(|| format!("edge {ei} bounds no block"))?;
                    let blk = &layout.blocks[bi];
                    let face = &model.faces[blk.face.idx()];
                    let hint = sample_hint(&side_local[bi][k], *s);
                    let target = vec3::lerp(pts[s.seg], pts[s.seg + 1], s.lambda);
                    let (uv, p) = onto_face(face, hint, target, tol).ok_or_else(|| {
                        format!(
                            "edge {ei}: a node does not map onto face {}",
                            blk.face.0 + 1
                        )
                    })?;
                    (p, NodeClass::Face(blk.face, Some(uv)))
                }
            };
            chain.push(mesh.nodes.len() as u32);
            mesh.nodes.push(p);
            mesh.node_class.push(class);
        }
        chain.push(e.ends[1]);
        if let Some(c) = e.curve {
            for w in chain.windows(2) {
                mesh.curve_edges.push(([w[0], w[1]], c));
            }
        }
        edge_nodes.push(chain);
        resampled.push(samples);
    }
    // the blocks' grids
    let mut block_grid = Vec::with_capacity(layout.blocks.len());
    for (bi, blk) in layout.blocks.iter().enumerate() {
        let face = &model.faces[blk.face.idx()];
        let w = [0, 1, 2, 3].map(|k| loops.edge_width(blk.sides[k].0));
        if w[0] != w[2] || w[1] != w[3] {
            return Err(format!("block {bi}: opposite sides have different widths"));
        }
        // each side's fine nodes and their (u, v) in this face, in block order
        let mut sides: Vec<(Vec<u32>, Vec<[f64; 2]>)> = Vec::with_capacity(4);
        for k in 0..4 {
            let (e, rev) = blk.sides[k];
            let local = &side_local[bi][k];
            let mut nodes: Vec<LocalNode> = Vec::with_capacity(w[k] + 1);
            nodes.push(local[0]);
            for s in &resampled[e as usize] {
                let g = edge_nodes[e as usize][nodes.len()];
                let hint = sample_hint(local, *s);
                nodes.push(resampled_node(face, mesh.node_class[g as usize], g, hint));
            }
            nodes.push(local[local.len() - 1]);
            let mut ids = edge_nodes[e as usize].clone();
            if rev {
                nodes.reverse();
                ids.reverse();
            }
            // a vertex classified inside the face without (u, v) takes its local one
            for (&g, l) in ids.iter().zip(&nodes) {
                if let NodeClass::Face(f, None) = mesh.node_class[g as usize] {
                    mesh.node_class[g as usize] = NodeClass::Face(f, Some(l.uv));
                }
            }
            sides.push((ids, side_uvs(&nodes)));
        }
        let [w1, w2] = [w[0], w[1]];
        let rev_of = |v: &Vec<[f64; 2]>| v.iter().rev().copied().collect::<Vec<_>>();
        let uv = UvSides {
            bottom: sides[0].1.clone(),
            right: sides[1].1.clone(),
            top: rev_of(&sides[2].1),
            left: rev_of(&sides[3].1),
        };
        let mut grid = vec![u32::MAX; (w1 + 1) * (w2 + 1)];
        let id = |i: usize, j: usize| i + (w1 + 1) * j;
        for i in 0..=w1 {
            grid[id(i, 0)] = sides[0].0[i];
            grid[id(w1 - i, w2)] = sides[2].0[i];
        }
        for j in 0..=w2 {
            grid[id(w1, j)] = sides[1].0[j];
            grid[id(0, w2 - j)] = sides[3].0[j];
        }
        for j in 1..w2 {
            for i in 1..w1 {
                let p = uv
                    .at(i, j)
                    .ok_or_else(|| format!("block {bi}: sides do not match"))?;
                let x = face.surface.eval(p);
                if !x.iter().chain(p.iter()).all(|c| c.is_finite()) {
                    return Err(format!(
                        "block {bi}: an inner node is off face {}",
                        blk.face.0 + 1
                    ));
                }
                grid[id(i, j)] = mesh.nodes.len() as u32;
                mesh.nodes.push(x);
                mesh.node_class.push(NodeClass::Face(blk.face, Some(p)));
            }
        }
        let first_quad = mesh.quads.len() as u32;
        for j in 0..w2 {
            for i in 0..w1 {
                mesh.quads.push([
                    grid[id(i, j)],
                    grid[id(i + 1, j)],
                    grid[id(i + 1, j + 1)],
                    grid[id(i, j + 1)],
                ]);
                mesh.quad_face.push(blk.face);
            }
        }
        block_grid.push(BlockGrid {
            size: [w1, w2],
            nodes: grid,
            first_quad,
        });
    }
    for (v, c) in mesh
        .node_class
        .iter()
        .enumerate()
        .take(layout.vertex_node.len())
    {
        if let NodeClass::Corner(k) = c {
            mesh.corner_nodes.push((v as u32, *k));
        }
    }
    Ok(FineMesh {
        mesh,
        block_grid,
        edge_nodes,
    })
}

/// A vertex's class with its parameters: a curve node or face node without
/// them (a mesh read from a file) projected onto its curve or face.
fn complete_params(model: &Model, class: NodeClass, p: Vec3) -> NodeClass {
    match class {
        NodeClass::Curve(c, None) => {
            let t = model
                .curves
                .get(c.idx())
                .and_then(|ce| ce.geom.as_ref())
                .and_then(|g| g.project(p, None))
                .map(|r| r.0);
            NodeClass::Curve(c, t)
        }
        other => other,
    }
}

/// Smooths the face-interior nodes of `mesh` face by face, then slides its
/// curve nodes (module documentation). Returns the node moves kept by the
/// face smoothing.
pub(crate) fn smooth(model: &Model, mesh: &mut QuadMesh) -> Result<usize, String> {
    let patches = face_patches(model, mesh)?;
    let mut order: Vec<usize> = (0..patches.len()).collect();
    order.sort_by_key(|&i| (std::cmp::Reverse(patches[i].patch.quads.len()), i));
    let results = map_in_order(&order, |&i| {
        let fp = &patches[i];
        let fid: FaceId = fp.face;
        let face = &model.faces[fid.idx()];
        let sharp = sharp_corners_of(model, fid);
        let mut p = fp.patch.clone();
        untangle(
            face,
            &mut p,
            UNTANGLE_BELOW,
            UNTANGLE_PASSES,
            UNTANGLE_MAX_NODES,
            &sharp,
        );
        let r = optimize(face, &mut p, &OptimizeOptions::default());
        untangle(
            face,
            &mut p,
            UNTANGLE_BELOW,
            UNTANGLE_PASSES,
            UNTANGLE_MAX_NODES,
            &sharp,
        );
        let moved: Vec<(u32, Vec3, [f64; 2])> = p
            .nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| n.node == NodeRef::Interior)
            .map(|(l, n)| (fp.global[l], p.pos[l], n.uv))
            .collect();
        (fid, moved, r.moves)
    });
    let mut moves = 0;
    for (fid, moved, m) in results {
        moves += m;
        for (g, x, uv) in moved {
            if let NodeClass::Face(f, _) = mesh.node_class[g as usize] {
                if f == fid {
                    mesh.nodes[g as usize] = x;
                    mesh.node_class[g as usize] = NodeClass::Face(f, Some(uv));
                }
            }
        }
    }
    slide_curve_nodes(model, mesh, FINE_SLIDE_SWEEPS);
    Ok(moves)
}

#[cfg(test)]
mod tests;
