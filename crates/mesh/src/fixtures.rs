//! Small hand-built classified meshes with their models (a square grid and a
//! cube; a patch of high-order quads over any map), so that tests of
//! statistics, writers and renderers run on exactly known input without a
//! mesher or a CAD file.

use std::collections::HashMap;
use std::sync::Arc;

use geometry::primitives::{square, Line, Line2d, Plane};
use geometry::vec3::{add, dot, lerp, scale, sub, Vec3};
use geometry::{
    Bounds2, Corner, CornerId, CurveEntity, CurveId, CurveUse, Face, FaceId, Loop, Model,
};

use crate::high_order::{HighOrderQuadMesh, MAX_ORDER};
use crate::quadmesh::{NodeClass, QuadMesh};

/// `geometry::primitives::square(side)` meshed by an `n × n` grid of quads
/// (`n ≥ 1`), every node classified with its parameters, the boundary edges
/// as curve edges and the four corners as corner nodes.
pub fn square_grid(side: f64, n: usize) -> (Model, QuadMesh) {
    let n = n.max(1);
    let model = square(side);
    let mut mesh = QuadMesh::default();
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (side * i as f64 / n as f64, side * j as f64 / n as f64);
            mesh.nodes.push([u, v, 0.0]);
            let (bi, bj) = (i == 0 || i == n, j == 0 || j == n);
            let class = match (bi, bj) {
                (true, true) => {
                    let c = match (i == 0, j == 0) {
                        (true, true) => 0,
                        (false, true) => 1,
                        (false, false) => 2,
                        (true, false) => 3,
                    };
                    NodeClass::Corner(CornerId(c))
                }
                // curves: 0 bottom (x increasing), 1 right (y increasing),
                // 2 top (x decreasing), 3 left (y decreasing); t in [0, 1]
                (false, true) if j == 0 => NodeClass::Curve(CurveId(0), Some(u / side)),
                (false, true) => NodeClass::Curve(CurveId(2), Some(1.0 - u / side)),
                (true, false) if i == n => NodeClass::Curve(CurveId(1), Some(v / side)),
                (true, false) => NodeClass::Curve(CurveId(3), Some(1.0 - v / side)),
                (false, false) => NodeClass::Face(FaceId(0), Some([u, v])),
            };
            mesh.node_class.push(class);
        }
    }
    for j in 0..n {
        for i in 0..n {
            mesh.quads
                .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            mesh.quad_face.push(FaceId(0));
        }
    }
    // grouped by curve, each in its direction: the order the MSH writer keeps
    mesh.curve_edges
        .extend((0..n).map(|k| ([id(k, 0), id(k + 1, 0)], CurveId(0))));
    mesh.curve_edges
        .extend((0..n).map(|k| ([id(n, k), id(n, k + 1)], CurveId(1))));
    mesh.curve_edges
        .extend((0..n).map(|k| ([id(n - k, n), id(n - k - 1, n)], CurveId(2))));
    mesh.curve_edges
        .extend((0..n).map(|k| ([id(0, n - k), id(0, n - k - 1)], CurveId(3))));
    mesh.corner_nodes = vec![
        (id(0, 0), CornerId(0)),
        (id(n, 0), CornerId(1)),
        (id(n, n), CornerId(2)),
        (id(0, n), CornerId(3)),
    ];
    (model, mesh)
}

/// Corners of the cube `[0, side]³`, numbered by the bits (x, y, z).
fn cube_corner(side: f64, k: usize) -> Vec3 {
    [
        (k & 1) as f64 * side,
        ((k >> 1) & 1) as f64 * side,
        ((k >> 2) & 1) as f64 * side,
    ]
}

/// The faces of the cube as corner quadruples, counter-clockwise seen from outside.
const CUBE_FACES: [[usize; 4]; 6] = [
    [0, 2, 3, 1], // z = 0
    [4, 5, 7, 6], // z = 1
    [0, 1, 5, 4], // y = 0
    [2, 6, 7, 3], // y = 1
    [0, 4, 6, 2], // x = 0
    [1, 3, 7, 5], // x = 1
];

