//! STEP output of B-spline multipatches (`occt::write_bspline_step`): a
//! curved 2 × 2 multipatch built with `spline` (a dome over a square, four
//! bicubic patches around a centre node), and a single patch, are written
//! and read back with `occt::load` (and with Gmsh when the Python that has
//! it is there): face, edge and corner counts, edges on the parameter
//! bounds, shared and free edges, and the read-back surfaces evaluated
//! against the patches. Bad input is an error that leaves no file behind.

use geometry::vec3::dist;
use occt::{write_bspline_step, BSplineSurfaceData, StepWriteError};
use spline::{
    fit_curve, ArcUse, BSplineCurve, BSplinePatch, Multipatch, MultipatchBuilder, Point3,
};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The dome z = 0.5 (1 − x²)(1 − y²) over [−1, 1]².
fn dome(x: f64, y: f64) -> Point3 {
    [x, y, 0.5 * (1.0 - x * x) * (1.0 - y * y)]
}

/// A cubic fitted with `spans` spans to the dome above the segment a → b.
fn arc_on_dome(a: (f64, f64), b: (f64, f64), spans: usize) -> BSplineCurve {
    let m = 40;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let pts: Vec<Point3> = params
        .iter()
        .map(|&t| dome(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t))
        .collect();
    fit_curve(&pts, &params, spans).unwrap()
}

/// Four Coons patches on the dome; node (i, j) at x = i − 1, y = j − 1;
/// 12 arcs, 4 of them interior (shared by two patches).
fn dome_multipatch(spans: usize) -> Multipatch {
    let mut b = MultipatchBuilder::new();
    let mut node = [[0usize; 3]; 3];
    for (j, row) in node.iter_mut().enumerate() {
        for (i, n) in row.iter_mut().enumerate() {
            *n = b.add_node(dome(i as f64 - 1.0, j as f64 - 1.0));
        }
    }
    let xy = |i: usize, j: usize| (i as f64 - 1.0, j as f64 - 1.0);
    // h[j][i]: node (i, j) → (i+1, j); v[j][i]: node (i, j) → (i, j+1).
    let mut h = [[None; 2]; 3];
    let mut v = [[None; 3]; 2];
    for j in 0..3 {
        for i in 0..2 {
            let c = arc_on_dome(xy(i, j), xy(i + 1, j), spans);
            h[j][i] = Some(b.add_arc(node[j][i], node[j][i + 1], &c).unwrap());
        }
    }
    for j in 0..2 {
        for i in 0..3 {
            let c = arc_on_dome(xy(i, j), xy(i, j + 1), spans);
            v[j][i] = Some(b.add_arc(node[j][i], node[j + 1][i], &c).unwrap());
        }
    }
    for j in 0..2 {
        for i in 0..2 {
            b.add_coons_patch([
                ArcUse::forward(h[j][i].unwrap()),
                ArcUse::forward(h[j + 1][i].unwrap()),
                ArcUse::forward(v[j][i].unwrap()),
                ArcUse::forward(v[j][i + 1].unwrap()),
            ])
            .unwrap();
        }
    }
    b.build().unwrap()
}

/// The conversion the caller owns: a `spline` patch as `occt`'s plain data.
fn to_data(p: &BSplinePatch) -> BSplineSurfaceData {
    BSplineSurfaceData {
        degree_s: p.knots_s().degree(),
        degree_t: p.knots_t().degree(),
        knots_s: p.knots_s().knots().to_vec(),
        knots_t: p.knots_t().knots().to_vec(),
        control: p.control_points().to_vec(),
    }
}

fn patches_of(mp: &Multipatch) -> Vec<BSplinePatch> {
    (0..mp.patches().len())
        .map(|k| mp.patch(k).unwrap())
        .collect()
}

/// Files in `dir` (to see that nothing, not even a temporary, is left).
fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// What the read-back model showed.
#[derive(Debug, Default)]
struct ReadBack {
    faces: usize,
    curves: usize,
    corners: usize,
    edges_per_face: Vec<usize>,
    shared: usize,
    free: usize,
    reversed: usize,
    /// Largest distance of a pcurve sample from its face's parameter bounds.
    off_bounds: f64,
    /// Largest |S_read(u, v) − S_patch(u, v)| / diagonal.
    eval_diff: f64,
}

