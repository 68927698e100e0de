//! Cone proposal and the core run with cones on CAD shells (issue 31 S2;
//! BENCHMARKS.md "spline cones"): per shell, triangles, χ, the proposed
//! cones, Σ I against 4χ, the Ricci iterations and residual after the
//! cone one-rings are refined, the cut paths' quarter turns and the times.
//!
//! `cargo run --profile pytest -p quadrille --example cones_bench -- FILE FACES [FILE FACES …]`
//! with FACES 1-based and comma-separated (`all`: every face), optionally
//! `FACES@SIZE` for a triangle size other than the diagonal / 72.
//! `--png DIR` first: a picture of each shell (refined) with its cones
//! marked and the cut drawn, `DIR/spline_cones_<file>_<faces>.png`; then
//! `--eye X,Y,Z` for the view direction (default: the renderer's).

use std::time::Instant;

use quadrille::cones::{propose_cones, ConeSummary};
use quadrille::methods::spline::cone_core;
use quadrille::shell::shell_from_model;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let png_dir = if args.first().map(String::as_str) == Some("--png") && args.len() > 1 {
        let d = args[1].clone();
        args.drain(..2);
        Some(std::path::PathBuf::from(d))
    } else {
        None
    };
    let mut eye = None;
    if args.first().map(String::as_str) == Some("--eye") && args.len() > 1 {
        let v: Vec<f64> = args[1].split(',').filter_map(|x| x.parse().ok()).collect();
        if let [x, y, z] = v[..] {
            eye = Some([x, y, z]);
        }
        args.drain(..2);
    }
    println!("| shell | triangles | χ | cones +1 / −1 / other / boundary | Σ I vs 4χ | proposal s | refined triangles | Ricci iterations | max abs(K̄−K) | cut paths | paths with k = 0/1/2/3 | max angle err | core s | refine / ricci / cut / immersion s |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for pair in args.chunks(2) {
        let [file, faces] = pair else {
            eprintln!("usage: FILE FACES …");
            return;
        };
        let model = match occt::load(std::path::Path::new(file)) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{file}: {e}");
                continue;
            }
        };
        let (faces, size) = match faces.split_once('@') {
            Some((f, s)) => (f, s.parse::<f64>().ok()),
            None => (faces.as_str(), None),
        };
        let chosen: Vec<usize> = if faces == "all" {
            Vec::new()
        } else {
            faces
                .split(',')
                .filter_map(|f| f.parse::<usize>().ok())
                .map(|f| f - 1)
                .collect()
        };
        let name = format!(
            "{} faces {faces}",
            std::path::Path::new(file)
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default()
        );
        let shell = match shell_from_model(&model, &chosen, size.unwrap_or(model.diagonal() / 72.0))
        {
            Ok(s) => s,
            Err(e) => {
                println!("| {name} | shell: {e} |");
                continue;
            }
        };
        let topo = match shell.check() {
            Ok(t) => t,
            Err(e) => {
                println!("| {name} | {} | shell: {e} |", shell.triangles.len());
                continue;
            }
        };
        let t0 = Instant::now();
        let cones = match propose_cones(&shell, &topo) {
            Ok(c) => c,
            Err(e) => {
                println!(
                    "| {name} | {} | {} | proposal: {e} |",
                    shell.triangles.len(),
                    topo.euler
                );
                continue;
            }
        };
        let t_prop = t0.elapsed().as_secs_f64();
        let s = ConeSummary::of(&topo, &cones);
        let t1 = Instant::now();
        let core = cone_core(&shell, &topo, &cones);
        let t_core = t1.elapsed().as_secs_f64();
        let head = format!(
            "| {name} | {} | {} | {} / {} / {} / {} | {} vs {} | {t_prop:.2} ",
            shell.triangles.len(),
            topo.euler,
            s.plus,
            s.minus,
            s.other_interior,
            s.boundary,
            s.index_sum(),
            s.needed()
        );
        match core {
            Ok(c) => {
                if let Some(dir) = &png_dir {
                    let stem = std::path::Path::new(file)
                        .file_stem()
                        .map(|f| f.to_string_lossy().into_owned())
                        .unwrap_or_default();
                    let path = dir.join(format!(
                        "spline_cones_{stem}_{}.png",
                        faces.replace(',', "_")
                    ));
                    if let Err(e) = picture(&c, &name, &path, eye) {
                        eprintln!("{}: {e}", path.display());
                    }
                }
                let mut turns = [0usize; 4];
                for t in &c.immersion.transitions {
                    turns[usize::from(t.quarter_turns % 4)] += 1;
                }
                let angle = c
                    .immersion
                    .transitions
                    .iter()
                    .map(|t| t.angle_error)
                    .fold(0.0, f64::max);
                let t = c.times;
                println!(
                    "{head}| {} | {} | {:.1e} | {} | {turns:?} | {angle:.1e} | {t_core:.2} | {:.2} / {:.2} / {:.2} / {:.2} |",
                    c.shell.triangles.len(),
                    c.metric.iterations,
                    c.metric.max_error,
                    c.cut.paths.len(),
                    t.refine,
                    t.ricci,
                    t.cut,
                    t.immersion
                );
            }
            Err(e) => println!("{head}| core: {e} | | | | | | {t_core:.2} | |"),
        }
    }
}

