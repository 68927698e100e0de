use super::*;

/// A flat grid shell: the unit cells (i, j) of an n × n grid of side `h`
/// for which `keep(i, j)` holds, each split into two triangles, mapped by `map`.
pub(crate) fn grid_shell(
    n: usize,
    keep: impl Fn(usize, usize) -> bool,
    map: impl Fn(f64, f64) -> [f64; 3],
) -> Shell {
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            vertices.push(map(i as f64 / n as f64, j as f64 / n as f64));
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if keep(i, j) {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    Shell::from_used_vertices(&vertices, triangles)
}

/// An L-shaped plate in z = 0.3: the square [0, 2]² without [1, 2]².
pub(crate) fn l_plate(n: usize) -> Shell {
    grid_shell(
        n,
        |i, j| !(2 * i >= n && 2 * j >= n),
        |u, v| [2.0 * u, 2.0 * v, 0.3],
    )
}

#[test]
fn the_checked_entry_uses_the_callers_topology_and_gives_the_same_patches() {
    let shell = l_plate(12);
    let topo = shell.check().unwrap();
    let opts = SplineOptions::default();
    let checked = splines_from_checked_shell(&shell, &topo, &opts).unwrap();
    let whole = splines_from_shell(&shell, &opts).unwrap();
    assert_eq!(checked.multipatch.points(), whole.multipatch.points());
    assert_eq!(checked.report.patches, 3);
    assert_eq!(
        (checked.report.control_points, checked.report.boundary_loops),
        (whole.report.control_points, 1)
    );
    // The cut and the immersion are timed on their own.
    let t = &checked.report.times;
    assert!(t.cut > 0.0 && t.immersion > 0.0, "{t:?}");
}

#[test]
fn l_plate_gives_three_watertight_flat_patches() {
    let shell = l_plate(12);
    let r = splines_from_shell(&shell, &SplineOptions::default()).unwrap();
    let rep = &r.report;
    assert_eq!((rep.corners, rep.reflex_corners), (6, 1));
    assert_eq!(rep.separatrices, 2);
    assert_eq!(rep.patches, 3);
    assert_eq!(r.multipatch.patches().len(), 3);
    // two interior arcs, each shared by two patches, bit-identical
    assert_eq!(rep.shared_sides, 2);
    assert_eq!(rep.max_gap, 0.0);
    assert!(rep.min_scaled_jacobian > 0.0, "{}", rep.min_scaled_jacobian);
    let d = rep.diagonal;
    for p in r.multipatch.points() {
        assert!((p[2] - 0.3).abs() < 1e-9 * d, "{p:?}");
    }
    assert!(rep.max_distance < 1e-9 * d);
    // flat: one span is enough
    assert_eq!(rep.segments, 1);
    assert!(rep.ricci_error < 1e-9);
    assert!(rep.boundary_deviation < 1e-6);
}

#[test]
fn quarter_cylinder_is_one_patch_close_to_the_cylinder() {
    let radius = 1.0;
    let shell = grid_shell(
        16,
        |_, _| true,
        |u, v| {
            let a = u * std::f64::consts::FRAC_PI_2;
            [radius * a.cos(), radius * a.sin(), 2.0 * v]
        },
    );
    for interior in [Interior::Coons, Interior::Fit] {
        let opts = SplineOptions {
            interior,
            ..Default::default()
        };
        let r = splines_from_shell(&shell, &opts).unwrap();
        let rep = &r.report;
        assert_eq!((rep.corners, rep.patches, rep.separatrices), (4, 1, 0));
        assert!(rep.tolerance_met, "{rep:?}");
        // the patch against the true cylinder
        let patch = r.multipatch.patch(0).unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..=20 {
            for j in 0..=20 {
                let p = patch.eval(i as f64 / 20.0, j as f64 / 20.0);
                worst = worst.max(((p[0] * p[0] + p[1] * p[1]).sqrt() - radius).abs());
            }
        }
        assert!(worst < rep.tolerance, "{worst} vs {}", rep.tolerance);
        assert!(rep.min_scaled_jacobian > 0.5, "{}", rep.min_scaled_jacobian);
    }
}

#[test]
fn fixed_segments_and_refinement_set_the_net() {
    let shell = l_plate(8);
    let opts = SplineOptions {
        segments: Segments::Fixed(3),
        refine: 2,
        ..Default::default()
    };
    let r = splines_from_shell(&shell, &opts).unwrap();
    for g in r.multipatch.patches() {
        // 3 spans × 2 = 6 spans, cubic: 9 control points per direction
        assert_eq!((g.n_s(), g.n_t()), (9, 9));
    }
    assert_eq!(r.multipatch.shared_sides().max_gap, 0.0);
}

/// A spherical cap over the unit disk (polar rings: a smooth boundary).
pub(crate) fn spherical_cap(rings: usize, sectors: usize) -> Shell {
    let lift = |x: f64, y: f64| [x, y, (3.0 - x * x - y * y).sqrt()];
    let mut vertices = vec![lift(0.0, 0.0)];
    for r in 1..=rings {
        for k in 0..sectors {
            let a = std::f64::consts::TAU * k as f64 / sectors as f64;
            let rr = r as f64 / rings as f64;
            vertices.push(lift(rr * a.cos(), rr * a.sin()));
        }
    }
    let id = |r: usize, k: usize| {
        if r == 0 {
            0
        } else {
            1 + (r - 1) * sectors + k % sectors
        }
    };
    let mut triangles = Vec::new();
    for k in 0..sectors {
        triangles.push([0, id(1, k), id(1, k + 1)]);
    }
    for r in 1..rings {
        for k in 0..sectors {
            triangles.push([id(r, k), id(r + 1, k), id(r + 1, k + 1)]);
            triangles.push([id(r, k), id(r + 1, k + 1), id(r, k + 1)]);
        }
    }
    Shell::from_triangles(vertices, triangles)
}

#[test]
fn a_cap_without_corners_needs_cones() {
    // smooth boundary: no corner, Σ I = 0 ≠ 4
    let shell = spherical_cap(6, 24);
    let e = splines_from_shell(&shell, &SplineOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, SplineMethodError::NeedsCones(_)), "{msg}");
    assert!(
        msg.contains("interior cones") && msg.contains("Σ I = 0") && !msg.contains('\n'),
        "{msg}"
    );
}

