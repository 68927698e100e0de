//! Linear views of a high-order mesh, for the renderer and the linear file
//! writers: each element evaluated on a grid ([`HighOrderQuadMesh::tessellate`]),
//! or its corners alone ([`HighOrderQuadMesh::to_linear_corners`]).

use std::collections::HashMap;

use geometry::{CurveId, Vec3};

use super::jacobian::lagrange_basis;
use super::{HighOrderError, HighOrderQuadMesh, MAX_SUBDIVISION};
use crate::quadmesh::{NodeClass, QuadMesh};
use crate::render::{Overlay, OverlaySegment};

/// A high-order mesh drawn with linear quads: what
/// [`HighOrderQuadMesh::tessellate`] returns.
#[derive(Clone, Debug, Default)]
pub struct Tessellation {
    /// `sub × sub` quads per element, counter-clockwise like the element,
    /// sharing their nodes along element edges. Element corners keep their
    /// node's classification; points inside an element edge are on its CAD
    /// curve when the edge is a curve edge, else on the element's face (no
    /// parameters); curve edges and corner nodes follow the high-order ones.
    pub mesh: QuadMesh,
    /// The element of each quad of `mesh`.
    pub quad_element: Vec<u32>,
    /// Every element edge once, as `sub` segments along the curved edge: the
    /// block edges to draw over the picture ([`Tessellation::edge_overlay`]).
    pub element_edges: Vec<[Vec3; 2]>,
}

impl Tessellation {
    /// The element edges as an [`Overlay`] of `color` (no legend), to draw
    /// the block edges over a picture of [`Self::mesh`].
    pub fn edge_overlay(&self, color: [u8; 3]) -> Overlay {
        Overlay {
            segments: self
                .element_edges
                .iter()
                .map(|&[a, b]| OverlaySegment {
                    a,
                    b,
                    color,
                    normal: None,
                })
                .collect(),
            ..Default::default()
        }
    }
}

/// The tensor positions `(i, j)` of element edge `k` (0: bottom, 1: right,
/// 2: top, 3: left), walked counter-clockwise, for `t = 0..=n`.
fn edge_position(k: usize, t: usize, n: usize) -> (usize, usize) {
    match k {
        0 => (t, 0),
        1 => (n, t),
        2 => (n - t, n),
        _ => (0, n - t),
    }
}

/// The nodes of an edge in a direction both elements agree on (the smaller
/// of the two node sequences), and whether that reverses `seq`.
fn canonical(seq: Vec<u32>) -> (Vec<u32>, bool) {
    let rev: Vec<u32> = seq.iter().rev().copied().collect();
    if rev < seq {
        (rev, true)
    } else {
        (seq, false)
    }
}

