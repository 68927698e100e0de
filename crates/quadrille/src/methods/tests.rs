//! Tests of the methods' driver, options and reports.

use std::time::Duration;

use geometry::{primitives, CornerId, FaceId};
use mesh::NodeClass;

use super::*;
use crate::core::error::FaceError;
use crate::core::options::{default_size, Size, DEFAULT_DIVISIONS};
use crate::core::patch::QuadPatch;
use crate::methods::report::{FaceOutcome, MadeBy};
use crate::topology::defects::DefectReport;
use crate::topology::regular_pass::RegularPassReport;

#[test]
fn sizes_resolve_against_the_default() {
    let m = primitives::square(1.0);
    let d = default_size(&m);
    assert!((d - 2f64.sqrt() / DEFAULT_DIVISIONS).abs() < 1e-12);
    assert_eq!(resolve_size(&m, Size::Factor(2.0)).unwrap(), 2.0 * d);
    assert_eq!(resolve_size(&m, Size::Absolute(0.3)).unwrap(), 0.3);
    assert!(resolve_size(&m, Size::Absolute(-1.0)).is_err());
    assert!(resolve_size(&m, Size::Factor(f64::INFINITY)).is_err());
}

#[test]
fn nodes_are_numbered_corners_then_curves_then_faces() {
    let m = primitives::cylinder(1.0, 1.0);
    let mesh = crate::fixtures::grids::mesh_baseline(&m, &MeshOptions::default()).unwrap();
    let rank = |c: &NodeClass| match c {
        NodeClass::Corner(_) => 0,
        NodeClass::Curve(..) => 1,
        NodeClass::Face(..) => 2,
        NodeClass::Unclassified => 3,
    };
    let ranks: Vec<u8> = mesh.node_class.iter().map(rank).collect();
    assert!(ranks.windows(2).all(|w| w[0] <= w[1]));
    assert!(!ranks.contains(&3));
    // face-interior nodes grouped by face, in face order
    let faces: Vec<u32> = mesh
        .node_class
        .iter()
        .filter_map(|c| {
            if let NodeClass::Face(f, _) = c {
                Some(f.0)
            } else {
                None
            }
        })
        .collect();
    assert!(faces.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(mesh.corner_nodes, vec![(0, CornerId(0)), (1, CornerId(1))]);
}

#[test]
fn stages_switch_steps_off_and_stage_times_are_reported() {
    let opts = MeshOptions {
        size: Size::Absolute(0.12),
        threads: Some(1),
        progress: None,
        ..Default::default()
    };
    // the sphere without patterns (with them it is one cube, crate::direct::sphere_face)
    let sphere = primitives::sphere(1.0);
    let unpatterned = Stages {
        patterns: false,
        ..Stages::ALL
    };
    let (with, all) =
        mesh_model_with(&sphere, &opts, MeshMethod::QuasiStructured(unpatterned)).unwrap();
    assert!(
        all.cavities.replaced.iter().sum::<usize>() > 0,
        "{:?}",
        all.cavities
    );
    assert!(
        all.times.fields > Duration::ZERO
            && all.times.frontal > Duration::ZERO
            && all.times.cavities > Duration::ZERO,
        "{:?}",
        all.times
    );
    assert!(
        all.times.total >= all.times.fields + all.times.faces,
        "{:?}",
        all.times
    );
    let (without, off) = mesh_model_with(
        &sphere,
        &opts,
        MeshMethod::QuasiStructured(Stages {
            cavities: false,
            ..unpatterned
        }),
    )
    .unwrap();
    assert_eq!(
        off.cavities,
        crate::topology::cavity::CavityReport::default()
    );
    assert_eq!(off.times.cavities, Duration::ZERO);
    assert_eq!(off.defects, all.defects, "defects run before cavities");
    assert_ne!(with.quads, without.quads);
    let (_, none) =
        mesh_model_with(&sphere, &opts, MeshMethod::QuasiStructured(Stages::NONE)).unwrap();
    assert_eq!(
        none.defects,
        crate::topology::defects::DefectReport::default()
    );
    assert_eq!(none.regular_pass, (0, 0, 0));
    assert_eq!(none.times.regular_pass, Duration::ZERO);
    // with patterns, the sphere is a cube: one pattern, no cavity
    let (_, cube) =
        mesh_model_with(&sphere, &opts, MeshMethod::QuasiStructured(Stages::ALL)).unwrap();
    assert_eq!(cube.patterns.len(), 1, "{:?}", cube.patterns);
    // a square is meshed by a pattern unless patterns are off
    let square = primitives::square(1.0);
    let (_, p) = mesh_model_with(&square, &opts, MeshMethod::QuasiStructured(Stages::ALL)).unwrap();
    assert_eq!(p.patterns.len(), 1, "{:?}", p.patterns);
    let (_, q) = mesh_model_with(
        &square,
        &opts,
        MeshMethod::QuasiStructured(Stages {
            patterns: false,
            ..Stages::ALL
        }),
    )
    .unwrap();
    assert!(
        q.patterns.is_empty()
            && q.times.patterns == Duration::ZERO
            && q.times.frontal > Duration::ZERO,
        "{q:?}"
    );
    // the baseline's faces are all timed as baseline meshing
    let (_, b) = mesh_model_with(&square, &opts, MeshMethod::Baseline).unwrap();
    assert!(
        b.times.fallback > Duration::ZERO && b.times.frontal == Duration::ZERO,
        "{:?}",
        b.times
    );
}

#[test]
fn the_report_sums_the_outcomes_of_the_faces_whose_method_mesh_was_kept() {
    let patch = QuadPatch::default();
    let defects = |found| DefectReport {
        found,
        replaced: 1,
        ..Default::default()
    };
    let pass = |kept, irregular| RegularPassReport {
        tried: true,
        kept,
        irregular,
        ..Default::default()
    };
    let mut by_method = FaceOutcome::new(patch.clone(), MadeBy::Method);
    by_method.topology = Some((defects(3), Default::default()));
    by_method.regular_pass = Some(pass(true, (5, 2)));
    let mut second = FaceOutcome::new(patch.clone(), MadeBy::Method);
    second.topology = Some((defects(4), Default::default()));
    second.regular_pass = Some(pass(false, (6, 6)));
    // a fallback face's reports are not counted, whatever it holds
    let mut fallen = FaceOutcome::new(
        patch.clone(),
        MadeBy::Fallback(FaceError::EmptyTriangulation),
    );
    fallen.topology = Some((defects(100), Default::default()));
    let outcomes = vec![
        Some(by_method),
        Some(FaceOutcome::new(
            patch.clone(),
            MadeBy::Pattern("grid".into()),
        )),
        Some(fallen),
        None,
        Some(second),
    ];
    let r = MeshReport::from_faces(&outcomes);
    assert_eq!(r.patterns, vec![(FaceId(1), "grid".to_string())]);
    assert_eq!(r.fallback, vec![(FaceId(2), FaceError::EmptyTriangulation)]);
    assert_eq!((r.defects.found, r.defects.replaced), (7, 2));
    // tried on two faces, kept on one, 5 - 2 irregular vertices removed there
    assert_eq!(r.regular_pass, (2, 1, 3));
}

#[test]
fn a_timed_stage_adds_its_time_and_returns_its_value() {
    let mut slot = Duration::from_millis(5);
    let v = crate::methods::report::timed(&mut slot, "test", || {
        std::thread::sleep(Duration::from_millis(2));
        7
    });
    assert_eq!(v, 7);
    assert!(slot >= Duration::from_millis(7), "{slot:?}");
}
