//! Shared helpers of the integration tests: the bundled CAD models, loaded
//! once, and uv-plane geometry (point in loops, sampling inside a face).
#![allow(dead_code)]

use std::path::PathBuf;
use std::sync::OnceLock;

use geometry::{FaceId, Model};

/// Directory of the bundled CAD models.
pub const CAD_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/cad");

/// Every CAD model of data/cad (sorted by name).
pub fn cad_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(CAD_DIR)
        .expect("data/cad exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| occt::Format::from_path(p).is_some())
        .collect();
    v.sort();
    v
}

/// Every model, imported once per test binary.
pub fn imports() -> &'static Vec<(String, occt::Import)> {
    static CELL: OnceLock<Vec<(String, occt::Import)>> = OnceLock::new();
    CELL.get_or_init(|| {
        cad_files()
            .into_iter()
            .map(|p| {
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                let imp = occt::import(&p).unwrap_or_else(|e| panic!("{e}"));
                (name, imp)
            })
            .collect()
    })
}

/// The uv polylines of every loop of a face (open: last point ≠ first).
pub fn loop_polys(model: &Model, f: usize, samples: usize) -> Vec<Vec<[f64; 2]>> {
    (0..model.faces[f].loops.len())
        .map(|l| model.loop_uv_polyline(FaceId(f as u32), l, samples))
        .collect()
}

/// Even-odd point-in-polygon over all loops.
pub fn inside(polys: &[Vec<[f64; 2]>], p: [f64; 2]) -> bool {
    let mut c = false;
    for poly in polys {
        let n = poly.len();
        for i in 0..n {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    c = !c;
                }
            }
        }
    }
    c
}

/// Distance from `p` to the nearest loop segment.
pub fn dist_to_loops(polys: &[Vec<[f64; 2]>], p: [f64; 2]) -> f64 {
    let mut best = f64::INFINITY;
    for poly in polys {
        let n = poly.len();
        for i in 0..n {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let t = if l2 > 0.0 {
                (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (qx, qy) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
            best = best.min((qx * qx + qy * qy).sqrt());
        }
    }
    best
}

/// At least `want` uv points strictly inside face `f` (away from its loops
/// by 1e-3 of the uv extent), from ever finer grids over its uv bounds.
pub fn interior_points(model: &Model, f: usize, want: usize) -> Vec<[f64; 2]> {
    let face = &model.faces[f];
    let polys = loop_polys(model, f, 64);
    let b = face.uv_bounds;
    let ext = (b.umax - b.umin).max(b.vmax - b.vmin);
    let mut n = 8;
    loop {
        let mut pts = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let uv = [
                    b.umin + (b.umax - b.umin) * (i as f64 + 0.5) / n as f64,
                    b.vmin + (b.vmax - b.vmin) * (j as f64 + 0.5) / n as f64,
                ];
                if inside(&polys, uv) && dist_to_loops(&polys, uv) > 1e-3 * ext {
                    pts.push(uv);
                }
            }
        }
        if pts.len() >= want || n >= 512 {
            return pts;
        }
        n *= 2;
    }
}