impl HighOrderQuadMesh {
    /// Evaluates every element on a `(sub + 1) × (sub + 1)` grid of
    /// reference points (Lagrange interpolation) and returns the linear quad
    /// mesh of those points and the element edges as segments (see
    /// [`Tessellation`]). `sub` is 1..=[`MAX_SUBDIVISION`]; 1 gives the corners.
    pub fn tessellate(&self, sub: usize) -> Result<Tessellation, HighOrderError> {
        self.validate()?;
        if !(1..=MAX_SUBDIVISION).contains(&sub) {
            return Err(HighOrderError::BadSubdivision(sub));
        }
        let n = self.order;
        let basis: Vec<Vec<f64>> = (0..=sub)
            .map(|s| lagrange_basis(n, s as f64 / sub as f64).map(|b| b.0))
            .collect::<Result<_, _>>()?;
        let curve_of: HashMap<Vec<u32>, CurveId> = (0..self.num_curve_edges())
            .map(|k| {
                (
                    canonical(self.curve_edge(k).to_vec()).0,
                    self.curve_edge_curve[k],
                )
            })
            .collect();
        let mut out = Tessellation::default();
        let mesh = &mut out.mesh;
        let mut corner_map: HashMap<u32, u32> = HashMap::new();
        // canonical edge → tessellation nodes inside it, canonical direction
        let mut edge_map: HashMap<Vec<u32>, Vec<u32>> = HashMap::new();
        let g = sub + 1;
        for e in 0..self.num_elements() {
            let elem = self.element(e);
            let face = self.element_face[e];
            let eval = |a: usize, b: usize| {
                let mut p = [0.0; 3];
                for j in 0..=n {
                    for i in 0..=n {
                        let w = basis[a][i] * basis[b][j];
                        let x = self.nodes[elem[i + (n + 1) * j] as usize];
                        for c in 0..3 {
                            p[c] += w * x[c];
                        }
                    }
                }
                p
            };
            let mut local = vec![0u32; g * g];
            for (a, b, i, j) in [
                (0, 0, 0, 0),
                (sub, 0, n, 0),
                (sub, sub, n, n),
                (0, sub, 0, n),
            ] {
                let v = elem[i + (n + 1) * j];
                local[a + g * b] = *corner_map.entry(v).or_insert_with(|| {
                    mesh.nodes.push(self.nodes[v as usize]);
                    mesh.node_class.push(self.node_class[v as usize]);
                    (mesh.nodes.len() - 1) as u32
                });
            }
            for k in 0..4 {
                let seq = (0..=n)
                    .map(|t| {
                        let (i, j) = edge_position(k, t, n);
                        elem[i + (n + 1) * j]
                    })
                    .collect();
                let (key, reversed) = canonical(seq);
                let along = |s: usize| if reversed { sub - s } else { s };
                if !edge_map.contains_key(&key) {
                    let class = match curve_of.get(&key) {
                        Some(&c) => NodeClass::Curve(c, None),
                        None => NodeClass::Face(face, None),
                    };
                    let points: Vec<Vec3> = (0..=sub)
                        .map(|s| {
                            let (a, b) = edge_position(k, along(s), sub);
                            eval(a, b)
                        })
                        .collect();
                    out.element_edges
                        .extend(points.windows(2).map(|w| [w[0], w[1]]));
                    let ids = points[1..sub]
                        .iter()
                        .map(|&p| {
                            mesh.nodes.push(p);
                            mesh.node_class.push(class);
                            (mesh.nodes.len() - 1) as u32
                        })
                        .collect();
                    edge_map.insert(key.clone(), ids);
                }
                let ids = &edge_map[&key];
                for s in 1..sub {
                    let (a, b) = edge_position(k, s, sub);
                    local[a + g * b] = ids[along(s) - 1];
                }
            }
            for b in 1..sub {
                for a in 1..sub {
                    mesh.nodes.push(eval(a, b));
                    mesh.node_class.push(NodeClass::Face(face, None));
                    local[a + g * b] = (mesh.nodes.len() - 1) as u32;
                }
            }
            for b in 0..sub {
                for a in 0..sub {
                    let at = |a: usize, b: usize| local[a + g * b];
                    mesh.quads
                        .push([at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)]);
                    mesh.quad_face.push(face);
                    out.quad_element.push(e as u32);
                }
            }
        }
        // curve edges that are element edges, sub segments each, in their direction
        for k in 0..self.num_curve_edges() {
            let seq = self.curve_edge(k);
            let (key, reversed) = canonical(seq.to_vec());
            let Some(inner) = edge_map.get(&key) else {
                continue;
            };
            let (first, last) = (corner_map[&key[0]], corner_map[&key[n]]);
            let mut chain: Vec<u32> = std::iter::once(first)
                .chain(inner.iter().copied())
                .chain(std::iter::once(last))
                .collect();
            if reversed {
                chain.reverse();
            }
            let c = self.curve_edge_curve[k];
            mesh.curve_edges
                .extend(chain.windows(2).map(|w| ([w[0], w[1]], c)));
        }
        mesh.corner_nodes = self
            .corner_nodes
            .iter()
            .filter_map(|(v, c)| corner_map.get(v).map(|&t| (t, *c)))
            .collect();
        Ok(out)
    }

    /// The order-1 view: a [`QuadMesh`] of the element corners (nodes
    /// renumbered in increasing index, keeping their classification), the
    /// curve edges from end to end, and the corner nodes that are element
    /// corners.
    pub fn to_linear_corners(&self) -> Result<QuadMesh, HighOrderError> {
        self.validate()?;
        let mut new_index = vec![u32::MAX; self.nodes.len()];
        for e in 0..self.num_elements() {
            for v in self.corners(e) {
                new_index[v as usize] = 0;
            }
        }
        let mut mesh = QuadMesh::default();
        for (v, slot) in new_index.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = mesh.nodes.len() as u32;
                mesh.nodes.push(self.nodes[v]);
                mesh.node_class.push(self.node_class[v]);
            }
        }
        let map = |v: u32| Some(new_index[v as usize]).filter(|&t| t != u32::MAX);
        for e in 0..self.num_elements() {
            mesh.quads
                .push(self.corners(e).map(|v| new_index[v as usize]));
            mesh.quad_face.push(self.element_face[e]);
        }
        for k in 0..self.num_curve_edges() {
            let seq = self.curve_edge(k);
            if let (Some(a), Some(b)) = (map(seq[0]), map(seq[self.order])) {
                mesh.curve_edges.push(([a, b], self.curve_edge_curve[k]));
            }
        }
        mesh.corner_nodes = self
            .corner_nodes
            .iter()
            .filter_map(|&(v, c)| map(v).map(|t| (t, c)))
            .collect();
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::vec3::{dist, norm};
    use geometry::{CornerId, FaceId};

    use crate::fixtures::high_order_patch;

    /// A quarter of the unit cylinder around z, 3 × 2 elements.
    fn cylinder(order: usize) -> HighOrderQuadMesh {
        high_order_patch(order, 3, 2, |u, v| {
            let a = u * std::f64::consts::FRAC_PI_2 / 3.0;
            [a.cos(), a.sin(), 0.5 * v]
        })
    }

    #[test]
    fn tessellation_shares_nodes_and_follows_the_curved_elements() {
        let ho = cylinder(4);
        let sub = 5;
        let t = ho.tessellate(sub).unwrap();
        // a (3·5 + 1) × (2·5 + 1) grid of points, shared along element edges
        assert_eq!(t.mesh.nodes.len(), 16 * 11);
        assert_eq!(t.mesh.quads.len(), 6 * 25);
        assert_eq!(t.quad_element.len(), 150);
        assert_eq!(t.quad_element[26], 1);
        // the distinct element edges: 3 · 3 horizontal and 4 · 2 vertical, 5 segments each
        assert_eq!(t.element_edges.len(), (9 + 8) * sub);
        // every point is close to the cylinder (order-4 interpolation of a circle)
        for p in &t.mesh.nodes {
            let r = norm([p[0], p[1], 0.0]);
            assert!((r - 1.0).abs() < 1e-5, "{p:?} at radius {r}");
        }
        for [a, b] in &t.element_edges {
            assert!(dist(*a, *b) > 0.0 && dist(*a, *b) < 0.15);
        }
        // boundary: 2·(15 + 10) curve segments; curves 0 and 2 have 15 each
        assert_eq!(t.mesh.curve_edges.len(), 50);
        let on = |c: u32| t.mesh.curve_edges.iter().filter(|e| e.1 .0 == c).count();
        assert_eq!([on(0), on(1), on(2), on(3)], [15, 10, 15, 10]);
        for ([a, b], c) in &t.mesh.curve_edges {
            for v in [a, b] {
                let class = t.mesh.node_class[*v as usize];
                assert!(
                    matches!(class, NodeClass::Curve(k, _) if k == *c)
                        || matches!(class, NodeClass::Corner(_)),
                    "{class:?} on curve {c:?}"
                );
            }
        }
        // curve edges run in the direction of the high-order ones: curve 0 along +u
        let ([a, b], _) = t.mesh.curve_edges[0];
        assert_eq!(t.mesh.nodes[a as usize], [1.0, 0.0, 0.0]);
        assert!(t.mesh.nodes[b as usize][1] > 0.0);
        assert_eq!(t.mesh.corner_nodes.len(), 4);
        assert_eq!(t.mesh.corner_nodes[2].1, CornerId(2));
        // quads keep the elements' orientation: outward normals (x, y, 0)
        for q in &t.mesh.quads {
            let p: Vec<Vec3> = q.iter().map(|&v| t.mesh.nodes[v as usize]).collect();
            let n = geometry::vec3::cross(
                geometry::vec3::sub(p[1], p[0]),
                geometry::vec3::sub(p[3], p[0]),
            );
            assert!(n[0] * p[0][0] + n[1] * p[0][1] > 0.0);
        }
        let faces = t
            .mesh
            .node_class
            .iter()
            .filter(|c| matches!(c, NodeClass::Face(FaceId(0), None)))
            .count();
        // inside the patch: 14 × 9 points, of which 2 are element corners (with parameters)
        assert_eq!(faces, 14 * 9 - 2);
        // a tessellation of 1 is the corner view
        let one = ho.tessellate(1).unwrap();
        let corners = ho.to_linear_corners().unwrap();
        assert_eq!(one.mesh.nodes.len(), corners.nodes.len());
        assert_eq!(one.mesh.quads.len(), corners.quads.len());
        assert_eq!(one.element_edges.len(), 17);
    }

    #[test]
    fn block_edges_draw_over_the_tessellated_picture() {
        use crate::render::{render_image, RenderOptions};
        let t = cylinder(3).tessellate(6).unwrap();
        let overlay = t.edge_overlay([255, 0, 0]);
        assert_eq!(overlay.segments.len(), t.element_edges.len());
        let opts = RenderOptions {
            width: 240,
            height: 240,
            eye_dir: [1.0, 1.0, 0.3],
            show_info: false,
            show_edges: false,
            ..Default::default()
        };
        let plain = render_image(&t.mesh, &opts).unwrap();
        let with = render_image(
            &t.mesh,
            &RenderOptions {
                overlay: Some(&overlay),
                ..opts
            },
        )
        .unwrap();
        let red = |img: &crate::render::RenderedImage| {
            img.rgba
                .chunks(4)
                .filter(|p| p[0] > 200 && p[1] < 60 && p[2] < 60)
                .count()
        };
        assert_eq!(red(&plain), 0);
        assert!(red(&with) > 200, "{} red pixels", red(&with));
    }

    #[test]
    fn corner_view_keeps_classification_and_curves() {
        let ho = cylinder(3);
        let m = ho.to_linear_corners().unwrap();
        assert_eq!(m.nodes.len(), 4 * 3);
        assert_eq!(m.quads.len(), 6);
        assert_eq!(m.quads[0], [0, 1, 5, 4]);
        // the first element's corners are the high-order nodes (0,0), (3,0), (3,3), (0,3)
        assert_eq!(m.nodes[5], ho.nodes[ho.node_at(0, 3, 3) as usize]);
        assert_eq!(m.node_class[1], ho.node_class[3]);
        assert_eq!(m.curve_edges.len(), ho.num_curve_edges());
        assert_eq!(m.curve_edges[0], ([0, 1], CurveId(0)));
        assert_eq!(m.corner_nodes.len(), 4);
        assert!(crate::vtu::check_mesh(&m).is_ok());
    }

    #[test]
    fn bad_requests_are_refused() {
        let ho = cylinder(2);
        assert_eq!(
            ho.tessellate(0).unwrap_err(),
            HighOrderError::BadSubdivision(0)
        );
        assert!(ho.tessellate(MAX_SUBDIVISION + 1).is_err());
        let mut broken = ho.clone();
        broken.element_nodes.truncate(5);
        assert!(matches!(
            broken.tessellate(3),
            Err(HighOrderError::Length { .. })
        ));
        assert!(matches!(
            broken.to_linear_corners(),
            Err(HighOrderError::Length { .. })
        ));
    }
}
