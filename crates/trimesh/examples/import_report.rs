//! Imports triangle-mesh files and prints, per file, what the discrete B-rep
//! holds: faces, curves, corners, seams, the smallest (u, v) triangle area
//! and the stage times.
//!
//! ```sh
//! cargo run --release -p trimesh --example import_report -- part.stl [more.stl ...] [--feature-angle 30]
//! ```

use std::path::PathBuf;

fn main() {
    let mut opts = trimesh::Options::default();
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--feature-angle" {
            opts.feature_angle = args
                .next()
                .and_then(|s| s.parse().ok())
                .expect("--feature-angle DEGREES");
        } else {
            files.push(PathBuf::from(a));
        }
    }
    println!(
        "{:<32} {:>8} {:>6} {:>6} {:>7} {:>5} {:>11} {:>7}",
        "file", "tris", "faces", "curves", "corners", "seams", "min uv area", "time s"
    );
    for f in files {
        match trimesh::load(&f, &opts) {
            Ok(imp) => {
                let r = &imp.report;
                let min = r
                    .faces
                    .iter()
                    .map(|f| f.min_uv_area)
                    .fold(f64::INFINITY, f64::min);
                let seams: usize = r.faces.iter().map(|f| f.seams).sum();
                println!(
                    "{:<32} {:>8} {:>6} {:>6} {:>7} {:>5} {:>11.3e} {:>7.3}",
                    f.file_name().unwrap().to_string_lossy(),
                    r.triangles,
                    imp.model.faces.len(),
                    imp.model.curves.len(),
                    imp.model.corners.len(),
                    seams,
                    min,
                    r.seconds.iter().sum::<f64>()
                );
                for w in &r.warnings {
                    println!("    warning: {w}");
                }
                if std::env::var_os("IMPORT_REPORT_FACES").is_some() {
                    for (i, fr) in r.faces.iter().enumerate() {
                        println!(
                            "    face {:>3}: {:>6} tris, {:?}, {} seams, scale spread {:.2}",
                            i + 1,
                            fr.triangles,
                            fr.shape,
                            fr.seams,
                            fr.scale_spread
                        );
                    }
                }
            }
            Err(e) => println!("{:<32} error: {e}", f.display()),
        }
    }
}
