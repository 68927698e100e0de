//! The baseline mesher on every CAD model of `data/cad`: all quads, no
//! inverted quad (SICN with the CAD normals), watertight (open edges only on
//! the model's own boundary), nodes on the CAD, curve chains. Prints a table.
//!
//! `QUADRILLE_MODELS=name1,name2` restricts the run to models whose file name
//! contains one of the given strings; `QUADRILLE_SIZE_FACTOR=f` meshes at
//! `Size::Factor(f)` instead of the default size.

mod common;

use std::path::PathBuf;
use std::time::Instant;

use quadrille::{MeshOptions, Size};

/// The baseline method's mesh of `model`.
fn mesh_baseline(
    model: &geometry::Model,
    opts: &quadrille::MeshOptions,
) -> Result<mesh::QuadMesh, quadrille::MeshError> {
    quadrille::mesh_model_with(model, opts, quadrille::MeshMethod::Baseline).map(|(m, _)| m)
}


#[test]
fn every_cad_model_meshes_validly() {
    let paths = common::cad_models();
    if std::env::var("QUADRILLE_MODELS").is_err() {
        assert!(
            paths.len() >= 26,
            "expected the 26 CAD models in data/cad, found {}",
            paths.len()
        );
    }
    let factor: f64 = std::env::var("QUADRILLE_SIZE_FACTOR")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let mut failures = Vec::new();
    let (mut opposite_pairs, mut opposite_close) = (0usize, 0usize);
    println!(
        "{:<28} {:>6} {:>7} {:>7} {:>8} {:>8} {:>6} {:>6} {:>9}",
        "model", "faces", "quads", "time s", "min SICN", "avg SICN", "inv", "open", "dist/diag"
    );
    for path in &paths {
        let name = path
            .file_stem()
            .and_then(|n| n.to_str())
            .unwrap_or("?")
            .to_string();
        let model = match occt::load(path) {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!("{name}: import failed: {e}"));
                continue;
            }
        };
        let t = Instant::now();
        let mesh = match mesh_baseline(
            &model,
            &MeshOptions {
                size: Size::Factor(factor),
                threads: None,
                progress: None,
                ..Default::default()
            },
        ) {
            Ok(m) => m,
            Err(e) => {
                println!("{name:<28} FAILED: {e}");
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let secs = t.elapsed().as_secs_f64();
        let r = common::check(&model, &mesh);
        let boundary = common::boundary_mesh_edges(&model, &mesh);
        println!(
            "{:<28} {:>6} {:>7} {:>7.2} {:>8.3} {:>8.3} {:>6} {:>6} {:>9.1e}",
            name,
            model.faces.len(),
            r.quads,
            secs,
            r.min_sicn,
            r.avg_sicn,
            r.inverted,
            r.open_edges,
            r.max_dist / r.diagonal
        );
        let mut bad = Vec::new();
        if !mesh.triangles.is_empty() {
            bad.push("triangles in output".to_string());
        }
        if r.inverted > 0 {
            bad.push(format!("{} inverted quads", r.inverted));
        }
        if r.open_edges != boundary {
            bad.push(format!(
                "{} open edges, model boundary has {boundary}",
                r.open_edges
            ));
        }
        if r.nonmanifold_edges > 0 {
            bad.push(format!("{} non-manifold edges", r.nonmanifold_edges));
        }
        if r.max_dist > 1e-6 * r.diagonal {
            bad.push(format!("node {:.2e} off the CAD", r.max_dist));
        }
        if !r.chain_errors.is_empty() {
            bad.push(format!(
                "curve chains: {:?}",
                &r.chain_errors[..r.chain_errors.len().min(3)]
            ));
        }
        if !r.class_errors.is_empty() {
            bad.push(format!(
                "classification: {:?}",
                &r.class_errors[..r.class_errors.len().min(3)]
            ));
        }
        // opposite sides of 4-sided faces: equal counts unless very different (spec §6.3)
        let plan = quadrille::curves::plan_curves(
            &model,
            quadrille::resolve_size(&model, Size::Factor(factor)).unwrap(),
        );
        let mut edges_per_curve = vec![0usize; model.curves.len()];
        for (_, c) in &mesh.curve_edges {
            edges_per_curve[c.idx()] += 1;
        }
        for [a, b] in quadrille::curves::opposite_pairs(&model) {
            let (ia, ib) = (
                plan.ideal(geometry::CurveId(a as u32)),
                plan.ideal(geometry::CurveId(b as u32)),
            );
            opposite_pairs += 1;
            if (ia - ib).abs() <= quadrille::curves::CHORD_TOLERANCE * ia.max(ib) {
                opposite_close += 1;
                if edges_per_curve[a] != edges_per_curve[b] {
                    bad.push(format!(
                        "opposite curves {} and {} have {} and {} edges",
                        a + 1,
                        b + 1,
                        edges_per_curve[a],
                        edges_per_curve[b]
                    ));
                }
            }
        }
        if !bad.is_empty() {
            failures.push(format!("{name}: {}", bad.join("; ")));
        }
    }
    println!("opposite curve pairs of 4-sided faces: {opposite_pairs}, of which {opposite_close} within the chord tolerance (all equal)");
    assert!(
        opposite_close > 100,
        "expected many 4-sided faces in the shared models, found {opposite_close} pairs"
    );
    assert!(failures.is_empty(), "failures:\n{}", failures.join("\n"));
}

#[test]
fn cad_output_is_identical_for_any_thread_count() {
    // i04o_m4 goes through curve refinement rounds, the hardest path for determinism
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/cad/i04o_m4.step");
    let model = occt::load(&path).expect("i04o_m4 loads");
    let run = |threads| {
        mesh_baseline(
            &model,
            &MeshOptions {
                size: Size::Factor(1.0),
                threads: Some(threads),
                progress: None,
                ..Default::default()
            },
        )
        .expect("meshes")
    };
    let (a, b) = (run(1), run(2));
    let bits = |m: &mesh::QuadMesh| {
        m.nodes
            .iter()
            .flat_map(|p| p.map(f64::to_bits))
            .collect::<Vec<u64>>()
    };
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.quads, b.quads);
    assert_eq!(a.node_class, b.node_class);
    assert_eq!(a.curve_edges, b.curve_edges);
}
