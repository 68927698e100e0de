//! `quadrille spline`: open shells that need no interior cone (disks whose
//! boundary corners sum to Σ I = 4, annuli with smooth loops) to untrimmed,
//! watertight bicubic B-spline patches; shells needing cones refused with
//! one line, no file.

mod common;

use std::fmt::Write as _;
use std::path::Path;

use common::{assert_clean_failure, cad, quadrille};

/// An OBJ triangle mesh of the grid cells (i, j) of an n × n grid kept by
/// `keep`, mapped by `map` from [0, 1]².
fn grid_obj(
    n: usize,
    keep: impl Fn(usize, usize) -> bool,
    map: impl Fn(f64, f64) -> [f64; 3],
) -> String {
    let mut s = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let p = map(i as f64 / n as f64, j as f64 / n as f64);
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            if keep(i, j) {
                let _ = writeln!(s, "f {} {} {}", id(i, j), id(i + 1, j), id(i + 1, j + 1));
                let _ = writeln!(s, "f {} {} {}", id(i, j), id(i + 1, j + 1), id(i, j + 1));
            }
        }
    }
    s
}

fn run_json(input: &Path, out: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "spline",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(extra);
    let r = quadrille(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    serde_json::from_slice(&r.stdout).unwrap()
}

#[test]
fn l_plate_gives_three_watertight_flat_patches() {
    let dir = tempfile::tempdir().unwrap();
    let input = l_plate_obj(dir.path());
    let out = dir.path().join("lplate.json");
    let rep = run_json(&input, &out, &[]);
    assert_eq!(rep["corners"], 6);
    assert_eq!(rep["reflex_corners"], 1);
    assert_eq!(rep["separatrices"], 2);
    assert_eq!(rep["patches"], 3);
    assert_eq!(rep["shared_sides"], 2);
    assert_eq!(rep["max_gap"], 0.0);
    assert!(rep["min_scaled_jacobian"].as_f64().unwrap() > 0.0);
    let mp = spline::json::read_json(&out).unwrap();
    assert_eq!(mp.patches().len(), 3);
    let shared = mp.shared_sides();
    assert_eq!((shared.pairs, shared.max_gap), (2, 0.0));
    let d = rep["diagonal"].as_f64().unwrap();
    for p in mp.points() {
        assert!((p[2] - 5.0).abs() < 1e-9 * d, "{p:?}");
    }
    // the patches cover the L: area 300
    let mut area = 0.0;
    for k in 0..3 {
        let p = mp.patch(k).unwrap();
        let (a, c) = (p.eval(0.0, 0.0), p.eval(1.0, 1.0));
        area += ((c[0] - a[0]) * (c[1] - a[1])).abs();
    }
    assert!((area - 300.0).abs() < 1e-6, "{area}");
    // as STEP, read back: 3 faces; the 2 inner arcs shared by 2 faces, the 8 boundary arcs free
    let step = dir.path().join("lplate.step");
    let r = quadrille(&[
        "spline",
        input.to_str().unwrap(),
        "-o",
        step.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let back = occt::load(&step).unwrap();
    assert_eq!(back.faces.len(), 3);
    let users: Vec<usize> = back.curve_faces().iter().map(|f| f.len()).collect();
    assert_eq!(users.iter().filter(|&&n| n == 2).count(), 2, "{users:?}");
    assert_eq!(users.iter().filter(|&&n| n == 1).count(), 8, "{users:?}");
    assert_eq!(users.len(), 10, "{users:?}");
}

#[test]
fn quarter_cylinder_is_one_patch_within_the_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("quarter.obj");
    let r = 3.0;
    let obj = grid_obj(
        24,
        |_, _| true,
        |u, v| {
            let a = u * std::f64::consts::FRAC_PI_2;
            [r * a.cos(), r * a.sin(), 4.0 * v]
        },
    );
    std::fs::write(&input, obj).unwrap();
    for interior in ["coons", "fit"] {
        let out = dir.path().join(format!("quarter_{interior}.iges"));
        let json = dir.path().join(format!("quarter_{interior}.json"));
        let rep = run_json(&input, &json, &["--interior", interior]);
        assert_eq!(rep["patches"], 1);
        assert_eq!(rep["corners"], 4);
        assert_eq!(rep["tolerance_met"], true);
        let tol = rep["tolerance"].as_f64().unwrap();
        let mp = spline::json::read_json(&json).unwrap();
        let p = mp.patch(0).unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..=30 {
            for j in 0..=30 {
                let x = p.eval(i as f64 / 30.0, j as f64 / 30.0);
                worst = worst.max(((x[0] * x[0] + x[1] * x[1]).sqrt() - r).abs());
            }
        }
        assert!(worst < tol, "{interior}: {worst} vs {tol}");
        // IGES: one type 128 entity, no trims
        let r2 = quadrille(&[
            "spline",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(r2.status.success());
        let text = std::fs::read_to_string(&out).unwrap();
        let de: Vec<&str> = text
            .lines()
            .filter(|l| l.len() >= 73 && &l[72..73] == "D")
            .collect();
        let types: Vec<&str> = de.iter().step_by(2).map(|l| l[..8].trim()).collect();
        assert_eq!(types, vec!["128"], "{types:?}");
    }
}

#[test]
fn cad_face_written_as_step_reads_back_open_and_untrimmed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("face.step");
    // a planar square face of the cube
    let model = cad("s11o_cube_cyl.stp");
    let rep = run_json(
        &model,
        &out,
        &["--faces", "2", "--segments", "2", "--refine", "2"],
    );
    assert_eq!(rep["patches"], 1);
    assert_eq!(rep["segments"], 2);
    let back = occt::load(&out).unwrap();
    assert_eq!(back.faces.len(), 1);
    assert_eq!(back.faces[0].loops.len(), 1);
    // free edges only: the 4 boundary curves, each used by the one face
    assert_eq!(back.curves.len(), 4);
    for (c, users) in back.curve_faces().iter().enumerate() {
        assert_eq!(users.len(), 1, "curve {c}");
    }
}

/// Issue 31: the flange's torus fillet (face 2) at `--triangle-size 0.5`, a
/// 338 × 5 strip in ψ, was refused ("a boundary loop in ψ bends 2.3e-4 × its
/// size"): the unfolding compounded the Ricci residue. `immerse` now checks
/// every edge of Ω against its Ricci length (1e-8 relative), so success means
/// that check held; the loops lie on their lines and the seam closes.
#[test]
fn flange_fillet_at_half_millimetre_triangles_is_one_seamless_patch() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fillet.step");
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/industrial/blind_flange_1in_150.step");
    let rep = run_json(&model, &out, &["--faces", "2", "--triangle-size", "0.5"]);
    assert_eq!(rep["boundary_loops"], 2);
    assert_eq!(rep["patches"], 1);
    assert!(rep["triangles"].as_u64().unwrap() > 20_000, "{rep}");
    assert!(rep["seam_rotation"].as_f64().unwrap() < 1e-8, "{rep}");
    assert!(rep["boundary_deviation"].as_f64().unwrap() < 1e-9, "{rep}");
    assert!(rep["min_scaled_jacobian"].as_f64().unwrap() > 0.0, "{rep}");
    assert_eq!(rep["tolerance_met"], true);
    assert!(out.exists());
}

#[test]
fn washer_side_is_one_step_face_closed_along_its_seam() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("side.step");
    // the inner cylinder of an M8 washer: an annulus with two smooth loops
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/industrial/plain_washer_m8.step");
    let rep = run_json(&model, &out, &["--faces", "1"]);
    assert_eq!(rep["boundary_loops"], 2);
    assert_eq!(rep["corners"], 0);
    assert_eq!(rep["patches"], 1);
    assert!(rep["seam_rotation"].as_f64().unwrap() < 1e-8, "{rep}");
    assert_eq!(rep["tolerance_met"], true);
    assert!(rep["min_scaled_jacobian"].as_f64().unwrap() > 0.0, "{rep}");
    // the seam: one arc, the patch's left and right side (gap 0)
    assert_eq!((rep["shared_sides"].as_u64(), rep["max_gap"].as_f64()), (Some(1), Some(0.0)));
    let back = occt::load(&out).unwrap();
    assert_eq!(back.faces.len(), 1);
    // three edges: the seam, used twice by the one face, and the two loops
    assert_eq!(back.curves.len(), 3);
    let uses: Vec<_> = back.faces[0].curve_uses().collect();
    assert_eq!(uses.len(), 4);
    let seams: Vec<_> = uses.iter().filter(|u| u.seam).collect();
    assert_eq!(seams.len(), 2, "the seam appears twice");
    assert_eq!(seams[0].curve, seams[1].curve);
    // free edges: only the two loops, each closed (one corner at both ends)
    for (c, users) in back.curve_faces().iter().enumerate() {
        assert_eq!(users.len(), 1, "curve {c}");
        let e = &back.curves[c];
        if c != seams[0].curve.0 as usize {
            assert_eq!(e.start, e.end, "loop {c} is closed");
        }
    }
}

#[test]
fn cap_needing_cones_is_refused_with_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cap.obj");
    // a spherical cap over the unit disk, polar rings: a smooth boundary, Σ I = 0
    let (rings, sectors) = (6, 32);
    let lift = |x: f64, y: f64| [x, y, (3.0 - x * x - y * y).sqrt()];
    let mut s = String::new();
    let c = lift(0.0, 0.0);
    let _ = writeln!(s, "v {} {} {}", c[0], c[1], c[2]);
    for r in 1..=rings {
        for k in 0..sectors {
            let a = std::f64::consts::TAU * k as f64 / sectors as f64;
            let rr = r as f64 / rings as f64;
            let p = lift(rr * a.cos(), rr * a.sin());
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
    }
    let id = |r: usize, k: usize| {
        if r == 0 {
            1
        } else {
            2 + (r - 1) * sectors + k % sectors
        }
    };
    for k in 0..sectors {
        let _ = writeln!(s, "f {} {} {}", id(0, 0), id(1, k), id(1, k + 1));
    }
    for r in 1..rings {
        for k in 0..sectors {
            let _ = writeln!(s, "f {} {} {}", id(r, k), id(r + 1, k), id(r + 1, k + 1));
            let _ = writeln!(s, "f {} {} {}", id(r, k), id(r + 1, k + 1), id(r, k + 1));
        }
    }
    std::fs::write(&input, s).unwrap();
    let out = dir.path().join("cap.step");
    let r = quadrille(&[
        "spline",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = assert_clean_failure(&r, "cap.obj");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("interior cones") && err.contains("Σ I = 0"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn bad_options_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.step");
    let model = cad("s11o_cube_cyl.stp");
    for (flag, value, needle) in [
        ("--segments", "0", "--segments"),
        ("--segments", "many", "--segments"),
        ("--refine", "0", "--refine"),
        ("--tolerance", "0", "--tolerance"),
        ("--faces", "99", "out of range"),
    ] {
        let r = quadrille(&[
            "spline",
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            flag,
            value,
        ]);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{flag} {value}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(needle),
            "{stderr}"
        );
        assert!(!out.exists());
    }
}

#[test]
fn cones_out_is_written_and_a_shell_with_interior_cones_is_refused_without_output() {
    // Issue 31 shell (c): the torus tube and the drilled cylinder, χ = −1.
    let dir = tempfile::tempdir().unwrap();
    let model = cad("n10o_qtorus_cyl.step");
    let out = dir.path().join("c.step");
    let cones = dir.path().join("c.cones");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "spline",
            model.to_str().unwrap(),
            "--faces",
            "5,7",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        quadrille(&args)
    };
    let r = run(&["--cones-out", cones.to_str().unwrap()]);
    let err = assert_clean_failure(&r, "n10o_qtorus_cyl.step");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("interior cones")
            && err.contains("Σ I = -4, 4χ = -4")
            && err.contains("S6–S7 layout energy converged: residual")
            && err.contains("S8 traced")
            && err.contains("spline patches on a traced layout (S9 across the cuts' charts) are not built yet"),
        "{err}"
    );
    assert!(!out.exists());
    // The proposal was written before the refusal, and reads back as the same set.
    let text = std::fs::read_to_string(&cones).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(!lines.is_empty());
    let sum: i32 = lines
        .iter()
        .map(|l| l.split_whitespace().nth(3).unwrap().parse::<i32>().unwrap())
        .sum();
    assert_eq!(sum, -4);
    let r = run(&["--cones", cones.to_str().unwrap()]);
    let again = assert_clean_failure(&r, "n10o_qtorus_cyl.step");
    assert_eq!(again, err);
    assert!(!out.exists());
    // A hand edit gone wrong: one cone moved far off the shell.
    let bad = dir.path().join("bad.cones");
    let mut edited = text.clone();
    edited.push_str("100 100 100 1\n");
    std::fs::write(&bad, &edited).unwrap();
    let r = run(&["--cones", bad.to_str().unwrap()]);
    let err = assert_clean_failure(&r, "bad.cones");
    let line = text.lines().count() + 1;
    assert!(
        err.contains(&format!("bad.cones:{line}:"))
            && err.contains("from the nearest shell vertex"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn an_l_plate_s_cone_file_holds_its_six_corners_and_reads_back_to_the_same_patches() {
    let dir = tempfile::tempdir().unwrap();
    let input = l_plate_obj(dir.path());
    let cones = dir.path().join("lplate.cones");
    let out = dir.path().join("a.json");
    let rep = run_json(&input, &out, &["--cones-out", cones.to_str().unwrap()]);
    assert_eq!(rep["patches"], 3);
    // Five convex corners +1 and the reflex corner (10, 10) −1; no interior cone.
    let text = std::fs::read_to_string(&cones).unwrap();
    let mut rows: Vec<(f64, f64, i32)> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(t[2], "5", "{l}");
            assert!(l.ends_with("# boundary"), "{l}");
            (
                t[0].parse().unwrap(),
                t[1].parse().unwrap(),
                t[3].parse().unwrap(),
            )
        })
        .collect();
    rows.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        rows,
        [
            (0.0, 0.0, 1),
            (0.0, 20.0, 1),
            (10.0, 10.0, -1),
            (10.0, 20.0, 1),
            (20.0, 0.0, 1),
            (20.0, 10.0, 1)
        ]
    );
    // Given back, the corners are the cones of the cone-free path: the same patches.
    let again = dir.path().join("b.json");
    let rep2 = run_json(&input, &again, &["--cones", cones.to_str().unwrap()]);
    assert_eq!(rep2["patches"], 3);
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        std::fs::read_to_string(&again).unwrap()
    );
    // The reflex corner's −1 moved inside: an interior cone, refused, no file.
    let moved = dir.path().join("moved.cones");
    std::fs::write(&moved, text.replace("10 10 5 -1", "7.4 7.6 5 -1")).unwrap();
    let bad = dir.path().join("c.json");
    let err = refused_with_cones(&input, &bad, &moved);
    assert!(
        err.contains("S6–S7") && err.contains("1 interior cones (+1: 0, −1: 1"),
        "{err}"
    );
    // On the boundary but off the corner: boundary cones other than the corners.
    std::fs::write(&moved, text.replace("10 10 5 -1", "10 12.5 5 -1")).unwrap();
    let err = refused_with_cones(&input, &bad, &moved);
    assert!(
        err.contains("boundary cones other than the shell's corners") && err.contains("S6–S7"),
        "{err}"
    );
}

/// `quadrille spline INPUT -o OUT --cones CONES`, which must fail cleanly
/// (one line, no panic) and write no `OUT`; returns the error line.
fn refused_with_cones(input: &Path, out: &Path, cones: &Path) -> String {
    let r = quadrille(&[
        "spline",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--cones",
        cones.to_str().unwrap(),
    ]);
    let err = assert_clean_failure(&r, &input.file_name().unwrap().to_string_lossy());
    assert!(!out.exists(), "{}", out.display());
    err
}

/// Writes `lplate.obj` in `dir`: [0, 20]² without [10, 20]², in the plane
/// z = 5, as an 8 × 8 grid of quads less a quarter; returns its path.
fn l_plate_obj(dir: &Path) -> std::path::PathBuf {
    let input = dir.join("lplate.obj");
    let obj = grid_obj(
        8,
        |i, j| !(i >= 4 && j >= 4),
        |u, v| [20.0 * u, 20.0 * v, 5.0],
    );
    std::fs::write(&input, obj).unwrap();
    input
}
