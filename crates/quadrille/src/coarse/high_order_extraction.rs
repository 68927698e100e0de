//! High-order quads from the smoothed fine mesh (coarse paper §IV.F, spec
//! §5.6): one Lagrange quad of order N (equidistant nodes) per block.
//!
//! - Each layout vertex gives one node (the fine mesh's, classified alike).
//! - Each layout edge gives N − 1 nodes by equal-arc-length resampling of its
//!   fine polyline: on a CAD curve at the interpolated curve parameter (on
//!   the curve), elsewhere projected onto the face from the interpolated
//!   (u, v). Blocks on both sides share them.
//! - Each block gives (N − 1)² nodes by transfinite interpolation of its
//!   four high-order sides: in the face's (u, v), evaluated on the face, or
//!   in 3D, projected onto the face from there (the spec's reading),
//!   whichever gives the element the larger Jacobian ratio (near a pole the
//!   (u, v) interpolation crowds the nodes).
//!
//! Then the Jacobian determinant, measured against the CAD normal, is
//! checked at every node of every element; an element where it is ≤ 0
//! (numerically: [`MIN_JACOBIAN_RATIO`]) gets
//! its inner nodes resampled from its block's smoothed fine grid instead
//! (bilinear in the grid at the nodes' reference positions, projected onto
//! the face), and is listed in [`HighOrderReport::invalid_elements`] if it
//! stays invalid. (The last resort, splitting the element's quad
//! loops, is not done here.)

use geometry::{vec3, Model, Vec3};
use mesh::high_order::{HighOrderQuadMesh, MAX_ORDER};
use mesh::stats::node_cad_distances;
use mesh::{NodeClass, QuadMesh};

use crate::coarse::block_layout::BlockLayout;
use crate::coarse::face_patches::{face_patches, quad_corner_nodes};
use crate::coarse::fine_mesh::{BlockGrid, FineMesh, PROJECTION_TOLERANCE};
use crate::coarse::resample::{
    equal_arc_samples, resampled_node, onto_face, path_params, sample_hint, side_uvs, Sample, UvSides,
};
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::work_queue::map_in_order;

/// What [`extract_high_order`] found.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HighOrderReport {
    /// Elements with det J ≤ 0 at some node after every repair (their
    /// Jacobian ratio at most [`MIN_JACOBIAN_RATIO`]; still written).
    pub invalid_elements: Vec<u32>,
    /// The smallest ratio, over the elements, of the element's smallest to
    /// largest det J at its nodes (negative for an inverted element, about
    /// 0 for a flat one, 1 for an affine one; infinite without elements).
    pub min_jacobian_ratio: f64,
    /// The largest distance of a node to its CAD entity (closest-point
    /// projection, as `quadrille stats --cad` measures it).
    pub max_cad_distance: f64,
    /// Elements whose inner nodes were resampled from the fine grid.
    pub resampled: Vec<u32>,
}

/// An element whose smallest det J over its largest is at most this is
/// invalid: a ratio of 1e-16 is a rounding error away from a fold.
pub(crate) const MIN_JACOBIAN_RATIO: f64 = 1e-9;

/// Blocks per task of the parallel element loop.
const BLOCK_CHUNK: usize = 64;

/// One element while it is built: its nodes in tensor order (mesh node, or
/// `None` for an inner node not yet numbered), their positions, classes
/// and (u, v) in the element's face.
#[derive(Clone)]
struct Element {
    nodes: Vec<Option<u32>>,
    pos: Vec<Vec3>,
    class: Vec<NodeClass>,
    local: Vec<LocalNode>,
}

