//! Quad quality on the CAD: the minimum corner SICN of a quad measured
//! with the face's normals (quasi-structured meshing paper Eq. 12), the
//! normal rule at poles and folds, and a per-node cache of normals.

use geometry::vec3::{self, Vec3};
use geometry::Face;
use mesh::quality::quad_sicn_both_judges;

use crate::core::patch::{LocalNode, NodeRef, QuadPatch};

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
/// normal is undefined), lowered to the element-geometry SICN where that is
/// negative ([`mesh::quality::quad_sicn_both_judges`]): every per-face
/// decision rejects a quad either validity judge calls inverted.
pub fn quad_quality(face: &Face, nodes: &[LocalNode], pos: &[Vec3], q: &[u32; 4]) -> f64 {
    quad_quality_with(face, nodes, pos, q, &[None; 4])
}

/// [`quad_quality`] with some corner normals already known: `known[k]` is
/// used for corner `k` when set (an optimizer moving one node keeps the
/// Worst and average SICN (CAD normals) of `p`'s quads.
pub fn patch_quality(face: &Face, p: &QuadPatch) -> (f64, f64) {
    let mut worst = f64::INFINITY;
    let mut sum = 0.0;
    for q in &p.quads {
        let s = quad_quality(face, &p.nodes, &p.pos, q);
        worst = worst.min(s);
        sum += s;
    }
    (worst, sum / p.quads.len().max(1) as f64)
}

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
    quad_sicn_both_judges(&p, &n)
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
    // the known normals of the face-interior corners (no allocation: this
    // runs for every quad a smoothing sweep measures)
    let mut inner = [[0.0; 3]; 4];
    let mut count = 0;
    for k in (0..4).filter(|&k| !on_curve(k)) {
        if let Some(m) = known[k] {
            inner[count] = m;
            count += 1;
        }
    }
    let interior = &inner[..count];
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
