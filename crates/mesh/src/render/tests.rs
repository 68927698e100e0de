//! Tests of the renderer on hand-built meshes: properties of the pixels, not
//! just "it ran".

use std::collections::HashMap;
use std::f64::consts::TAU;

use geometry::primitives;
use geometry::vec3::{cross, dot, sub, Vec3};
use geometry::{CornerId, CurveId, FaceId, Model};

use super::legend::thousands;
use super::*;
use crate::quadmesh::NodeClass;

/// The unit cube `[0, 1]³` as 6 × n × n quads, outward oriented, with shared
/// nodes classified on corners (8), edges (12) and faces (6), and the cube
/// edges as curve edges.
pub(crate) fn cube_mesh(n: usize) -> QuadMesh {
    let n = n.max(1) as i64;
    let mut mesh = QuadMesh::default();
    let mut ids: HashMap<[i64; 3], u32> = HashMap::new();
    let mut curve_ids: HashMap<Vec<(usize, i64)>, u32> = HashMap::new();
    let on = |c: i64| c == 0 || c == n;
    let mut node = |mesh: &mut QuadMesh, l: [i64; 3], face: u32| -> u32 {
        if let Some(&i) = ids.get(&l) {
            return i;
        }
        let fixed: Vec<(usize, i64)> = (0..3).filter(|&a| on(l[a])).map(|a| (a, l[a])).collect();
        let class = match fixed.len() {
            3 => NodeClass::Corner(CornerId(
                (l[0] / n + 2 * (l[1] / n) + 4 * (l[2] / n)) as u32,
            )),
            2 => {
                let next = curve_ids.len() as u32;
                NodeClass::Curve(CurveId(*curve_ids.entry(fixed).or_insert(next)), None)
            }
            _ => NodeClass::Face(FaceId(face), None),
        };
        let i = mesh.nodes.len() as u32;
        mesh.nodes.push(l.map(|c| c as f64 / n as f64));
        mesh.node_class.push(class);
        ids.insert(l, i);
        i
    };
    for axis in 0..3 {
        for side in [0, n] {
            let face = (2 * axis + (side == n) as usize) as u32;
            let (mut ua, mut va) = ((axis + 1) % 3, (axis + 2) % 3);
            if side == 0 {
                std::mem::swap(&mut ua, &mut va);
            }
            let lat = |i: i64, j: i64| {
                let mut l = [0i64; 3];
                l[axis] = side;
                l[ua] = i;
                l[va] = j;
                l
            };
            for j in 0..n {
                for i in 0..n {
                    let q = [lat(i, j), lat(i + 1, j), lat(i + 1, j + 1), lat(i, j + 1)]
                        .map(|l| node(&mut mesh, l, face));
                    mesh.quads.push(q);
                    mesh.quad_face.push(FaceId(face));
                }
            }
        }
    }
    // cube edges: quad edges whose midpoint lies on two cube faces
    let inv: HashMap<u32, [i64; 3]> = ids.iter().map(|(l, i)| (*i, *l)).collect();
    let mut seen = std::collections::HashSet::new();
    for q in mesh.quads.clone() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let m: Vec<i64> = (0..3).map(|c| inv[&a][c] + inv[&b][c]).collect();
            if m.iter().filter(|&&c| c == 0 || c == 2 * n).count() >= 2
                && seen.insert((a.min(b), a.max(b)))
            {
                mesh.curve_edges.push(([a, b], CurveId(0)));
            }
        }
    }
    mesh
}

