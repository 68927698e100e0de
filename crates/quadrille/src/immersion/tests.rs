//! The whole geometric core (shell → Ricci → cut → immersion) on shells
//! built here: squares, curved disks, annuli, and the bad-input errors.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::time::Instant;

use super::*;
use crate::cut::{cut_to_disk, CutTarget};
use crate::ricci::{ricci_flow, Cone, RicciError, RicciOptions};
use crate::shell::tests::grid;

/// What one run measured (printed as a table row).
struct Run {
    topo: ShellTopology,
    metric: RicciMetric,
    cut: CutMesh,
    immersion: Immersion,
}

fn run(name: &str, shell: &Shell, cones: &[Cone]) -> Run {
    let t0 = Instant::now();
    let topo = shell.check().expect("a valid open shell");
    let metric =
        ricci_flow(shell, &topo, cones, &RicciOptions::default()).expect("Ricci converges");
    let t_ricci = t0.elapsed();
    let cut = cut_to_disk(shell, &topo, cones).expect("a disk");
    let immersion = immerse(shell, &topo, &cut, &metric).expect("an immersion");
    let total = t0.elapsed();
    let angle = immersion
        .transitions
        .iter()
        .map(|t| t.angle_error)
        .fold(0.0, f64::max);
    let shift = immersion
        .transitions
        .iter()
        .map(|t| t.translation_error)
        .fold(0.0, f64::max);
    let indices: Vec<i32> = cones.iter().map(|c| c.index).collect();
    eprintln!(
        "| {name} | {} | {} | {} | {} | {indices:?} | {} | {:.2e} | {:.3} s ({:.3} s Ricci) | {:.3e} | {} paths, quarter turns {:?}, max angle err {:.1e}, max shift err {:.1e} |",
        shell.vertices.len(),
        shell.triangles.len(),
        topo.boundary_loops.len(),
        topo.euler,
        metric.iterations,
        metric.max_error,
        total.as_secs_f64(),
        t_ricci.as_secs_f64(),
        immersion.min_area_ratio,
        cut.paths.len(),
        immersion.transitions.iter().map(|t| t.quarter_turns).collect::<Vec<_>>(),
        angle,
        shift,
    );
    Run {
        topo,
        metric,
        cut,
        immersion,
    }
}

fn corner_cones(n: usize) -> Vec<Cone> {
    [0, n, (n + 1) * (n + 1) - 1, n * (n + 1)]
        .iter()
        .map(|&vertex| Cone { vertex, index: 1 })
        .collect()
}

/// Checks common to every converged run.
fn assert_converged(r: &Run) {
    assert!(r.metric.max_error < 1e-9, "{}", r.metric.max_error);
    assert!(r.metric.iterations <= 100);
    assert!(r
        .metric
        .history
        .windows(2)
        .all(|w| w[1] <= w[0] * (1.0 + 1e-12) + 1e-15));
    assert_eq!(r.cut.euler, 1);
    assert!(
        r.immersion.min_signed_area > 0.0,
        "{}",
        r.immersion.min_signed_area
    );
    assert!(
        r.immersion.loop_axis_spread.iter().all(|&e| e < 1e-8),
        "{:?}",
        r.immersion.loop_axis_spread
    );
    for t in &r.immersion.transitions {
        assert!(t.angle_error < 1e-8, "{t:?}");
        assert!(t.translation_error < 1e-8, "{t:?}");
    }
}

/// The area of `r`'s flat image: its triangles' signed areas summed.
fn flat_area(r: &Run) -> f64 {
    r.cut
        .corners
        .iter()
        .map(|c| {
            signed_area(
                r.immersion.uv[c[0]],
                r.immersion.uv[c[1]],
                r.immersion.uv[c[2]],
            )
        })
        .sum()
}

fn bounding_box(uv: &[[f64; 2]]) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in uv {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    b
}

#[test]
fn a_flat_square_with_four_corner_cones_immerses_as_a_square() {
    let n = 12;
    let shell = grid(n, |x, y| [2.0 * x, 2.0 * y, 0.0]);
    let r = run("flat square", &shell, &corner_cones(n));
    assert_converged(&r);
    // No interior cone and one loop: nothing to cut.
    assert!(r.cut.branches.is_empty() && r.cut.paths.is_empty());
    assert_eq!(r.cut.parent.len(), shell.vertices.len());
    assert!(
        r.immersion.boundary_axis_error < 1e-8,
        "{}",
        r.immersion.boundary_axis_error
    );
    // A 2 × 2 square: every boundary vertex on a side of the bounding box.
    let b = bounding_box(&r.immersion.uv);
    assert!(
        (b[2] - b[0] - 2.0).abs() < 1e-8 && (b[3] - b[1] - 2.0).abs() < 1e-8,
        "{b:?}"
    );
    for loop_v in &r.topo.boundary_loops[0] {
        let child = r.cut.parent.iter().position(|p| p == loop_v).unwrap();
        let p = r.immersion.uv[child];
        let off = [p[0] - b[0], b[2] - p[0], p[1] - b[1], b[3] - p[1]];
        assert!(
            off.iter().any(|d| d.abs() < 1e-8),
            "{p:?} off the square {b:?}"
        );
    }
}