/// The curved Lagrange quads of order `order` (1..=[`MAX_ORDER`]) of
/// `layout`, one per block, from its smoothed fine mesh `fine` (module
/// documentation). Elements keep the blocks' order and corner order; node
/// `v` is layout vertex `v`, then come the edges' inner nodes (edge by
/// edge, from `ends[0]`), then the blocks'. An error for an order out of
/// range, a fine mesh that is not `layout`'s, or a node that cannot be
/// placed on the CAD.
#[cfg_attr(not(test), allow(dead_code))] // called by the coarse method (to come)
pub(crate) fn extract_high_order(
    model: &Model,
    layout: &BlockLayout,
    fine: &FineMesh,
    order: usize,
) -> Result<(HighOrderQuadMesh, HighOrderReport), String> {
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(format!("order {order} is not in 1..={MAX_ORDER}"));
    }
    let m = &fine.mesh;
    if fine.block_grid.len() != layout.blocks.len()
        || fine.edge_nodes.len() != layout.edges.len()
        || m.nodes.len() < layout.vertex_node.len()
    {
        return Err("the fine mesh is not that of this layout".into());
    }
    for (bi, blk) in layout.blocks.iter().enumerate() {
        if blk.face.idx() >= model.faces.len() {
            return Err(format!(
                "block {bi} is on face {}, not in the model",
                blk.face.0 + 1
            ));
        }
    }
    let patches = face_patches(model, m)?;
    let ctx = Ctx {
        model,
        layout,
        fine,
        corners: quad_corner_nodes(&patches, m.quads.len()),
        n: order,
        tol: PROJECTION_TOLERANCE * model.diagonal().max(f64::MIN_POSITIVE),
    };
    let nv = layout.vertex_node.len();
    let mut ho = HighOrderQuadMesh {
        order,
        nodes: m.nodes[..nv].to_vec(),
        node_class: m.node_class[..nv].to_vec(),
        ..Default::default()
    };
    let EdgeChains {
        nodes: edge_ho,
        samples: edge_samples,
    } = ctx.edges(&mut ho)?;
    // elements, in parallel by chunks of blocks
    let chunks: Vec<std::ops::Range<usize>> = (0..layout.blocks.len())
        .step_by(BLOCK_CHUNK)
        .map(|s| s..(s + BLOCK_CHUNK).min(layout.blocks.len()))
        .collect();
    let diff = LagrangeDiff::new(order);
    let built = map_in_order(&chunks, |r| {
        r.clone()
            .map(|b| {
                let mut el = ctx.element(&ho, &edge_ho, &edge_samples, b)?;
                let mut ratio = ctx.jacobian_ratio(b, &el, &diff);
                // the 3D interpolation projected, where it does better
                if order > 1 {
                    let mut el3 = el.clone();
                    ctx.project_tfi(b, &mut el3);
                    let r3 = ctx.jacobian_ratio(b, &el3, &diff);
                    if r3 > ratio {
                        (el, ratio) = (el3, r3);
                    }
                }
                let mut resampled = false;
                if ratio <= MIN_JACOBIAN_RATIO && order > 1 {
                    ctx.resample_inner(b, &mut el);
                    ratio = ctx.jacobian_ratio(b, &el, &diff);
                    resampled = true;
                }
                Ok((el, ratio, resampled))
            })
            .collect::<Result<Vec<_>, String>>()
    });
    let mut report = HighOrderReport {
        invalid_elements: Vec::new(),
        min_jacobian_ratio: f64::INFINITY,
        max_cad_distance: 0.0,
        resampled: Vec::new(),
    };
    let mut b = 0u32;
    for chunk in built {
        for (el, ratio, resampled) in chunk? {
            for (k, node) in el.nodes.iter().enumerate() {
                let id = match node {
                    Some(id) => *id,
                    None => {
                        ho.nodes.push(el.pos[k]);
                        ho.node_class.push(el.class[k]);
                        ho.nodes.len() as u32 - 1
                    }
                };
                ho.element_nodes.push(id);
            }
            ho.element_face.push(layout.blocks[b as usize].face);
            report.min_jacobian_ratio = report.min_jacobian_ratio.min(ratio);
            if ratio <= MIN_JACOBIAN_RATIO {
                report.invalid_elements.push(b);
            }
            if resampled {
                report.resampled.push(b);
            }
            b += 1;
        }
    }
    for (v, c) in ho.node_class.iter().enumerate().take(nv) {
        if let NodeClass::Corner(k) = c {
            ho.corner_nodes.push((v as u32, *k));
        }
    }
    let probe = QuadMesh {
        nodes: ho.nodes.clone(),
        node_class: ho.node_class.clone(),
        ..Default::default()
    };
    report.max_cad_distance = node_cad_distances(&probe, model)
        .into_iter()
        .flatten()
        .fold(0.0, f64::max);
    Ok((ho, report))
}

