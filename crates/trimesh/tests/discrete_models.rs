//! Triangle meshes generated in code (box, cylinder, sphere, torus, open
//! sheet) imported as discrete B-reps: faces, curves, seams, the
//! parametrization of every face, the consistency of pcurves with curves and
//! surfaces, and errors for what cannot be imported.

use std::path::Path;
use std::sync::Arc;

use geometry::vec3::{self, Vec3};
use geometry::{Curve, Model};
use trimesh::{Format, Options, Shape};

type Mesh = (Vec<Vec3>, Vec<[u32; 3]>);

/// Adds a grid patch `origin + i/n·a + j/m·b` (triangles counter-clockwise
/// seen from `a × b`).
fn grid_patch(mesh: &mut Mesh, origin: Vec3, a: Vec3, b: Vec3, n: usize, m: usize) {
    let base = mesh.0.len() as u32;
    for j in 0..=m {
        for i in 0..=n {
            let p = vec3::add(
                origin,
                vec3::add(
                    vec3::scale(a, i as f64 / n as f64),
                    vec3::scale(b, j as f64 / m as f64),
                ),
            );
            mesh.0.push(p);
        }
    }
    let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
    for j in 0..m {
        for i in 0..n {
            mesh.1.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            mesh.1.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
}

/// A box [0,2]×[0,1]×[0,1.5], each face a grid (vertices duplicated between faces: welding joins them).
fn box_mesh(n: usize) -> Mesh {
    let mut m = (Vec::new(), Vec::new());
    let (x, y, z) = ([2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.5]);
    let o = [0.0; 3];
    grid_patch(&mut m, o, y, x, n, n); // bottom, normal -z
    grid_patch(&mut m, z, x, y, n, n); // top, +z
    grid_patch(&mut m, o, x, z, n, n); // front, -y
    grid_patch(&mut m, y, z, x, n, n); // back, +y
    grid_patch(&mut m, o, z, y, n, n); // left, -x
    grid_patch(&mut m, x, y, z, n, n); // right, +x
    m
}

/// A closed cylinder of radius 1 and height 2: `k` segments around, `h` rows
/// on the side, `r` rings on each cap.
fn cylinder_mesh(k: usize, h: usize, r: usize) -> Mesh {
    let mut p = Vec::new();
    let mut t = Vec::new();
    let ring = |rad: f64, z: f64, p: &mut Vec<Vec3>| -> u32 {
        let b = p.len() as u32;
        for i in 0..k {
            let a = i as f64 / k as f64 * std::f64::consts::TAU;
            p.push([rad * a.cos(), rad * a.sin(), z]);
        }
        b
    };
    let side: Vec<u32> = (0..=h)
        .map(|j| ring(1.0, 2.0 * j as f64 / h as f64, &mut p))
        .collect();
    for j in 0..h {
        for i in 0..k {
            let (a, b) = (side[j] + i as u32, side[j] + ((i + 1) % k) as u32);
            let (c, d) = (side[j + 1] + ((i + 1) % k) as u32, side[j + 1] + i as u32);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    for (z, up) in [(0.0, false), (2.0, true)] {
        let mut rings: Vec<u32> = (1..=r)
            .map(|q| ring(q as f64 / r as f64, z, &mut p))
            .collect();
        let c = p.len() as u32;
        p.push([0.0, 0.0, z]);
        rings.insert(0, c);
        let mut push = |tri: [u32; 3]| t.push(if up { tri } else { [tri[0], tri[2], tri[1]] });
        for i in 0..k {
            push([c, rings[1] + i as u32, rings[1] + ((i + 1) % k) as u32]);
        }
        for q in 1..r {
            for i in 0..k {
                let (a, b) = (rings[q] + i as u32, rings[q] + ((i + 1) % k) as u32);
                let (cc, d) = (rings[q + 1] + ((i + 1) % k) as u32, rings[q + 1] + i as u32);
                push([a, d, cc]);
                push([a, cc, b]);
            }
        }
    }
    (p, t)
}

/// A UV sphere of radius 1 (`k` meridians, `l` parallels).
fn sphere_mesh(k: usize, l: usize) -> Mesh {
    let mut p = vec![[0.0, 0.0, -1.0]];
    for j in 1..l {
        let th = std::f64::consts::PI * j as f64 / l as f64 - std::f64::consts::FRAC_PI_2;
        for i in 0..k {
            let a = std::f64::consts::TAU * i as f64 / k as f64;
            p.push([th.cos() * a.cos(), th.cos() * a.sin(), th.sin()]);
        }
    }
    p.push([0.0, 0.0, 1.0]);
    let top = p.len() as u32 - 1;
    let id = |j: usize, i: usize| 1 + ((j - 1) * k + i % k) as u32;
    let mut t = Vec::new();
    for i in 0..k {
        t.push([0, id(1, i + 1), id(1, i)]);
        t.push([top, id(l - 1, i), id(l - 1, i + 1)]);
    }
    for j in 1..l - 1 {
        for i in 0..k {
            t.push([id(j, i), id(j, i + 1), id(j + 1, i + 1)]);
            t.push([id(j, i), id(j + 1, i + 1), id(j + 1, i)]);
        }
    }
    (p, t)
}

/// A torus (major radius 2, minor 0.7).
fn torus_mesh(k: usize, l: usize) -> Mesh {
    let mut p = Vec::new();
    for j in 0..l {
        let b = std::f64::consts::TAU * j as f64 / l as f64;
        for i in 0..k {
            let a = std::f64::consts::TAU * i as f64 / k as f64;
            let r = 2.0 + 0.7 * b.cos();
            p.push([r * a.cos(), r * a.sin(), 0.7 * b.sin()]);
        }
    }
    let id = |j: usize, i: usize| ((j % l) * k + i % k) as u32;
    let mut t = Vec::new();
    for j in 0..l {
        for i in 0..k {
            t.push([id(j, i), id(j, i + 1), id(j + 1, i + 1)]);
            t.push([id(j, i), id(j + 1, i + 1), id(j + 1, i)]);
        }
    }
    (p, t)
}

fn import(m: &Mesh, opts: &Options) -> Result<trimesh::Import, trimesh::TrimeshError> {
    let bytes = trimesh::read::write_stl_binary(&m.0, &m.1);
    let soup = trimesh::read::read_bytes(&bytes, Format::Stl, Path::new("generated.stl"))?;
    trimesh::build(soup, opts, Path::new("generated.stl"))
}

/// Checks the model conventions on a discrete model: uses meet in (u, v),
/// the outer loop is counter-clockwise, `S(pcurve(t)) = C(t)`, projection
/// returns the point, every face's map has no flipped triangle.
fn check_model(imp: &trimesh::Import) {
    let model: &Model = &imp.model;
    let diag = model.diagonal();
    let tol = 1e-9 * diag;
    for r in &imp.report.faces {
        assert!(r.min_uv_area > 0.0, "flipped triangle: {r:?}");
    }
    for (fi, f) in model.faces.iter().enumerate() {
        assert!(f.loops[0].outer && f.loops.iter().skip(1).all(|l| !l.outer));
        for (li, lp) in f.loops.iter().enumerate() {
            for (k, u) in lp.uses.iter().enumerate() {
                let c = &model.curves[u.curve.idx()];
                let geom = c.geom.as_ref().unwrap();
                let (t0, t1) = c.range;
                for s in 0..=20 {
                    let t = t0 + (t1 - t0) * s as f64 / 20.0;
                    let uv = u.pcurve.eval(t);
                    let d = vec3::dist(f.surface.eval(uv), geom.eval(t));
                    assert!(
                        d < tol,
                        "face {fi} curve {}: S(pcurve(t)) is {d} from C(t)",
                        u.curve.0
                    );
                }
                let next = &lp.uses[(k + 1) % lp.uses.len()];
                let nc = &model.curves[next.curve.idx()];
                let end = u.pcurve.eval(if u.forward { c.range.1 } else { c.range.0 });
                let start = next
                    .pcurve
                    .eval(if next.forward { nc.range.0 } else { nc.range.1 });
                assert!(
                    ((end[0] - start[0]).powi(2) + (end[1] - start[1]).powi(2)).sqrt() < tol,
                    "face {fi}: uses {k} and {} do not meet",
                    k + 1
                );
                assert_eq!(
                    u.seam,
                    lp.uses.iter().filter(|v| v.curve == u.curve).count() == 2
                );
            }
            let poly = model.loop_uv_polyline(geometry::FaceId(fi as u32), li, 64);
            let a = geometry::model::signed_area(&poly);
            assert!(
                if li == 0 { a > 0.0 } else { a < 0.0 },
                "face {fi} loop {li}: signed area {a}"
            );
        }
        // projection of surface points returns them
        let b = f.uv_bounds;
        let uv = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
        let p = f.surface.eval(uv);
        let (uv2, q) = f.surface.project(p, None).unwrap();
        assert!(vec3::dist(p, q) < tol && vec3::dist(f.surface.eval(uv2), p) < tol);
    }
    // every curve used by one or two faces (closed input): never dangling
    for (c, faces) in model.curve_faces().iter().enumerate() {
        assert!(!faces.is_empty(), "curve {c} is used by no face");
    }
}

#[test]
fn box_gives_6_faces_12_curves_8_corners() {
    let imp = import(&box_mesh(4), &Options::default()).unwrap();
    let m = &imp.model;
    assert_eq!((m.faces.len(), m.curves.len(), m.corners.len()), (6, 12, 8));
    // flat faces are projected onto their plane
    assert!(imp.report.faces.iter().all(|f| f.shape == Shape::Plane));
    assert!(m.curve_faces().iter().all(|f| f.len() == 2));
    // welding joined the duplicated edge vertices: 6·25 points → 8 + 12·3 + 6·9
    assert_eq!(imp.report.vertices, 8 + 12 * 3 + 6 * 9);
    check_model(&imp);
    // the straight curves keep their lengths
    let mut lens: Vec<f64> = m.curves.iter().map(|c| c.range.1).collect();
    lens.sort_by(f64::total_cmp);
    assert!(
        (lens[0] - 1.0).abs() < 1e-12 && (lens[11] - 2.0).abs() < 1e-12,
        "{lens:?}"
    );
}

#[test]
fn cylinder_gives_two_discs_and_a_side_with_a_seam() {
    let imp = import(&cylinder_mesh(40, 6, 4), &Options::default()).unwrap();
    let m = &imp.model;
    assert_eq!(m.faces.len(), 3);
    // two circles and the seam of the side
    assert_eq!(m.curves.len(), 3);
    let closed: Vec<usize> = (0..3)
        .filter(|&c| m.curves[c].start == m.curves[c].end)
        .collect();
    assert_eq!(closed.len(), 2);
    for &c in &closed {
        let len = m.curves[c].range.1;
        assert!(
            (len - std::f64::consts::TAU).abs() < 0.01,
            "circle length {len}"
        );
    }
    let side = m
        .faces
        .iter()
        .position(|f| f.loops[0].uses.len() == 4)
        .expect("a side face with 4 uses");
    assert_eq!(m.faces[side].curve_uses().filter(|u| u.seam).count(), 2);
    // a rectangle: the circles' length by the seam's, in either order
    let Shape::Rectangle(w, h) = imp.report.faces[side].shape else {
        panic!("{:?}", imp.report.faces[side])
    };
    let (w, h) = (w.max(h), w.min(h));
    assert!(
        (w - std::f64::consts::TAU).abs() < 0.01 && (h - 2.0).abs() < 1e-9,
        "{w} × {h}"
    );
    check_model(&imp);
}

#[test]
fn closed_sphere_is_split_into_disk_charts() {
    // cut open along one seam, a sphere's Tutte map spreads lengths too much
    // (scale spread above the bound): it is split into charts instead
    let imp = import(&sphere_mesh(24, 12), &Options::default()).unwrap();
    let m = &imp.model;
    assert_eq!(imp.report.charted_faces, 1);
    assert_eq!(imp.report.charts, m.faces.len());
    // normal cones of ±50° cover the sphere with at least 6 charts
    assert!(
        (6..=20).contains(&m.faces.len()),
        "{} charts",
        m.faces.len()
    );
    // closed: every curve is shared by two faces, no seam
    assert!(m.curve_faces().iter().all(|f| f.len() == 2));
    assert!(m
        .faces
        .iter()
        .all(|f| f.loops.len() == 1 && f.loops[0].uses.iter().all(|u| !u.seam)));
    // Euler: V − E + F = 2 on the chart layout
    assert_eq!(
        m.corners.len() as i64 - m.curves.len() as i64 + m.faces.len() as i64,
        2
    );
    for r in &imp.report.faces {
        assert!(r.scale_spread <= trimesh::MAX_SCALE_SPREAD, "{r:?}");
    }
    check_model(&imp);
}

#[test]
fn feature_angle_and_user_edges_are_honoured() {
    // a box with 120° between its faces would be smooth at 60°: here a cube at 95°
    let imp = import(
        &box_mesh(2),
        &Options {
            feature_angle: 95.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(
        imp.report.patches, 1,
        "no edge is sharper than 95°: one closed patch"
    );
    // no single map flattens a cube's surface: charts, one per flat side
    assert_eq!((imp.report.charted_faces, imp.model.faces.len()), (1, 6));
    check_model(&imp);
    // an open flat sheet, split in two by user feature edges along its middle column
    let mut sheet = (Vec::new(), Vec::new());
    grid_patch(&mut sheet, [0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 4, 4);
    let imp = import(&sheet, &Options::default()).unwrap();
    // one face, its square boundary split at the four 90° corners
    assert_eq!(
        (
            imp.model.faces.len(),
            imp.model.curves.len(),
            imp.model.corners.len()
        ),
        (1, 4, 4)
    );
    // STL numbering: vertex k of facet f is 3f + k + 1; find the middle column's edges
    let bytes = trimesh::read::write_stl_binary(&sheet.0, &sheet.1);
    let soup = trimesh::read::read_bytes(&bytes, Format::Stl, Path::new("s")).unwrap();
    let num = |p: Vec3| soup.points.iter().position(|q| *q == p).unwrap() as u32 + 1;
    let user: Vec<[u32; 2]> = (0..4)
        .map(|j| {
            [
                num([0.5, j as f64 / 4.0, 0.0]),
                num([0.5, (j + 1) as f64 / 4.0, 0.0]),
            ]
        })
        .collect();
    let imp = trimesh::build(
        soup,
        &Options {
            feature_edges: user,
            ..Default::default()
        },
        Path::new("s"),
    )
    .unwrap();
    assert_eq!(imp.model.faces.len(), 2);
    check_model(&imp);
}

#[test]
fn torus_is_split_into_disk_charts() {
    // a face with a handle cannot be cut into one disk by seams between
    // boundary loops: it is split into charts, each a disk
    let imp = import(&torus_mesh(48, 24), &Options::default()).unwrap();
    let m = &imp.model;
    assert_eq!(imp.report.charted_faces, 1);
    assert!(m.faces.len() >= 4, "{} charts", m.faces.len());
    assert!(m.faces.iter().all(|f| f.loops.len() == 1));
    // Euler characteristic of the torus: V − E + F = 0 on the chart layout
    assert_eq!(
        m.corners.len() as i64 - m.curves.len() as i64 + m.faces.len() as i64,
        0
    );
    check_model(&imp);
}

#[test]
fn bad_meshes_give_clear_errors() {
    // non-manifold: three triangles on one edge
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let e = import(
        &(p.clone(), vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]),
        &Options::default(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("non-manifold edge") && e.contains("[0.0, 0.0, 0.0]"),
        "{e}"
    );
    // all degenerate
    let e = import(&(p.clone(), vec![[0, 1, 1]]), &Options::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("degenerate"), "{e}");
    // a degenerate triangle among good ones: dropped with a warning
    let mut b = box_mesh(2);
    b.1.push([0, 0, 1]);
    let imp = import(&b, &Options::default()).unwrap();
    assert_eq!(imp.report.dropped_degenerate, 1);
    assert!(imp.report.warnings.iter().any(|w| w.contains("degenerate")));
    // flipped triangles are reoriented
    let mut b = box_mesh(2);
    b.1[3].swap(1, 2);
    b.1[40].swap(0, 1);
    let imp = import(&b, &Options::default()).unwrap();
    assert_eq!(imp.report.flipped, 2);
    assert_eq!(imp.model.faces.len(), 6);
    // a user edge that is no edge of the mesh
    let e = import(
        &box_mesh(2),
        &Options {
            feature_edges: vec![[1, 1000]],
            ..Default::default()
        },
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("feature edge 1"), "{e}");
}

#[test]
fn obj_and_ply_give_the_same_model_as_stl() {
    let (p, t) = cylinder_mesh(24, 3, 2);
    let mut obj = String::new();
    for q in &p {
        obj += &format!("v {} {} {}\n", q[0], q[1], q[2]);
    }
    for tri in &t {
        obj += &format!("f {} {} {}\n", tri[0] + 1, tri[1] + 1, tri[2] + 1);
    }
    let soup = trimesh::read::read_bytes(obj.as_bytes(), Format::Obj, Path::new("c.obj")).unwrap();
    let a = trimesh::build(soup, &Options::default(), Path::new("c.obj")).unwrap();
    let mut ply = format!("ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n", p.len(), t.len());
    for q in &p {
        ply += &format!("{} {} {}\n", q[0], q[1], q[2]);
    }
    for tri in &t {
        ply += &format!("3 {} {} {}\n", tri[0], tri[1], tri[2]);
    }
    let soup = trimesh::read::read_bytes(ply.as_bytes(), Format::Ply, Path::new("c.ply")).unwrap();
    let b = trimesh::build(soup, &Options::default(), Path::new("c.ply")).unwrap();
    let c = import(&(p, t), &Options::default()).unwrap();
    for m in [&a, &b] {
        assert_eq!(
            (m.model.faces.len(), m.model.curves.len()),
            (c.model.faces.len(), c.model.curves.len())
        );
        check_model(m);
    }
    let _: Option<Arc<dyn Curve>> = None;
}

#[test]
fn msh_triangles_are_read() {
    // a tetrahedron in MSH 2.2 (orientations mixed: the import repairs them)
    let msh = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n\
$Elements\n4\n1 2 2 0 1 1 3 2\n2 2 2 0 1 1 2 4\n3 2 2 0 1 2 3 4\n4 2 2 0 1 1 3 4\n$EndElements\n";
    let soup =
        trimesh::read::read_bytes(msh.as_bytes(), Format::Msh, Path::new("tet.msh")).unwrap();
    assert_eq!(soup.tris.len(), 4);
    let imp = trimesh::build(soup, &Options::default(), Path::new("tet.msh")).unwrap();
    assert_eq!(
        (
            imp.model.faces.len(),
            imp.model.curves.len(),
            imp.model.corners.len()
        ),
        (4, 6, 4)
    );
    assert_eq!(imp.report.flipped, 1);
    check_model(&imp);
}