/// The cube `[0, side]³` as a B-rep solid (8 corners, 12 line curves with
/// t ∈ [0, 1], 6 planar faces with outward normals), meshed by `n × n` quads
/// per face (`n ≥ 1`), every node classified with its parameters.
pub fn cube(side: f64, n: usize) -> (Model, QuadMesh) {
    let n = n.max(1);
    let corners: Vec<Corner> = (0..8)
        .map(|k| Corner {
            point: cube_corner(side, k),
        })
        .collect();
    let mut curve_of: HashMap<(usize, usize), u32> = HashMap::new();
    let mut curves = Vec::new();
    for f in CUBE_FACES {
        for k in 0..4 {
            let (a, b) = (f[k].min(f[(k + 1) % 4]), f[k].max(f[(k + 1) % 4]));
            curve_of.entry((a, b)).or_insert_with(|| {
                let (pa, pb) = (cube_corner(side, a), cube_corner(side, b));
                curves.push(CurveEntity {
                    geom: Some(Arc::new(Line {
                        origin: pa,
                        dir: sub(pb, pa),
                        range: (0.0, 1.0),
                    })),
                    range: (0.0, 1.0),
                    start: CornerId(a as u32),
                    end: CornerId(b as u32),
                    degenerate: false,
                });
                (curves.len() - 1) as u32
            });
        }
    }
    let mut faces = Vec::new();
    for f in CUBE_FACES {
        let o = cube_corner(side, f[0]);
        let xdir = scale(sub(cube_corner(side, f[1]), o), 1.0 / side);
        let ydir = scale(sub(cube_corner(side, f[3]), o), 1.0 / side);
        let uv = |p: Vec3| [dot(sub(p, o), xdir), dot(sub(p, o), ydir)];
        let bounds = Bounds2 {
            umin: 0.0,
            umax: side,
            vmin: 0.0,
            vmax: side,
        };
        let uses = (0..4)
            .map(|k| {
                let (a, b) = (f[k], f[(k + 1) % 4]);
                let forward = a < b;
                let (s, e) = if forward { (a, b) } else { (b, a) };
                let (us, ue) = (uv(cube_corner(side, s)), uv(cube_corner(side, e)));
                CurveUse {
                    curve: CurveId(curve_of[&(s, e)]),
                    forward,
                    pcurve: Arc::new(Line2d {
                        origin: us,
                        dir: [ue[0] - us[0], ue[1] - us[1]],
                    }),
                    seam: false,
                }
            })
            .collect();
        faces.push(Face {
            surface: Arc::new(Plane {
                origin: o,
                xdir,
                ydir,
                bounds,
            }),
            reversed: false,
            loops: vec![Loop { uses, outer: true }],
            uv_bounds: bounds,
        });
    }
    let model = Model {
        corners,
        curves,
        faces,
    };

    // Nodes on the integer lattice of the surface, shared between faces.
    let mut mesh = QuadMesh::default();
    let mut node_of: HashMap<[i64; 3], u32> = HashMap::new();
    let step = side / n as f64;
    let mut node = |mesh: &mut QuadMesh, p: Vec3, fi: usize| -> u32 {
        let key = p.map(|x| (x / step).round() as i64);
        *node_of.entry(key).or_insert_with(|| {
            let on_side: Vec<usize> = (0..3)
                .filter(|&k| key[k] == 0 || key[k] == n as i64)
                .collect();
            let class = match on_side.len() {
                3 => NodeClass::Corner(CornerId(
                    key.iter()
                        .enumerate()
                        .map(|(k, &x)| ((x != 0) as u32) << k)
                        .sum(),
                )),
                2 => {
                    // the free axis is the curve direction; its ends differ only there
                    let free = (0..3).find(|k| !on_side.contains(k)).unwrap_or(0);
                    let base: usize = (0..3)
                        .filter(|&k| k != free && key[k] != 0)
                        .map(|k| 1 << k)
                        .sum();
                    let c = curve_of[&(base, base | (1 << free))];
                    NodeClass::Curve(CurveId(c), Some(p[free] / side))
                }
                _ => {
                    let o = cube_corner(side, CUBE_FACES[fi][0]);
                    let xdir = scale(sub(cube_corner(side, CUBE_FACES[fi][1]), o), 1.0 / side);
                    let ydir = scale(sub(cube_corner(side, CUBE_FACES[fi][3]), o), 1.0 / side);
                    NodeClass::Face(
                        FaceId(fi as u32),
                        Some([dot(sub(p, o), xdir), dot(sub(p, o), ydir)]),
                    )
                }
            };
            mesh.nodes.push(p);
            mesh.node_class.push(class);
            (mesh.nodes.len() - 1) as u32
        })
    };
    for (fi, f) in CUBE_FACES.iter().enumerate() {
        let [a, b, _, d] = f.map(|k| cube_corner(side, k));
        let at = |i: usize, j: usize| {
            add(
                lerp(a, b, i as f64 / n as f64),
                sub(lerp(a, d, j as f64 / n as f64), a),
            )
        };
        let mut ids = vec![vec![0u32; n + 1]; n + 1];
        for (j, row) in ids.iter_mut().enumerate() {
            for (i, slot) in row.iter_mut().enumerate() {
                *slot = node(&mut mesh, at(i, j), fi);
            }
        }
        for j in 0..n {
            for i in 0..n {
                mesh.quads
                    .push([ids[j][i], ids[j][i + 1], ids[j + 1][i + 1], ids[j + 1][i]]);
                mesh.quad_face.push(FaceId(fi as u32));
            }
        }
    }
    for (ci, c) in model.curves.iter().enumerate() {
        let (pa, pb) = (
            model.corners[c.start.idx()].point,
            model.corners[c.end.idx()].point,
        );
        for k in 0..n {
            let key = |t: f64| lerp(pa, pb, t).map(|x| (x / step).round() as i64);
            let e = [
                node_of[&key(k as f64 / n as f64)],
                node_of[&key((k + 1) as f64 / n as f64)],
            ];
            mesh.curve_edges.push((e, CurveId(ci as u32)));
        }
    }
    for (k, c) in model.corners.iter().enumerate() {
        let key = c.point.map(|x| (x / step).round() as i64);
        mesh.corner_nodes.push((node_of[&key], CornerId(k as u32)));
    }
    (model, mesh)
}

