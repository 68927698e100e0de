//! The last resort for high-order elements that stay invalid (issue 29,
//! item 6; not in the paper): split their quad loops in two. Every block of
//! a split loop is cut across the loop along the fine grid line nearest its
//! middle, so each high-order element of the loop becomes two (four where
//! both loops of a block are split), half as wide: curved CAD boundaries are
//! followed more closely by the smaller elements.
//!
//! The fine mesh stays as it is (its nodes renumbered so that the new
//! layout vertices come first, as [`FineMesh`] wants): the split layout
//! lies on the fine mesh, each of its edges a run of fine edges, each block
//! a sub-grid. Cuts are propagated along each loop through the blocks so
//! that opposite sides of every block are cut at the same grid line (for an
//! odd width the middle is not symmetric); a loop whose cuts disagree (a
//! non-orientable loop) or whose width is 1 is not split.

use std::collections::{BTreeSet, VecDeque};

use geometry::Model;
use mesh::high_order::HighOrderQuadMesh;
use mesh::QuadMesh;

use crate::coarse::block_layout::{Block, BlockLayout, LayoutEdge};
use crate::coarse::fine_mesh::{BlockGrid, FineMesh};
use crate::coarse::high_order_extraction::{extract_high_order, HighOrderReport};
use crate::coarse::quad_loops::QuadLoops;
use crate::core::fast_hash::FastMap;

/// The grid coordinate (along `i` for sides 0 and 2, `j` for sides 1 and 3)
/// of point `s` (from the side's first corner) of side `k` of a block of
/// size `[w1, w2]`; the inverse map is the same.
fn side_to_grid(k: usize, s: usize, size: [usize; 2]) -> usize {
    match k {
        0 | 1 => s,
        2 => size[0] - s,
        _ => size[1] - s,
    }
}

