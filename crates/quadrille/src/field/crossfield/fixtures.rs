//! Synthetic face triangulations for tests and benchmarks of the cross-field
//! stages: a convex polygon (square, triangle, wedge, …), a disk bounded by one
//! circle, an annulus, a UV sphere with seam and pole copies, and a closed torus.
//! Every builder returns a consistently oriented [`FaceMesh`] (counter-clockwise
//! about the outward / +z normal) with its vertex classification.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use geometry::{CornerId, CurveId};

use super::{FaceMesh, VertexClass};

fn key(p: [f64; 3]) -> [u64; 3] {
    // +0.0 and −0.0 are the same point
    [
        (p[0] + 0.0).to_bits(),
        (p[1] + 0.0).to_bits(),
        (p[2] + 0.0).to_bits(),
    ]
}

/// A convex polygon in the z = 0 plane (vertices counter-clockwise), split
/// into a fan around its centroid, each fan triangle subdivided `n × n`.
/// Polygon vertex `k` is `Corner(k)`, side `k` (from vertex k to k+1) is `Curve(k)`.
pub fn convex_polygon(corners: &[[f64; 2]], n: usize) -> FaceMesh {
    let m = corners.len();
    let n = n.max(1);
    let c = [
        corners.iter().map(|p| p[0]).sum::<f64>() / m as f64,
        corners.iter().map(|p| p[1]).sum::<f64>() / m as f64,
    ];
    let mut mesh = FaceMesh::default();
    let mut ids: BTreeMap<[u64; 3], u32> = BTreeMap::new();
    for k in 0..m {
        let (b, d) = (corners[k], corners[(k + 1) % m]);
        let mut local = vec![vec![0u32; n + 1]; n + 1];
        for i in 0..=n {
            for j in 0..=n - i {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                let p = [
                    c[0] + (b[0] - c[0]) * s + (d[0] - c[0]) * t,
                    c[1] + (b[1] - c[1]) * s + (d[1] - c[1]) * t,
                    0.0,
                ];
                let class = if i + j < n {
                    VertexClass::Interior
                } else if i == n {
                    VertexClass::Corner(CornerId(k as u32))
                } else if j == n {
                    VertexClass::Corner(CornerId(((k + 1) % m) as u32))
                } else {
                    VertexClass::Curve(CurveId(k as u32))
                };
                let id = *ids.entry(key(p)).or_insert_with(|| {
                    mesh.uv.push([p[0], p[1]]);
                    mesh.xyz.push(p);
                    mesh.vertex_class.push(class);
                    (mesh.xyz.len() - 1) as u32
                });
                local[i][j] = id;
            }
        }
        for i in 0..n {
            for j in 0..n - i {
                mesh.triangles
                    .push([local[i][j], local[i + 1][j], local[i][j + 1]]);
                if i + j + 1 < n {
                    mesh.triangles
                        .push([local[i + 1][j], local[i + 1][j + 1], local[i][j + 1]]);
                }
            }
        }
    }
    mesh
}

/// The square `[0, side]²` as an `n × n` grid of cells, each split in two
/// triangles (diagonals alternating). Corners 0..3 counter-clockwise from the
/// origin; sides 0..3 bottom, right, top, left.
pub fn square_grid(side: f64, n: usize) -> FaceMesh {
    let n = n.max(1);
    let mut mesh = FaceMesh::default();
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..=n {
        for i in 0..=n {
            let p = [side * i as f64 / n as f64, side * j as f64 / n as f64, 0.0];
            let class = match (i, j) {
                (0, 0) => VertexClass::Corner(CornerId(0)),
                (x, 0) if x == n => VertexClass::Corner(CornerId(1)),
                (x, y) if x == n && y == n => VertexClass::Corner(CornerId(2)),
                (0, y) if y == n => VertexClass::Corner(CornerId(3)),
                (_, 0) => VertexClass::Curve(CurveId(0)),
                (x, _) if x == n => VertexClass::Curve(CurveId(1)),
                (_, y) if y == n => VertexClass::Curve(CurveId(2)),
                (0, _) => VertexClass::Curve(CurveId(3)),
                _ => VertexClass::Interior,
            };
            mesh.uv.push([p[0], p[1]]);
            mesh.xyz.push(p);
            mesh.vertex_class.push(class);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                mesh.triangles.push([a, b, c]);
                mesh.triangles.push([a, c, d]);
            } else {
                mesh.triangles.push([a, b, d]);
                mesh.triangles.push([b, c, d]);
            }
        }
    }
    mesh
}

/// Stitches two concentric closed rings (vertex ids with their angles, both
/// starting at angle 0) with triangles, counter-clockwise.
fn zipper(inner: &[u32], outer: &[u32], tris: &mut Vec<[u32; 3]>) {
    let (a, b) = (inner.len(), outer.len());
    let (mut i, mut j) = (0usize, 0usize);
    while i < a || j < b {
        let next_in = (i + 1) as f64 / a as f64;
        let next_out = (j + 1) as f64 / b as f64;
        if j < b && (i == a || next_out <= next_in) {
            tris.push([inner[i % a], outer[j % b], outer[(j + 1) % b]]);
            j += 1;
        } else {
            tris.push([inner[i % a], outer[j % b], inner[(i + 1) % a]]);
            i += 1;
        }
    }
}