/// The high-order nodes along every layout edge, from `ends[0]`, and where
/// the inner ones lie on the edge's fine polyline.
struct EdgeChains {
    nodes: Vec<Vec<u32>>,
    samples: Vec<Vec<Sample>>,
}

/// What the element builder reads.
struct Ctx<'a> {
    model: &'a Model,
    layout: &'a BlockLayout,
    fine: &'a FineMesh,
    /// The local nodes (u, v in the quad's face) at the corners of every fine quad.
    corners: Vec<[LocalNode; 4]>,
    /// The order N.
    n: usize,
    /// Tolerance of the projections onto a face.
    tol: f64,
}

impl Ctx<'_> {
    /// Fine grid node `(i, j)` of `g` as seen from its block.
    fn local_at(&self, g: &BlockGrid, i: usize, j: usize) -> LocalNode {
        let (q, k) = g.cell_of(i, j);
        self.corners[q as usize][k]
    }

    /// Block `b`'s side `k` as fine local nodes, in the edge's direction.
    fn side_fine(&self, b: usize, k: usize) -> Result<Vec<LocalNode>, String> {
        let g = &self.fine.block_grid[b];
        let [w1, w2] = g.size;
        let cells: Vec<(usize, usize)> = match k {
            0 => (0..=w1).map(|i| (i, 0)).collect(),
            1 => (0..=w2).map(|j| (w1, j)).collect(),
            2 => (0..=w1).map(|i| (w1 - i, w2)).collect(),
            _ => (0..=w2).map(|j| (0, w2 - j)).collect(),
        };
        let (e, rev) = self.layout.blocks[b].sides[k];
        let mut chain = self.fine.edge_nodes[e as usize].clone();
        if rev {
            chain.reverse();
        }
        if cells.len() != chain.len()
            || cells
                .iter()
                .zip(&chain)
                .any(|(&(i, j), &c)| g.at(i, j) != c)
        {
            return Err(format!(
                "block {b}: side {k} is not the fine nodes of edge {e}"
            ));
        }
        let mut out: Vec<LocalNode> = cells.iter().map(|&(i, j)| self.local_at(g, i, j)).collect();
        if rev {
            out.reverse();
        }
        Ok(out)
    }

    /// The N − 1 inner nodes of every layout edge, added to `ho` (curve
    /// edges listed): each edge's high-order chain from `ends[0]` and
    /// where its inner nodes lie on the fine polyline.
    fn edges(&self, ho: &mut HighOrderQuadMesh) -> Result<EdgeChains, String> {
        let (model, m) = (self.model, &self.fine.mesh);
        let mut first_use: Vec<Option<(usize, usize)>> = vec![None; self.layout.edges.len()];
        for (bi, blk) in self.layout.blocks.iter().enumerate() {
            for (k, &(e, _)) in blk.sides.iter().enumerate() {
                first_use[e as usize].get_or_insert((bi, k));
            }
        }
        let mut edge_ho = Vec::with_capacity(self.layout.edges.len());
        let mut edge_samples = Vec::with_capacity(self.layout.edges.len());
        for (ei, e) in self.layout.edges.iter().enumerate() {
            let chain = &self.fine.edge_nodes[ei];
            let pts: Vec<Vec3> = chain.iter().map(|&v| m.nodes[v as usize]).collect();
            let samples = equal_arc_samples(&pts, self.n);
            let params = match e.curve {
                Some(c) => Some(path_params(model, &m.node_class, &m.nodes, chain, c)?),
                None => None,
            };
            let mut out = vec![e.ends[0]];
            for s in &samples {
                let (p, class) = match (&params, e.curve) {
                    (Some(t), Some(c)) => {
                        let x = t[s.seg] + s.lambda * (t[s.seg + 1] - t[s.seg]);
                        (
                            model.curves[c.idx()].eval(model, x),
                            NodeClass::Curve(c, Some(x)),
                        )
                    }
                    _ => {
                        let (b, k) =
                            first_use[ei].ok_or_else(|| format!("edge {ei} bounds no block"))?;
                        let fid = self.layout.blocks[b].face;
                        let hint = sample_hint(&self.side_fine(b, k)?, *s);
                        let target = vec3::lerp(pts[s.seg], pts[s.seg + 1], s.lambda);
                        let (uv, p) = onto_face(&model.faces[fid.idx()], hint, target, self.tol)
                            .ok_or_else(|| {
                                format!("edge {ei}: a node does not map onto face {}", fid.0 + 1)
                            })?;
                        (p, NodeClass::Face(fid, Some(uv)))
                    }
                };
                out.push(ho.nodes.len() as u32);
                ho.nodes.push(p);
                ho.node_class.push(class);
            }
            out.push(e.ends[1]);
            if let Some(c) = e.curve {
                ho.curve_edge_nodes.extend_from_slice(&out);
                ho.curve_edge_curve.push(c);
            }
            edge_ho.push(out);
            edge_samples.push(samples);
        }
        Ok(EdgeChains {
            nodes: edge_ho,
            samples: edge_samples,
        })
    }

    /// Element `b` before numbering its inner nodes: corners and edge nodes
    /// from `edge_ho` (already in `ho`; `edge_samples` where they lie on
    /// the fine polylines), inner nodes by transfinite interpolation of the
    /// sides in (u, v).
    fn element(
        &self,
        ho: &HighOrderQuadMesh,
        edge_ho: &[Vec<u32>],
        edge_samples: &[Vec<Sample>],
        b: usize,
    ) -> Result<Element, String> {
        let n = self.n;
        let blk = &self.layout.blocks[b];
        let face = &self.model.faces[blk.face.idx()];
        let k1 = n + 1;
        let mut el = Element {
            nodes: vec![None; k1 * k1],
            pos: vec![[0.0; 3]; k1 * k1],
            class: vec![NodeClass::Unclassified; k1 * k1],
            local: vec![
                LocalNode {
                    uv: [0.0; 2],
                    node: NodeRef::Interior,
                    pole: None,
                };
                k1 * k1
            ],
        };
        let mut uv_sides: Vec<Vec<[f64; 2]>> = Vec::with_capacity(4);
        for k in 0..4 {
            let (e, rev) = blk.sides[k];
            let fine_local = self.side_fine(b, k)?;
            let chain = &edge_ho[e as usize];
            let mut nodes = vec![fine_local[0]];
            for (s, &g) in edge_samples[e as usize].iter().zip(&chain[1..n]) {
                let hint = sample_hint(&fine_local, *s);
                nodes.push(resampled_node(face, ho.node_class[g as usize], g, hint));
            }
            nodes.push(fine_local[fine_local.len() - 1]);
            let mut ids = chain.clone();
            if rev {
                nodes.reverse();
                ids.reverse();
            }
            // side k's tensor positions, in block order
            for (t, (&g, l)) in ids.iter().zip(&nodes).enumerate() {
                let (i, j) = match k {
                    0 => (t, 0),
                    1 => (n, t),
                    2 => (n - t, n),
                    _ => (0, n - t),
                };
                let at = i + k1 * j;
                el.nodes[at] = Some(g);
                el.pos[at] = ho.nodes[g as usize];
                el.class[at] = ho.node_class[g as usize];
                el.local[at] = *l;
            }
            uv_sides.push(side_uvs(&nodes));
        }
        let rev_of = |v: &Vec<[f64; 2]>| v.iter().rev().copied().collect::<Vec<_>>();
        let sides = UvSides {
            bottom: uv_sides[0].clone(),
            right: uv_sides[1].clone(),
            top: rev_of(&uv_sides[2]),
            left: rev_of(&uv_sides[3]),
        };
        for j in 1..n {
            for i in 1..n {
                let uv = sides
                    .at(i, j)
                    .ok_or_else(|| format!("block {b}: sides do not match"))?;
                let p = face.surface.eval(uv);
                if !p.iter().chain(uv.iter()).all(|x| x.is_finite()) {
                    return Err(format!(
                        "block {b}: an inner node is off face {}",
                        blk.face.0 + 1
                    ));
                }
                el.set_inner(i + k1 * j, blk.face, uv, p);
            }
        }
        Ok(el)
    }

    /// Replaces the inner nodes of element `b` by the transfinite
    /// interpolation of its sides in 3D, projected onto the face from their
    /// present (u, v) (spec §5.6's reading; near a pole, where the (u, v)
    /// interpolation crowds the nodes, it keeps them apart). A node that
    /// cannot be projected keeps its place.
    fn project_tfi(&self, b: usize, el: &mut Element) {
        let n = self.n;
        let k1 = n + 1;
        let fid = self.layout.blocks[b].face;
        let face = &self.model.faces[fid.idx()];
        let x = |i: usize, j: usize| el.pos[i + k1 * j];
        let (c00, c10, c11, c01) = (x(0, 0), x(n, 0), x(n, n), x(0, n));
        let mut inner = Vec::with_capacity((n - 1) * (n - 1));
        for j in 1..n {
            for i in 1..n {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                let mut p = [0.0; 3];
                for d in 0..3 {
                    p[d] = (1.0 - t) * x(i, 0)[d]
                        + t * x(i, n)[d]
                        + (1.0 - s) * x(0, j)[d]
                        + s * x(n, j)[d]
                        - ((1.0 - s) * (1.0 - t) * c00[d]
                            + s * (1.0 - t) * c10[d]
                            + s * t * c11[d]
                            + (1.0 - s) * t * c01[d]);
                }
                inner.push((i + k1 * j, p));
            }
        }
        for (at, p) in inner {
            if let Some((uv, q)) = onto_face(face, el.local[at].uv, p, self.tol) {
                el.set_inner(at, fid, uv, q);
            }
        }
    }

    /// Resamples the inner nodes of element `b` from its block's fine grid:
    /// node `(i, j)` at grid position `(i w1 / N, j w2 / N)`, bilinear in 3D
    /// and in (u, v) within its cell, projected onto the face. A node that
    /// cannot be projected keeps its place.
    fn resample_inner(&self, b: usize, el: &mut Element) {
        let n = self.n;
        let g = &self.fine.block_grid[b];
        let fid = self.layout.blocks[b].face;
        let face = &self.model.faces[fid.idx()];
        let [w1, w2] = g.size;
        for j in 1..n {
            for i in 1..n {
                let (x, y) = (
                    i as f64 * w1 as f64 / n as f64,
                    j as f64 * w2 as f64 / n as f64,
                );
                let (ci, cj) = (
                    (x.floor() as usize).min(w1 - 1),
                    (y.floor() as usize).min(w2 - 1),
                );
                let (fx, fy) = (x - ci as f64, y - cj as f64);
                let cell = [(ci, cj), (ci + 1, cj), (ci + 1, cj + 1), (ci, cj + 1)];
                let w = [
                    (1.0 - fx) * (1.0 - fy),
                    fx * (1.0 - fy),
                    fx * fy,
                    (1.0 - fx) * fy,
                ];
                let locals = cell.map(|(a, c)| self.local_at(g, a, c));
                let centre = uv_centre(&locals);
                let mut target = [0.0; 3];
                let mut hint = [0.0; 2];
                for c in 0..4 {
                    let (a, d) = cell[c];
                    target = vec3::add(
                        target,
                        vec3::scale(self.fine.mesh.nodes[g.at(a, d) as usize], w[c]),
                    );
                    let uv = locals[c].uv_toward(centre);
                    hint = [hint[0] + w[c] * uv[0], hint[1] + w[c] * uv[1]];
                }
                if let Some((uv, p)) = onto_face(face, hint, target, self.tol) {
                    el.set_inner(i + (n + 1) * j, fid, uv, p);
                }
            }
        }
    }

    /// Element `b`'s smallest over largest det J at its nodes, against the
    /// CAD normals ([`geometry::Face::corner_normal`] toward the element's
    /// (u, v) centre); over the largest `|∂x/∂ξ| |∂x/∂η|` instead when det J
    /// is about zero everywhere (a flat element); −1 when a normal is
    /// undefined.
    fn jacobian_ratio(&self, b: usize, el: &Element, diff: &LagrangeDiff) -> f64 {
        let face = &self.model.faces[self.layout.blocks[b].face.idx()];
        let centre = uv_centre(&el.local);
        let mut normals = Vec::with_capacity(el.local.len());
        for l in &el.local {
            match face.corner_normal(l.corner_uv(), centre) {
                Some(nv) => normals.push(nv),
                None => return -1.0,
            }
        }
        let (dets, scale) = diff.dets(&el.pos, &normals);
        let (lo, hi) = dets
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
                (lo.min(d), hi.max(d))
            });
        if !(lo.is_finite() && hi.is_finite() && scale > 0.0) {
            -1.0
        } else if hi > MIN_JACOBIAN_RATIO * scale {
            lo / hi
        } else {
            // flat everywhere: measured against the element's size
            lo / scale
        }
    }
}

