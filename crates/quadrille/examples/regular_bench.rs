//! Benchmark of the regular method on CAD models: baseline mesh (triangle
//! split), then `regularize_mesh`; prints one Markdown row per model.
//!
//! Usage: `cargo run --release -p quadrille --example regular_bench -- [--pictures DIR] FILE...`

use std::path::{Path, PathBuf};
use std::time::Instant;

use mesh::stats::MeshStats;
use quadrille::regularize::{regularize_mesh, RegularizeOptions};
use quadrille::{mesh_model, MeshOptions};

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut pictures: Option<PathBuf> = None;
    if let Some(i) = args.iter().position(|a| a == "--pictures") {
        if i + 1 < args.len() {
            pictures = Some(PathBuf::from(args.remove(i + 1)));
        }
        args.remove(i);
    }
    println!("| model | quads before → after | nodes before → after | irregular interior % before → after | irregular incl. boundary % before → after | inverted quads before → after | invalid (5°,175°) after | min SICN before → after | window reached (median face) | mesh s | regularize s | skipped faces |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for a in &args {
        let path = Path::new(a);
        let name = path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
        let model = match occt::load(path) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | import failed: {e} |");
                continue;
            }
        };
        let t0 = Instant::now();
        let mut mesh = match mesh_model(&model, &MeshOptions::default()) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | baseline mesher failed: {e} |");
                continue;
            }
        };
        let t_mesh = t0.elapsed().as_secs_f64();
        let s0 = MeshStats::compute(&mesh, Some(&model));
        if let Some(dir) = &pictures {
            let _ = std::fs::create_dir_all(dir);
            let title = format!("{name}: triangle split (before)");
            let o = mesh::render::RenderOptions { title: Some(&title), ..Default::default() };
            if let Err(e) = mesh::render::render_png(&mesh, &o, &dir.join(format!("regular_{name}_before.png"))) {
                eprintln!("{name}: picture failed: {e}");
            }
        }
        let t1 = Instant::now();
        let env = |k: &str, d: usize| std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d);
        let d = RegularizeOptions::default();
        let ropts = RegularizeOptions { max_sequence: env("QR_DEPTH", d.max_sequence), search_budget: env("QR_BUDGET", d.search_budget), ..d };
        let rep = match regularize_mesh(&model, &mut mesh, &ropts) {
            Ok(r) => r,
            Err(e) => {
                println!("| {name} | regularization failed: {e} |");
                continue;
            }
        };
        let t_reg = t1.elapsed().as_secs_f64();
        let s1 = MeshStats::compute(&mesh, Some(&model));
        if let Some(dir) = &pictures {
            let title = format!("{name}: regularized (after)");
            let o = mesh::render::RenderOptions { title: Some(&title), ..Default::default() };
            if let Err(e) = mesh::render::render_png(&mesh, &o, &dir.join(format!("regular_{name}_after.png"))) {
                eprintln!("{name}: picture failed: {e}");
            }
        }
        let (ib, ia) = rep.irregular();
        let vb: usize = rep.faces.iter().map(|f| f.verts.0).sum();
        let va: usize = rep.faces.iter().map(|f| f.verts.1).sum();
        let invalid_after = rep.invalid().1;
        let mut wins: Vec<f64> = rep.faces.iter().map(|f| f.window.min_deg).collect();
        wins.sort_by(f64::total_cmp);
        let med = wins.get(wins.len() / 2).copied().unwrap_or(5.0);
        println!(
            "| {name} | {} → {} | {} → {} | {:.1} → {:.1} | {:.1} → {:.1} | {} → {} | {} | {:.3} → {:.3} | ({:.0}°, {:.0}°) | {:.2} | {:.2} | {} |",
            s0.quads,
            s1.quads,
            s0.nodes,
            s1.nodes,
            s0.irregular_percent,
            s1.irregular_percent,
            100.0 * ib as f64 / vb.max(1) as f64,
            100.0 * ia as f64 / va.max(1) as f64,
            s0.inverted_quads,
            s1.inverted_quads,
            invalid_after,
            s0.sicn.min,
            s1.sicn.min,
            med,
            180.0 - med,
            t_mesh,
            t_reg,
            rep.skipped.len()
        );
        if std::env::var("QR_VERBOSE").is_ok() {
            for f in &rep.faces {
                eprintln!("  face {}: quads {:?} verts {:?} irregular {:?} invalid {:?} window {:?} ops {:?}", f.face.0 + 1, f.quads, f.verts, f.irregular, f.invalid, f.window, f.ops);
            }
            eprintln!("  valence histogram after: {:?}", s1.valence_histogram);
        }
        for (f, why) in &rep.skipped {
            eprintln!("{name}: face {} skipped: {why}", f.0 + 1);
        }
        let o = rep.ops();
        eprintln!("{name}: ops swaps {} collapses {} splits {} compositions {} rejected {} sweeps {}", o.swaps, o.collapses, o.splits, o.compositions, o.rejected, o.sweeps);
    }
}
