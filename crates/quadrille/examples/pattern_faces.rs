//! Which faces of each CAD model a pattern meshes directly
//! ([`quadrille::direct::mesh_face_pattern`], paper §6.1.2): curves
//! planned at the default size, then every face tried. Prints a Markdown
//! table: faces, faces meshed by a pattern (by pattern name), the worst SICN
//! of those meshes, and the reasons the others were not.
//!
//! Run: `cargo run --release -p quadrille --example pattern_faces [dir]` (default `data/cad`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use geometry::FaceId;
use quadrille::core::quad_quality;
use quadrille::curves::{discretize_all, plan_curves};
use quadrille::direct::mesh_face_pattern;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "data/cad".into()));
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(d) => d.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(e) => {
            eprintln!(
                "usage: pattern_faces [folder of CAD models]: {}: {e}",
                dir.display()
            );
            std::process::exit(2);
        }
    };
    files.sort();
    println!("| model | faces | by pattern | patterns | min SICN | not matched (reason: faces) |");
    println!("|---|---:|---:|---|---:|---|");
    let (mut total, mut matched) = (0, 0);
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
        let Ok(model) = occt::load(&path) else {
            continue;
        };
        let h = quadrille::default_size(&model);
        let cms = discretize_all(&model, &plan_curves(&model, h));
        let mut used: BTreeMap<String, usize> = BTreeMap::new();
        let mut why: BTreeMap<String, usize> = BTreeMap::new();
        let mut worst = f64::INFINITY;
        for f in 0..model.faces.len() {
            match mesh_face_pattern(&model, FaceId(f as u32), &cms, true) {
                Ok((p, n)) => {
                    *used.entry(n).or_default() += 1;
                    let face = &model.faces[f];
                    worst = p
                        .quads
                        .iter()
                        .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
                        .fold(worst, f64::min);
                }
                Err(e) => {
                    // the reason without its numbers (`n` for a count)
                    let cut = e.find(['[', '(']).unwrap_or(e.len());
                    let cut = e.find("SICN").map_or(cut, |i| i + 4).min(cut);
                    let key: String = e[..cut]
                        .split_whitespace()
                        .map(|w| {
                            if w.chars().all(|c| c.is_ascii_digit()) {
                                "n"
                            } else {
                                w
                            }
                        })
                        .collect::<Vec<_>>()
                        .join(" ");
                    *why.entry(key).or_default() += 1;
                }
            }
        }
        let n: usize = used.values().sum();
        total += model.faces.len();
        matched += n;
        let fmt = |m: &BTreeMap<String, usize>| {
            m.iter()
                .map(|(k, v)| format!("{k}: {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "| {name} | {} | {n} | {} | {} | {} |",
            model.faces.len(),
            fmt(&used),
            if worst.is_finite() {
                format!("{worst:.3}")
            } else {
                "–".into()
            },
            fmt(&why)
        );
    }
    println!(
        "\n{matched} of {total} faces meshed by a pattern ({:.1} %)",
        100.0 * matched as f64 / total.max(1) as f64
    );
}
