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

use geometry::vec3::Vec3;
use geometry::Face;

use crate::core::patch::{LocalNode, NodeRef, QuadPatch};
use crate::triangulate::face_triangulation::{centroid_uv, edge_mid_uv, BoundaryMid};

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::quality::{quad_quality, NodeNormals};
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
