//! Curve networks from the bundled CAD models (issue 30, item 1): every face
//! without a seam is a cycle (a pole at a corner is left out of its loop),
//! every cycle is valid (closed, simple, with an inward side, orientable
//! against its neighbours), and on the convex rounded cube every outer loop
//! turns counter-clockwise about the outward direction.
//!
//! `cargo test --test curvenet_cad -- --nocapture` prints one table row per
//! model: faces, cycles, skipped faces, most holes in a cycle, curve points.

mod common;

use std::collections::BTreeMap;
use std::path::Path;

use geometry::vec3::{self, Vec3};
use geometry::Model;
use quadrille::curvenet::{network_from_model, CurveNetError, CurveNetwork, SkipReason};

fn load(name: &str) -> Model {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cad")
        .join(name);
    occt::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Newell vector of a closed polyline.
fn newell(p: &[Vec3]) -> Vec3 {
    let mut s = [0.0; 3];
    for i in 0..p.len() {
        s = vec3::add(s, vec3::cross(p[i], p[(i + 1) % p.len()]));
    }
    vec3::scale(s, 0.5)
}

/// The network of every face of `model`, each cycle checked; prints a row.
fn network(name: &str, model: &Model) -> Result<CurveNetwork, CurveNetError> {
    let (net, skipped) = network_from_model(model, None)?;
    let errors: Vec<String> = net.validate().iter().map(|e| e.to_string()).collect();
    assert!(errors.is_empty(), "{name}:\n{}", errors.join("\n"));
    let holes = net.cycles().iter().map(|c| c.loops.len() - 1).max();
    let mut reasons = BTreeMap::new();
    for s in &skipped {
        let why = match s.reason {
            SkipReason::Seam(_) => "seam",
            SkipReason::DegenerateCurve(_) => "poles only",
            SkipReason::NoLoop => "no loop",
        };
        *reasons.entry(why).or_insert(0) += 1;
    }
    println!(
        "| {name} | {} | {} | {} {reasons:?} | {} | {} |",
        model.faces.len(),
        net.cycles().len(),
        skipped.len(),
        holes.unwrap_or(0),
        net.point_count(),
    );
    Ok(net)
}

#[test]
fn the_rounded_cube_gives_26_cycles_facing_out() {
    let model = load("s12o_cube_rounded_1.stp");
    assert_eq!(model.faces.len(), 26);
    let (net, skipped) = network_from_model(&model, None).unwrap();
    assert!(skipped.is_empty(), "{skipped:?}");
    assert_eq!(net.cycles().len(), 26);
    assert!(net.validate().is_empty());
    // 6 squares and 12 fillets (4 fixed corners: lines meet lines or arcs at
    // right angles), 8 spherical triangles (3: the pole of the sphere is one
    // of the corners, its degenerate curve left out)
    let (lo, hi) = model.bounding_box();
    let centre = vec3::scale(vec3::add(lo, hi), 0.5);
    let mut by_corners = BTreeMap::new();
    for c in 0..net.cycles().len() {
        let l = net.cycle_loops(c).unwrap();
        assert!(l.holes.is_empty());
        *by_corners.entry(l.outer.fixed.len()).or_insert(0) += 1;
        let n = newell(&l.outer.points);
        let mid = l
            .outer
            .points
            .iter()
            .fold([0.0; 3], |a, p| vec3::add(a, *p));
        let mid = vec3::scale(mid, 1.0 / l.outer.points.len() as f64);
        assert!(
            vec3::dot(n, vec3::sub(mid, centre)) > 0.0,
            "cycle {c} faces in"
        );
    }
    assert_eq!(by_corners, BTreeMap::from([(3, 8), (4, 18)]));
    // every CAD curve sampled once, at most D/200 apart
    let d = model.diagonal();
    for c in net.curves() {
        assert!(c.cad.is_some());
        for w in c.points.windows(2) {
            assert!(vec3::dist(w[0], w[1]) <= d / 200.0 * (1.0 + 1e-9));
        }
    }
    let cads: std::collections::HashSet<_> = net.curves().iter().map(|c| c.cad).collect();
    assert_eq!(cads.len(), net.curves().len());
}

#[test]
fn mambo_faces_with_holes() {
    for (name, holes) in [("i01o_m1.step", 9), ("i02o_m2.step", 3)] {
        let model = load(name);
        let net = network(name, &model).unwrap();
        assert_eq!(net.cycles().len(), model.faces.len(), "{name}");
        let most = net.cycles().iter().map(|c| c.loops.len() - 1).max();
        assert_eq!(most, Some(holes), "{name}");
        // the holes run against the outer loop
        for c in 0..net.cycles().len() {
            let l = net.cycle_loops(c).unwrap();
            assert_eq!(l.holes.len(), net.cycles()[c].loops.len() - 1);
        }
    }
}

#[test]
fn every_bundled_model_gives_valid_cycles() {
    for p in common::cad_models() {
        let name = p.file_name().unwrap().to_str().unwrap().to_string();
        let model = occt::load(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
        match network(&name, &model) {
            Ok(net) => assert!(!net.cycles().is_empty()),
            // a single face with a seam (torus, sphere, wing): nothing left
            Err(e @ CurveNetError::Empty { .. }) => {
                assert_eq!(model.faces.len(), 1, "{name}: {e}");
                println!("| {name} | 1 | 0 | 1 (seam) | – | – |");
            }
            Err(e) => panic!("{name}: {e}"),
        }
    }
}

/// Issue 30, "Done when": the rounded cube and the cube with a spherical
/// corner are meshed cycle by cycle and the network stage (spec §7) makes
/// the whole mesh watertight: every cycle meshed, no edge used once (the
/// solids are closed) or more than twice, no interval mismatch left.
#[test]
fn the_rounded_cubes_are_watertight() {
    use quadrille::methods::curvenet::{mesh_curve_network, CurvesOptions};
    for name in ["s12o_cube_rounded_1.stp", "s14o_cube_corner_sub_sphere.stp"] {
        let model = load(name);
        let (net, _) = network_from_model(&model, None).unwrap();
        let opts = CurvesOptions { threads: Some(1), ..Default::default() };
        let (mesh, report) = mesh_curve_network(&net, &opts).unwrap();
        assert!(report.skipped.is_empty(), "{name}: {:?}", report.skipped);
        assert_eq!(report.cycles.len(), net.cycles().len(), "{name}");
        assert_eq!(report.network.mismatch, 0, "{name}: {:?}", report.network);
        assert_eq!(report.network.t_junctions.unresolved, 0, "{name}: {:?}", report.network);
        let mut uses: BTreeMap<(u32, u32), usize> = BTreeMap::new();
        for q in &mesh.quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let open = uses.values().filter(|&&n| n == 1).count();
        let non_manifold = uses.values().filter(|&&n| n > 2).count();
        assert_eq!((open, non_manifold), (0, 0), "{name}: open and non-manifold edges");
    }
}
