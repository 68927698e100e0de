//! The figure tests, end to end: each figure cycle segmented and
//! paired (§3.1), laid out and sampled (§3.2); counts of segments, patches
//! and interior layout vertices, and every dense quad valid.

use geometry::vec3::{self, cross, sub};

use super::fixtures;
use super::{pair_cycle, quadrangulate, CycleLoops, CycleQuads, PairingOptions, PairingReport};

/// Runs the pipeline on `cycle` at edge length `h` (in the cycle's units).
fn run(cycle: &CycleLoops, h: f64) -> (usize, PairingReport, CycleQuads) {
    let (paired, report) = pair_cycle(cycle, &PairingOptions::default()).unwrap();
    let quads = quadrangulate(&paired, h).unwrap();
    (paired.starts.len(), report, quads)
}

/// Smallest corner Jacobian sign test of the dense quads against `normal`
/// (planar cycles) or against each quad's neighbours' mean normal: the
/// minimum over quads of the corner cross products' component along it,
/// scaled by the corner edge lengths (the scaled Jacobian).
fn min_scaled_jacobian(q: &CycleQuads, normal: Option<[f64; 3]>) -> f64 {
    let mut worst = f64::INFINITY;
    for quad in &q.quads {
        let p = quad.map(|v| q.nodes[v]);
        let n = normal.unwrap_or_else(|| {
            vec3::normalize(cross(sub(p[2], p[0]), sub(p[3], p[1]))).unwrap_or([0.0, 0.0, 1.0])
        });
        for k in 0..4 {
            let a = sub(p[(k + 1) % 4], p[k]);
            let b = sub(p[(k + 3) % 4], p[k]);
            let j = vec3::dot(n, cross(a, b)) / (vec3::norm(a) * vec3::norm(b));
            worst = worst.min(j);
        }
    }
    worst
}

const UP: Option<[f64; 3]> = Some([0.0, 0.0, 1.0]);

/// Segments, patches and interior layout valences of a figure cycle, with
/// every dense quad valid (scaled Jacobian > 0).
fn counts(cycle: &CycleLoops, normal: Option<[f64; 3]>) -> (usize, usize, Vec<usize>, PairingReport) {
    let (segments, report, q) = run(cycle, 0.1);
    let sj = min_scaled_jacobian(&q, normal);
    assert!(sj > 0.0, "min scaled Jacobian {sj}");
    (segments, q.patches, q.interior_vertex_valences.clone(), report)
}

#[test]
fn saddle_fig_4_is_one_patch() {
    let (s, p, v, _) = counts(&fixtures::saddle(0.5), None);
    assert_eq!((s, p, v), (4, 1, vec![]));
}

#[test]
fn triangle_and_octant_fig_12_are_three_patches_around_a_valence_3_vertex() {
    for (c, n) in [(fixtures::triangle(), UP), (fixtures::octant(60), None)] {
        let (s, p, v, r) = counts(&c, n);
        assert_eq!((s, p, v), (6, 3, vec![3]));
        assert_eq!(r.odd_parties.len(), 1);
    }
    // the octant's valence-3 vertex lies on its symmetry axis x = y = z
    let (paired, _) = pair_cycle(&fixtures::octant(60), &PairingOptions::default()).unwrap();
    let q = quadrangulate(&paired, 0.1).unwrap();
    let centre = q.layout.positions[q.layout.boundary_vertices];
    assert!((centre[0] - centre[1]).abs() < 1e-6 && (centre[1] - centre[2]).abs() < 1e-6, "{centre:?}");
}

#[test]
fn house_figs_5_and_7_is_two_patches() {
    let (s, p, v, _) = counts(&fixtures::house(), UP);
    assert_eq!((s, p, v), (6, 2, vec![]));
}

#[test]
fn ell_fig_5_bottom_is_three_patches() {
    let (s, p, v, _) = counts(&fixtures::ell(), UP);
    assert_eq!((s, p, v), (8, 3, vec![]));
}

#[test]
fn circle_and_lens_fall_back_to_one_all_quad_patch() {
    for c in [fixtures::circle(200), fixtures::lens(100)] {
        let (s, p, v, r) = counts(&c, UP);
        assert_eq!((s, p, v), (4, 1, vec![]));
        assert_eq!(r.fallbacks.len(), 1);
    }
}
