//! Triangle → 3 quads, with the new nodes placed on the CAD.
//!
//! A triangle `(a, b, c)` with edge midpoints `m_ab, m_bc, m_ca` and centroid
//! `g` becomes the quads `(a, m_ab, g, m_ca)`, `(b, m_bc, g, m_ab)`,
//! `(c, m_ca, g, m_bc)`. Boundary edge midpoints are the odd points of the
//! shared curve meshes (so they lie on the CAD curve and are identical for the
//! neighbouring face); interior midpoints and centroids are evaluated on the
//! surface at their (u, v). Quads are oriented counter-clockwise seen from the
//! oriented face normal.

use crate::core::fast_hash::FastMap;
use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::Face;
use mesh::quality::corner_sicn;

use crate::triangulate::face_triangulation::{
    centroid_uv, edge_mid_uv, BoundaryMid, LocalNode, NodeRef,
};

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
}

/// Splits `tris` (counter-clockwise in (u, v), on `nodes` with 3D positions
/// `pos`) into quads. `boundary_mid` gives the midpoint of boundary edges,
/// keyed by the sorted local pair.
pub fn split_triangles(
    face: &Face,
    nodes: &[LocalNode],
    pos: &[Vec3],
    tris: &[[u32; 3]],
    boundary_mid: &FastMap<(u32, u32), BoundaryMid>,
) -> QuadPatch {
    let mut out = QuadPatch {
        nodes: nodes.to_vec(),
        pos: pos.to_vec(),
        quads: Vec::with_capacity(3 * tris.len()),
        quad_tri: Vec::new(),
    };
    // a pole is keyed by its first local instance so edges to "the same" pole share a midpoint
    let mut pole_canon: HashMap<NodeRef, u32> = HashMap::new();
    for (i, n) in nodes.iter().enumerate() {
        if n.pole.is_some() {
            pole_canon.entry(n.node).or_insert(i as u32);
        }
    }
    let canon = |i: u32| -> u32 {
        let n = &nodes[i as usize];
        if n.pole.is_some() {
            pole_canon.get(&n.node).copied().unwrap_or(i)
        } else {
            i
        }
    };
    let mut mids: FastMap<(u32, u32), u32> = FastMap::default();
    for (ti, t) in tris.iter().enumerate() {
        let mut m = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            if let Some(bm) = boundary_mid.get(&key) {
                let id = *mids.entry(key).or_insert_with(|| {
                    out.nodes.push(bm.node);
                    out.pos.push(bm.pos);
                    (out.nodes.len() - 1) as u32
                });
                m[k] = id;
                continue;
            }
            let (ca, cb) = (canon(a), canon(b));
            let ikey = (ca.min(cb), ca.max(cb));
            m[k] = *mids.entry(ikey).or_insert_with(|| {
                let uv = edge_mid_uv(&nodes[a as usize], &nodes[b as usize]);
                out.nodes.push(LocalNode {
                    uv,
                    node: NodeRef::Interior,
                    pole: None,
                });
                out.pos.push(face.surface.eval(uv));
                (out.nodes.len() - 1) as u32
            });
        }
        // the centre of the quadratic triangle through the vertices and the
        // edge midpoints: follows curved boundary edges (equals the centroid
        // when every edge is straight)
        let c0 = centroid_uv(nodes, *t);
        let mut guv = [0.0, 0.0];
        for k in 0..3 {
            let v = nodes[t[k] as usize].uv_toward(c0);
            let mu = out.nodes[m[k] as usize].uv_toward(c0);
            guv[0] += (4.0 * mu[0] - v[0]) / 9.0;
            guv[1] += (4.0 * mu[1] - v[1]) / 9.0;
        }
        if !(guv[0].is_finite() && guv[1].is_finite()) {
            guv = c0;
        }
        out.nodes.push(LocalNode {
            uv: guv,
            node: NodeRef::Interior,
            pole: None,
        });
        out.pos.push(face.surface.eval(guv));
        let g = (out.nodes.len() - 1) as u32;
        let [a, b, c] = *t;
        let qs = [[a, m[0], g, m[2]], [b, m[1], g, m[0]], [c, m[2], g, m[1]]];
        for q in qs {
            out.quads.push(if face.reversed {
                [q[0], q[3], q[2], q[1]]
            } else {
                q
            });
            out.quad_tri.push(ti as u32);
        }
    }
    out
}

/// Oriented unit normal of the face at node `k` of quad `q`: the CAD normal at
/// the node's (u, v); at a pole (a node on a degenerate curve) or another
/// singular point, the limit normal taken slightly inside the quad, toward its
/// (u, v) centre. One rule with the mesh statistics: [`Face::corner_normal`].
pub fn node_normal(face: &Face, nodes: &[LocalNode], q: &[u32; 4], k: usize) -> Option<Vec3> {
    let n = &nodes[q[k] as usize];
    face.corner_normal(n.corner_uv(), quad_uv_centre(nodes, q))
}