fn curved_disk(name: &str, lift: impl Fn(f64, f64) -> [f64; 3]) {
    let n = 16;
    let shell = grid(n, lift);
    let cones = corner_cones(n);
    let r = run(name, &shell, &cones);
    assert_converged(&r);
    assert!(r.metric.iterations >= 1, "a curved disk needs Newton steps");
    assert!(
        r.immersion.boundary_axis_error < 1e-8,
        "{}",
        r.immersion.boundary_axis_error
    );
    // Curvature hits the targets: π/2 at the corners, 0 elsewhere.
    for (v, k) in r.metric.curvature.iter().enumerate() {
        let want = if cones.iter().any(|c| c.vertex == v) {
            FRAC_PI_2
        } else {
            0.0
        };
        assert!((k - want).abs() < 1e-9, "vertex {v}: K = {k}");
    }
    // The flat image keeps the 3D area.
    let area = flat_area(&r);
    assert!((area - shell.area()).abs() < 1e-9 * shell.area());
    // The image of a disk with four right-angle corners and straight sides
    // is a rectangle: its area equals its bounding box's.
    let b = bounding_box(&r.immersion.uv);
    assert!(
        ((b[2] - b[0]) * (b[3] - b[1]) - area).abs() < 1e-7 * area,
        "{b:?} vs {area}"
    );
}

#[test]
fn a_spherical_cap_with_four_corner_cones_flattens_to_a_rectangle() {
    curved_disk("spherical cap", |x, y| {
        let (x, y) = (2.0 * x - 1.0, 2.0 * y - 1.0);
        [x, y, (4.0 - x * x - y * y).sqrt()]
    });
}

#[test]
fn a_saddle_with_four_corner_cones_flattens_to_a_rectangle() {
    curved_disk("saddle", |x, y| {
        let (x, y) = (2.0 * x - 1.0, 2.0 * y - 1.0);
        [x, y, 0.4 * (x * x - y * y)]
    });
}

