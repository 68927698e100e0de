//! Defect removal ([`quadrille::topology::remove_defects`]) on the baseline
//! mesher's faces (triangle split: about half the interior vertices have
//! valence 6): per model, interior vertices of valence ≥ 6 or ≤ 2 before and
//! after, irregular interior share, worst SICN, and time.
//!
//! Run: `cargo run --release -p quadrille --example defects_bench [dir]` (default `data/cad`).

use std::path::PathBuf;
use std::time::Instant;

use geometry::FaceId;
use quadrille::core::quad_quality;
use quadrille::core::NodeRef;
use quadrille::core::QuadPatch;
use quadrille::curves::{discretize_all, plan_curves};
use quadrille::methods::mesh_face;
use quadrille::topology::remove_defects;

/// (interior vertices, irregular ones, defects) of a patch.
fn counts(p: &QuadPatch) -> (usize, usize, usize) {
    let mut val = vec![0usize; p.nodes.len()];
    for q in &p.quads {
        for &v in q {
            val[v as usize] += 1;
        }
    }
    let interior: Vec<usize> = (0..p.nodes.len())
        .filter(|&i| p.nodes[i].node == NodeRef::Interior && val[i] > 0)
        .map(|i| val[i])
        .collect();
    (
        interior.len(),
        interior.iter().filter(|&&k| k != 4).count(),
        interior.iter().filter(|&&k| k >= 6 || k <= 2).count(),
    )
}

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "data/cad".into()));
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(d) => d.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(e) => {
            eprintln!(
                "usage: defects_bench [folder of CAD models]: {}: {e}",
                dir.display()
            );
            std::process::exit(2);
        }
    };
    files.sort();
    println!("| model | interior vertices | defects before → after | irregular % before → after | replaced / undone | min SICN before → after | s |");
    println!("|---|---:|---|---|---|---|---:|");
    for path in files {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if !["step", "stp"].contains(&ext.as_str()) {
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
        let (mut n0, mut irr0, mut def0, mut irr1, mut def1, mut rep, mut und) =
            (0, 0, 0, 0, 0, 0, 0);
        let (mut w0, mut w1) = (f64::INFINITY, f64::INFINITY);
        let mut secs = 0.0;
        for f in 0..model.faces.len() {
            let Ok(mut p) = mesh_face(&model, FaceId(f as u32), &cms, 2.0 * h) else {
                continue;
            };
            let face = &model.faces[f];
            let worst = |p: &QuadPatch| {
                p.quads
                    .iter()
                    .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
                    .fold(f64::INFINITY, f64::min)
            };
            let (n, i, d) = counts(&p);
            w0 = w0.min(worst(&p));
            let t = Instant::now();
            let r = remove_defects(face, &mut p);
            secs += t.elapsed().as_secs_f64();
            let (_, i2, d2) = counts(&p);
            w1 = w1.min(worst(&p));
            n0 += n;
            irr0 += i;
            def0 += d;
            irr1 += i2;
            def1 += d2;
            rep += r.replaced;
            und += r.undone;
        }
        let pct = |a: usize| 100.0 * a as f64 / n0.max(1) as f64;
        println!("| {name} | {n0} | {def0} → {def1} | {:.1} → {:.1} | {rep} / {und} | {w0:.3} → {w1:.3} | {secs:.2} |", pct(irr0), pct(irr1));
    }
}