#[test]
fn a_plate_with_a_hole_needs_cones() {
    let shell = grid_shell(
        6,
        |i, j| !((2..4).contains(&i) && (2..4).contains(&j)),
        |u, v| [u, v, 0.0],
    );
    let e = splines_from_shell(&shell, &SplineOptions::default()).unwrap_err();
    assert!(matches!(e, SplineMethodError::NeedsCones(_)), "{e}");
}

/// An annulus shell: `sectors` × `rings` cells of the parameters (a, r) ∈
/// [0, 2π) × [0, 1], periodic in a, each cell two triangles, mapped by `map`.
pub(crate) fn periodic_band(
    sectors: usize,
    rings: usize,
    map: impl Fn(f64, f64) -> [f64; 3],
) -> Shell {
    let mut vertices = Vec::new();
    for j in 0..=rings {
        for i in 0..sectors {
            let a = std::f64::consts::TAU * i as f64 / sectors as f64;
            vertices.push(map(a, j as f64 / rings as f64));
        }
    }
    let id = |i: usize, j: usize| j * sectors + i % sectors;
    let mut triangles = Vec::new();
    for j in 0..rings {
        for i in 0..sectors {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Shell::from_triangles(vertices, triangles)
}

/// The left and right control-point columns of patch 0: same indices, and
/// so bit-identical points.
fn assert_seam_closed(mp: &Multipatch) {
    let g = &mp.patches()[0];
    let (left, right) = (g.side(3), g.side(1));
    assert_eq!(left, right, "the seam's two copies are one arc");
    let pts = mp.points();
    for (&l, &r) in left.iter().zip(&right) {
        assert_eq!(pts[l], pts[r]);
    }
    // not a degenerate patch: the seam is not its opposite side's copy
    assert_ne!(g.side(0), g.side(2));
}

#[test]
fn cylinder_side_is_one_patch_closing_along_its_seam() {
    let (radius, height, sectors) = (1.0, 2.0, 64);
    let shell = periodic_band(sectors, 16, |a, r| {
        [radius * a.cos(), radius * a.sin(), height * r]
    });
    // the prism's sides are planar rectangles: a polygon of `sectors` sides
    let sagitta = radius * (1.0 - (std::f64::consts::PI / sectors as f64).cos());
    for refine in [1, 2] {
        let opts = SplineOptions {
            refine,
            ..Default::default()
        };
        let r = splines_from_shell(&shell, &opts).unwrap();
        let rep = &r.report;
        assert_eq!((rep.boundary_loops, rep.corners, rep.patches), (2, 0, 1));
        assert_eq!(r.multipatch.patches().len(), 1);
        let rotation = rep.seam_rotation.unwrap();
        assert!(rotation < 1e-8, "seam rotation {rotation}");
        assert!(rep.tolerance_met, "{rep:?}");
        assert!(rep.min_scaled_jacobian > 0.5, "{}", rep.min_scaled_jacobian);
        assert_seam_closed(&r.multipatch);
        // the seam is the patch's only shared side, with gap 0
        assert_eq!((rep.shared_sides, rep.max_gap), (1, 0.0));
        let patch = r.multipatch.patch(0).unwrap();
        let (mut worst, mut zmin, mut zmax) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=40 {
            for j in 0..=20 {
                let p = patch.eval(i as f64 / 40.0, j as f64 / 20.0);
                worst = worst.max(((p[0] * p[0] + p[1] * p[1]).sqrt() - radius).abs());
                zmin = zmin.min(p[2]);
                zmax = zmax.max(p[2]);
            }
        }
        assert!(worst < rep.tolerance + sagitta, "{worst} vs {}", rep.tolerance);
        assert!(zmin.abs() < 1e-6 && (zmax - height).abs() < 1e-6, "{zmin} {zmax}");
        // the patch goes once around: its s = 1/4 column is a quarter turn from s = 0
        let (p0, p1) = (patch.eval(0.0, 0.5), patch.eval(0.25, 0.5));
        let turn = (p0[0] * p1[0] + p0[1] * p1[1]).clamp(-1.0, 1.0).acos();
        assert!((turn - std::f64::consts::FRAC_PI_2).abs() < 0.02, "{turn}");
    }
}

#[test]
fn flat_ring_is_one_patch_closing_along_its_seam() {
    let (inner, outer) = (1.0, 2.0);
    let shell = periodic_band(48, 8, |a, r| {
        let rr = inner + (outer - inner) * r;
        [rr * a.cos(), rr * a.sin(), 0.5]
    });
    let r = splines_from_shell(&shell, &SplineOptions::default()).unwrap();
    let rep = &r.report;
    assert_eq!((rep.boundary_loops, rep.patches, rep.separatrices), (2, 1, 0));
    assert!(rep.seam_rotation.unwrap() < 1e-8, "{rep:?}");
    assert!(rep.ricci_error < 1e-9);
    assert!(rep.min_scaled_jacobian > 0.0, "{}", rep.min_scaled_jacobian);
    assert!(rep.tolerance_met, "{rep:?}");
    assert_seam_closed(&r.multipatch);
    let d = rep.diagonal;
    for p in r.multipatch.points() {
        assert!((p[2] - 0.5).abs() < 1e-9 * d, "{p:?}");
    }
    // the loops are the circles (up to the 48-gon's sagitta and the tolerance)
    let patch = r.multipatch.patch(0).unwrap();
    let sagitta = outer * (1.0 - (std::f64::consts::PI / 48.0).cos());
    let mut radii = [Vec::new(), Vec::new()];
    for i in 0..=96 {
        for (k, t) in [0.0, 1.0].into_iter().enumerate() {
            let p = patch.eval(i as f64 / 96.0, t);
            radii[k].push((p[0] * p[0] + p[1] * p[1]).sqrt());
        }
    }
    let (lo, hi) = if radii[0][0] < radii[1][0] { (0, 1) } else { (1, 0) };
    for (k, want) in [(lo, inner), (hi, outer)] {
        for &r in &radii[k] {
            assert!((r - want).abs() < sagitta + rep.tolerance, "{r} vs {want}");
        }
    }
}

#[test]
fn an_annulus_with_corners_still_needs_cones() {
    // a square plate with a square hole: two loops, Σ I = 4 − 4 = 0, but corners
    let shell = grid_shell(
        6,
        |i, j| !((2..4).contains(&i) && (2..4).contains(&j)),
        |u, v| [u, v, 0.0],
    );
    let e = splines_from_shell(&shell, &SplineOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, SplineMethodError::NeedsCones(_)), "{msg}");
    assert!(msg.contains("2 boundary loop(s)") && msg.contains("Σ I = 0") && !msg.contains('\n'), "{msg}");
}

#[test]
fn cylinder_layout_is_the_unrolled_prism() {
    // the prism of 64 sides is flat with straight loops already: ψ is it unrolled
    let (sectors, height) = (64, 2.0);
    let shell = periodic_band(sectors, 16, |a, r| [a.cos(), a.sin(), height * r]);
    let l = layout_of_shell(&shell).unwrap();
    let perimeter = sectors as f64 * 2.0 * (std::f64::consts::PI / sectors as f64).sin();
    assert_eq!((l.nodes.len(), l.arcs.len(), l.rects.len()), (4, 3, 1));
    assert_eq!(l.node_glue, vec![0, 1, 0, 1]);
    assert_eq!(l.period_x.map(|c| (c - perimeter).abs() < 1e-9), Some(true), "{:?}", l.period_x);
    let [bl, br, tr, tl] = l.rects[0].corners.map(|k| l.nodes[k]);
    assert!((br[0] - bl[0] - perimeter).abs() < 1e-9 && (tr[0] - tl[0] - perimeter).abs() < 1e-9);
    assert!((tl[1] - bl[1] - height).abs() < 1e-9, "{bl:?} {tl:?}");
    // left and right sides: the one seam arc, vertical; bottom and top: closed loop arcs
    let sides = l.rects[0].sides;
    assert_eq!(sides[2], sides[3]);
    assert_eq!(l.arc_on_boundary, vec![true, true, false]);
    for a in [sides[0].0, sides[1].0] {
        let [s, e] = l.arcs[a];
        assert_eq!(l.node_glue[s], l.node_glue[e], "a loop arc starts and ends on one node");
    }
}