/// The unit disk triangulated by `rings` concentric rings (ring k has 6k
/// vertices): `6·rings²` nearly equilateral triangles. The circle is
/// `Curve(0)`; its vertex at angle 0 is `Corner(0)`.
pub fn disk(rings: usize) -> FaceMesh {
    let rings = rings.max(1);
    let mut mesh = FaceMesh::default();
    mesh.uv.push([0.0, 0.0]);
    mesh.xyz.push([0.0, 0.0, 0.0]);
    mesh.vertex_class.push(VertexClass::Interior);
    let mut prev = vec![0u32];
    for k in 1..=rings {
        let r = k as f64 / rings as f64;
        let cnt = 6 * k;
        let mut ring = Vec::with_capacity(cnt);
        for m in 0..cnt {
            let a = 2.0 * PI * m as f64 / cnt as f64;
            let p = [r * a.cos(), r * a.sin(), 0.0];
            let class = if k < rings {
                VertexClass::Interior
            } else if m == 0 {
                VertexClass::Corner(CornerId(0))
            } else {
                VertexClass::Curve(CurveId(0))
            };
            ring.push(mesh.xyz.len() as u32);
            mesh.uv.push([p[0], p[1]]);
            mesh.xyz.push(p);
            mesh.vertex_class.push(class);
        }
        if k == 1 {
            for m in 0..cnt {
                mesh.triangles.push([0, ring[m], ring[(m + 1) % cnt]]);
            }
        } else {
            zipper(&prev, &ring, &mut mesh.triangles);
        }
        prev = ring;
    }
    mesh
}

/// The planar annulus `r0 ≤ r ≤ r1` with `nr` rings of cells (radii in
/// geometric progression, so cells stay nearly square) and `nt` cells around.
/// Inner circle `Curve(0)` with `Corner(0)`, outer circle `Curve(1)` with `Corner(1)`.
pub fn annulus(r0: f64, r1: f64, nr: usize, nt: usize) -> FaceMesh {
    let (nr, nt) = (nr.max(1), nt.max(3));
    let mut mesh = FaceMesh::default();
    let id = |i: usize, j: usize| (i * nt + j % nt) as u32;
    for i in 0..=nr {
        let r = r0 * (r1 / r0).powf(i as f64 / nr as f64);
        for j in 0..nt {
            let a = 2.0 * PI * j as f64 / nt as f64;
            let p = [r * a.cos(), r * a.sin(), 0.0];
            let class = match (i, j) {
                (0, 0) => VertexClass::Corner(CornerId(0)),
                (0, _) => VertexClass::Curve(CurveId(0)),
                (x, 0) if x == nr => VertexClass::Corner(CornerId(1)),
                (x, _) if x == nr => VertexClass::Curve(CurveId(1)),
                _ => VertexClass::Interior,
            };
            mesh.uv.push([p[0], p[1]]);
            mesh.xyz.push(p);
            mesh.vertex_class.push(class);
        }
    }
    for i in 0..nr {
        for j in 0..nt {
            let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
            if (i + j) % 2 == 0 {
                mesh.triangles.push([a, b, c]);
                mesh.triangles.push([a, c, d]);
            } else {
                mesh.triangles.push([a, b, d]);
                mesh.triangles.push([b, c, d]);
            }
        }
    }
    mesh
}

/// The sphere of radius `r` as a CAD-like periodic face: a UV grid with
/// `nu` cells around and `nv` from pole to pole, the seam column duplicated
/// (`Curve(0)`) and each pole row made of `nu + 1` copies of the pole
/// (`Corner(0)`, `Corner(1)`). After welding it is a closed surface (χ = 2).
pub fn uv_sphere(r: f64, nu: usize, nv: usize) -> FaceMesh {
    let (nu, nv) = (nu.max(3), nv.max(2));
    let mut mesh = FaceMesh::default();
    let id = |i: usize, j: usize| (i * (nu + 1) + j) as u32;
    for i in 0..=nv {
        let v = -PI / 2.0 + PI * i as f64 / nv as f64;
        for j in 0..=nu {
            let u = 2.0 * PI * j as f64 / nu as f64;
            let p = if i == 0 {
                [0.0, 0.0, -r]
            } else if i == nv {
                [0.0, 0.0, r]
            } else {
                [r * v.cos() * u.cos(), r * v.cos() * u.sin(), r * v.sin()]
            };
            let class = if i == 0 {
                VertexClass::Corner(CornerId(0))
            } else if i == nv {
                VertexClass::Corner(CornerId(1))
            } else if j == 0 || j == nu {
                VertexClass::Curve(CurveId(0))
            } else {
                VertexClass::Interior
            };
            mesh.uv.push([u, v]);
            mesh.xyz.push(p);
            mesh.vertex_class.push(class);
        }
    }
    for i in 0..nv {
        for j in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    mesh
}

/// A closed torus (major radius `big_r`, minor `r`) as an `nu × nv` periodic
/// grid, every vertex interior (no boundary, χ = 0).
pub fn torus(big_r: f64, r: f64, nu: usize, nv: usize) -> FaceMesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let mut mesh = FaceMesh::default();
    let id = |i: usize, j: usize| ((i % nv) * nu + j % nu) as u32;
    for i in 0..nv {
        let v = 2.0 * PI * i as f64 / nv as f64;
        for j in 0..nu {
            let u = 2.0 * PI * j as f64 / nu as f64;
            let rr = big_r + r * v.cos();
            mesh.uv.push([u, v]);
            mesh.xyz.push([rr * u.cos(), rr * u.sin(), r * v.sin()]);
            mesh.vertex_class.push(VertexClass::Interior);
        }
    }
    for i in 0..nv {
        for j in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    mesh
}