/// The refined shell with its cones (+1 red, −1 blue, −2 and below
/// magenta, boundary corners green) and the cut (orange).
fn picture(
    c: &quadrille::methods::spline::ConeCore,
    name: &str,
    path: &std::path::Path,
    eye: Option<[f64; 3]>,
) -> Result<(), mesh::render::RenderError> {
    use mesh::render::{Overlay, OverlayPoint, OverlaySegment, RenderOptions};
    let mut m = mesh::quadmesh::QuadMesh::default();
    m.nodes = c.shell.vertices.clone();
    m.node_class = vec![mesh::quadmesh::NodeClass::Unclassified; m.nodes.len()];
    for t in &c.shell.triangles {
        m.triangles.push(t.map(|v| v as u32));
        m.triangle_face.push(geometry::FaceId(0));
    }
    let (red, blue, magenta, green, orange) = (
        [220, 30, 30],
        [30, 60, 220],
        [200, 30, 200],
        [20, 150, 60],
        [240, 140, 20],
    );
    let mut overlay = Overlay {
        line_width: 3.0,
        point_radius: 9.0,
        ..Default::default()
    };
    for (e, &[a, b]) in c.topo.edges.iter().enumerate() {
        if c.cut.is_cut[e] {
            overlay.segments.push(OverlaySegment {
                a: c.shell.vertices[a],
                b: c.shell.vertices[b],
                color: orange,
                normal: None,
            });
        }
    }
    for cone in &c.cones {
        let color = if c.topo.on_boundary[cone.vertex] {
            green
        } else if cone.index > 0 {
            red
        } else if cone.index == -1 {
            blue
        } else {
            magenta
        };
        overlay.points.push(OverlayPoint {
            position: c.shell.vertices[cone.vertex],
            color,
        });
    }
    let s = &c.summary;
    overlay.legend = vec![
        (red, format!("+1 interior ({})", s.plus)),
        (blue, format!("-1 interior ({})", s.minus)),
        (magenta, format!("other interior ({})", s.other_interior)),
        (green, format!("boundary corner ({})", s.boundary)),
        (orange, "cut".into()),
    ];
    let title = format!(
        "{name}: cones, sum I = {} = 4 chi (chi = {}), Ricci {} it.",
        s.index_sum(),
        s.euler,
        c.metric.iterations
    );
    let mut opts = RenderOptions {
        title: Some(&title),
        overlay: Some(&overlay),
        show_irregular: false,
        show_info: false,
        ..Default::default()
    };
    if let Some(e) = eye {
        opts.eye_dir = e;
    }
    mesh::render::render_png(&m, &opts, path)
}