/// A planar disk of radius 1 at height `z` around a face-interior centre node
/// of quad valence `k` (k quads `[centre, b2i, b2i+1, b2i+2]`), counter-clockwise seen from +z.
pub(crate) fn star_mesh(k: usize, z: f64, face: u32) -> QuadMesh {
    let mut mesh = QuadMesh::default();
    mesh.nodes.push([0.0, 0.0, z]);
    mesh.node_class.push(NodeClass::Face(FaceId(face), None));
    for j in 0..2 * k {
        let a = TAU * j as f64 / (2 * k) as f64;
        let r = if j % 2 == 1 { 1.0 } else { 0.8 };
        mesh.nodes.push([r * a.cos(), r * a.sin(), z]);
        mesh.node_class.push(NodeClass::Curve(CurveId(face), None));
    }
    for i in 0..k {
        let b = |j: usize| (1 + j % (2 * k)) as u32;
        mesh.quads.push([0, b(2 * i), b(2 * i + 1), b(2 * i + 2)]);
        mesh.quad_face.push(FaceId(face));
    }
    mesh
}

/// Appends `other` to `mesh`.
fn merge(mut mesh: QuadMesh, other: &QuadMesh) -> QuadMesh {
    let off = mesh.nodes.len() as u32;
    mesh.nodes.extend_from_slice(&other.nodes);
    mesh.node_class.extend_from_slice(&other.node_class);
    mesh.quads
        .extend(other.quads.iter().map(|q| q.map(|i| i + off)));
    mesh.quad_face.extend_from_slice(&other.quad_face);
    mesh.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + off)));
    mesh.triangle_face.extend_from_slice(&other.triangle_face);
    mesh
}

/// Orients `q` so its normal agrees with face `f` of `model` at `uv`.
fn oriented(model: &Model, f: usize, uv: [f64; 2], nodes: &[Vec3], q: [u32; 4]) -> [u32; 4] {
    let p = q.map(|i| nodes[i as usize]);
    let n = cross(sub(p[2], p[0]), sub(p[3], p[1]));
    match model.faces[f].normal(uv) {
        Some(fnrm) if dot(n, fnrm) < 0.0 => [q[0], q[3], q[2], q[1]],
        _ => q,
    }
}

/// `geometry::primitives::cylinder(r, h)` sampled into quads: the side as an
/// `nu × nv` grid, each cap as rings around a centre of valence `nu / 2`
/// (so the caps carry irregular vertices of valence nu/2 and 3).
pub(crate) fn cylinder_mesh(r: f64, h: f64, nu: usize, nv: usize, rings: usize) -> QuadMesh {
    let model = primitives::cylinder(r, h);
    let nu = nu.max(4) & !1;
    let mut mesh = QuadMesh::default();
    let side = &model.faces[0].surface;
    let idx = |i: usize, j: usize| (j * nu + i % nu) as u32;
    for j in 0..=nv {
        for i in 0..nu {
            let uv = [TAU * i as f64 / nu as f64, h * j as f64 / nv as f64];
            mesh.nodes.push(side.eval(uv));
            mesh.node_class.push(if j == 0 || j == nv {
                NodeClass::Curve(CurveId((j == nv) as u32), None)
            } else {
                NodeClass::Face(FaceId(0), Some(uv))
            });
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let uv = [
                TAU * (i as f64 + 0.5) / nu as f64,
                h * (j as f64 + 0.5) / nv as f64,
            ];
            let q = oriented(
                &model,
                0,
                uv,
                &mesh.nodes,
                [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)],
            );
            mesh.quads.push(q);
            mesh.quad_face.push(FaceId(0));
        }
    }
    for (f, j) in [(1usize, 0usize), (2, nv)] {
        let plane = &model.faces[f].surface;
        let centre = mesh.nodes.len() as u32;
        mesh.nodes.push(plane.eval([0.0, 0.0]));
        mesh.node_class
            .push(NodeClass::Face(FaceId(f as u32), Some([0.0, 0.0])));
        // ring k (1..rings) at radius r k / rings; the outermost ring is the side's boundary row
        let mut ring_ids: Vec<Vec<u32>> = Vec::new();
        for k in 1..rings {
            let rr = r * k as f64 / rings as f64;
            let start = mesh.nodes.len() as u32;
            for i in 0..nu {
                let a = TAU * i as f64 / nu as f64;
                let uv = [rr * a.cos(), rr * a.sin()];
                mesh.nodes.push(plane.eval(uv));
                mesh.node_class
                    .push(NodeClass::Face(FaceId(f as u32), Some(uv)));
            }
            ring_ids.push((start..start + nu as u32).collect());
        }
        ring_ids.push((0..nu).map(|i| idx(i, j)).collect());
        for i in 0..nu / 2 {
            let ring = &ring_ids[0];
            let q = [centre, ring[2 * i], ring[2 * i + 1], ring[(2 * i + 2) % nu]];
            let q = oriented(&model, f, [0.0, 0.0], &mesh.nodes, q);
            mesh.quads.push(q);
            mesh.quad_face.push(FaceId(f as u32));
        }
        for k in 0..ring_ids.len() - 1 {
            let (a, b) = (&ring_ids[k], &ring_ids[k + 1]);
            for i in 0..nu {
                let q = oriented(
                    &model,
                    f,
                    [0.0, 0.0],
                    &mesh.nodes,
                    [a[i], a[(i + 1) % nu], b[(i + 1) % nu], b[i]],
                );
                mesh.quads.push(q);
                mesh.quad_face.push(FaceId(f as u32));
            }
        }
    }
    for i in 0..nu {
        for j in [0, nv] {
            mesh.curve_edges
                .push(([idx(i, j), idx(i + 1, j)], CurveId((j == nv) as u32)));
        }
    }
    mesh
}

