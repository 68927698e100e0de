//! Unit tests of the cross-field stage (spec §14.2, "CR and cross field").

use super::assembly::cr_stiffness;
use super::*;
use crate::fixtures::crossfield_meshes as fixtures;

fn cot(x: f64) -> f64 {
    x.cos() / x.sin()
}

#[test]
fn cr_stiffness_matches_cotangent_form_and_mass_sums_to_area() {
    let mesh = FaceMesh {
        xyz: vec![[0.0, 0.0, 0.0], [2.0, 0.1, 0.0], [0.7, 1.3, 0.4]],
        triangles: vec![[0, 1, 2]],
        vertex_class: vec![VertexClass::Interior; 3],
        ..Default::default()
    };
    let topo = FaceTopology::build(&mesh).unwrap();
    let k = cr_stiffness(&topo, 0);
    let g = [
        topo.corner_angle(0, 0),
        topo.corner_angle(0, 1),
        topo.corner_angle(0, 2),
    ];
    assert!((g.iter().sum::<f64>() - std::f64::consts::PI).abs() < 1e-12);
    for a in 0..3 {
        // rows sum to zero
        assert!(k[a].iter().sum::<f64>().abs() < 1e-12);
        // diagonal: 2 (cot of the angles at the edge's two endpoints)
        let d = 2.0 * (cot(g[(a + 1) % 3]) + cot(g[(a + 2) % 3]));
        assert!((k[a][a] - d).abs() < 1e-12, "{} vs {}", k[a][a], d);
        // off-diagonal: −2 cot of the angle between the two edges (at their shared vertex)
        let b = (a + 1) % 3;
        let shared = 3 - a - b;
        assert!((k[a][b] + 2.0 * cot(g[shared])).abs() < 1e-12);
    }
    // Σ M_jj = area (boundary edges counted once)
    let sq = fixtures::square_grid(2.0, 7);
    let topo = FaceTopology::build(&sq).unwrap();
    let mut m = vec![0.0; topo.edges.len()];
    for t in 0..topo.triangles.len() {
        for &e in &topo.tri_edges[t] {
            m[e as usize] += topo.areas[t] / 3.0;
        }
    }
    assert!((m.iter().sum::<f64>() - 4.0).abs() < 1e-12);
}

#[test]
fn topology_counts_and_welding() {
    let sq = fixtures::square_grid(1.0, 5);
    let topo = FaceTopology::build(&sq).unwrap();
    assert_eq!(topo.euler_characteristic(), 1);
    assert_eq!(topo.feature.iter().filter(|&&f| f).count(), 20);
    // the UV sphere welds its seam and its poles into a closed surface
    let s = fixtures::uv_sphere(1.0, 16, 8);
    let topo = FaceTopology::build(&s).unwrap();
    assert_eq!(topo.positions.len(), 16 * 7 + 2);
    assert_eq!(topo.triangles.len(), 2 * 16 * 8 - 2 * 16);
    assert_eq!(topo.euler_characteristic(), 2);
    assert!(!topo.feature.iter().any(|&f| f));
    let t = fixtures::torus(2.0, 0.5, 12, 6);
    assert_eq!(FaceTopology::build(&t).unwrap().euler_characteristic(), 0);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mut m = fixtures::square_grid(1.0, 2);
    m.triangles.push([0, 1, 99]);
    assert!(matches!(
        compute_cross_field(&m, &CrossFieldOptions::default()),
        Err(CrossFieldError::InvalidInput(_))
    ));
    let mut m = fixtures::square_grid(1.0, 2);
    m.triangles[0] = [m.triangles[0][1], m.triangles[0][0], m.triangles[0][2]];
    assert!(compute_cross_field(&m, &CrossFieldOptions::default()).is_err());
    let m = FaceMesh {
        xyz: vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        triangles: vec![[0, 1, 2]],
        vertex_class: vec![VertexClass::Interior; 3],
        ..Default::default()
    };
    assert!(compute_cross_field(&m, &CrossFieldOptions::default()).is_err());
    assert!(compute_cross_field(&FaceMesh::default(), &CrossFieldOptions::default()).is_err());
    let mut m = fixtures::square_grid(1.0, 2);
    m.xyz[3][1] = f64::NAN;
    assert!(compute_cross_field(&m, &CrossFieldOptions::default()).is_err());
}