/// Reads `path` with `occt::load` and compares it with `patches`: each face
/// is matched to the patch whose centre it passes through, then evaluated
/// on a 7 × 7 grid of the patch domain.
fn read_back(path: &Path, patches: &[BSplinePatch]) -> ReadBack {
    let m = occt::load(path).unwrap();
    m.validate().unwrap();
    let diag = m.diagonal();
    let mut out = ReadBack {
        faces: m.faces.len(),
        curves: m.curves.len(),
        corners: m.corners.len(),
        ..ReadBack::default()
    };
    for cf in m.curve_faces() {
        match cf.len() {
            1 => out.free += 1,
            2 => out.shared += 1,
            n => panic!("a curve bounds {n} faces"),
        }
    }
    let mut matched = vec![false; patches.len()];
    for (fi, f) in m.faces.iter().enumerate() {
        out.reversed += f.reversed as usize;
        out.edges_per_face
            .push(f.loops.iter().map(|l| l.uses.len()).sum());
        let b = f.surface.uv_bounds();
        for u in f.curve_uses() {
            let c = &m.curves[u.curve.idx()];
            for k in 0..=8 {
                let t = c.range.0 + (c.range.1 - c.range.0) * k as f64 / 8.0;
                let [pu, pv] = u.pcurve.eval(t);
                let d = [pu - b.umin, b.umax - pu, pv - b.vmin, b.vmax - pv]
                    .iter()
                    .map(|x| x.abs())
                    .fold(f64::INFINITY, f64::min);
                out.off_bounds = out.off_bounds.max(d);
            }
        }
        let centre = f
            .surface
            .eval([0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)]);
        let k = patches
            .iter()
            .position(|p| dist(p.eval(0.5, 0.5), centre) < 1e-6 * diag)
            .unwrap_or_else(|| panic!("face {fi}: no patch passes through its centre"));
        assert!(!matched[k], "face {fi}: patch {k} matched twice");
        matched[k] = true;
        let (s0, s1) = patches[k].knots_s().domain();
        let (t0, t1) = patches[k].knots_t().domain();
        assert_eq!(
            (b.umin, b.umax, b.vmin, b.vmax),
            (s0, s1, t0, t1),
            "face {fi}: surface bounds = the knot domains"
        );
        let fb = f.uv_bounds;
        assert!(
            (fb.umin - s0).abs() < 1e-9
                && (fb.umax - s1).abs() < 1e-9
                && (fb.vmin - t0).abs() < 1e-9
                && (fb.vmax - t1).abs() < 1e-9,
            "face {fi}: face bounds {fb:?} = the knot domains (untrimmed)"
        );
        for a in 0..7 {
            for c in 0..7 {
                let s = s0 + (s1 - s0) * a as f64 / 6.0;
                let t = t0 + (t1 - t0) * c as f64 / 6.0;
                let d = dist(f.surface.eval([s, t]), patches[k].eval(s, t)) / diag;
                out.eval_diff = out.eval_diff.max(d);
            }
        }
    }
    out
}

#[path = "../../mesh/tests/common/python.rs"]
mod python;
use python::python;

/// True when gmsh imports; false (the check skips) otherwise, unless
/// `QUADRILLE_REQUIRE_GMSH=1`.
fn gmsh_available() -> bool {
    python::python_module_available("gmsh")
}