/// `geometry::primitives::sphere(1)` as latitude–longitude quads with
/// triangle fans at the poles.
fn sphere_mesh(nu: usize, nv: usize) -> QuadMesh {
    let model = primitives::sphere(1.0);
    let s = &model.faces[0].surface;
    let mut mesh = QuadMesh::default();
    let lat = |j: usize| -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * j as f64 / nv as f64;
    for j in 1..nv {
        for i in 0..nu {
            let uv = [TAU * i as f64 / nu as f64, lat(j)];
            mesh.nodes.push(s.eval(uv));
            mesh.node_class.push(NodeClass::Face(FaceId(0), Some(uv)));
        }
    }
    let id = |i: usize, j: usize| ((j - 1) * nu + i % nu) as u32;
    for j in 1..nv - 1 {
        for i in 0..nu {
            let q = oriented(
                &model,
                0,
                [TAU * (i as f64 + 0.5) / nu as f64, lat(j) + 0.01],
                &mesh.nodes,
                [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)],
            );
            mesh.quads.push(q);
            mesh.quad_face.push(FaceId(0));
        }
    }
    for (pole, j, sign) in [([0.0, 0.0, -1.0], 1, 1.0), ([0.0, 0.0, 1.0], nv - 1, -1.0)] {
        let p = mesh.nodes.len() as u32;
        mesh.nodes.push(pole);
        mesh.node_class.push(NodeClass::Corner(CornerId(0)));
        for i in 0..nu {
            let t = if sign > 0.0 {
                [p, id(i + 1, j), id(i, j)]
            } else {
                [p, id(i, j), id(i + 1, j)]
            };
            mesh.triangles.push(t);
            mesh.triangle_face.push(FaceId(0));
        }
    }
    mesh
}

fn small(opts: RenderOptions) -> RenderOptions {
    RenderOptions {
        width: 400,
        height: 300,
        ..opts
    }
}

fn at(img: &RenderedImage, p: [f64; 3]) -> [u8; 3] {
    let px = img.pixel(p[0] as u32, p[1] as u32).unwrap();
    [px[0], px[1], px[2]]
}

fn close(a: [u8; 3], b: [f32; 3], tol: f32) -> bool {
    (0..3).all(|i| (a[i] as f32 - b[i]).abs() <= tol)
}