/// `layout` and its smoothed `fine` mesh with the quad loops `split` (loop
/// ids of [`QuadLoops::of`]`(layout)`) cut in two (module documentation):
/// the new layout lies on the returned fine mesh (same nodes, renumbered;
/// same quads, reordered block by block). Loops of width 1 or with
/// disagreeing cuts are left whole; returns how many loops were split. An
/// error when `fine` is not `layout`'s fine mesh.
pub(crate) fn split_loops(
    layout: &BlockLayout,
    fine: &FineMesh,
    split: &[u32],
) -> Result<(BlockLayout, FineMesh, usize), String> {
    let ne = layout.edges.len();
    if fine.edge_nodes.len() != ne || fine.block_grid.len() != layout.blocks.len() {
        return Err("the fine mesh is not that of this layout".into());
    }
    let loops = QuadLoops::of(layout);
    let width = |e: usize| fine.edge_nodes[e].len().saturating_sub(1);
    // the block sides on each edge
    let mut uses: Vec<Vec<(usize, usize)>> = vec![Vec::new(); ne];
    for (b, blk) in layout.blocks.iter().enumerate() {
        for (k, &(e, _)) in blk.sides.iter().enumerate() {
            uses[e as usize].push((b, k));
        }
    }
    // the cut of each edge: its fine node index from ends[0]
    let mut cut: Vec<Option<usize>> = vec![None; ne];
    let mut wanted: Vec<u32> = split.to_vec();
    wanted.sort_unstable();
    wanted.dedup();
    let mut done = 0;
    for &l in &wanted {
        let Some(e0) = loops.edge_loop.iter().position(|&x| x == l) else {
            continue;
        };
        if width(e0) < 2 {
            continue;
        }
        let mut set: Vec<usize> = vec![e0];
        cut[e0] = Some(width(e0) / 2);
        let mut queue = VecDeque::from([e0]);
        let mut consistent = true;
        'walk: while let Some(e) = queue.pop_front() {
            let c = cut[e].unwrap_or(0);
            for &(b, k) in &uses[e] {
                let blk = &layout.blocks[b];
                let size = fine.block_grid[b].size;
                let w = width(e);
                let s = if blk.sides[k].1 { w - c } else { c };
                let g = side_to_grid(k, s, size);
                let k2 = (k + 2) % 4;
                let (e2, rev2) = blk.sides[k2];
                let e2 = e2 as usize;
                let w2 = width(e2);
                let s2 = side_to_grid(k2, g, size);
                if w2 != w || s2 > w2 {
                    consistent = false;
                    break 'walk;
                }
                let c2 = if rev2 { w2 - s2 } else { s2 };
                match cut[e2] {
                    None => {
                        cut[e2] = Some(c2);
                        set.push(e2);
                        queue.push_back(e2);
                    }
                    Some(x) if x == c2 => {}
                    Some(_) => {
                        consistent = false;
                        break 'walk;
                    }
                }
            }
        }
        if consistent {
            done += 1;
        } else {
            for e in set {
                cut[e] = None;
            }
        }
    }
    // the new layout vertices: the old ones, the edges' cuts, the blocks' centres
    let mut vertex_fine: Vec<u32> = (0..layout.vertex_node.len() as u32).collect();
    for (e, c) in cut.iter().enumerate() {
        if let Some(c) = c {
            vertex_fine.push(fine.edge_nodes[e][*c]);
        }
    }
    // each block's cut lines in grid coordinates
    let block_cut: Vec<[Option<usize>; 2]> = layout
        .blocks
        .iter()
        .enumerate()
        .map(|(b, blk)| {
            let size = fine.block_grid[b].size;
            [0, 1].map(|k| {
                let (e, rev) = blk.sides[k];
                cut[e as usize].map(|c| {
                    let s = if rev { width(e as usize) - c } else { c };
                    side_to_grid(k, s, size)
                })
            })
        })
        .collect();
    for (b, bc) in block_cut.iter().enumerate() {
        if let [Some(a), Some(c)] = *bc {
            vertex_fine.push(fine.block_grid[b].at(a, c));
        }
    }
    // fine nodes renumbered: the new vertices first
    let m = &fine.mesh;
    let mut new_id = vec![u32::MAX; m.nodes.len()];
    for (v, &n) in vertex_fine.iter().enumerate() {
        if new_id[n as usize] != u32::MAX {
            return Err(format!("fine node {n} is two layout vertices"));
        }
        new_id[n as usize] = v as u32;
    }
    let rest = new_id.iter_mut().filter(|x| **x == u32::MAX);
    for (next, id) in (vertex_fine.len() as u32..).zip(rest) {
        *id = next;
    }
    let mut mesh = QuadMesh {
        nodes: vec![[0.0; 3]; m.nodes.len()],
        node_class: m.node_class.clone(),
        curve_edges: m
            .curve_edges
            .iter()
            .map(|&([a, b], c)| ([new_id[a as usize], new_id[b as usize]], c))
            .collect(),
        corner_nodes: m
            .corner_nodes
            .iter()
            .map(|&(n, c)| (new_id[n as usize], c))
            .collect(),
        ..Default::default()
    };
    for (old, &new) in new_id.iter().enumerate() {
        mesh.nodes[new as usize] = m.nodes[old];
        mesh.node_class[new as usize] = m.node_class[old];
    }
    // the sub-blocks, their edges found by their paths' first steps
    let mut out = BlockLayout {
        vertex_node: (0..vertex_fine.len() as u32).collect(),
        ..Default::default()
    };
    let mut edge_of: FastMap<(u32, u32), u32> = FastMap::default();
    let mut grids = Vec::new();
    for (b, blk) in layout.blocks.iter().enumerate() {
        let g = &fine.block_grid[b];
        let [w1, w2] = g.size;
        let ranges = |c: Option<usize>, w: usize| match c {
            Some(a) if a > 0 && a < w => vec![(0, a), (a, w)],
            _ => vec![(0, w)],
        };
        for &(j0, j1) in &ranges(block_cut[b][1], w2) {
            for &(i0, i1) in &ranges(block_cut[b][0], w1) {
                let node = |i: usize, j: usize| new_id[g.at(i, j) as usize];
                let chains: [Vec<u32>; 4] = [
                    (i0..=i1).map(|i| node(i, j0)).collect(),
                    (j0..=j1).map(|j| node(i1, j)).collect(),
                    (i0..=i1).rev().map(|i| node(i, j1)).collect(),
                    (j0..=j1).rev().map(|j| node(i0, j)).collect(),
                ];
                let on_old = [j0 == 0, i1 == w1, j1 == w2, i0 == 0];
                let mut sides = [(0u32, false); 4];
                for k in 0..4 {
                    let ch = &chains[k];
                    let curve = if on_old[k] {
                        layout.edges[blk.sides[k].0 as usize].curve
                    } else {
                        None
                    };
                    sides[k] = find_or_add(&mut out, &mut edge_of, ch, curve)?;
                }
                let corners = [chains[0][0], chains[1][0], chains[2][0], chains[3][0]];
                out.blocks.push(Block {
                    corners,
                    sides,
                    face: blk.face,
                });
                let first_quad = mesh.quads.len() as u32;
                let mut nodes = Vec::with_capacity((i1 - i0 + 1) * (j1 - j0 + 1));
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        nodes.push(node(i, j));
                    }
                }
                for j in j0..j1 {
                    for i in i0..i1 {
                        mesh.quads.push([
                            node(i, j),
                            node(i + 1, j),
                            node(i + 1, j + 1),
                            node(i, j + 1),
                        ]);
                        mesh.quad_face.push(blk.face);
                    }
                }
                grids.push(BlockGrid {
                    size: [i1 - i0, j1 - j0],
                    nodes,
                    first_quad,
                });
            }
        }
    }
    let edge_nodes = out.edges.iter().map(|e| e.path.clone()).collect();
    Ok((
        out,
        FineMesh {
            mesh,
            block_grid: grids,
            edge_nodes,
        },
        done,
    ))
}

