//! Relation (2) of the paper on every face of every CAD model in a folder:
//! imports each model (OpenCASCADE), and for each face computes the cross
//! field on the baseline background triangulation and its singularities
//! ([`quadrille::field::model_fields`], the routine behind
//! `quadrille field`), and checks `Σ singularity indices = 4χ − Σ_corners (2 − n̄)`.
//!
//! Run: `cargo run --release -p quadrille --example crossfield_models [dir] [refine]`
//! (default `data/cad`, refine 8: background triangles of a quarter of the
//! default quad size). Prints one line per failing face and the share of
//! faces that satisfy the relation.

use std::path::PathBuf;

use quadrille::field::{model_fields, FieldOptions, BACKGROUND_REFINE};

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "data/cad".into()));
    // background size = default quad size / `refine` (second argument)
    let refine: f64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(BACKGROUND_REFINE);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("model folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    let (mut ok, mut bad, mut skipped) = (0usize, 0usize, 0usize);
    let opts = FieldOptions {
        refine,
        size_map: false,
        ..Default::default()
    };
    for path in files {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
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
        let fields = match model_fields(&model, &opts) {
            Ok(f) => f,
            Err(e) => {
                println!("{}: {e}", path.display());
                continue;
            }
        };
        let (mut m_ok, mut m_bad, mut m_skip) = (0, 0, 0);
        for report in &fields.faces {
            let f = report.face.idx();
            match &report.outcome {
                Ok(ff) if ff.singularities.satisfies_eq2() => m_ok += 1,
                Ok(ff) => {
                    m_bad += 1;
                    let s = &ff.singularities;
                    let corners: Vec<String> = s
                        .corners
                        .iter()
                        .map(|c| format!("{:.0}°", c.angle.to_degrees()))
                        .collect();
                    println!(
                        "  {} face {f}: Σk = {} but 4χ − Σ(2 − n̄) = {} (χ = {}, corners [{}], {} triangles)",
                        path.display(),
                        s.index_sum(),
                        s.expected_index_sum(),
                        s.euler_characteristic,
                        corners.join(" "),
                        ff.triangles()
                    );
                }
                Err(e) => {
                    println!("  {} face {f}: {e}", path.display());
                    m_skip += 1;
                }
            }
        }
        println!(
            "{}: {m_ok}/{} faces satisfy Eq. (2), {m_skip} skipped",
            path.display(),
            m_ok + m_bad
        );
        ok += m_ok;
        bad += m_bad;
        skipped += m_skip;
    }
    println!(
        "TOTAL: {ok}/{} faces satisfy Eq. (2) ({:.1} %), {skipped} faces skipped",
        ok + bad,
        100.0 * ok as f64 / (ok + bad).max(1) as f64
    );
}