#[test]
fn cube_picture_has_the_size_coverage_shading_and_edges_expected() {
    let mesh = cube_mesh(6);
    let opts = small(RenderOptions::default());
    let img = render_image(&mesh, &opts).unwrap();
    let png = img.encode_png().unwrap();
    let decoded = Pixmap::decode_png(&png).unwrap();
    assert_eq!((decoded.width(), decoded.height()), (400, 300));

    let covered =
        img.rgba.chunks(4).filter(|p| p[..3] != BACKGROUND).count() as f64 / (400.0 * 300.0);
    assert!((0.2..0.75).contains(&covered), "covered fraction {covered}");

    let scene = Scene::new(&mesh, &opts).unwrap();
    let cam = scene.camera;
    // centres of quads on the three visible faces (+x, −y, +z) have their lit colour
    let h = 0.5 / 6.0;
    let mut seen = Vec::new();
    for (centre, normal) in [
        ([1.0, 0.5 + h, 0.5 + h], [1.0, 0.0, 0.0]),
        ([0.5 + h, 0.0, 0.5 + h], [0.0, -1.0, 0.0]),
        ([0.5 + h, 0.5 + h, 1.0], [0.0, 0.0, 1.0]),
    ] {
        let c = at(&img, cam.project(centre));
        let want = cam.shade(Some(normal), FRONT, false);
        assert!(
            close(c, want, 3.0),
            "face {normal:?}: pixel {c:?}, want {want:?}"
        );
        seen.push(c);
    }
    assert!(
        seen[0] != seen[1] && seen[1] != seen[2] && seen[0] != seen[2],
        "faces not told apart: {seen:?}"
    );
    // a point on a mesh edge is much darker than the face around it
    let e = at(&img, cam.project([1.0, 0.5, 0.5 + h]));
    let lum = |c: [u8; 3]| c.iter().map(|&x| x as u32).sum::<u32>();
    assert!(
        4 * lum(e) < 3 * lum(seen[0]),
        "edge pixel {e:?}, face {:?}",
        seen[0]
    );
    // the hidden −x face does not show: the pixel of its centre shows the +x or another front face
    let hidden = at(&img, cam.project([0.0, 0.5 + h, 0.5 + h]));
    assert!(hidden[2] > hidden[0], "back colour visible: {hidden:?}");
}

#[test]
fn irregular_vertices_get_their_valence_colour_where_they_project() {
    for (k, want) in [
        (3usize, valence_color(3)),
        (5, valence_color(5)),
        (6, valence_color(6)),
        (7, valence_color(7)),
    ] {
        let mesh = star_mesh(k, 0.0, 0);
        let opts = small(RenderOptions {
            eye_dir: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            ..RenderOptions::default()
        });
        let img = render_image(&mesh, &opts).unwrap();
        let c = at(
            &img,
            Scene::new(&mesh, &opts)
                .unwrap()
                .camera
                .project(mesh.nodes[0]),
        );
        assert!(
            close(c, want.map(|c| c as f32), 12.0),
            "valence {k}: {c:?}, want {want:?}"
        );
        // turned off: the centre shows the mesh instead
        let off = render_image(
            &mesh,
            &RenderOptions {
                show_irregular: false,
                ..opts.clone()
            },
        )
        .unwrap();
        let c = at(
            &off,
            Scene::new(&mesh, &opts)
                .unwrap()
                .camera
                .project(mesh.nodes[0]),
        );
        assert!(
            !close(c, want.map(|c| c as f32), 40.0),
            "valence {k} dot drawn while turned off"
        );
    }
}

#[test]
fn hidden_irregular_vertices_are_not_drawn() {
    // a valence-5 star at z = 0 under a valence-3 star at z = 1, seen from +z
    let back = star_mesh(5, 0.0, 0);
    let front = star_mesh(3, 1.0, 1);
    let opts = small(RenderOptions {
        eye_dir: [0.0, 0.0, 1.0],
        up: [0.0, 1.0, 0.0],
        show_info: false,
        ..RenderOptions::default()
    });
    let both = merge(back.clone(), &front);
    let img = render_image(&both, &opts).unwrap();
    let red = valence_color(5).map(|c| c as f32);
    let blue = valence_color(3).map(|c| c as f32);
    let pos = Scene::new(&both, &opts)
        .unwrap()
        .camera
        .project([0.0, 0.0, 0.0]);
    assert!(
        close(at(&img, pos), blue, 12.0),
        "front vertex: {:?}",
        at(&img, pos)
    );
    // above the legend line at the bottom, no red dot
    let plot_rows = 300 - 50;
    let reds = img.rgba[..400 * plot_rows * 4]
        .chunks(4)
        .filter(|p| close([p[0], p[1], p[2]], red, 30.0))
        .count();
    assert_eq!(reds, 0, "the hidden valence-5 vertex was drawn");
    // the legend still counts both (its valence-5 swatch is red)
    assert!(img.rgba[400 * plot_rows * 4..].chunks(4).any(|p| close(
        [p[0], p[1], p[2]],
        red,
        30.0
    )));
    assert!(Scene::new(&both, &opts).unwrap().irregular.len() == 2);
}