impl Element {
    /// Sets inner node `at` at `uv` / `p` on face `fid`.
    fn set_inner(&mut self, at: usize, fid: geometry::FaceId, uv: [f64; 2], p: Vec3) {
        self.nodes[at] = None;
        self.pos[at] = p;
        self.class[at] = NodeClass::Face(fid, Some(uv));
        self.local[at] = LocalNode {
            uv,
            node: NodeRef::Interior,
            pole: None,
        };
    }
}

/// The mean (u, v) of the nodes that are not poles (of all when all are).
fn uv_centre(nodes: &[LocalNode]) -> [f64; 2] {
    let plain: Vec<[f64; 2]> = nodes
        .iter()
        .filter(|l| l.pole.is_none())
        .map(|l| l.uv)
        .collect();
    let pts: Vec<[f64; 2]> = if plain.is_empty() {
        nodes.iter().map(|l| l.uv).collect()
    } else {
        plain
    };
    let k = pts.len().max(1) as f64;
    let s = pts
        .iter()
        .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
    [s[0] / k, s[1] / k]
}

/// Derivatives of the 1D Lagrange basis on N + 1 equidistant nodes at
/// those nodes: `d[a][i] = L_i'(x_a)`, `x_m = m / N`.
struct LagrangeDiff {
    n: usize,
    d: Vec<f64>,
}

