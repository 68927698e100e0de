//! Per-call timings of the OCCT-backed geometry on every bundled CAD model:
//! `cargo run --release -p occt --example timing`.
//!
//! Prints the mean time of surface eval / derivs / project (no hint, hint,
//! off-surface with hint) and curve eval / project, over points spread on
//! every face and curve.

use std::path::Path;
use std::time::Instant;

use geometry::vec3::{add, dist, scale};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/cad"));
    let mut files: Vec<_> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.retain(|p| occt::Format::from_path(p).is_some());
    files.sort();
    let mut pts = Vec::new(); // (model, face, uv)
    let mut models = Vec::new();
    let t = Instant::now();
    for f in &files {
        models.push(occt::load(f).map_err(|e| format!("{}: {e}", f.display()))?);
    }
    println!(
        "load all {} models: {:.3} s",
        files.len(),
        t.elapsed().as_secs_f64()
    );
    for (mi, m) in models.iter().enumerate() {
        for (fi, face) in m.faces.iter().enumerate() {
            let b = face.uv_bounds;
            for i in 0..6 {
                for j in 0..6 {
                    let uv = [
                        b.umin + (b.umax - b.umin) * (i as f64 + 0.5) / 6.0,
                        b.vmin + (b.vmax - b.vmin) * (j as f64 + 0.5) / 6.0,
                    ];
                    pts.push((mi, fi, uv));
                }
            }
        }
    }
    let n = pts.len() as f64;
    let time = |label: &str, f: &dyn Fn(&geometry::Face, [f64; 2], f64) -> f64| {
        let t = Instant::now();
        let mut acc = 0.0;
        for &(mi, fi, uv) in &pts {
            acc += f(&models[mi].faces[fi], uv, models[mi].diagonal_cached());
        }
        println!(
            "{label:<40} {:8.2} µs/call   (checksum {acc:.3e})",
            t.elapsed().as_secs_f64() * 1e6 / n
        );
    };
    time("surface eval", &|f, uv, _| f.surface.eval(uv)[0]);
    time("surface derivs (D2)", &|f, uv, _| {
        f.surface.derivs(uv).duu[0]
    });
    time("surface normal", &|f, uv, _| {
        f.surface.normal(uv).map_or(0.0, |n| n[0])
    });
    time("surface project, on surface, no hint", &|f, uv, _| {
        let p = f.surface.eval(uv);
        f.surface.project(p, None).map_or(1.0, |r| dist(r.1, p))
    });
    time("surface project, on surface, hint", &|f, uv, _| {
        let p = f.surface.eval(uv);
        let b = f.uv_bounds;
        f.surface
            .project(p, Some([uv[0] + 0.01 * (b.umax - b.umin), uv[1]]))
            .map_or(1.0, |r| dist(r.1, p))
    });
    time("surface project, 1e-3·diag off, hint", &|f, uv, d| {
        let Some(nrm) = f.surface.normal(uv) else {
            return 0.0;
        };
        let p = add(f.surface.eval(uv), scale(nrm, 1e-3 * d));
        f.surface.project(p, Some(uv)).map_or(1.0, |r| dist(r.1, p))
    });
    time("surface project, 1e-3·diag off, no hint", &|f, uv, d| {
        let Some(nrm) = f.surface.normal(uv) else {
            return 0.0;
        };
        let p = add(f.surface.eval(uv), scale(nrm, 1e-3 * d));
        f.surface.project(p, None).map_or(1.0, |r| dist(r.1, p))
    });
    let mut cpts = Vec::new();
    for (mi, m) in models.iter().enumerate() {
        for (ci, c) in m.curves.iter().enumerate() {
            if c.geom.is_some() {
                for k in 0..10 {
                    cpts.push((
                        mi,
                        ci,
                        c.range.0 + (c.range.1 - c.range.0) * (k as f64 + 0.5) / 10.0,
                    ));
                }
            }
        }
    }
    let nc = cpts.len() as f64;
    let ctime = |label: &str, f: &dyn Fn(&dyn geometry::Curve, f64) -> f64| {
        let t = Instant::now();
        let mut acc = 0.0;
        for &(mi, ci, tt) in &cpts {
            // only curves with a geometry were sampled
            if let Some(g) = models[mi].curves[ci].geom.as_deref() {
                acc += f(g, tt);
            }
        }
        println!(
            "{label:<40} {:8.2} µs/call   (checksum {acc:.3e})",
            t.elapsed().as_secs_f64() * 1e6 / nc
        );
    };
    ctime("curve eval", &|c, t| c.eval(t)[0]);
    ctime("curve project, on curve, no hint", &|c, t| {
        let p = c.eval(t);
        c.project(p, None).map_or(1.0, |r| dist(r.1, p))
    });
    ctime("curve project, on curve, hint", &|c, t| {
        let p = c.eval(t);
        c.project(p, Some(t + 1e-3)).map_or(1.0, |r| dist(r.1, p))
    });
    println!("{} surface points, {} curve points", pts.len(), cpts.len());
    Ok(())
}

trait DiagCached {
    fn diagonal_cached(&self) -> f64;
}
impl DiagCached for geometry::Model {
    fn diagonal_cached(&self) -> f64 {
        use std::collections::HashMap;
        use std::sync::Mutex;
        static CACHE: Mutex<Option<HashMap<usize, f64>>> = Mutex::new(None);
        let key = self as *const _ as usize;
        let mut g = CACHE.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        *g.get_or_insert_with(HashMap::new)
            .entry(key)
            .or_insert_with(|| self.diagonal())
    }
}
