//! The baseline mesher on the analytic primitives: all quads, valid with the
//! CAD normals, watertight, on the CAD, curve chains, deterministic.

mod common;

use geometry::{primitives, Model};
use mesh::{NodeClass, QuadMesh};
use quadrille::{MeshOptions, Size};

/// The baseline method's mesh of `model`.
fn mesh_baseline(
    model: &geometry::Model,
    opts: &quadrille::MeshOptions,
) -> Result<mesh::QuadMesh, quadrille::MeshError> {
    quadrille::mesh_model_with(model, opts, quadrille::MeshMethod::Baseline).map(|(m, _)| m)
}

fn run(model: &Model, size: Size, threads: usize) -> QuadMesh {
    mesh_baseline(
        model,
        &MeshOptions {
            size,
            threads: Some(threads),
            progress: None,
            ..Default::default()
        },
    )
    .expect("meshing failed")
}

fn assert_valid(model: &Model, mesh: &QuadMesh, closed: bool) -> common::Report {
    let r = common::check(model, mesh);
    assert!(mesh.triangles.is_empty(), "all-quad output expected");
    assert!(r.quads > 0);
    assert_eq!(r.inverted, 0, "{r:?}");
    assert!(r.min_sicn > 0.0, "{r:?}");
    assert_eq!(r.nonmanifold_edges, 0, "{r:?}");
    assert!(r.max_dist <= 1e-9 * r.diagonal.max(1.0), "{r:?}");
    assert!(r.chain_errors.is_empty(), "{:?}", r.chain_errors);
    assert!(r.class_errors.is_empty(), "{:?}", r.class_errors);
    assert_eq!(mesh.node_class.len(), mesh.nodes.len());
    assert_eq!(mesh.quad_face.len(), mesh.quads.len());
    if closed {
        assert_eq!(r.open_edges, 0, "{r:?}");
        assert_eq!(r.euler, 2, "{r:?}");
    }
    r
}

#[test]
fn square_is_all_quad_and_its_boundary_is_open() {
    let m = primitives::square(2.0);
    let mesh = run(&m, Size::Absolute(0.1), 1);
    let r = assert_valid(&m, &mesh, false);
    assert_eq!(r.open_edges, mesh.curve_edges.len());
    assert_eq!(r.open_edges, common::boundary_mesh_edges(&m, &mesh));
    assert_eq!(r.euler, 1, "a disc");
    // 20 edges per side at h = 0.1
    assert_eq!(mesh.curve_edges.len(), 80);
    assert!(r.avg_sicn > 0.6, "{r:?}");
}

#[test]
fn cylinder_is_closed_and_valid() {
    let m = primitives::cylinder(1.0, 3.0);
    for size in [Size::Factor(1.0), Size::Absolute(0.15), Size::Factor(4.0)] {
        let mesh = run(&m, size, 2);
        let r = assert_valid(&m, &mesh, true);
        assert!(r.avg_sicn > 0.5, "{size:?}: {r:?}");
    }
}

#[test]
fn sphere_is_closed_and_valid() {
    let m = primitives::sphere(1.5);
    for size in [Size::Factor(1.0), Size::Absolute(0.1), Size::Factor(5.0)] {
        let mesh = run(&m, size, 2);
        let r = assert_valid(&m, &mesh, true);
        assert!(r.avg_sicn > 0.4, "{size:?}: {r:?}");
        // the poles are corner nodes used by quads
        let used = |n: u32| mesh.quads.iter().any(|q| q.contains(&n));
        assert!(used(0) && used(1));
        assert!(matches!(mesh.node_class[0], NodeClass::Corner(_)));
    }
}

#[test]
fn output_is_identical_for_any_thread_count() {
    for m in [
        primitives::square(1.0),
        primitives::cylinder(1.0, 2.0),
        primitives::sphere(1.0),
    ] {
        let a = run(&m, Size::Factor(0.5), 1);
        let b = run(&m, Size::Factor(0.5), 2);
        let bits = |x: &QuadMesh| {
            x.nodes
                .iter()
                .flat_map(|p| p.map(f64::to_bits))
                .collect::<Vec<u64>>()
        };
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.quads, b.quads);
        assert_eq!(a.quad_face, b.quad_face);
        assert_eq!(a.node_class, b.node_class);
        assert_eq!(a.curve_edges, b.curve_edges);
    }
}

#[test]
fn default_size_gives_a_moderate_count() {
    let m = primitives::sphere(1.0);
    let mesh = run(&m, Size::default(), 1);
    assert!(
        mesh.quads.len() > 200 && mesh.quads.len() < 3000,
        "{}",
        mesh.quads.len()
    );
}

#[test]
fn bad_sizes_are_errors() {
    let m = primitives::square(1.0);
    for s in [
        Size::Absolute(0.0),
        Size::Absolute(f64::NAN),
        Size::Factor(-1.0),
    ] {
        assert!(mesh_baseline(
            &m,
            &MeshOptions {
                size: s,
                ..Default::default()
            }
        )
        .is_err());
    }
    assert!(mesh_baseline(&Model::default(), &MeshOptions::default()).is_err());
}

#[test]
fn progress_reports_every_face() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    let m = primitives::cylinder(1.0, 1.0);
    let max = Arc::new(AtomicUsize::new(0));
    let seen = max.clone();
    let opts = MeshOptions {
        size: Size::Factor(1.0),
        threads: Some(1),
        progress: Some(Arc::new(move |d, t| {
            assert_eq!(t, 3);
            seen.fetch_max(d, Ordering::Relaxed);
        })),
        ..Default::default()
    };
    mesh_baseline(&m, &opts).unwrap();
    assert_eq!(max.load(Ordering::Relaxed), 3);
}
