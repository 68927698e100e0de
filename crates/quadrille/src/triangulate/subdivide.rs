//! Midpoint subdivision of a quad-dominant mesh into an all-quad mesh, with
//! the new nodes on the CAD (paper §5.2, spec §7.4–7.5).
//!
//! A quad becomes four quads and a triangle three (Catmull–Clark topology):
//! one new node per edge and one per element. Midpoints of edges on CAD
//! curves are the odd points of the shared curve meshes (spec §1.2: on the
//! curve and identical for both faces); the other new nodes are evaluated on
//! the surface at the (u, v) midpoint of their edge, and element centres at
//! the centre of the quadratic element through the corners and edge
//! midpoints (it follows curved boundary edges). Quads are counter-clockwise
//! seen from the oriented face normal.
//!
//! CAD snapping with revert ([`snap_repair`]): every node is already on the
//! surface; where an (u, v) position makes an adjacent quad inverted, the
//! alternative position — the surface point closest to the straight 3D
//! midpoint (or centre) — is tried and kept only when the worst adjacent quad
//! gets better, so a node never makes things worse.

use crate::core::fast_hash::FastMap;
use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::Face;

use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;
use crate::triangulate::face_triangulation::{edge_mid_uv, BoundaryMid};

/// Where a new node of the subdivision came from: the local nodes whose 3D
/// mean is its straight (not snapped) position.
#[derive(Clone, Debug, Default)]
pub struct Origins {
    /// Per new face-interior node (by local id), its source nodes.
    pub sources: HashMap<u32, Vec<u32>>,
}

