//! Development aid: imports a triangle mesh and meshes each of its faces on
//! its own with the baseline stages, printing per-face time and result (to
//! find the face that is slow or fails).
//!
//! ```sh
//! cargo run --release -p trimesh --example face_timings -- part.stl [FACTOR]
//! ```

use std::time::Instant;

use geometry::FaceId;
use quadrille::curves::{discretize_all, plan_curves};
use quadrille::methods::mesh_face;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: face_timings FILE [FACTOR]");
        std::process::exit(2);
    };
    let factor: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let imp = match trimesh::load(std::path::Path::new(path), &trimesh::Options::default()) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    let model = imp.model;
    if let Some(f) = std::env::var("FACE_DUMP")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        // the (u, v) polylines of face f's loops (1-based), one "loop" line then "u v" lines
        for li in 0..model.faces[f - 1].loops.len() {
            println!("loop {li}");
            for p in model.loop_uv_polyline(FaceId(f as u32 - 1), li, 8) {
                println!("{} {}", p[0], p[1]);
            }
        }
        return;
    }
    let h = quadrille::default_size(&model) * factor;
    let plan = plan_curves(&model, h);
    let cms = discretize_all(&model, &plan);
    for (f, face) in model.faces.iter().enumerate() {
        let t = Instant::now();
        let r = mesh_face(&model, FaceId(f as u32), &cms, 2.0 * h);
        let seams = face.curve_uses().filter(|u| u.seam).count();
        match r {
            Ok(p) => println!(
                "face {}: {} quads {:.3}s loops {} seam uses {}",
                f + 1,
                p.quads.len(),
                t.elapsed().as_secs_f64(),
                face.loops.len(),
                seams
            ),
            Err(e) => println!(
                "face {}: FAILED {e:?} {:.3}s loops {} seam uses {}",
                f + 1,
                t.elapsed().as_secs_f64(),
                face.loops.len(),
                seams
            ),
        }
    }
}