/// (u, v) centre of a quad (poles ignored unless all nodes are poles).
pub fn quad_uv_centre(nodes: &[LocalNode], q: &[u32; 4]) -> [f64; 2] {
    let mut s = [0.0, 0.0];
    let mut k = 0.0;
    for &i in q {
        let n = &nodes[i as usize];
        if n.pole.is_none() {
            s[0] += n.uv[0];
            s[1] += n.uv[1];
            k += 1.0;
        }
    }
    if k == 0.0 {
        return nodes[q[0] as usize].uv;
    }
    [s[0] / k, s[1] / k]
}

/// Minimum corner SICN of quad `q` measured with the CAD normals (−1 when a
/// normal is undefined).
pub fn quad_quality(face: &Face, nodes: &[LocalNode], pos: &[Vec3], q: &[u32; 4]) -> f64 {
    quad_quality_with(face, nodes, pos, q, &[None; 4])
}

/// [`quad_quality`] with some corner normals already known: `known[k]` is
/// used for corner `k` when set (an optimizer moving one node keeps the
/// others' normals instead of evaluating the CAD again).
pub fn quad_quality_with(
    face: &Face,
    nodes: &[LocalNode],
    pos: &[Vec3],
    q: &[u32; 4],
    known: &[Option<Vec3>; 4],
) -> f64 {
    let p = [
        pos[q[0] as usize],
        pos[q[1] as usize],
        pos[q[2] as usize],
        pos[q[3] as usize],
    ];
    let mut n = [[0.0; 3]; 4];
    for (k, nk) in n.iter_mut().enumerate() {
        match known[k].or_else(|| node_normal(face, nodes, q, k)) {
            Some(v) => *nk = v,
            None => {
                // no CAD normal at all: fall back to the quad's own normal
                match vec3::normalize(vec3::cross(vec3::sub(p[2], p[0]), vec3::sub(p[3], p[1]))) {
                    Some(v) => *nk = v,
                    None => return -1.0,
                }
            }
        }
    }
    corner_sicn(&p, &n)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// Cosine of the largest angle between a curve node's normal and the
/// normals at a quad's face-interior corners for which
/// [`keep_unfolded_curve_normals`] keeps the node's own normal (60°).
const UNFOLDED_COS: f64 = 0.5;

/// Corner normals known per node (`known[k]`: the CAD normal at corner
/// `k`'s (u, v), `None` where unknown) made safe for [`quad_quality_with`]:
/// a curve or corner node's normal depends on the quad where the surface
/// folds back inside it ([`Face::corner_normal`]), so it is kept only when
/// the quad has a face-interior corner and every such corner's normal is
/// within 60° of it (the surface does not fold there); otherwise it is
/// dropped and evaluated for the quad. This spares the centre's normal on
/// the quads along every curve; the mesh statistics, which judge the
/// assembled mesh, apply the full rule.
pub fn keep_unfolded_curve_normals(
    nodes: &[LocalNode],
    q: &[u32; 4],
    known: &mut [Option<Vec3>; 4],
) {
    let on_curve = |k: usize| nodes[q[k] as usize].node != NodeRef::Interior;
    if !(0..4).any(on_curve) {
        return;
    }
    let interior: Vec<Vec3> = (0..4)
        .filter(|&k| !on_curve(k))
        .filter_map(|k| known[k])
        .collect();
    for k in (0..4).filter(|&k| on_curve(k)) {
        if let Some(n) = known[k] {
            let unfolded =
                !interior.is_empty() && interior.iter().all(|&m| vec3::dot(n, m) >= UNFOLDED_COS);
            if !unfolded {
                known[k] = None;
            }
        }
    }
}

/// Corner normals of a patch's nodes kept between quality evaluations, so
/// that smoothing, which measures the quads around one moving node again and
/// again, evaluates the CAD once per node and move instead of at every corner
/// of every measured quad. At an ordinary point the corner normal depends on
/// the node's (u, v) alone ([`Face::regular_normal`]); poles and singular
/// points are evaluated per quad, as [`node_normal`] does, and so are
/// curve nodes where the surface may fold inside the quad
/// ([`keep_unfolded_curve_normals`]). Results are bit-identical to
/// [`quad_quality`] wherever it does not fold. Whoever moves a node calls
/// [`NodeNormals::forget`] for it.
pub struct NodeNormals {
    at: Vec<NodeNormal>,
}

/// What [`NodeNormals`] knows of one node.
#[derive(Clone, Copy, Debug)]
pub enum NodeNormal {
    /// Not evaluated since the node last moved.
    Unknown,
    /// An ordinary point: its normal.
    Regular(Vec3),
    /// A pole or singular point: the normal depends on the quad.
    PerQuad,
}

impl NodeNormals {
    /// Nothing known yet for `n` nodes.
    pub fn new(n: usize) -> Self {
        NodeNormals {
            at: vec![NodeNormal::Unknown; n],
        }
    }

    /// What is known of node `i` (to restore it with [`NodeNormals::set`]
    /// when a trial move is undone).
    pub fn get(&self, i: usize) -> NodeNormal {
        self.at[i]
    }

    /// Restores what was known of node `i`.
    pub fn set(&mut self, i: usize, v: NodeNormal) {
        self.at[i] = v;
    }

    /// Node `i` moved: its normal is evaluated again when next needed.
    pub fn forget(&mut self, i: usize) {
        self.at[i] = NodeNormal::Unknown;
    }

    /// [`quad_quality`] of `q`, with the corner normals taken from (and
    /// added to) the cache.
    pub fn quality(&mut self, face: &Face, nodes: &[LocalNode], pos: &[Vec3], q: &[u32; 4]) -> f64 {
        let mut known = [None; 4];
        for (k, slot) in known.iter_mut().enumerate() {
            let j = q[k] as usize;
            // poles: the normal depends on the quad
            if nodes[j].pole.is_some() {
                continue;
            }
            if let NodeNormal::Unknown = self.at[j] {
                self.at[j] = match face.regular_normal(nodes[j].uv) {
                    Some(n) => NodeNormal::Regular(n),
                    None => NodeNormal::PerQuad,
                };
            }
            if let NodeNormal::Regular(n) = self.at[j] {
                *slot = Some(n);
            }
        }
        keep_unfolded_curve_normals(nodes, q, &mut known);
        quad_quality_with(face, nodes, pos, q, &known)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curves::curve_mesh::{discretize_all, plan_curves};
    use crate::triangulate::face_triangulation::FaceTriangulation;
    use geometry::{primitives, FaceId};

    #[test]
    fn a_quad_repeats_a_node_on_one_local_node_or_two_instances_of_one_cad_node() {
        let node = |node: NodeRef, u: f64| LocalNode {
            uv: [u, 0.0],
            node,
            pole: None,
        };
        let corner = NodeRef::Corner(geometry::CornerId(0));
        let p = QuadPatch {
            nodes: vec![
                node(NodeRef::Interior, 0.0),
                node(NodeRef::Interior, 1.0),
                node(NodeRef::Interior, 2.0),
                node(NodeRef::Interior, 3.0),
                // two instances of one CAD corner (the two sides of a seam)
                node(corner, 4.0),
                node(corner, 5.0),
            ],
            ..Default::default()
        };
        assert!(!p.repeats_a_node(&[0, 1, 2, 3]));
        assert!(p.repeats_a_node(&[0, 1, 2, 1]));
        assert!(p.repeats_a_node(&[0, 4, 2, 5]));
        // one instance of the corner with distinct interior nodes is fine
        assert!(!p.repeats_a_node(&[0, 4, 2, 3]));
    }

    #[test]
    fn cached_normals_give_the_same_quality_and_follow_moves() {
        // a cone: ordinary points and an apex (a pole, evaluated per quad)
        let m = primitives::cone(1.0, 1.0);
        let face = &m.faces[0];
        let plan = plan_curves(&m, 0.2);
        let cms = discretize_all(&m, &plan);
        let mut ft = FaceTriangulation::new(&m, FaceId(0), &cms, 0.4).unwrap();
        ft.refine().unwrap();
        let mut p = split_triangles(face, &ft.nodes, &ft.pos, &ft.triangles(), &ft.boundary_mid);
        let mut cache = NodeNormals::new(p.nodes.len());
        let exact = |p: &QuadPatch| {
            p.quads
                .iter()
                .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
                .collect::<Vec<f64>>()
        };
        let cached = |p: &QuadPatch, c: &mut NodeNormals| {
            p.quads
                .iter()
                .map(|q| c.quality(face, &p.nodes, &p.pos, q))
                .collect::<Vec<f64>>()
        };
        // bit-identical, twice (the second time from the cache)
        assert_eq!(cached(&p, &mut cache), exact(&p));
        assert_eq!(cached(&p, &mut cache), exact(&p));
        // move an interior node: stale until forgotten
        let i = (0..p.nodes.len())
            .find(|&i| p.nodes[i].node == NodeRef::Interior && p.nodes[i].pole.is_none())
            .unwrap();
        let uv = [p.nodes[i].uv[0] + 0.05, p.nodes[i].uv[1]];
        p.nodes[i].uv = uv;
        p.pos[i] = face.surface.eval(uv);
        assert_ne!(
            cached(&p, &mut cache),
            exact(&p),
            "the old normal of the moved node is still used"
        );
        cache.forget(i);
        assert_eq!(cached(&p, &mut cache), exact(&p));
    }

    #[test]
    fn square_split_gives_valid_ccw_quads() {
        let m = primitives::square(1.0);
        let plan = plan_curves(&m, 0.1);
        let cms = discretize_all(&m, &plan);
        let mut ft = FaceTriangulation::new(&m, FaceId(0), &cms, 0.2).unwrap();
        ft.refine().unwrap();
        let tris = ft.triangles();
        let p = split_triangles(&m.faces[0], &ft.nodes, &ft.pos, &tris, &ft.boundary_mid);
        assert_eq!(p.quads.len(), 3 * tris.len());
        for q in &p.quads {
            assert!(quad_quality(&m.faces[0], &p.nodes, &p.pos, q) > 0.0);
        }
    }
}
