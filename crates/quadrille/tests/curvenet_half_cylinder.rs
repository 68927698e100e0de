//! Curve networks on a curved CAD face (issue 30): a half-cylinder, the
//! shape whose quads came out inverted on i02o_m2 and i04o_m4. Its outer
//! loop is two 180° arcs joined by two axial lines; each arc is split into
//! pieces (turn ≤ 100°), and bridged in the arcs' own plane the pieces of
//! one arc paired with each other across the flat half-disk, so the Coons
//! patches cut through the cylinder. With the face's surface in the cycle,
//! bridge directions are n_CAD × tangent: along the axis, across the band.

use geometry::primitives;
use geometry::vec3::{self, Vec3};
use geometry::Model;
use quadrille::curvenet::{network_from_model, pair_cycle, PairedCycle, PairingOptions};
use quadrille::methods::curvenet::{mesh_curve_network, CurvesOptions};

/// Radius and height of i02o_m2's face 20 (a short half-cylinder).
const R: f64 = 2.37;
const H: f64 = 0.76;

/// The half-cylinder x² + y² = R², y ≥ 0, 0 ≤ z ≤ H, normal outward
/// ([`primitives::half_cylinder`]: the arc at z = 0 is curve 0, the line at
/// x = −R curve 1, the arc at z = H curve 2, the line at x = R curve 3).
fn half_cylinder() -> Model {
    primitives::half_cylinder(R, H)
}

/// Which boundary curve point `p` lies on (the numbering of
/// [`half_cylinder`]), or `None` for a point on none.
fn curve_of(p: Vec3) -> Option<usize> {
    // arcs are sampled as polylines (≤ 5° a segment: sagitta < 1e-3 R)
    let on_arc = ((p[0] * p[0] + p[1] * p[1]).sqrt() - R).abs() < 1e-3 * R && p[1] > 1e-6;
    let tol = 1e-9;
    match () {
        _ if on_arc && p[2].abs() < tol => Some(0),
        _ if on_arc && (p[2] - H).abs() < tol => Some(2),
        _ if p[1].abs() < tol && (p[0] + R).abs() < tol => Some(1),
        _ if p[1].abs() < tol && (p[0] - R).abs() < tol => Some(3),
        _ => None,
    }
}

/// The curve segment `s` of `paired` lies on, judged at its middle point.
fn segment_curve(paired: &PairedCycle, s: usize) -> Option<usize> {
    let n = paired.points.len();
    let k = paired.starts.len();
    let (a, b) = (paired.starts[s], paired.starts[(s + 1) % k]);
    let len = (b + n - a) % n;
    curve_of(paired.points[(a + len / 2) % n])
}

/// The pairs `(curve, curve)` of a pairing.
fn paired_curves(paired: &PairedCycle) -> Vec<(Option<usize>, Option<usize>)> {
    paired
        .pairs
        .iter()
        .map(|&(i, j)| (segment_curve(paired, i), segment_curve(paired, j)))
        .collect()
}

#[test]
fn the_half_cylinder_pairs_across_its_band_not_across_the_half_disk() {
    let model = half_cylinder();
    let (net, skipped) = network_from_model(&model, None).unwrap();
    assert!(skipped.is_empty());
    let loops = net.cycle_loops(0).unwrap();
    assert!(
        loops.surface.is_some(),
        "a CAD cycle carries its face's surface"
    );
    let opts = PairingOptions::default();

    // the cause, with the curves alone: a pair of pieces of one arc
    let alone = quadrille::curvenet::CycleLoops {
        surface: None,
        ..loops.clone()
    };
    let (paired, _) = pair_cycle(&alone, &opts).unwrap();
    let curves = paired_curves(&paired);
    assert!(
        curves.iter().all(|(a, b)| a.is_some() && b.is_some()),
        "{curves:?}"
    );
    assert!(
        curves.iter().any(|(a, b)| a == b),
        "without the surface an arc pairs with itself: {curves:?}"
    );

    // with the surface: every chord joins two different curves, each arc
    // piece the other arc
    let (paired, _) = pair_cycle(&loops, &opts).unwrap();
    let curves = paired_curves(&paired);
    assert!(
        paired.starts.len() >= 6,
        "the arcs are split: {} segments",
        paired.starts.len()
    );
    for &(a, b) in &curves {
        let (a, b) = (a.unwrap(), b.unwrap());
        assert_ne!(a, b, "{curves:?}");
        if a % 2 == 0 || b % 2 == 0 {
            assert_eq!(
                (a.min(b), a.max(b)),
                (0, 2),
                "an arc piece bridges to the other arc: {curves:?}"
            );
        }
    }
}

#[test]
fn the_half_cylinder_is_meshed_on_its_surface_with_no_cad_inverted_quad() {
    let model = half_cylinder();
    let (net, _) = network_from_model(&model, None).unwrap();
    let opts = CurvesOptions {
        threads: Some(1),
        ..CurvesOptions::default()
    };
    let (mesh, report) = mesh_curve_network(&net, &opts).unwrap();
    assert!(report.skipped.is_empty());
    assert!(
        !report.cycles[0].midpoint_layout,
        "{:?}",
        report.cycles[0].notes
    );
    assert!(mesh.quads.len() >= 12, "{} quads", mesh.quads.len());
    // every interior node on the cylinder (projected), boundary nodes on
    // the curves' polylines (sagitta < 1e-3 R)
    for (v, p) in mesh.nodes.iter().enumerate() {
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let tol = if mesh.is_face_interior(v) { 1e-9 } else { 1e-3 };
        assert!((r - R).abs() < tol * R, "node {p:?} at r = {r}");
        assert!(
            p[1] > -1e-9 && p[2] > -1e-9 && p[2] < H + 1e-9,
            "node {p:?} off the face"
        );
    }
    // the CAD normal is radial, outward; every corner SICN with it is > 0
    let mut worst = f64::INFINITY;
    for q in &mesh.quads {
        let p = q.map(|v| mesh.nodes[v as usize]);
        let n = p.map(|x| vec3::normalize([x[0], x[1], 0.0]).unwrap());
        worst = worst.min(mesh::quality::quad_sicn(&p, &n));
        assert!(mesh::quality::quad_element_sicn(&p) > 0.0, "{p:?}");
    }
    assert!(
        worst > 0.0,
        "a quad is inverted against the CAD normals (min corner SICN {worst})"
    );
}
