//! The size guard's estimate ([`quadrille::estimate_quads`]) against the
//! quads each method makes, on CAD models at one size factor: the table
//! behind the per-method constants of the guard (`methods/guard.rs`).
//!
//! ```sh
//! cargo run --release -p quadrille --example estimate_calibration -- data/cad/*.st* [--size-factor F] [--methods qs,unstructured,baseline,regular]
//! ```

use std::time::Instant;

use quadrille::{estimate_quads, mesh_model_with, MeshMethod, MeshOptions, Size};

fn method(name: &str) -> MeshMethod {
    match name {
        "qs" => MeshMethod::default(),
        "unstructured" => MeshMethod::Unstructured,
        "baseline" => MeshMethod::Baseline,
        "regular" => MeshMethod::regular(Some(2)),
        other => panic!("unknown method {other} (qs, unstructured, baseline, regular)"),
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut paths, mut factor, mut methods) = (Vec::new(), 1.0, "qs".to_string());
    while let Some(a) = args.next() {
        match a.as_str() {
            "--size-factor" => factor = args.next().and_then(|x| x.parse().ok()).expect("a number"),
            "--methods" => methods = args.next().expect("a list"),
            _ => paths.push(a),
        }
    }
    let opts = MeshOptions {
        size: Size::Factor(factor),
        threads: Some(2),
        max_quads: 0,
        ..Default::default()
    };
    println!(
        "{:<34} {:<13} {:>9} {:>9} {:>6} {:>9}",
        "model", "method", "estimate", "quads", "ratio", "est. s"
    );
    for name in methods.split(',') {
        let m = method(name);
        let mut logs = Vec::new();
        for path in &paths {
            let model = match occt::load(std::path::Path::new(path)) {
                Ok(m) => m,
                Err(e) => {
                    eprintln!("{path}: {e}");
                    continue;
                }
            };
            let t = Instant::now();
            let est = estimate_quads(&model, &opts, &m).expect("estimate");
            let secs = t.elapsed().as_secs_f64();
            let made = match mesh_model_with(&model, &opts, m.clone()) {
                Ok((mesh, _)) => mesh.quads.len(),
                Err(e) => {
                    eprintln!("{path}: {e}");
                    continue;
                }
            };
            let ratio = est as f64 / made as f64;
            logs.push(ratio.ln());
            let short = std::path::Path::new(path)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            println!("{short:<34} {name:<13} {est:>9} {made:>9} {ratio:>6.2} {secs:>9.3}");
        }
        let n = logs.len().max(1) as f64;
        let gm = (logs.iter().sum::<f64>() / n).exp();
        let lo = logs.iter().cloned().fold(f64::INFINITY, f64::min).exp();
        let hi = logs.iter().cloned().fold(f64::NEG_INFINITY, f64::max).exp();
        println!("{name}: ratio geometric mean {gm:.3}, min {lo:.2}, max {hi:.2}");
    }
}
