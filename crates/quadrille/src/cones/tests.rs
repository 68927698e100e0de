//! The cone stage on shells built here (the paper's Figs. 3/8 and 10, a
//! square), its file format and errors, and the proposal on a CAD shell.

use std::f64::consts::TAU;

use super::*;
use crate::methods::spline::cone_core;
use crate::shell::tests::grid;

/// A flat ring of `rings` × `sectors` quads between radii 1 and 2.
fn ring(rings: usize, sectors: usize) -> Shell {
    let mut vertices = Vec::new();
    for i in 0..=rings {
        for j in 0..sectors {
            let (t, s) = (TAU * j as f64 / sectors as f64, i as f64 / rings as f64);
            vertices.push([(1.0 + s) * t.cos(), (1.0 + s) * t.sin(), 0.0]);
        }
    }
    let id = |i: usize, j: usize| i * sectors + j % sectors;
    let mut quads = Vec::new();
    for i in 0..rings {
        for j in 0..sectors {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Shell::from_quad_mesh(vertices, &quads)
}

/// The 6 × 6 plate of Fig. 10 with a round hole (radius 0.6 about
/// (3, 1.8)): `sectors` spokes from the circle to the square (the ray from
/// (3, 3); the square's corners are spokes 1/8, 3/8, … of the way round),
/// `rings` rings between.
fn plate_with_round_hole(rings: usize, sectors: usize) -> Shell {
    let mut vertices = Vec::new();
    for i in 0..=rings {
        for j in 0..sectors {
            let a = TAU * j as f64 / sectors as f64;
            let (c, s) = (a.cos(), a.sin());
            let m = c.abs().max(s.abs());
            let square = [3.0 + 3.0 * c / m, 3.0 + 3.0 * s / m];
            let circle = [3.0 + 0.6 * c, 1.8 + 0.6 * s];
            let w = i as f64 / rings as f64;
            vertices.push([
                (1.0 - w) * circle[0] + w * square[0],
                (1.0 - w) * circle[1] + w * square[1],
                0.0,
            ]);
        }
    }
    let id = |i: usize, j: usize| i * sectors + j % sectors;
    let mut quads = Vec::new();
    for i in 0..rings {
        for j in 0..sectors {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Shell::from_quad_mesh(vertices, &quads)
}

fn nearest(shell: &Shell, p: [f64; 3]) -> usize {
    (0..shell.vertices.len())
        .min_by(|&a, &b| {
            geometry::vec3::dist(shell.vertices[a], p)
                .total_cmp(&geometry::vec3::dist(shell.vertices[b], p))
        })
        .unwrap()
}

#[test]
fn fig_3_8_an_annulus_with_cones_plus_and_minus_one_converges_with_quarter_turn_cuts() {
    let shell = ring(8, 48);
    let topo = shell.check().unwrap();
    assert_eq!((topo.euler, topo.boundary_loops.len()), (0, 2));
    // The mid ring is i = 4: vertices 4·48 + j.
    let (plus, minus) = (4 * 48, 4 * 48 + 24);
    let cones = [
        Cone {
            vertex: plus,
            index: 1,
        },
        Cone {
            vertex: minus,
            index: -1,
        },
    ];
    let s = check_cones(&shell, &topo, &cones, "test").unwrap();
    assert_eq!((s.plus, s.minus, s.boundary, s.index_sum()), (1, 1, 0, 0));
    let core = cone_core(&shell, &topo, &cones).unwrap();
    eprintln!("Fig. 3/8: {}", core.describe());
    assert!(core.metric.max_error < 1e-9, "{}", core.metric.max_error);
    assert!(core.metric.iterations <= 100);
    // The one-rings were refined: every spoke of each cone split once.
    let spokes = topo
        .edges
        .iter()
        .filter(|e| e.contains(&plus) || e.contains(&minus))
        .count();
    assert!(spokes >= 12);
    assert_eq!(core.shell.vertices.len(), shell.vertices.len() + spokes);
    assert_eq!(core.cut.euler, 1);
    assert_eq!(core.loop_cuts(), 1);
    for t in &core.immersion.transitions {
        assert!(t.angle_error < 1e-8, "{t:?}");
    }
    for c in &cones {
        let at = core.transitions_at(c.vertex);
        assert_eq!(at.len(), 1, "one cut path ends at cone {c:?}");
        assert_eq!(at[0].quarter_turns % 2, 1, "{c:?}: a ±1 cone turns by ±π/2");
    }
    // The proposal on the flat ring: its field (the polar one) has no singularity.
    let proposal = propose_cones(&shell, &topo).unwrap();
    assert!(proposal.is_empty(), "{proposal:?}");
}

#[test]
fn fig_10_a_plate_with_a_hole_and_cones_minus_one_minus_one_minus_two_gets_hol_1_3_and_hol_2_cuts()
{
    let shell = plate_with_round_hole(24, 64);
    let topo = shell.check().unwrap();
    assert_eq!((topo.euler, topo.boundary_loops.len()), (0, 2));
    // Corners and interior cones given as a cone file (points off the
    // vertices by a little: they snap).
    let text = "# Fig. 10: four boundary +1, two -1, one -2\n\
        0 0 0 1\n6 0 0 1\n6 6 0 1\n0 6 0 1   # corners\n\
        1.0 4.6 0.01 -1\n5.0 4.6 0 -1\n\n3.0 5.0 0 -2\n";
    let cones = parse_cones(text, "fig10.cones", &shell, &topo).unwrap();
    let s = ConeSummary::of(&topo, &cones);
    assert_eq!(
        (
            s.minus,
            s.other_interior,
            s.boundary,
            s.boundary_sum,
            s.index_sum()
        ),
        (2, 1, 4, 4, 0)
    );
    // The corners snapped onto the square's corners, whose index is +1.
    let corners = crate::ricci::boundary_corner_cones(&shell, &topo);
    assert_eq!(corners.len(), 4);
    for c in &corners {
        assert!(cones.contains(c), "{c:?}");
    }
    let core = cone_core(&shell, &topo, &cones).unwrap();
    eprintln!("Fig. 10: {}", core.describe());
    assert!(core.metric.max_error < 1e-9 && core.metric.iterations <= 100);
    assert_eq!(core.cut.euler, 1);
    assert_eq!(core.loop_cuts(), 1);
    assert!(core.immersion.min_signed_area > 0.0);
    for t in &core.immersion.transitions {
        assert!(t.angle_error < 1e-8, "{t:?}");
        assert!(t.translation_error < 1e-8, "{t:?}");
    }
    for c in cones.iter().filter(|c| !topo.on_boundary[c.vertex]) {
        let at = core.transitions_at(c.vertex);
        assert_eq!(at.len(), 1, "{c:?}");
        let k = at[0].quarter_turns;
        match c.index {
            -1 => assert!(k == 1 || k == 3, "{c:?}: k = {k} (Hol1/Hol3)"),
            -2 => assert_eq!(k, 2, "{c:?}: Hol2"),
            _ => unreachable!(),
        }
    }
}

#[test]
fn a_square_gets_its_four_corner_cones_and_no_interior_cone() {
    for (name, shell) in [
        ("flat", grid(10, |x, y| [x, y, 0.0])),
        (
            "cap",
            grid(12, |x, y| {
                let (x, y) = (2.0 * x - 1.0, 2.0 * y - 1.0);
                [x, y, (4.0 - x * x - y * y).sqrt()]
            }),
        ),
    ] {
        let topo = shell.check().unwrap();
        let cones = propose_cones(&shell, &topo).unwrap();
        let n = if name == "flat" { 10 } else { 12 };
        let corners = [0, n, (n + 1) * (n + 1) - 1, n * (n + 1)];
        assert_eq!(cones.len(), 4, "{name}: {cones:?}");
        for c in &cones {
            assert!(corners.contains(&c.vertex) && c.index == 1, "{name}: {c:?}");
        }
    }
}

#[test]
fn the_written_file_reads_back_to_the_same_cones() {
    let shell = plate_with_round_hole(12, 32);
    let topo = shell.check().unwrap();
    let mut cones = crate::ricci::boundary_corner_cones(&shell, &topo);
    let a = nearest(&shell, [1.0, 4.6, 0.0]);
    let b = nearest(&shell, [5.0, 4.6, 0.0]);
    cones.push(Cone {
        vertex: a,
        index: 1,
    });
    cones.push(Cone {
        vertex: b,
        index: -1,
    });
    cones.push(Cone {
        vertex: nearest(&shell, [3.0, 5.0, 0.0]),
        index: -4,
    });
    cones.sort_by_key(|c| c.vertex);
    // Σ I = 4 + 1 − 1 − 4 = 0 = 4χ.
    let text = format_cones(&shell, &topo, &cones);
    assert_eq!(text.lines().filter(|l| !l.starts_with('#')).count(), 7);
    assert!(text.contains("Σ I = 0, 4χ = 0"), "{text}");
    assert_eq!(parse_cones(&text, "x", &shell, &topo).unwrap(), cones);
    let dir = std::env::temp_dir().join(format!("quadrille-cones-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("c.cones");
    write_cones(&path, &text).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    let missing = dir.join("no/such/dir/c.cones");
    assert!(matches!(
        write_cones(&missing, &text),
        Err(ConeError::Io { .. })
    ));
    assert!(!missing.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_cone_files_name_the_line() {
    let shell = grid(4, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    let corners = "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n";
    let line = |text: &str| match parse_cones(text, "f.cones", &shell, &topo) {
        Err(ConeError::Line { line, message, .. }) => (line, message),
        other => panic!("{other:?}"),
    };
    let (l, m) = line(&format!("# corners\n{corners}0.5 0.5 0\n"));
    assert_eq!(l, 6);
    assert!(m.contains("found 3 field"), "{m}");
    let (l, m) = line(&format!("{corners}0.5 zero 0 1\n"));
    assert_eq!(l, 5);
    assert!(m.contains("\"zero\""), "{m}");
    let (l, m) = line(&format!("{corners}0.5 0.5 0 1.5\n"));
    assert_eq!(l, 5);
    assert!(m.contains("whole number"), "{m}");
    // Mean edge ≈ 0.27 (0.25 sides, 0.35 diagonals): 2 sizes ≈ 0.54.
    let (l, m) = line(&format!("{corners}0.5 0.5 0.9 1\n"));
    assert_eq!(l, 5);
    assert!(m.contains("from the nearest shell vertex"), "{m}");
    let (l, m) = line(&format!("{corners}0.02 0.01 0 -1\n"));
    assert_eq!(l, 5);
    assert!(m.contains("like line 1"), "{m}");
    // Whole-set errors: the sums, and the caps.
    let err = parse_cones(&corners[..24], "f.cones", &shell, &topo).unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.cones: cone indices break Gauss–Bonnet: Σ I = 3 (0 interior + 3 boundary) but 4χ = 4 (χ = 1)"
    );
    let err = parse_cones(
        "0 0 0 2\n1 0 0 1\n1 1 0 1\n0.5 0.5 0 -1\n",
        "f.cones",
        &shell,
        &topo,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            ConeError::TooLarge {
                index: 2,
                cap: 1,
                where_: "boundary",
                ..
            }
        ),
        "{err}"
    );
    let err = parse_cones("0.5 0.5 0 4\n", "f.cones", &shell, &topo).unwrap_err();
    assert!(
        matches!(
            err,
            ConeError::TooLarge {
                index: 4,
                cap: 3,
                where_: "interior",
                ..
            }
        ),
        "{err}"
    );
    // Index 0 places nothing: the three corners are one short.
    let err = parse_cones(&format!("{}0 1 0 0\n", &corners[..24]), "f", &shell, &topo);
    assert!(matches!(err, Err(ConeError::IndexSum { index_sum: 3, .. })));
}

#[test]
fn the_proposal_on_the_torus_tube_and_drilled_cylinder_sums_to_four_chi() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cad/n10o_qtorus_cyl.step");
    let model = occt::load(&path).expect("n10o loads");
    // Issue 31 shell (c): faces 5 and 7, χ = −1.
    let shell = crate::shell::shell_from_model(&model, &[4, 6], model.diagonal() / 72.0).unwrap();
    let topo = shell.check().unwrap();
    assert_eq!(topo.euler, -1);
    let cones = propose_cones(&shell, &topo).unwrap();
    let s = ConeSummary::of(&topo, &cones);
    eprintln!("n10o faces 5, 7: {} triangles, {s}", shell.triangles.len());
    assert_eq!(s.index_sum(), -4);
    assert!(s.interior() > 0);
    let core = cone_core(&shell, &topo, &cones).unwrap();
    eprintln!("n10o faces 5, 7: {}", core.describe());
    assert!(core.metric.max_error < 1e-9 && core.metric.iterations <= 100);
    for t in &core.immersion.transitions {
        assert!(t.angle_error < 1e-8, "{t:?}");
    }
}
