//! The identity layout ([`BlockLayout::identity`]: every input quad a block,
//! q = l, the always-valid fallback) and the validity check every layout
//! passes before the geometry stages ([`BlockLayout::check`]).

use mesh::{NodeClass, QuadMesh};

use crate::coarse::block_layout::{Block, BlockLayout, LayoutEdge};
use crate::core::fast_hash::FastMap;

/// The input mesh's edges: each directed quad edge `a → b` with its quad and
/// the position of `a` in it (the quad lies to the left of `a → b`), and each
/// curve edge (undirected, smaller node first) with its curve.
pub(crate) struct InputEdges {
    /// Directed quad edge → (quad, position of its first node in the quad).
    pub directed: FastMap<(u32, u32), (u32, u8)>,
    /// Undirected curve edge → its CAD curve.
    pub curve: FastMap<(u32, u32), geometry::CurveId>,
}

impl InputEdges {
    /// The edges of `mesh`; an error when a directed edge is used twice (the
    /// quads are not a consistently oriented manifold) or a quad refers to a
    /// missing node.
    pub(crate) fn of(mesh: &QuadMesh) -> Result<Self, String> {
        let nn = mesh.nodes.len() as u32;
        if mesh.node_class.len() != mesh.nodes.len() || mesh.quad_face.len() != mesh.quads.len() {
            return Err("input mesh: node classes or quad faces missing".into());
        }
        let mut directed = FastMap::default();
        directed.reserve(4 * mesh.quads.len());
        for (qi, q) in mesh.quads.iter().enumerate() {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                if a >= nn || b >= nn || a == b {
                    return Err(format!("input quad {qi} has a missing or repeated node"));
                }
                if directed.insert((a, b), (qi as u32, k as u8)).is_some() {
                    return Err(format!(
                        "input edge {a} → {b} is used twice in one direction (quad {qi})"
                    ));
                }
            }
        }
        let mut curve = FastMap::default();
        for &([a, b], c) in &mesh.curve_edges {
            curve.insert((a.min(b), a.max(b)), c);
        }
        Ok(InputEdges { directed, curve })
    }

    /// True when `a`–`b` is an edge of an input quad.
    pub(crate) fn is_edge(&self, a: u32, b: u32) -> bool {
        self.directed.contains_key(&(a, b)) || self.directed.contains_key(&(b, a))
    }

    /// The CAD curve of input edge `a`–`b`, if it is a curve edge.
    pub(crate) fn curve_of(&self, a: u32, b: u32) -> Option<geometry::CurveId> {
        self.curve.get(&(a.min(b), a.max(b))).copied()
    }
}

impl Block {
    /// The input-mesh nodes along side `k` from `corners[k]` to
    /// `corners[(k + 1) % 4]` (the block lies to their left).
    pub(crate) fn side_path<'a>(
        &self,
        layout: &'a BlockLayout,
        k: usize,
    ) -> impl Iterator<Item = u32> + 'a {
        let (e, reversed) = self.sides[k];
        let path = &layout.edges[e as usize].path;
        let n = path.len();
        (0..n).map(move |i| if reversed { path[n - 1 - i] } else { path[i] })
    }
}