#[test]
fn square_field_is_constant_and_boundary_aligned() {
    // the diffusion itself (the parallel shortcut would skip it)
    let sq = fixtures::square_grid(1.0, 20);
    let opts = CrossFieldOptions {
        parallel_shortcut: false,
        ..Default::default()
    };
    let f = compute_cross_field(&sq, &opts).unwrap();
    let topo = &f.topology;
    for e in 0..topo.edges.len() {
        let u = f.u[e];
        assert!(
            ((u[0] * u[0] + u[1] * u[1]).sqrt() - 1.0).abs() < 1e-9,
            "unit norm"
        );
        if topo.feature[e] {
            assert_eq!(u, [1.0, 0.0]);
        }
    }
    // every triangle's cross is axis-aligned (θ = 0 mod 90° in the square's frame)
    for t in 0..topo.triangles.len() {
        let [d1, _] = f.triangle_cross(t).unwrap();
        let th = d1[1].atan2(d1[0]);
        let dev = (4.0 * th).sin().abs();
        assert!(dev < 1e-6, "triangle {t}: θ = {th}");
    }
    assert!(!f.levels.is_empty());
    assert!(f.levels.iter().all(|l| l.final_change <= 1e-3));
}

#[test]
fn levels_follow_algorithm_one() {
    let a = mbo::level_alphas(10.0, 0.01, 4);
    assert_eq!(a.len(), 4);
    assert!((a[0] - 1.0).abs() < 1e-12);
    assert!((a[3] - 9e-4).abs() < 1e-15);
    assert!((a[1] - (1.0 + (9e-4 - 1.0) / 3.0)).abs() < 1e-12);
    // a coarse face whose final α exceeds the initial one runs one level
    assert_eq!(mbo::level_alphas(1.0, 0.5, 5), vec![2.25]);
}

#[test]
fn bc_extension_fixes_the_boundary_layer() {
    let d = fixtures::disk(12);
    let with = compute_cross_field(&d, &CrossFieldOptions::default()).unwrap();
    let without = compute_cross_field(
        &d,
        &CrossFieldOptions {
            extend_boundary_conditions: false,
            ..Default::default()
        },
    )
    .unwrap();
    let topo = &with.topology;
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        let touches = topo.edge_tris[e].iter().any(|&t| {
            t != topology::NONE
                && topo.triangles[t as usize]
                    .iter()
                    .any(|&v| topo.on_feature[v as usize])
        });
        assert_eq!(with.fixed[e], touches, "edge {a}-{b}");
    }
    assert!(with.free_edges() < without.free_edges());
    assert_eq!(without.fixed, topo.feature);
}

#[test]
fn deterministic() {
    let d = fixtures::disk(10);
    let a = compute_cross_field(&d, &CrossFieldOptions::default()).unwrap();
    let b = compute_cross_field(&d, &CrossFieldOptions::default()).unwrap();
    assert_eq!(a.u, b.u);
}

#[test]
fn parallel_shortcut_gives_the_diffused_field_of_a_square() {
    let sq = fixtures::square_grid(1.0, 12);
    let fast = compute_cross_field(&sq, &CrossFieldOptions::default()).unwrap();
    let slow = compute_cross_field(
        &sq,
        &CrossFieldOptions {
            parallel_shortcut: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        fast.levels.is_empty() && fast.parallel,
        "no diffusion level ran"
    );
    assert!(!slow.levels.is_empty() && !slow.parallel);
    // the scaling of the parallel field is 0 without a solve, as the solve
    // gives for the diffused one
    let h_fast = crate::field::scaling::conformal_scaling(&fast).unwrap().h;
    let h_slow = crate::field::scaling::conformal_scaling(&slow).unwrap().h;
    assert!(h_fast.iter().all(|&x| x == 0.0));
    assert!(h_slow.iter().all(|&x| x.abs() < 1e-6), "{:?}", &h_slow[..4]);
    let topo = &fast.topology;
    for e in 0..topo.edges.len() {
        if topo.feature[e] {
            assert_eq!(fast.u[e], [1.0, 0.0], "edge {e}: boundary condition");
        }
        let step = topology::arg_ratio(fast.u[e], slow.u[e]).abs() / 4.0;
        assert!(step < 1e-3, "edge {e}: {step} rad from the diffused field");
    }
}

#[test]
fn disk_and_annulus_have_no_parallel_field() {
    // a round boundary cannot be parallel or orthogonal to one direction
    for mesh in [fixtures::disk(8), fixtures::annulus(1.0, 2.0, 4, 24)] {
        let topo = FaceTopology::build(&mesh).unwrap();
        assert!(parallel_field(&topo).is_none());
        let f = compute_cross_field(&mesh, &CrossFieldOptions::default()).unwrap();
        assert!(!f.levels.is_empty());
    }
}