/// The edge of `out` whose path is `chain` (either way), added if new:
/// `(edge, reversed)` as a block side running along `chain`. An error when
/// an end of `chain` is not a layout vertex.
fn find_or_add(
    out: &mut BlockLayout,
    edge_of: &mut FastMap<(u32, u32), u32>,
    chain: &[u32],
    curve: Option<geometry::CurveId>,
) -> Result<(u32, bool), String> {
    let m = chain.len() - 1;
    if let Some(&e) = edge_of.get(&(chain[0], chain[1])) {
        return Ok((e, out.edges[e as usize].path[0] != chain[0]));
    }
    let nv = out.vertex_node.len() as u32;
    let (a, b) = (chain[0], chain[m]);
    if a >= nv || b >= nv {
        return Err(format!(
            "a split side ends at fine node {}, not a vertex",
            a.max(b)
        ));
    }
    let e = out.edges.len() as u32;
    edge_of.insert((chain[0], chain[1]), e);
    edge_of.insert((chain[m], chain[m - 1]), e);
    out.edges.push(LayoutEdge {
        ends: [a, b],
        path: chain.to_vec(),
        curve,
    });
    Ok((e, false))
}

/// The loops of the blocks `blocks` (both loops of each), sorted.
fn loops_of_blocks(layout: &BlockLayout, blocks: &[u32]) -> Vec<u32> {
    let loops = QuadLoops::of(layout);
    let mut out = BTreeSet::new();
    for &b in blocks {
        if let Some(blk) = layout.blocks.get(b as usize) {
            for k in 0..2 {
                out.insert(loops.edge_loop[blk.sides[k].0 as usize]);
            }
        }
    }
    out.into_iter().collect()
}

/// Rounds of loop splitting for elements that stay invalid (issue 29: 3).
#[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
pub(crate) const SPLIT_ROUNDS: usize = 3;

/// What [`extract_with_splits`] made: the high-order mesh with its report,
/// and the layout and fine mesh it was extracted from (split where needed).
#[derive(Clone, Debug)]
pub(crate) struct Extraction {
    /// The layout of the elements (on `fine.mesh` when loops were split).
    pub layout: BlockLayout,
    /// Its fine mesh.
    pub fine: FineMesh,
    /// The high-order mesh, one element per block of `layout`.
    #[cfg_attr(not(test), allow(dead_code))] // read by the coarse method (to come)
    pub mesh: HighOrderQuadMesh,
    /// Its report.
    pub report: HighOrderReport,
    /// Quad loops split in all rounds.
    pub split_loops: usize,
}

/// [`extract_high_order`] of `layout` and its fine mesh `fine` at order
/// `order`; while elements stay invalid (at most `rounds` times), their
/// quad loops are split in two ([`split_loops`]) and the elements extracted
/// again. A split is kept only when it leaves fewer invalid elements (the
/// loops of an unstructured mesh's identity layout run through most of it,
/// and splitting them does not mend a fold at a sharp corner); the rounds
/// stop when none of the loops can be split (width 1).
#[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
pub(crate) fn extract_with_splits(
    model: &Model,
    layout: &BlockLayout,
    fine: &FineMesh,
    order: usize,
    rounds: usize,
) -> Result<Extraction, String> {
    let (mesh, report) = extract_high_order(model, layout, fine, order)?;
    let mut best = Extraction {
        layout: layout.clone(),
        fine: fine.clone(),
        mesh,
        report,
        split_loops: 0,
    };
    for _ in 0..rounds {
        let loops = loops_of_blocks(&best.layout, &best.report.invalid_elements);
        if loops.is_empty() {
            break;
        }
        let (layout, fine, done) = split_loops(&best.layout, &best.fine, &loops)?;
        if done == 0 {
            break;
        }
        let (mesh, report) = extract_high_order(model, &layout, &fine, order)?;
        if report.invalid_elements.len() >= best.report.invalid_elements.len() {
            break;
        }
        best = Extraction {
            layout,
            fine,
            mesh,
            report,
            split_loops: best.split_loops + done,
        };
    }
    Ok(best)
}

#[cfg(test)]
mod tests;
