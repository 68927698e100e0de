//! Relation (2) of the paper on every face of every CAD model in a folder:
//! imports each model (OpenCASCADE), triangulates each face with the baseline
//! background triangulation, computes the cross field and its singularities,
//! and checks `Σ singularity indices = 4χ − Σ_corners (2 − n̄)`.
//!
//! Run: `cargo run --release -p quadrille --example crossfield_models [dir]`
//! [refine]` (default `data/cad`, refine 8: background triangles of a quarter of the
//! default quad size). Prints one line per failing face and the share of
//! faces that satisfy the relation.

use std::path::PathBuf;

use quadrille::crossfield::{compute_cross_field, CrossFieldOptions, FaceMesh};
use quadrille::curve_mesh::{discretize_all, initial_counts};
use quadrille::face_triangulation::FaceTriangulation;
use quadrille::pipeline::default_size;
use quadrille::singularities::extract_singularities;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "data/cad".into()));
    // background size = default quad size / `refine` (second argument, default 4)
    let refine: f64 = std::env::args().nth(2).and_then(|a| a.parse().ok()).unwrap_or(8.0);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir).expect("model folder").filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    let (mut ok, mut bad, mut skipped) = (0usize, 0usize, 0usize);
    let opts = CrossFieldOptions::default();
    for path in files {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if !["step", "stp", "iges", "igs", "brep"].contains(&ext.as_str()) {
            continue;
        }
        let model = match occt::load(&path) {
            Ok(m) => m,
            Err(e) => {
                println!("{}: import failed: {e}", path.display());
                continue;
            }
        };
        let h = default_size(&model) / refine;
        let cms = discretize_all(&model, &initial_counts(&model, h));
        let (mut m_ok, mut m_bad, mut m_skip) = (0, 0, 0);
        for f in 0..model.faces.len() {
            let fid = geometry::FaceId(f as u32);
            let mesh = match FaceTriangulation::new(&model, fid, &cms, 2.0 * h).and_then(|mut ft| ft.refine().map(|_| ft)) {
                Ok(ft) => FaceMesh::from_face_triangulation(&ft),
                Err(e) => {
                    println!("  {} face {f}: no triangulation ({e:?})", path.display());
                    m_skip += 1;
                    continue;
                }
            };
            match compute_cross_field(&mesh, &opts) {
                Ok(field) => {
                    let s = extract_singularities(&field);
                    if s.satisfies_eq2() {
                        m_ok += 1;
                    } else {
                        m_bad += 1;
                        let corners: Vec<String> = s.corners.iter().map(|c| format!("{:.0}°", c.angle.to_degrees())).collect();
                        println!(
                            "  {} face {f}: Σk = {} but 4χ − Σ(2 − n̄) = {} (χ = {}, corners [{}], {} triangles)",
                            path.display(),
                            s.index_sum(),
                            s.expected_index_sum(),
                            s.euler_characteristic,
                            corners.join(" "),
                            field.topology.triangles.len()
                        );
                    }
                }
                Err(e) => {
                    println!("  {} face {f}: cross field failed: {e}", path.display());
                    m_skip += 1;
                }
            }
        }
        println!("{}: {m_ok}/{} faces satisfy Eq. (2), {m_skip} skipped", path.display(), m_ok + m_bad);
        ok += m_ok;
        bad += m_bad;
        skipped += m_skip;
    }
    println!("TOTAL: {ok}/{} faces satisfy Eq. (2) ({:.1} %), {skipped} faces skipped", ok + bad, 100.0 * ok as f64 / (ok + bad).max(1) as f64);
}
