//! Size map and curve quantization on every CAD model of a folder: for each
//! model, the time of the cross fields with the conformal scalings
//! ([`quadrille::field::model_fields`]), the time of the size map
//! alone ([`quadrille::field::build_size_map`], rebuilt from those fields),
//! the size range relative to the requested size, and the curve edges of the
//! uniform plan against those of the plan quantized on the size map.
//!
//! Run: `cargo run --release -p quadrille --example bench_size_map [dir]`
//! (default `data/cad`). Prints a Markdown table.

use std::path::PathBuf;
use std::time::Instant;

use quadrille::curves::plan_curves;
use quadrille::field::{build_size_map, FaceBackground, SizeMapOptions};
use quadrille::field::{model_fields, FieldOptions};

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "data/cad".into()));
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(d) => d.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(e) => {
            eprintln!(
                "usage: bench_size_map [folder of CAD models]: {}: {e}",
                dir.display()
            );
            std::process::exit(2);
        }
    };
    files.sort();
    println!("| model | faces | background vertices | fields s | size map s | size min / h | size max / h | curve edges uniform | curve edges sized |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for path in files {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if !["step", "stp", "iges", "igs", "brep"].contains(&ext.as_str()) {
            continue;
        }
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let model = match occt::load(&path) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | import failed: {e} |");
                continue;
            }
        };
        let t0 = Instant::now();
        let fields = match model_fields(&model, &FieldOptions::default()) {
            Ok(f) => f,
            Err(e) => {
                println!("| {name} | {e} |");
                continue;
            }
        };
        let t_fields = t0.elapsed().as_secs_f64();
        let inputs: Vec<FaceBackground<'_>> = fields
            .faces
            .iter()
            .filter_map(|r| {
                r.outcome.as_ref().ok().map(|f| FaceBackground {
                    face: r.face,
                    topo: &f.field.topology,
                    refs: &f.refs,
                    scaling: f.scaling.as_deref(),
                    curvature: f.curvature,
                })
            })
            .collect();
        let t1 = Instant::now();
        let map = build_size_map(
            &model,
            &fields.curves,
            &inputs,
            fields.size,
            &SizeMapOptions::default(),
        )
        .expect("default options are valid");
        let t_map = t1.elapsed().as_secs_f64();
        let (lo, hi) = map
            .size
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
        let uniform: usize = plan_curves(&model, fields.size)
            .counts
            .iter()
            .map(|n| 2 * n)
            .sum();
        let sized: usize = fields.curve_plan(&model).counts.iter().map(|n| 2 * n).sum();
        println!(
            "| {name} | {} | {} | {t_fields:.2} | {t_map:.3} | {:.3} | {:.2} | {uniform} | {sized} |",
            model.faces.len(),
            map.graph.len(),
            lo / fields.size,
            hi / fields.size
        );
    }
}