impl BlockLayout {
    /// The identity layout of `input`: one layout vertex per node used by a
    /// quad (in node order), one edge per quad edge (in the order the quads
    /// first use them, directed as that first use; curve edges carry their
    /// curve), one block per quad (in quad order, its face kept).
    #[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
    pub(crate) fn identity(input: &QuadMesh) -> BlockLayout {
        let mut vertex_of = vec![u32::MAX; input.nodes.len()];
        let mut layout = BlockLayout::default();
        let mut used = vec![false; input.nodes.len()];
        for &n in input.quads.iter().flatten() {
            if let Some(u) = used.get_mut(n as usize) {
                *u = true;
            }
        }
        for (n, _) in used.iter().enumerate().filter(|(_, &u)| u) {
            vertex_of[n] = layout.vertex_node.len() as u32;
            layout.vertex_node.push(n as u32);
        }
        let mut curve: FastMap<(u32, u32), geometry::CurveId> = FastMap::default();
        for &([a, b], c) in &input.curve_edges {
            curve.insert((a.min(b), a.max(b)), c);
        }
        let mut edge_of: FastMap<(u32, u32), u32> = FastMap::default();
        for (q, f) in input.quads.iter().zip(&input.quad_face) {
            if q.iter().any(|&n| n as usize >= input.nodes.len()) {
                continue;
            }
            let corners = q.map(|n| vertex_of[n as usize]);
            let mut sides = [(0u32, false); 4];
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                let key = (a.min(b), a.max(b));
                let e = *edge_of.entry(key).or_insert_with(|| {
                    layout.edges.push(LayoutEdge {
                        ends: [vertex_of[a as usize], vertex_of[b as usize]],
                        path: vec![a, b],
                        curve: curve.get(&key).copied(),
                    });
                    layout.edges.len() as u32 - 1
                });
                sides[k] = (e, layout.edges[e as usize].path[0] != a);
            }
            layout.blocks.push(Block {
                corners,
                sides,
                face: *f,
            });
        }
        layout
    }

    /// Checks that the layout is a valid conforming block structure on
    /// `input`: layout vertices on distinct input nodes, every CAD corner
    /// node among them; each edge a simple path of input edges between its
    /// two (distinct) end vertices through no other vertex, along one CAD
    /// curve exactly when it carries that curve, no two paths sharing an
    /// input edge, every input curve edge on an edge; each block with four
    /// distinct corners, sides joining them in turn, and on its sides'
    /// left the input quads of its face; every curve edge bounding one or
    /// two blocks, every other edge two blocks of one face, the two with
    /// opposite orientations; and the blocks tiling the input quads (each
    /// quad reached from exactly one block without crossing an edge).
    /// Returns the first problem found.
    #[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
    pub(crate) fn check(&self, input: &QuadMesh) -> Result<(), String> {
        self.check_with(input, &InputEdges::of(input)?)
    }

    /// [`BlockLayout::check`] with the input's edges at hand.
    pub(crate) fn check_with(&self, input: &QuadMesh, edges: &InputEdges) -> Result<(), String> {
        let nn = input.nodes.len();
        let nv = self.vertex_node.len();
        // vertices
        let mut vertex_at = vec![u32::MAX; nn];
        for (v, &n) in self.vertex_node.iter().enumerate() {
            let slot = vertex_at
                .get_mut(n as usize)
                .ok_or_else(|| format!("layout vertex {v} is on missing node {n}"))?;
            if *slot != u32::MAX {
                return Err(format!("layout vertices {} and {v} share node {n}", *slot));
            }
            *slot = v as u32;
        }
        for &n in input.quads.iter().flatten() {
            if let NodeClass::Corner(c) = input.node_class[n as usize] {
                if vertex_at[n as usize] == u32::MAX {
                    return Err(format!(
                        "CAD corner {} (node {n}) is not a layout vertex",
                        c.0 + 1
                    ));
                }
            }
        }
        // edges
        let mut step_owner: FastMap<(u32, u32), u32> = FastMap::default();
        for (ei, e) in self.edges.iter().enumerate() {
            let [a, b] = e.ends;
            if a as usize >= nv || b as usize >= nv || a == b {
                return Err(format!("edge {ei} has ends {a}, {b}: missing or equal"));
            }
            let p = &e.path;
            if p.len() < 2
                || p[0] != self.vertex_node[a as usize]
                || p[p.len() - 1] != self.vertex_node[b as usize]
            {
                return Err(format!(
                    "edge {ei}: its path does not join its two vertices"
                ));
            }
            let mut seen: Vec<u32> = p.clone();
            seen.sort_unstable();
            seen.dedup();
            if seen.len() != p.len() {
                return Err(format!("edge {ei}: its path repeats a node"));
            }
            if let Some(&n) = p[1..p.len() - 1]
                .iter()
                .find(|&&n| vertex_at.get(n as usize).is_none_or(|&v| v != u32::MAX))
            {
                return Err(format!("edge {ei}: its path runs through vertex node {n}"));
            }
            for (s, w) in p.windows(2).enumerate() {
                if !edges.is_edge(w[0], w[1]) {
                    return Err(format!(
                        "edge {ei}: step {s} ({} – {}) is not an input edge",
                        w[0], w[1]
                    ));
                }
                match (edges.curve_of(w[0], w[1]), e.curve) {
                    (Some(c), Some(d)) if c != d => {
                        return Err(format!(
                            "edge {ei} on curve {} runs along curve {} at step {s}",
                            d.0 + 1,
                            c.0 + 1
                        ))
                    }
                    (None, Some(d)) => {
                        return Err(format!(
                            "edge {ei} on curve {} leaves it at step {s}",
                            d.0 + 1
                        ))
                    }
                    (Some(c), None) => {
                        return Err(format!(
                            "edge {ei} runs along curve {} at step {s} but carries no curve",
                            c.0 + 1
                        ))
                    }
                    _ => {}
                }
                let key = (w[0].min(w[1]), w[0].max(w[1]));
                if let Some(o) = step_owner.insert(key, ei as u32) {
                    return Err(format!(
                        "edges {o} and {ei} share input edge {} – {}",
                        key.0, key.1
                    ));
                }
            }
        }
        for &([a, b], c) in &input.curve_edges {
            if edges.is_edge(a, b) && !step_owner.contains_key(&(a.min(b), a.max(b))) {
                return Err(format!(
                    "input edge {a} – {b} of curve {} is on no layout edge",
                    c.0 + 1
                ));
            }
        }
        // blocks
        let mut uses: Vec<Vec<(u32, bool)>> = vec![Vec::new(); self.edges.len()];
        let mut owner = vec![u32::MAX; input.quads.len()];
        for (bi, blk) in self.blocks.iter().enumerate() {
            let c = blk.corners;
            if c.iter().any(|&v| v as usize >= nv)
                || (0..4).any(|i| (i + 1..4).any(|j| c[i] == c[j]))
            {
                return Err(format!(
                    "block {bi}: its corners are not four distinct vertices"
                ));
            }
            let mut front: Vec<u32> = Vec::new();
            for k in 0..4 {
                let (e, rev) = blk.sides[k];
                let edge = self
                    .edges
                    .get(e as usize)
                    .ok_or_else(|| format!("block {bi}: side {k} is missing edge {e}"))?;
                let (from, to) = if rev {
                    (edge.ends[1], edge.ends[0])
                } else {
                    (edge.ends[0], edge.ends[1])
                };
                if from != c[k] || to != c[(k + 1) % 4] {
                    return Err(format!(
                        "block {bi}: side {k} (edge {e}) does not join its corners"
                    ));
                }
                uses[e as usize].push((bi as u32, rev));
                let path: Vec<u32> = blk.side_path(self, k).collect();
                for w in path.windows(2) {
                    let Some(&(q, _)) = edges.directed.get(&(w[0], w[1])) else {
                        return Err(format!(
                            "block {bi}: no input quad on the left of side {k} at {} → {}",
                            w[0], w[1]
                        ));
                    };
                    if input.quad_face[q as usize] != blk.face {
                        return Err(format!(
                            "block {bi} on face {}: input quad {q} left of side {k} is on face {}",
                            blk.face.0 + 1,
                            input.quad_face[q as usize].0 + 1
                        ));
                    }
                    front.push(q);
                }
            }
            // the block's input quads: from its sides, never across a layout edge
            while let Some(q) = front.pop() {
                match owner[q as usize] {
                    o if o == bi as u32 => continue,
                    u32::MAX => owner[q as usize] = bi as u32,
                    o => return Err(format!("blocks {o} and {bi} overlap at input quad {q}")),
                }
                let quad = input.quads[q as usize];
                for k in 0..4 {
                    let (a, b) = (quad[k], quad[(k + 1) % 4]);
                    if step_owner.contains_key(&(a.min(b), a.max(b))) {
                        continue;
                    }
                    if let Some(&(r, _)) = edges.directed.get(&(b, a)) {
                        front.push(r);
                    }
                }
            }
        }
        if let Some(q) = owner.iter().position(|&o| o == u32::MAX) {
            return Err(format!("input quad {q} is in no block"));
        }
        for (ei, u) in uses.iter().enumerate() {
            let curve = self.edges[ei].curve.is_some();
            let ok = match u.as_slice() {
                [_] => curve,
                [(b0, r0), (b1, r1)] => {
                    r0 != r1
                        && (curve
                            || self.blocks[*b0 as usize].face == self.blocks[*b1 as usize].face)
                }
                _ => false,
            };
            if !ok {
                return Err(format!(
                    "edge {ei} bounds {} block side(s) ({}): expected two with opposite \
                     orientations in one face, or one or two for a curve edge",
                    u.len(),
                    u.iter()
                        .map(|(b, r)| format!("{b}{}", if *r { "−" } else { "+" }))
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::layouts::{cylinder_ring, square_blocks};
    use crate::{mesh_model_with, MeshMethod, MeshOptions, Size};
    use geometry::{primitives, CurveId};

    /// The default method's mesh of `model` at size factor `f`, one thread.
    pub(crate) fn default_mesh(model: &geometry::Model, f: f64) -> QuadMesh {
        let opts = MeshOptions {
            size: Size::Factor(f),
            threads: Some(1),
            ..Default::default()
        };
        mesh_model_with(model, &opts, MeshMethod::default())
            .unwrap()
            .0
    }

    #[test]
    fn identity_layouts_of_fixture_meshes_pass_the_check() {
        let meshes = [
            mesh::fixtures::square_grid(1.0, 3).1,
            mesh::fixtures::cube(1.0, 3).1,
            default_mesh(&primitives::cylinder(1.0, 2.0), 1.0),
            default_mesh(&primitives::sphere(1.0), 1.0),
        ];
        for m in &meshes {
            let l = BlockLayout::identity(m);
            assert_eq!(l.blocks.len(), m.quads.len());
            assert_eq!(l.vertex_node.len(), m.nodes.len());
            // Euler on the quads' edges: every edge once
            let edges: std::collections::BTreeSet<(u32, u32)> = m
                .quads
                .iter()
                .flat_map(|q| {
                    (0..4).map(move |k| (q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4])))
                })
                .collect();
            assert_eq!(l.edges.len(), edges.len());
            assert_eq!(
                l.edges.iter().filter(|e| e.curve.is_some()).count(),
                m.curve_edges.len()
            );
            l.check(m).unwrap();
        }
    }

    #[test]
    fn hand_made_layouts_pass_the_check() {
        let (_, mesh, l) = square_blocks(8, 4);
        assert_eq!(
            (l.vertex_node.len(), l.edges.len(), l.blocks.len()),
            (9, 12, 4)
        );
        l.check(&mesh).unwrap();
        let (_, mesh, l) = cylinder_ring(1.0, 2.0, 12, 3, 4);
        l.check(&mesh).unwrap();
    }

    #[test]
    fn broken_layouts_are_refused_with_a_reason() {
        let (_, mesh, good) = square_blocks(8, 4);
        let expect = |l: &BlockLayout, what: &str| {
            let e = l.check(&mesh).unwrap_err();
            assert!(e.contains(what), "{e:?} should mention {what:?}");
        };
        // a block turned clockwise: its sides no longer join its corners
        let mut l = good.clone();
        l.blocks[0].corners.reverse();
        expect(&l, "does not join its corners");
        // a block dropped: its quads are in no block, an inner edge bounds one block
        let mut l = good.clone();
        l.blocks.pop();
        expect(&l, "is in no block");
        // a boundary edge that forgot its curve
        let mut l = good.clone();
        l.edges[0].curve = None;
        expect(&l, "carries no curve");
        // an inner edge claimed by a curve
        let mut l = good.clone();
        l.edges[2].curve = Some(CurveId(0));
        expect(&l, "leaves it");
        // a path that skips a node
        let mut l = good.clone();
        l.edges[0].path.remove(1);
        expect(&l, "not an input edge");
        // two vertices on one node
        let mut l = good.clone();
        l.vertex_node[1] = l.vertex_node[0];
        expect(&l, "share node");
        // a CAD corner that is not a vertex: the bottom-left block shrunk to 3 x 4
        let mut l = good.clone();
        l.vertex_node[0] = 1;
        l.edges[0].path.remove(0);
        expect(&l, "CAD corner 1");
        // a block that covers the quads of another (the same block twice)
        let mut l = good.clone();
        l.blocks.push(l.blocks[0].clone());
        expect(&l, "overlap");
        // broken input: a quad repeating a node
        let mut m = mesh.clone();
        m.quads[0][1] = m.quads[0][0];
        assert!(good.check(&m).unwrap_err().contains("repeated node"));
    }
}