#[test]
fn dome_2x2_round_trips_through_step() {
    let mp = dome_multipatch(3);
    let patches = patches_of(&mp);
    assert_eq!(patches.len(), 4);
    let data: Vec<BSplineSurfaceData> = patches.iter().map(to_data).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dome.step");
    let start = Instant::now();
    let report = write_bspline_step(&data, &path).unwrap();
    let write_time = start.elapsed();
    eprintln!("dome 2x2: {report:?}, written in {write_time:?}");
    assert_eq!(
        (report.faces, report.shells),
        (4, 1),
        "four faces in one shell"
    );
    assert_eq!(
        (
            report.shared_edges,
            report.free_edges,
            report.multiple_edges
        ),
        (4, 8, 0),
        "4 interior arcs shared, 8 boundary arcs free"
    );
    assert_eq!(files_in(dir.path()), vec!["dome.step".to_string()]);
    let text = std::fs::read_to_string(&path).unwrap();
    let count = |what: &str| text.matches(what).count();
    let entities = [
        "AUTOMOTIVE_DESIGN",
        "B_SPLINE_SURFACE_WITH_KNOTS(",
        "ADVANCED_FACE(",
        "EDGE_CURVE(",
        "OPEN_SHELL(",
        "CLOSED_SHELL(",
        "VERTEX_POINT(",
    ]
    .map(|e| (e, count(e)));
    eprintln!("dome 2x2 STEP entities: {entities:?}");
    assert_eq!(
        entities.map(|(_, n)| n),
        [1, 4, 4, 12, 1, 0, 9],
        "AP214, 4 untrimmed B-spline faces, 12 edges, one open shell, 9 vertices"
    );

    let start = Instant::now();
    let rb = read_back(&path, &patches);
    eprintln!("dome 2x2 read back: {rb:?} in {:?}", start.elapsed());
    assert_eq!((rb.faces, rb.curves, rb.corners), (4, 12, 9));
    assert_eq!(rb.edges_per_face, vec![4; 4], "four edges per face");
    assert_eq!((rb.shared, rb.free), (4, 8));
    assert_eq!(rb.reversed, 0, "the patches are oriented alike");
    assert!(
        rb.off_bounds < 1e-9,
        "pcurves off the bounds by {}",
        rb.off_bounds
    );
    assert!(
        rb.eval_diff < 1e-9,
        "evaluation differs by {} × diagonal",
        rb.eval_diff
    );

    if gmsh_available() {
        let script = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.importShapes(sys.argv[1])
gmsh.model.occ.synchronize()
print(len(gmsh.model.getEntities(2)), len(gmsh.model.getEntities(1)), len(gmsh.model.getEntities(0)))
print(*sorted(set(gmsh.model.getType(2, t) for _, t in gmsh.model.getEntities(2))))
gmsh.finalize()
"#;
        let out = Command::new(python())
            .args(["-c", script, path.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "gmsh failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8_lossy(&out.stdout);
        let mut lines = text.lines();
        let counts: Vec<usize> = lines
            .next()
            .unwrap_or("")
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        eprintln!("gmsh sees surfaces, curves, points: {counts:?}");
        assert_eq!(
            counts,
            vec![4, 12, 9],
            "gmsh: 4 surfaces, 12 curves, 9 points"
        );
        let types = lines.next().unwrap_or("");
        eprintln!("gmsh surface types: {types}");
        assert_eq!(
            types.trim(),
            "BSpline surface",
            "gmsh: untrimmed B-spline surfaces"
        );
    }
}

#[test]
fn refined_dome_keeps_its_topology() {
    // 5 × 5 spans per patch (8 × 8 control points), interior knots 0.2 … 0.8
    let mp = dome_multipatch(5);
    let patches = patches_of(&mp);
    assert_eq!(patches[0].n_s(), 8);
    let data: Vec<BSplineSurfaceData> = patches.iter().map(to_data).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dome5.stp");
    let report = write_bspline_step(&data, &path).unwrap();
    assert_eq!(
        (
            report.faces,
            report.shells,
            report.shared_edges,
            report.free_edges
        ),
        (4, 1, 4, 8)
    );
    let rb = read_back(&path, &patches);
    eprintln!("dome 5 spans read back: {rb:?}");
    assert_eq!(
        (rb.faces, rb.curves, rb.corners, rb.shared, rb.free),
        (4, 12, 9, 4, 8)
    );
    assert!(
        rb.eval_diff < 1e-9,
        "evaluation differs by {} × diagonal",
        rb.eval_diff
    );
}

/// A single bicubic patch with 2 × 3 spans on a bent plate.
fn bent_plate() -> BSplinePatch {
    let ks = spline::KnotVector::clamped_uniform(3, 2).unwrap();
    let kt = spline::KnotVector::clamped_uniform(3, 3).unwrap();
    let (ns, nt) = (ks.num_control_points(), kt.num_control_points());
    let mut net = Vec::new();
    for j in 0..nt {
        for i in 0..ns {
            let x = 2.0 * i as f64 / (ns - 1) as f64;
            let y = 3.0 * j as f64 / (nt - 1) as f64;
            net.push([x, y, 0.3 * x * x - 0.1 * y + 0.05 * x * y]);
        }
    }
    BSplinePatch::new(ks, kt, net).unwrap()
}

#[test]
fn single_patch_is_one_open_face() {
    let p = bent_plate();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.step");
    let report = write_bspline_step(&[to_data(&p)], &path).unwrap();
    eprintln!("single patch: {report:?}");
    assert_eq!(
        (
            report.faces,
            report.shells,
            report.shared_edges,
            report.free_edges
        ),
        (1, 1, 0, 4)
    );
    let rb = read_back(&path, std::slice::from_ref(&p));
    eprintln!("single patch read back: {rb:?}");
    assert_eq!((rb.faces, rb.curves, rb.corners), (1, 4, 4));
    assert_eq!(rb.edges_per_face, vec![4]);
    assert_eq!((rb.shared, rb.free), (0, 4));
    assert!(
        rb.off_bounds < 1e-9,
        "pcurves off the bounds by {}",
        rb.off_bounds
    );
    assert!(
        rb.eval_diff < 1e-9,
        "evaluation differs by {} × diagonal",
        rb.eval_diff
    );
}

#[test]
fn bad_input_is_an_error_and_leaves_no_file() {
    let good = to_data(&bent_plate());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.step");
    let expect = |patches: &[BSplineSurfaceData], want: &str| {
        let e = write_bspline_step(patches, &path).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(want), "{msg:?} should say {want:?}");
        assert!(msg.contains("bad.step") && !msg.contains('\n'), "{msg:?}");
        assert!(
            files_in(dir.path()).is_empty(),
            "left behind: {:?}",
            files_in(dir.path())
        );
        e
    };
    let e = expect(&[], "no B-spline patch");
    assert!(matches!(e, StepWriteError::NoPatch { .. }));

    let mut nan = good.clone();
    nan.control[7][1] = f64::NAN;
    let e = expect(
        &[good.clone(), nan],
        "patch 1: control point 7 is not finite",
    );
    assert!(matches!(e, StepWriteError::BadPatch { patch: 1, .. }));

    let mut short = good.clone();
    short.control.pop();
    expect(&[short], "5 × 6 = 30 control points, got 29");

    let mut unclamped = good.clone();
    unclamped.knots_s[0] = -0.5;
    expect(&[unclamped], "not clamped: end multiplicities 1 and 4");

    let mut degree0 = good.clone();
    degree0.degree_t = 0;
    expect(&[degree0], "degree in t is 0");

    let mut flat = good.clone();
    flat.control = vec![[1.0, 2.0, 3.0]; 30];
    expect(&[flat], "no extent");
}

#[test]
fn a_failed_write_keeps_the_old_file_and_leaves_no_temporary() {
    let good = to_data(&bent_plate());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.step");
    write_bspline_step(std::slice::from_ref(&good), &path).unwrap();
    let before = std::fs::read(&path).unwrap();
    let mut bad = good.clone();
    bad.knots_t[4] = f64::INFINITY;
    let e = write_bspline_step(&[bad], &path).unwrap_err();
    assert!(e.to_string().contains("knot 4 in t is inf"), "{e}");
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the old file is untouched"
    );
    assert_eq!(files_in(dir.path()), vec!["keep.step".to_string()]);

    // OCCT's writer fails on a directory that does not exist: an error, no file.
    let missing = dir.path().join("no-such-dir").join("x.step");
    let e = write_bspline_step(std::slice::from_ref(&good), &missing).unwrap_err();
    assert!(
        matches!(e, StepWriteError::Occt { .. } | StepWriteError::Io { .. }),
        "{e:?}"
    );
    assert!(!missing.exists());
    assert_eq!(files_in(dir.path()), vec!["keep.step".to_string()]);
}