/// A ring of `rings` × `sectors` quads between radii 1 and 2, flat or rolled
/// into a tube; returns the shell and the cones +1 and −1 on the middle ring.
fn annulus(tube: bool, rings: usize, sectors: usize) -> (Shell, Vec<Cone>) {
    let mut vertices = Vec::new();
    for i in 0..=rings {
        for j in 0..sectors {
            let t = TAU * j as f64 / sectors as f64;
            let s = i as f64 / rings as f64;
            vertices.push(if tube {
                [t.cos(), t.sin(), 1.5 * s]
            } else {
                [(1.0 + s) * t.cos(), (1.0 + s) * t.sin(), 0.0]
            });
        }
    }
    let id = |i: usize, j: usize| i * sectors + j % sectors;
    let mut quads = Vec::new();
    for i in 0..rings {
        for j in 0..sectors {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mid = rings / 2;
    let cones = vec![
        Cone {
            vertex: id(mid, 0),
            index: 1,
        },
        Cone {
            vertex: id(mid, sectors / 2),
            index: -1,
        },
    ];
    (Shell::from_quad_mesh(vertices, &quads), cones)
}

fn annulus_case(name: &str, tube: bool) {
    let (shell, cones) = annulus(tube, 8, 48);
    let r = run(name, &shell, &cones);
    assert_eq!((r.topo.boundary_loops.len(), r.topo.euler), (2, 0));
    assert_converged(&r);
    // One loop cut and one cut per interior cone.
    let loops = r
        .cut
        .branches
        .iter()
        .filter(|b| matches!(b.target, CutTarget::Loop(_)))
        .count();
    let to_cones: Vec<usize> = r
        .cut
        .branches
        .iter()
        .filter_map(|b| match b.target {
            CutTarget::Cone(v) => Some(v),
            _ => None,
        })
        .collect();
    assert_eq!(loops, 1);
    assert_eq!(to_cones.len(), 2);
    for c in &cones {
        assert!(to_cones.contains(&c.vertex));
        // A cut goes to a cone, not through it: a leaf with one child.
        assert_eq!(r.cut.parent.iter().filter(|&&p| p == c.vertex).count(), 1);
    }
    assert!(!r.cut.paths.is_empty());
    // The loop transitions and the cone transitions are quarter turns; the
    // path ending at the +1 cone turns by ±π/2 (its holonomy).
    assert!(r
        .immersion
        .transitions
        .iter()
        .any(|t| t.quarter_turns % 2 == 1));
}

#[test]
fn a_flat_ring_with_cones_plus_and_minus_one_is_cut_and_laid_out_seamlessly() {
    annulus_case("flat ring", false);
}

#[test]
fn a_tube_with_cones_plus_and_minus_one_is_cut_and_laid_out_seamlessly() {
    annulus_case("tube", true);
}

#[test]
fn a_wrong_index_sum_names_both_sums() {
    let n = 4;
    let shell = grid(n, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    let cones = &corner_cones(n)[..3];
    let err = ricci_flow(&shell, &topo, cones, &RicciOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            RicciError::IndexSum {
                index_sum: 3,
                needed: 4,
                euler: 1,
                ..
            }
        ),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("Σ I = 3") && msg.contains("4χ = 4") && msg.contains(&format!("{:.6}", TAU)),
        "{msg}"
    );
}

#[test]
fn bad_cones_are_errors() {
    let n = 4;
    let shell = grid(n, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    let o = RicciOptions::default();
    let mut cones = corner_cones(n);
    cones[0].index = 2; // boundary: target angle 0
    assert!(matches!(
        ricci_flow(&shell, &topo, &cones, &o),
        Err(RicciError::ConeAngle { index: 2, .. })
    ));
    let mut cones = corner_cones(n);
    cones[1].vertex = cones[0].vertex;
    assert!(matches!(
        ricci_flow(&shell, &topo, &cones, &o),
        Err(RicciError::DuplicateCone { .. })
    ));
    cones[1].vertex = 999;
    assert!(matches!(
        ricci_flow(&shell, &topo, &cones, &o),
        Err(RicciError::ConeVertex { vertex: 999, .. })
    ));
}

#[test]
fn an_unreachable_tolerance_reports_iterations_and_the_worst_vertex() {
    let shell = grid(8, |x, y| [x, y, 0.3 * x * y]);
    let topo = shell.check().unwrap();
    let o = RicciOptions {
        tolerance: 1e-9,
        max_iterations: 1,
    };
    let err = ricci_flow(&shell, &topo, &corner_cones(8), &o).unwrap_err();
    match err {
        RicciError::NotConverged {
            iterations,
            residual,
            ..
        } => {
            assert_eq!(iterations, 1);
            assert!(residual >= 1e-9);
        }
        e => panic!("{e}"),
    }
}

#[test]
fn a_20k_triangle_cap_runs_the_whole_core() {
    let n = 100;
    let shell = grid(n, |x, y| {
        let (x, y) = (2.0 * x - 1.0, 2.0 * y - 1.0);
        [x, y, (4.0 - x * x - y * y).sqrt()]
    });
    assert_eq!(shell.triangles.len(), 20_000);
    let r = run("20k cap", &shell, &corner_cones(n));
    assert_converged(&r);
    assert!(r.immersion.boundary_axis_error < 1e-8);
    let (tube, cones) = annulus(true, 50, 200);
    assert_eq!(tube.triangles.len(), 20_000);
    let r = run("20k tube", &tube, &cones);
    assert_converged(&r);
}

#[test]
fn a_plate_with_a_square_hole_and_an_interior_cone_pair_is_seamless() {
    // 12 × 12 grid over [0, 3]² without its middle 4 × 4 quads.
    let n = 12;
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            vertices.push([3.0 * i as f64 / n as f64, 3.0 * j as f64 / n as f64, 0.0]);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut quads = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if !((4..8).contains(&i) && (4..8).contains(&j)) {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    // Drop the hole's unused vertices, renumbering the rest.
    let mut new_id = vec![usize::MAX; vertices.len()];
    let mut kept = Vec::new();
    for q in &mut quads {
        for v in q.iter_mut() {
            if new_id[*v] == usize::MAX {
                new_id[*v] = kept.len();
                kept.push(vertices[*v]);
            }
            *v = new_id[*v];
        }
    }
    let shell = Shell::from_quad_mesh(kept, &quads);
    let cone = |i: usize, j: usize, index: i32| Cone {
        vertex: new_id[id(i, j)],
        index,
    };
    let mut cones: Vec<Cone> = [(0, 0), (n, 0), (n, n), (0, n)]
        .map(|(i, j)| cone(i, j, 1))
        .to_vec();
    // The hole's reentrant corners (270°) keep index −1.
    cones.extend([(4, 4), (8, 4), (8, 8), (4, 8)].map(|(i, j)| cone(i, j, -1)));
    cones.push(cone(2, 6, 1));
    cones.push(cone(10, 6, -1));
    let r = run("plate with hole", &shell, &cones);
    assert_eq!((r.topo.boundary_loops.len(), r.topo.euler), (2, 0));
    assert_converged(&r);
    // Each loop is straight with quarter-turn corners; the hole may stay
    // rotated against the outer square (reported, for the layout energy).
    eprintln!(
        "plate with hole: loop spreads {:?}, overall axis error {:.3}",
        r.immersion.loop_axis_spread, r.immersion.boundary_axis_error
    );
    assert!(
        r.immersion.loop_axis_spread.iter().all(|&e| e < 1e-8),
        "{:?}",
        r.immersion.loop_axis_spread
    );
    let loops = r
        .cut
        .branches
        .iter()
        .filter(|b| matches!(b.target, CutTarget::Loop(_)))
        .count();
    assert_eq!((loops, r.cut.branches.len()), (1, 3));
}

/// Largest |ψ length − Ricci length| / Ricci length over the edges of Ω.
fn worst_edge_error(r: &Run) -> f64 {
    let mut worst: f64 = 0.0;
    for (f, c) in r.cut.corners.iter().enumerate() {
        let l = r.metric.triangle_lengths(&r.topo, f);
        for k in 0..3 {
            let (p, q) = (r.immersion.uv[c[k]], r.immersion.uv[c[(k + 1) % 3]]);
            let planar = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            worst = worst.max((planar / r.immersion.scale - l[k]).abs() / l[k]);
        }
    }
    worst
}

/// Issue 31's check on a long thin torus strip (a fillet, 4 × 400 quads,
/// about 31 × 1 in ψ): every edge of Ω keeps its Ricci length within 1e-8
/// and the strip is a rectangle. (This strip does not reproduce the issue:
/// the old position-fed unfolding passes it too; the flange fillet in
/// `crates/cli/tests/spline.rs` does.)
#[test]
fn a_long_fillet_strip_keeps_every_ricci_length() {
    let (n, m) = (400, 4);
    let (major, minor) = (20.0, 2.0);
    let mut vertices = Vec::new();
    for j in 0..=m {
        for i in 0..=n {
            let a = 1.6 * i as f64 / n as f64;
            let b = FRAC_PI_2 * j as f64 / m as f64;
            let rr = major + minor * b.cos();
            vertices.push([rr * a.cos(), rr * a.sin(), minor * b.sin()]);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut quads = Vec::new();
    for j in 0..m {
        for i in 0..n {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let shell = Shell::from_quad_mesh(vertices, &quads);
    let cones: Vec<Cone> = [id(0, 0), id(n, 0), id(n, m), id(0, m)]
        .iter()
        .map(|&vertex| Cone { vertex, index: 1 })
        .collect();
    let r = run("fillet strip 4 × 400", &shell, &cones);
    assert!(r.metric.max_error < 1e-9, "{}", r.metric.max_error);
    let worst = worst_edge_error(&r);
    assert!(worst < 1e-8, "worst edge error {worst:e}");
    let area = flat_area(&r);
    let b = bounding_box(&r.immersion.uv);
    let (w, h) = (
        (b[2] - b[0]).max(b[3] - b[1]),
        (b[2] - b[0]).min(b[3] - b[1]),
    );
    assert!(w > 10.0 * h, "a long strip: {w} × {h}");
    assert!(
        ((b[2] - b[0]) * (b[3] - b[1]) - area).abs() < 1e-7 * area,
        "{b:?} vs {area}"
    );
}

/// A metric that is not flat at one interior vertex cannot be laid out:
/// the check refuses it instead of returning a wrong layout.
#[test]
fn a_metric_with_a_bent_vertex_is_refused_by_the_length_check() {
    let n = 8;
    let shell = grid(n, |x, y| [x, y, 0.0]);
    let cones = corner_cones(n);
    let topo = shell.check().expect("a valid open shell");
    let mut metric =
        ricci_flow(&shell, &topo, &cones, &RicciOptions::default()).expect("Ricci converges");
    let cut = cut_to_disk(&shell, &topo, &cones).expect("a disk");
    assert!(immerse(&shell, &topo, &cut, &metric).is_ok());
    // Lengthen one interior edge by 2 %: its ends are no longer flat.
    let centre = (n / 2) * (n + 1) + n / 2;
    let e = topo.edge(centre, centre + 1).expect("an interior edge");
    metric.lengths[e] *= 1.02;
    match immerse(&shell, &topo, &cut, &metric) {
        Err(ImmersionError::Inconsistent { relative, .. }) => {
            assert!(relative > INCONSISTENCY_LIMIT, "{relative}")
        }
        other => panic!("expected the length check to refuse, got {other:?}"),
    }
}