impl LagrangeDiff {
    fn new(n: usize) -> Self {
        let x = |m: usize| m as f64 / n as f64;
        let mut d = vec![0.0; (n + 1) * (n + 1)];
        for a in 0..=n {
            for i in 0..=n {
                d[a * (n + 1) + i] = if a == i {
                    (0..=n)
                        .filter(|&m| m != i)
                        .map(|m| 1.0 / (x(i) - x(m)))
                        .sum()
                } else {
                    let num: f64 = (0..=n)
                        .filter(|&m| m != i && m != a)
                        .map(|m| x(a) - x(m))
                        .product();
                    let den: f64 = (0..=n).filter(|&m| m != i).map(|m| x(i) - x(m)).product();
                    num / den
                };
            }
        }
        LagrangeDiff { n, d }
    }

    /// det J against `normal[k]` at every node `k` of an element with
    /// nodes `x` in tensor order, `(∂x/∂ξ × ∂x/∂η) · n`, and the largest
    /// `|∂x/∂ξ| |∂x/∂η|` (the scale of det J when the sides are square).
    fn dets(&self, x: &[Vec3], normal: &[Vec3]) -> (Vec<f64>, f64) {
        let k1 = self.n + 1;
        let mut out = Vec::with_capacity(k1 * k1);
        let mut scale = 0.0f64;
        for b in 0..k1 {
            for a in 0..k1 {
                let (mut dxi, mut deta) = ([0.0; 3], [0.0; 3]);
                for i in 0..k1 {
                    dxi = vec3::add(dxi, vec3::scale(x[i + k1 * b], self.d[a * k1 + i]));
                    deta = vec3::add(deta, vec3::scale(x[a + k1 * i], self.d[b * k1 + i]));
                }
                out.push(vec3::dot(vec3::cross(dxi, deta), normal[a + k1 * b]));
                scale = scale.max(vec3::norm(dxi) * vec3::norm(deta));
            }
        }
        (out, scale)
    }
}

#[cfg(test)]
mod tests;