/// A bicubic plate with 2 × 2 spans over [x0, x0 + 1] × [0, 1] on the graph
/// z = 0.2 x² + 0.1 x y (+ `dz`), its left column of control points raised
/// by `lift` (interior points only, so that the corners stay put).
fn plate_at(x0: f64, dz: f64, lift: f64) -> BSplineSurfaceData {
    let kv = spline::KnotVector::clamped_uniform(3, 2).unwrap();
    let n = kv.num_control_points();
    let mut control = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let x = x0 + i as f64 / (n - 1) as f64;
            let y = j as f64 / (n - 1) as f64;
            let raise = if i == 0 && j > 0 && j < n - 1 {
                lift
            } else {
                0.0
            };
            control.push([x, y, 0.2 * x * x + 0.1 * x * y + dz + raise]);
        }
    }
    BSplineSurfaceData {
        degree_s: 3,
        degree_t: 3,
        knots_s: kv.knots().to_vec(),
        knots_t: kv.knots().to_vec(),
        control,
    }
}

#[test]
fn disjoint_patches_are_two_shells() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two.step");
    let report =
        write_bspline_step(&[plate_at(0.0, 0.0, 0.0), plate_at(0.0, 5.0, 0.0)], &path).unwrap();
    assert_eq!(
        (
            report.faces,
            report.shells,
            report.shared_edges,
            report.free_edges
        ),
        (2, 2, 0, 8)
    );
    let m = occt::load(&path).unwrap();
    assert_eq!((m.faces.len(), m.curves.len(), m.corners.len()), (2, 8, 8));
}

