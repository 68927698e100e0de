//! Development aid: meshes each face of a CAD model on its own with the
//! baseline stages and prints per-face timing and results.
//! `cargo run -p quadrille --example baseline_faces -- MODEL [FACTOR]`

use std::time::Instant;

use geometry::FaceId;
use quadrille::curves::{discretize_all, plan_curves};
use quadrille::methods::mesh_face;

/// The baseline method's mesh of `model`.
fn mesh_baseline(
    model: &geometry::Model,
    opts: &quadrille::MeshOptions,
) -> Result<mesh::QuadMesh, quadrille::MeshError> {
    quadrille::mesh_model_with(model, opts, quadrille::MeshMethod::Baseline).map(|(m, _)| m)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: baseline_faces MODEL [FACTOR]");
        std::process::exit(2);
    };
    let factor: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let model = match occt::load(std::path::Path::new(path)) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    if args.get(3).map(String::as_str) == Some("full") {
        let t = Instant::now();
        let opts = quadrille::MeshOptions {
            size: quadrille::Size::Factor(factor),
            threads: Some(1),
            progress: None,
            ..Default::default()
        };
        match mesh_baseline(&model, &opts) {
            Ok(m) => println!(
                "{} quads in {:.2}s",
                m.quads.len(),
                t.elapsed().as_secs_f64()
            ),
            Err(e) => println!("error: {e} ({:.2}s)", t.elapsed().as_secs_f64()),
        }
        return;
    }
    let h = quadrille::default_size(&model) * factor;
    let plan = plan_curves(&model, h);
    let cms = discretize_all(&model, &plan);
    if args.get(3).map(String::as_str) == Some("face") {
        let f: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(0);
        dump(&model, f, &cms, h);
        return;
    }
    for f in 0..model.faces.len() {
        let face = &model.faces[f];
        let t = Instant::now();
        let r = mesh_face(&model, FaceId(f as u32), &cms, 2.0 * h);
        let uses: Vec<String> = face
            .curve_uses()
            .map(|u| {
                format!(
                    "{}{}{}",
                    u.curve.0,
                    if u.forward { "+" } else { "-" },
                    if u.seam { "s" } else { "" }
                )
            })
            .collect();
        match r {
            Ok(p) => println!(
                "face {f}: {} quads {:.3}s  surf {:?} loops {} uses {:?}",
                p.quads.len(),
                t.elapsed().as_secs_f64(),
                face.surface,
                face.loops.len(),
                uses
            ),
            Err(e) => println!(
                "face {f}: FAILED {e:?} {:.3}s surf {:?} uses {:?}",
                t.elapsed().as_secs_f64(),
                face.surface,
                uses
            ),
        }
    }
}

fn dump(model: &geometry::Model, f: usize, cms: &[quadrille::curves::CurveMesh], h: f64) {
    use quadrille::core::quad_quality;
    use quadrille::triangulate::split_triangles;
    use quadrille::triangulate::FaceTriangulation;
    let face = &model.faces[f];
    let b = face.uv_bounds;
    for (i, j) in [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0)] {
        let uv = [
            b.umin + i * (b.umax - b.umin),
            b.vmin + j * (b.vmax - b.vmin),
        ];
        let d = face.surface.derivs(uv);
        println!(
            "uv {uv:?}: p {:?} du {:?} dv {:?} n {:?} reversed {}",
            d.point,
            d.du,
            d.dv,
            face.normal(uv),
            face.reversed
        );
    }
    for l in &face.loops {
        println!("loop outer={} :", l.outer);
        for u in &l.uses {
            let ce = &model.curves[u.curve.idx()];
            let cm = &cms[u.curve.idx()];
            let uvs: Vec<[f64; 2]> = cm.params.iter().map(|&t| u.pcurve.eval(t)).collect();
            println!(
                "  curve {} fwd {} seam {} deg {} n {} uv {:?}",
                u.curve.0, u.forward, u.seam, ce.degenerate, cm.coarse, uvs
            );
        }
    }
    let mut ft = match FaceTriangulation::new(model, geometry::FaceId(f as u32), cms, 2.0 * h) {
        Ok(ft) => ft,
        Err(e) => {
            println!("{e:?}");
            return;
        }
    };
    let _ = ft.refine();
    let tris = ft.triangles();
    let p = split_triangles(face, &ft.nodes, &ft.pos, &tris, &ft.boundary_mid);
    println!("{} triangles, {} quads", tris.len(), p.quads.len());
    for (qi, q) in p.quads.iter().enumerate() {
        let s = quad_quality(face, &p.nodes, &p.pos, q);
        if s <= 0.0 {
            let t = tris[p.quad_tri[qi] as usize];
            println!("bad quad {qi} sicn {s:.3} tri {t:?}");
            for &i in &t {
                println!("   tri node {i}: {:?}", ft.nodes[i as usize]);
            }
            for &i in q {
                let n = &p.nodes[i as usize];
                println!(
                    "   node {i}: uv {:?} {:?} pole {:?} pos {:?} normal {:?}",
                    n.uv,
                    n.node,
                    n.pole.is_some(),
                    p.pos[i as usize],
                    face.normal(n.uv)
                );
            }
        }
    }
}