/// An `nu × nv` patch of Lagrange quads of `order` (clamped to
/// `1..=MAX_ORDER`) over `(u, v) ∈ [0, nu] × [0, nv]` mapped by `map`,
/// neighbours sharing their edge nodes. Classified like [`square_grid`]: one
/// face 0, curves 0 (v = 0, u rising), 1 (u = nu, v rising), 2 (v = nv, u
/// falling), 3 (u = 0, v falling), corners 0–3 counter-clockwise from
/// (0, 0); nodes keep their `(u, v)` (curve nodes their `u` or `v`) as
/// parameters. Node `(a, b)` of the global `(N nu + 1) × (N nv + 1)` grid has
/// index `a + (N nu + 1) b`.
pub fn high_order_patch(
    order: usize,
    nu: usize,
    nv: usize,
    map: impl Fn(f64, f64) -> Vec3,
) -> HighOrderQuadMesh {
    let n = order.clamp(1, MAX_ORDER);
    let (nu, nv) = (nu.max(1), nv.max(1));
    let (gu, gv) = (n * nu, n * nv);
    let id = |a: usize, b: usize| (a + (gu + 1) * b) as u32;
    let mut mesh = HighOrderQuadMesh {
        order: n,
        ..Default::default()
    };
    for b in 0..=gv {
        for a in 0..=gu {
            let (u, v) = (a as f64 / n as f64, b as f64 / n as f64);
            mesh.nodes.push(map(u, v));
            let (ends_u, ends_v) = (a == 0 || a == gu, b == 0 || b == gv);
            mesh.node_class.push(match (ends_u, ends_v) {
                (true, true) => NodeClass::Corner(CornerId(match (a == 0, b == 0) {
                    (true, true) => 0,
                    (false, true) => 1,
                    (false, false) => 2,
                    (true, false) => 3,
                })),
                (false, true) => NodeClass::Curve(CurveId(if b == 0 { 0 } else { 2 }), Some(u)),
                (true, false) => NodeClass::Curve(CurveId(if a == 0 { 3 } else { 1 }), Some(v)),
                (false, false) => NodeClass::Face(FaceId(0), Some([u, v])),
            });
        }
    }
    for eb in 0..nv {
        for ea in 0..nu {
            for j in 0..=n {
                for i in 0..=n {
                    mesh.element_nodes.push(id(ea * n + i, eb * n + j));
                }
            }
            mesh.element_face.push(FaceId(0));
        }
    }
    let mut edge = |curve: u32, nodes: Vec<u32>| {
        mesh.curve_edge_nodes.extend(nodes);
        mesh.curve_edge_curve.push(CurveId(curve));
    };
    for e in 0..nu {
        edge(0, (0..=n).map(|k| id(e * n + k, 0)).collect());
    }
    for e in 0..nv {
        edge(1, (0..=n).map(|k| id(gu, e * n + k)).collect());
    }
    for e in 0..nu {
        edge(2, (0..=n).map(|k| id(gu - e * n - k, gv)).collect());
    }
    for e in 0..nv {
        edge(3, (0..=n).map(|k| id(0, gv - e * n - k)).collect());
    }
    mesh.corner_nodes = vec![
        (id(0, 0), CornerId(0)),
        (id(gu, 0), CornerId(1)),
        (id(gu, gv), CornerId(2)),
        (id(0, gv), CornerId(3)),
    ];
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::MeshStats;

    #[test]
    fn cube_is_closed_and_classified() {
        let (model, mesh) = cube(2.0, 3);
        model.validate().unwrap();
        assert_eq!(mesh.nodes.len(), 6 * 4 + 12 * 2 + 8);
        assert_eq!(mesh.quads.len(), 54);
        assert_eq!(mesh.curve_edges.len(), 36);
        let s = MeshStats::compute(&mesh, Some(&model));
        assert_eq!(s.open_edges, 0);
        assert_eq!(s.non_manifold_edges, 0);
        assert_eq!(s.euler_characteristic, 2);
        assert_eq!(s.inverted_quads, 0, "{s}");
        assert!((s.sicn.min - 1.0).abs() < 1e-12, "{s}");
        assert!(s.cad_distance.unwrap().max < 1e-12);
        assert_eq!(s.face_interior_nodes, 24);
        assert_eq!(s.irregular_nodes, 0);
        // the mesh normals agree with the CAD ones
        let s2 = MeshStats::compute(&mesh, None);
        assert_eq!(s2.inverted_quads, 0);
        assert!((s2.sicn.min - 1.0).abs() < 1e-12);
        // every corner node has valence 3 and curve node 4
        let val = mesh.node_valences();
        for (v, c) in mesh.node_class.iter().enumerate() {
            match c {
                NodeClass::Corner(_) => assert_eq!(val[v], 3),
                _ => assert_eq!(val[v], 4),
            }
        }
    }

    #[test]
    fn square_grid_curve_parameters_match_geometry() {
        let (model, mesh) = square_grid(3.0, 4);
        for (p, c) in mesh.nodes.iter().zip(&mesh.node_class) {
            if let NodeClass::Curve(c, Some(t)) = c {
                let q = model.curves[c.idx()].eval(&model, *t);
                assert!(geometry::vec3::dist(*p, q) < 1e-12);
            }
        }
        for ([a, b], c) in &mesh.curve_edges {
            for v in [a, b] {
                match mesh.node_class[*v as usize] {
                    NodeClass::Curve(cc, _) => assert_eq!(cc, *c),
                    NodeClass::Corner(_) => {}
                    ref other => panic!("curve edge node classified {other:?}"),
                }
            }
        }
    }
}