#[test]
fn quad_values_change_the_colours_and_add_a_colour_bar() {
    let mesh = cube_mesh(4);
    let base = small(RenderOptions {
        show_irregular: false,
        ..RenderOptions::default()
    });
    let plain = render_image(&mesh, &base).unwrap();
    let cam = Scene::new(
        &mesh,
        &RenderOptions {
            quad_values: Some(&vec![1.0; mesh.quads.len()]),
            ..base.clone()
        },
    )
    .unwrap()
    .camera;
    let centre = cam.project([0.5 + 0.125, 0.5 + 0.125, 1.0]);
    let mut colours = Vec::new();
    for v in [1.0, 0.5, 0.0, -0.3] {
        let vals = vec![v; mesh.quads.len()];
        let opts = RenderOptions {
            quad_values: Some(&vals),
            ..base.clone()
        };
        let img = render_image(&mesh, &opts).unwrap();
        let c = at(&img, centre);
        let want = cam.shade(Some([0.0, 0.0, 1.0]), value_color(v), true);
        assert!(close(c, want, 3.0), "value {v}: {c:?}, want {want:?}");
        colours.push(c);
        let differing = img
            .rgba
            .chunks(4)
            .zip(plain.rgba.chunks(4))
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differing > 400 * 300 / 10,
            "value {v}: only {differing} pixels changed"
        );
    }
    assert!(
        colours[0][1] > colours[0][0],
        "1 is green: {:?}",
        colours[0]
    );
    assert!(
        colours[2][0] > colours[2][1] + 60,
        "0 is red: {:?}",
        colours[2]
    );
    assert!(
        colours[3][0] < colours[2][0],
        "negative is darker red: {:?}",
        colours[3]
    );
    let vals = vec![0.5; 3];
    assert!(matches!(
        render_image(
            &mesh,
            &RenderOptions {
                quad_values: Some(&vals),
                ..base
            }
        ),
        Err(RenderError::InvalidOptions(_))
    ));
}

#[test]
fn back_faces_are_darker_and_tinted() {
    let mesh = star_mesh(4, 0.0, 0);
    let top = small(RenderOptions {
        eye_dir: [0.0, 0.0, 1.0],
        up: [0.0, 1.0, 0.0],
        ..RenderOptions::default()
    });
    let bottom = RenderOptions {
        eye_dir: [0.0, 0.0, -1.0],
        ..top.clone()
    };
    let probe = [0.3, 0.3, 0.0];
    let front = at(
        &render_image(&mesh, &top).unwrap(),
        Scene::new(&mesh, &top).unwrap().camera.project(probe),
    );
    let back = at(
        &render_image(&mesh, &bottom).unwrap(),
        Scene::new(&mesh, &bottom).unwrap().camera.project(probe),
    );
    assert!(front[2] > front[0], "front is bluish: {front:?}");
    assert!(back[0] > back[2], "back is brownish: {back:?}");
    let lum = |c: [u8; 3]| c.iter().map(|&x| x as u32).sum::<u32>();
    assert!(
        lum(back) + 60 < lum(front),
        "back {back:?} not darker than front {front:?}"
    );
}

