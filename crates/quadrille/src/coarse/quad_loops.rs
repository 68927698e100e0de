//! Quad loops of the block layout (coarse paper §IV.D, spec §5.4): opposite
//! sides of a block must be split into the same number of fine edges, so the
//! edges linked through blocks by "opposite side" (the chords of the coarse
//! mesh, closed or ending on the boundary) share one integer width: the
//! rounded mean of their target lengths, at least 1. The target length of a
//! layout edge is the number of input-mesh edges along its path (the
//! paper's "integer length"; spec §10 item 4).

use crate::coarse::block_layout::BlockLayout;
use crate::core::union_find::UnionFind;

/// The quad loops of a layout and their widths.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct QuadLoops {
    /// The loop of each layout edge (loops numbered by their first edge).
    pub edge_loop: Vec<u32>,
    /// The width of each loop: fine edges per layout edge of the loop.
    pub width: Vec<usize>,
}

impl QuadLoops {
    /// The quad loops of `layout`: sides 0 and 2, and sides 1 and 3, of
    /// every block joined; each loop's width is the rounded mean of its
    /// edges' path lengths in input-mesh edges, at least 1. Block sides
    /// naming a missing edge are ignored ([`BlockLayout::check`] reports them).
    #[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
    pub(crate) fn of(layout: &BlockLayout) -> QuadLoops {
        let ne = layout.edges.len();
        let mut uf = UnionFind::new(ne);
        for b in &layout.blocks {
            for k in 0..2 {
                let (e, f) = (b.sides[k].0 as usize, b.sides[k + 2].0 as usize);
                if e < ne && f < ne {
                    uf.union(e, f);
                }
            }
        }
        let mut loop_of_root = vec![u32::MAX; ne];
        let mut edge_loop = Vec::with_capacity(ne);
        let (mut sum, mut count) = (Vec::new(), Vec::new());
        for e in 0..ne {
            let r = uf.find(e);
            if loop_of_root[r] == u32::MAX {
                loop_of_root[r] = sum.len() as u32;
                sum.push(0usize);
                count.push(0usize);
            }
            let l = loop_of_root[r];
            edge_loop.push(l);
            sum[l as usize] += layout.edges[e].path.len().saturating_sub(1);
            count[l as usize] += 1;
        }
        let width = sum
            .iter()
            .zip(&count)
            .map(|(&s, &c)| ((s as f64 / c as f64).round() as usize).max(1))
            .collect();
        QuadLoops { edge_loop, width }
    }

    /// The width of the loop of edge `e`.
    pub(crate) fn edge_width(&self, e: u32) -> usize {
        self.width[self.edge_loop[e as usize] as usize]
    }

    /// Number of loops.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.width.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coarse::block_layout::{Block, LayoutEdge};
    use geometry::FaceId;

    /// A strip of `n` blocks side by side (vertices 0..=n at the bottom,
    /// n+1..=2n+1 at the top), bottom edges `lengths[i]` input edges long,
    /// top and vertical edges 2.
    fn strip(lengths: &[usize]) -> BlockLayout {
        let n = lengths.len();
        let mut l = BlockLayout {
            vertex_node: (0..2 * (n as u32 + 1)).collect(),
            ..Default::default()
        };
        let edge = |a: u32, b: u32, len: usize| LayoutEdge {
            ends: [a, b],
            path: (0..=len as u32).map(|i| 1000 * (a + 1) + i).collect(),
            curve: None,
        };
        let top = |i: u32| n as u32 + 1 + i;
        for i in 0..=n as u32 {
            l.edges.push(edge(i, top(i), 2)); // vertical i
        }
        for i in 0..n as u32 {
            l.edges.push(edge(i, i + 1, lengths[i as usize])); // bottom i
            l.edges.push(edge(top(i), top(i + 1), 2)); // top i
        }
        for i in 0..n as u32 {
            let (bottom, topi) = (n as u32 + 1 + 2 * i, n as u32 + 2 + 2 * i);
            l.blocks.push(Block {
                corners: [i, i + 1, top(i + 1), top(i)],
                sides: [(bottom, false), (i + 1, false), (topi, true), (i, true)],
                face: FaceId(0),
            });
        }
        l
    }

    #[test]
    fn opposite_sides_share_a_loop_and_the_width_is_the_rounded_mean() {
        // bottom 5 and top 2: mean 3.5 rounds to 4; the verticals all share one loop of width 2
        let l = strip(&[5, 1]);
        let loops = QuadLoops::of(&l);
        assert_eq!(loops.len(), 3);
        let n = 2u32;
        for v in 0..=n {
            assert_eq!(loops.edge_loop[v as usize], loops.edge_loop[0]);
            assert_eq!(loops.edge_width(v), 2);
        }
        let (b0, t0, b1, t1) = (n + 1, n + 2, n + 3, n + 4);
        assert_eq!(loops.edge_loop[b0 as usize], loops.edge_loop[t0 as usize]);
        assert_ne!(loops.edge_loop[b0 as usize], loops.edge_loop[b1 as usize]);
        assert_eq!(loops.edge_width(b0), 4);
        // bottom 1 and top 2: mean 1.5 rounds to 2
        assert_eq!(loops.edge_width(b1), 2);
        assert_eq!(loops.edge_width(t1), 2);
    }

    #[test]
    fn a_loop_is_at_least_one_edge_wide() {
        let mut l = strip(&[1]);
        for e in &mut l.edges {
            e.path.truncate(1); // no input edge at all
        }
        let loops = QuadLoops::of(&l);
        assert!(loops.width.iter().all(|&w| w == 1));
    }
}