#[test]
fn sewing_closes_gaps_below_its_tolerance_only() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pair.step");
    let left = plate_at(0.0, 0.0, 0.0);
    // the shared side of the right plate is the left plate's right side, up to `lift`
    let mut rows = Vec::new();
    for lift in [0.0, 1e-9, 1e-3] {
        let report = write_bspline_step(&[left.clone(), plate_at(1.0, 0.0, lift)], &path).unwrap();
        let m = occt::load(&path).unwrap();
        rows.push((
            lift,
            report.shared_edges,
            report.free_edges,
            m.curves.len(),
            report.shells,
        ));
        eprintln!(
            "lift {lift:e}: sew tolerance {:.3e}, {report:?}",
            report.sew_tolerance
        );
    }
    assert_eq!(
        rows.iter().map(|r| (r.1, r.2, r.3, r.4)).collect::<Vec<_>>(),
        vec![(1, 6, 7, 1), (1, 6, 7, 1), (0, 8, 8, 2)],
        "exact and 1e-9 gaps are sewn (1 shared edge, 7 curves, 1 shell), a 1e-3 gap is not: {rows:?}"
    );
}

#[test]
fn ten_by_ten_grid_of_patches_sews_into_one_shell() {
    // Bicubic Bézier patches over [0, 1]², control points on a global grid of
    // step 1/30 on z = x y − 0.3 y², so that neighbours share their sides exactly.
    let n = 10;
    let kv = spline::KnotVector::clamped_uniform(3, 1).unwrap();
    let mut data = Vec::new();
    for pj in 0..n {
        for pi in 0..n {
            let mut control = Vec::new();
            for j in 0..4 {
                for i in 0..4 {
                    let x = (3 * pi + i) as f64 / (3 * n) as f64;
                    let y = (3 * pj + j) as f64 / (3 * n) as f64;
                    control.push([x, y, x * y - 0.3 * y * y]);
                }
            }
            data.push(BSplineSurfaceData {
                degree_s: 3,
                degree_t: 3,
                knots_s: kv.knots().to_vec(),
                knots_t: kv.knots().to_vec(),
                control,
            });
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("grid.step");
    let start = Instant::now();
    let report = write_bspline_step(&data, &path).unwrap();
    let took = start.elapsed();
    eprintln!("10 x 10 grid: {report:?}, written in {took:?}");
    assert_eq!(
        (
            report.faces,
            report.shells,
            report.shared_edges,
            report.free_edges
        ),
        (n * n, 1, 2 * n * (n - 1), 4 * n)
    );
    let start = Instant::now();
    let m = occt::load(&path).unwrap();
    eprintln!("10 x 10 grid read back in {:?}", start.elapsed());
    assert_eq!(
        (m.faces.len(), m.curves.len(), m.corners.len()),
        (n * n, 2 * n * (n + 1), (n + 1) * (n + 1))
    );
    let shared = m.curve_faces().iter().filter(|f| f.len() == 2).count();
    assert_eq!(shared, 2 * n * (n - 1));
}