/// Subdivides `quads` and `tris` (counter-clockwise in (u, v), on `nodes` at
/// 3D positions `pos`). `boundary_mid` gives the midpoint of each boundary
/// edge keyed by its sorted local pair. Element `e` of the output's
/// `quad_tri` numbers the triangles first (`0..tris.len()`), then the quads.
pub fn subdivide(
    face: &Face,
    nodes: &[LocalNode],
    pos: &[Vec3],
    quads: &[[u32; 4]],
    tris: &[[u32; 3]],
    boundary_mid: &FastMap<(u32, u32), BoundaryMid>,
) -> (QuadPatch, Origins) {
    let mut out = QuadPatch {
        nodes: nodes.to_vec(),
        pos: pos.to_vec(),
        quads: Vec::with_capacity(3 * tris.len() + 4 * quads.len()),
        quad_tri: Vec::with_capacity(3 * tris.len() + 4 * quads.len()),
    };
    let mut origins = Origins::default();
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
    let elements = tris
        .iter()
        .map(|t| t.to_vec())
        .chain(quads.iter().map(|q| q.to_vec()));
    for (ei, el) in elements.enumerate() {
        let n = el.len();
        let mut m = Vec::with_capacity(n);
        for k in 0..n {
            let (a, b) = (el[k], el[(k + 1) % n]);
            let key = (a.min(b), a.max(b));
            if let Some(bm) = boundary_mid.get(&key) {
                let id = *mids.entry(key).or_insert_with(|| {
                    out.nodes.push(bm.node);
                    out.pos.push(bm.pos);
                    (out.nodes.len() - 1) as u32
                });
                m.push(id);
                continue;
            }
            let (ca, cb) = (canon(a), canon(b));
            let ikey = (ca.min(cb), ca.max(cb));
            let id = *mids.entry(ikey).or_insert_with(|| {
                let uv = edge_mid_uv(&nodes[a as usize], &nodes[b as usize]);
                out.nodes.push(LocalNode {
                    uv,
                    node: NodeRef::Interior,
                    pole: None,
                });
                out.pos.push(face.surface.eval(uv));
                let id = (out.nodes.len() - 1) as u32;
                origins.sources.insert(id, vec![a, b]);
                id
            });
            m.push(id);
        }
        // centre of the quadratic element (6-node triangle, 8-node serendipity quad)
        let mut c0 = [0.0, 0.0];
        let mut k0 = 0.0;
        for &v in &el {
            if nodes[v as usize].pole.is_none() {
                c0[0] += nodes[v as usize].uv[0];
                c0[1] += nodes[v as usize].uv[1];
                k0 += 1.0;
            }
        }
        if k0 > 0.0 {
            c0 = [c0[0] / k0, c0[1] / k0];
        } else {
            c0 = nodes[el[0] as usize].uv;
        }
        let (wv, wm) = if n == 3 {
            (-1.0 / 9.0, 4.0 / 9.0)
        } else {
            (-0.25, 0.5)
        };
        let mut guv = [0.0, 0.0];
        for k in 0..n {
            let v = nodes[el[k] as usize].uv_toward(c0);
            let mu = out.nodes[m[k] as usize].uv_toward(c0);
            guv[0] += wv * v[0] + wm * mu[0];
            guv[1] += wv * v[1] + wm * mu[1];
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
        origins.sources.insert(g, el.clone());
        for k in 0..n {
            let q = [el[k], m[k], g, m[(k + n - 1) % n]];
            out.quads.push(if face.reversed {
                [q[0], q[3], q[2], q[1]]
            } else {
                q
            });
            out.quad_tri.push(ei as u32);
        }
    }
    (out, origins)
}

/// Tries the alternative CAD position of every new face-interior node that
/// touches a quad with SICN ≤ 0: the surface point closest to its straight
/// 3D position (mean of its sources). The move is kept when the worst quad
/// around the node gets better (the paper's "revert projections that create
/// negative elements", seen from the other side: our default position is
/// already on the CAD). Repeats while something improves (at most `passes`).
/// Returns the number of kept moves.
pub fn snap_repair(face: &Face, p: &mut QuadPatch, origins: &Origins, passes: usize) -> usize {
    let mut quads_of: Vec<Vec<u32>> = vec![Vec::new(); p.nodes.len()];
    for (qi, q) in p.quads.iter().enumerate() {
        for &i in q {
            quads_of[i as usize].push(qi as u32);
        }
    }
    let worst = |p: &QuadPatch, qs: &[u32]| {
        qs.iter()
            .map(|&q| quad_quality(face, &p.nodes, &p.pos, &p.quads[q as usize]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut kept = 0;
    let mut ids: Vec<u32> = origins.sources.keys().copied().collect();
    ids.sort_unstable();
    for _ in 0..passes {
        let mut any = false;
        for &i in &ids {
            let qs = &quads_of[i as usize];
            let before = worst(p, qs);
            if before > 0.0 {
                continue;
            }
            let src = &origins.sources[&i];
            let mut c = [0.0; 3];
            for &s in src {
                c = vec3::add(c, p.pos[s as usize]);
            }
            let c = vec3::scale(c, 1.0 / src.len() as f64);
            let old = (p.nodes[i as usize].uv, p.pos[i as usize]);
            let Some((uv, x)) = face.surface.project(c, Some(old.0)) else {
                continue;
            };
            if !(uv[0].is_finite() && uv[1].is_finite())
                || x.iter().any(|v| !v.is_finite())
                || face.is_singular(uv)
                || face.surface.normal(uv).is_none()
            {
                continue;
            }
            p.nodes[i as usize].uv = uv;
            p.pos[i as usize] = x;
            if worst(p, qs) > before {
                kept += 1;
                any = true;
            } else {
                p.nodes[i as usize].uv = old.0;
                p.pos[i as usize] = old.1;
            }
        }
        if !any {
            break;
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    fn node(u: f64, v: f64) -> LocalNode {
        LocalNode {
            uv: [u, v],
            node: NodeRef::Interior,
            pole: None,
        }
    }

    #[test]
    fn counts_are_3t_plus_4q() {
        let m = primitives::rectangle(3.0, 1.0);
        let face = &m.faces[0];
        // a unit square quad [0,1]² and two triangles on [1,2] × [0,1], plus a quad on [2,3]
        let nodes = vec![
            node(0.0, 0.0),
            node(1.0, 0.0),
            node(2.0, 0.0),
            node(3.0, 0.0),
            node(3.0, 1.0),
            node(2.0, 1.0),
            node(1.0, 1.0),
            node(0.0, 1.0),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| face.surface.eval(n.uv)).collect();
        let quads = [[0, 1, 6, 7], [2, 3, 4, 5]];
        let tris = [[1, 2, 5], [1, 5, 6]];
        let (p, origins) = subdivide(face, &nodes, &pos, &quads, &tris, &FastMap::default());
        assert_eq!(p.quads.len(), 3 * 2 + 4 * 2);
        // new nodes: one per edge (11 distinct edges) and one per element (4)
        assert_eq!(p.nodes.len(), 8 + 11 + 4);
        assert_eq!(origins.sources.len(), 11 + 4);
        for q in &p.quads {
            assert!(quad_quality(face, &p.nodes, &p.pos, q) > 0.2, "{q:?}");
        }
        // the centre of the first square is at (0.5, 0.5), its quads are squares
        for q in &p.quads[6..10] {
            assert!((quad_quality(face, &p.nodes, &p.pos, q) - 1.0).abs() < 1e-9);
        }
        // every interior edge is shared by exactly two quads, boundary edges by one
        let mut count: HashMap<(u32, u32), usize> = HashMap::new();
        for q in &p.quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let boundary = count.values().filter(|&&c| c == 1).count();
        assert_eq!(boundary, 2 * 8, "8 boundary edges split in two");
        assert!(count.values().all(|&c| c <= 2));
    }

    #[test]
    fn snapping_repairs_a_node_only_when_it_helps() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let nodes = vec![
            node(0.0, 0.0),
            node(1.0, 0.0),
            node(1.0, 1.0),
            node(0.0, 1.0),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| face.surface.eval(n.uv)).collect();
        let (mut p, origins) = subdivide(
            face,
            &nodes,
            &pos,
            &[[0, 1, 2, 3]],
            &[],
            &FastMap::default(),
        );
        let before: Vec<Vec3> = p.pos.clone();
        // all valid: nothing moves
        assert_eq!(snap_repair(face, &mut p, &origins, 3), 0);
        assert_eq!(p.pos, before);
        // push the centre outside the square: its quads fold; the repair brings it back
        let g = (p.nodes.len() - 1) as u32;
        p.nodes[g as usize].uv = [1.4, 0.5];
        p.pos[g as usize] = face.surface.eval([1.4, 0.5]);
        assert!(p
            .quads
            .iter()
            .any(|q| quad_quality(face, &p.nodes, &p.pos, q) <= 0.0));
        assert_eq!(snap_repair(face, &mut p, &origins, 3), 1);
        assert!(p
            .quads
            .iter()
            .all(|q| quad_quality(face, &p.nodes, &p.pos, q) > 0.99));
    }
}