#[test]
fn triangles_and_primitive_surfaces_are_drawn() {
    let sphere = sphere_mesh(24, 12);
    assert!(!sphere.triangles.is_empty());
    let opts = small(RenderOptions::default());
    let img = render_image(&sphere, &opts).unwrap();
    let cam = Scene::new(&sphere, &opts).unwrap().camera;
    // the north-pole fan faces the viewer (from above); a point inside it is shaded, not background
    let c = at(&img, cam.project([0.05, -0.05, 0.9987]));
    assert!(c != BACKGROUND && c[2] > c[0], "pole fan pixel {c:?}");
    let triangles_only = QuadMesh {
        quads: vec![],
        quad_face: vec![],
        ..sphere
    };
    let img = render_image(&triangles_only, &opts).unwrap();
    assert!(img.rgba.chunks(4).filter(|p| p[..3] != BACKGROUND).count() > 200);

    let cyl = cylinder_mesh(1.0, 2.0, 20, 8, 3);
    let img = render_image(&cyl, &opts).unwrap();
    let covered =
        img.rgba.chunks(4).filter(|p| p[..3] != BACKGROUND).count() as f64 / (400.0 * 300.0);
    assert!((0.1..0.7).contains(&covered), "cylinder covers {covered}");
    // the top cap centre (valence 10) is visible from above: a magenta dot
    let c = at(
        &img,
        Scene::new(&cyl, &opts)
            .unwrap()
            .camera
            .project([0.0, 0.0, 2.0]),
    );
    assert!(
        close(c, valence_color(10).map(|c| c as f32), 12.0),
        "cap centre {c:?}"
    );
}

#[test]
fn thousands_groups_digits() {
    assert_eq!(thousands(0), "0");
    assert_eq!(thousands(999), "999");
    assert_eq!(thousands(1000), "1,000");
    assert_eq!(thousands(1234567), "1,234,567");
}

#[test]
fn bad_input_gives_clear_errors() {
    let opts = small(RenderOptions::default());
    assert!(matches!(
        render_image(&QuadMesh::default(), &opts),
        Err(RenderError::EmptyMesh)
    ));
    let mut broken = star_mesh(5, 0.0, 0);
    broken.quads[2][1] = 1000;
    let e = render_image(&broken, &opts).unwrap_err();
    assert!(
        matches!(e, RenderError::InvalidMesh(_)) && e.to_string().contains("quad 2"),
        "{e}"
    );
    let mut nan = star_mesh(5, 0.0, 0);
    nan.nodes[1][0] = f64::INFINITY;
    assert!(matches!(
        render_image(&nan, &opts),
        Err(RenderError::InvalidMesh(_))
    ));
    let mesh = star_mesh(5, 0.0, 0);
    for bad in [
        RenderOptions {
            width: 0,
            ..opts.clone()
        },
        RenderOptions {
            supersample: 9,
            ..opts.clone()
        },
        RenderOptions {
            eye_dir: [0.0; 3],
            ..opts.clone()
        },
        RenderOptions {
            eye_dir: [f64::NAN, 0.0, 1.0],
            ..opts.clone()
        },
    ] {
        assert!(matches!(
            render_image(&mesh, &bad),
            Err(RenderError::InvalidOptions(_))
        ));
    }
    // too many pixels is refused; a big image just loses supersampling
    assert!(matches!(
        render_image(
            &mesh,
            &RenderOptions {
                width: 16000,
                height: 16000,
                ..opts.clone()
            }
        ),
        Err(RenderError::InvalidOptions(_))
    ));
    assert_eq!(
        Scene::new(
            &mesh,
            &RenderOptions {
                width: 6000,
                height: 4000,
                supersample: 4,
                ..opts.clone()
            }
        )
        .unwrap()
        .ss,
        1
    );
    assert_eq!(
        Scene::new(
            &mesh,
            &RenderOptions {
                supersample: 3,
                ..opts.clone()
            }
        )
        .unwrap()
        .ss,
        3
    );
    // up parallel to the view direction still renders
    assert!(render_image(
        &mesh,
        &RenderOptions {
            eye_dir: [0.0, 0.0, 2.0],
            up: [0.0, 0.0, 1.0],
            ..opts.clone()
        }
    )
    .is_ok());
    // a degenerate mesh (all nodes at one point) renders without panicking
    let mut point = star_mesh(5, 0.0, 0);
    point.nodes.iter_mut().for_each(|p| *p = [1.0, 1.0, 1.0]);
    assert!(render_image(&point, &opts).is_ok());
}

#[test]
fn png_file_is_written_atomically() {
    let dir = std::env::temp_dir().join(format!("quadrille-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = cube_mesh(3);
    let opts = RenderOptions {
        width: 320,
        height: 200,
        title: Some("cube.step"),
        ..RenderOptions::default()
    };
    let path = dir.join("cube.png");
    render_png(&mesh, &opts, &path).unwrap();
    let img = Pixmap::decode_png(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!((img.width(), img.height()), (320, 200));
    // unwritable targets: an error naming the file, nothing left behind
    let blocker = dir.join("taken.png");
    std::fs::create_dir_all(blocker.join("x")).unwrap();
    let e = render_png(&mesh, &opts, &blocker).unwrap_err();
    assert!(
        matches!(e, RenderError::Io { .. }) && e.to_string().contains("taken.png"),
        "{e}"
    );
    let e = render_png(&mesh, &opts, &dir.join("missing/m.png")).unwrap_err();
    assert!(e.to_string().contains("m.png"), "{e}");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["cube.png", "taken.png"]);
    // an empty mesh leaves no file either
    assert!(render_png(&QuadMesh::default(), &opts, &dir.join("empty.png")).is_err());
    assert!(!dir.join("empty.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Writes pictures to /tmp for review and prints the time of a large render:
/// `cargo test -p mesh --release render::tests::pictures_for_review -- --ignored --nocapture`.
#[test]
#[ignore]
fn pictures_for_review() {
    let cube = cube_mesh(10);
    render_png(
        &cube,
        &RenderOptions {
            title: Some("cube (6 x 10 x 10)"),
            ..Default::default()
        },
        Path::new("/tmp/quadrille-cube.png"),
    )
    .unwrap();
    let small_opts = RenderOptions {
        width: 480,
        height: 360,
        title: Some("cube 480x360"),
        ..Default::default()
    };
    render_png(
        &cube_mesh(5),
        &small_opts,
        Path::new("/tmp/quadrille-cube-small.png"),
    )
    .unwrap();
    let cyl = cylinder_mesh(1.0, 2.5, 40, 16, 6);
    render_png(
        &cyl,
        &RenderOptions {
            title: Some("cylinder"),
            ..Default::default()
        },
        Path::new("/tmp/quadrille-cylinder.png"),
    )
    .unwrap();
    let sicn: Vec<f64> = (0..cyl.quads.len())
        .map(|i| ((i * 37) % 101) as f64 / 80.0 - 0.1)
        .collect();
    render_png(
        &cyl,
        &RenderOptions {
            title: Some("cylinder, SICN"),
            quad_values: Some(&sicn),
            ..Default::default()
        },
        Path::new("/tmp/quadrille-cylinder-sicn.png"),
    )
    .unwrap();
    let sphere = sphere_mesh(32, 16);
    render_png(
        &sphere,
        &RenderOptions {
            title: Some("sphere"),
            ..Default::default()
        },
        Path::new("/tmp/quadrille-sphere.png"),
    )
    .unwrap();
    let big = cylinder_mesh(1.0, 2.5, 500, 400, 40);
    let t = std::time::Instant::now();
    render_png(
        &big,
        &RenderOptions {
            title: Some("large cylinder"),
            ..Default::default()
        },
        Path::new("/tmp/quadrille-large.png"),
    )
    .unwrap();
    println!(
        "{} quads, {} nodes: rendered and written in {:.2} s",
        big.quads.len(),
        big.nodes.len(),
        t.elapsed().as_secs_f64()
    );
}
