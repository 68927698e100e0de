//! A curved 2 × 2 multipatch (a dome over a square, four patches around a
//! centre node) written as IGES, VTU and JSON and read back: IGES by Gmsh's
//! OpenCASCADE, VTU by Python's XML parser, when the Python that has them is there
//! (`QUADRILLE_PYTHON`, else `python3`; the test skips those checks cleanly
//! when the module is missing, unless `QUADRILLE_REQUIRE_GMSH=1`).

use spline::iges::write_iges;
use spline::json::{read_json, write_json};
use spline::multipatch::SharedSides;
use spline::vtu::{to_vtu_string, write_vtu};
use spline::{
    fit_curve, jacobian_check, ArcUse, BSplineCurve, Multipatch, MultipatchBuilder, Point3,
};
use std::process::Command;

#[path = "../../mesh/tests/common/python.rs"]
mod python;
use python::{python, python_module_available};

/// The dome z = 0.5 (1 − x²)(1 − y²) over [−1, 1]².
fn dome(x: f64, y: f64) -> Point3 {
    [x, y, 0.5 * (1.0 - x * x) * (1.0 - y * y)]
}

fn arc_on_dome(a: (f64, f64), b: (f64, f64), spans: usize) -> BSplineCurve {
    let m = 60;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let pts: Vec<Point3> = params
        .iter()
        .map(|&t| dome(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t))
        .collect();
    fit_curve(&pts, &params, spans).unwrap()
}

/// Four patches on the dome; node (i, j) at x = i − 1, y = j − 1.
fn dome_multipatch(spans: usize) -> Multipatch {
    let mut b = MultipatchBuilder::new();
    let mut node = [[0usize; 3]; 3];
    for (j, row) in node.iter_mut().enumerate() {
        for (i, n) in row.iter_mut().enumerate() {
            *n = b.add_node(dome(i as f64 - 1.0, j as f64 - 1.0));
        }
    }
    let xy = |i: usize, j: usize| (i as f64 - 1.0, j as f64 - 1.0);
    // Horizontal arcs h[j][i]: (i, j) → (i+1, j); vertical v[j][i]: (i, j) → (i, j+1).
    let mut h = [[None; 2]; 3];
    let mut v = [[None; 3]; 2];
    for j in 0..3 {
        for i in 0..2 {
            h[j][i] = Some(
                b.add_arc(
                    node[j][i],
                    node[j][i + 1],
                    &arc_on_dome(xy(i, j), xy(i + 1, j), spans),
                )
                .unwrap(),
            );
        }
    }
    for j in 0..2 {
        for i in 0..3 {
            // The middle vertical arcs are stored downwards, to exercise reversal.
            if i == 1 {
                let c = arc_on_dome(xy(i, j + 1), xy(i, j), spans);
                v[j][i] = Some(b.add_arc(node[j + 1][i], node[j][i], &c).unwrap());
            } else {
                v[j][i] = Some(
                    b.add_arc(
                        node[j][i],
                        node[j + 1][i],
                        &arc_on_dome(xy(i, j), xy(i, j + 1), spans),
                    )
                    .unwrap(),
                );
            }
        }
    }
    let side = |i: usize, j: usize| {
        if i == 1 {
            ArcUse::reverse(v[j][i].unwrap())
        } else {
            ArcUse::forward(v[j][i].unwrap())
        }
    };
    for (j, rows) in h.windows(2).enumerate() {
        for (i, (low, high)) in rows[0].iter().zip(&rows[1]).enumerate() {
            b.add_coons_patch([
                ArcUse::forward(low.unwrap()),
                ArcUse::forward(high.unwrap()),
                side(i, j),
                side(i + 1, j),
            ])
            .unwrap();
        }
    }
    b.build().unwrap()
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("spline-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn dome_is_watertight_connected_and_positive() {
    for (spans, r, n) in [(1, 8, 11), (4, 2, 11), (3, 4, 15)] {
        let mp = dome_multipatch(spans).refined(r).unwrap();
        assert_eq!(mp.patches().len(), 4);
        assert!(mp.patches().iter().all(|g| (g.n_s(), g.n_t()) == (n, n)));
        // 4 n² minus the shared: 4 interior arcs of n points, centre counted 4 times → 4n² − 4n + 1.
        assert_eq!(mp.points().len(), 4 * n * n - 4 * n + 1);
        assert_eq!(
            mp.shared_sides(),
            SharedSides {
                pairs: 4,
                max_gap: 0.0
            }
        );
        assert_eq!(mp.components(), 1);
        for k in 0..4 {
            let rep = jacobian_check(&mp.patch(k).unwrap(), &|_, _, _| [0.0, 0.0, 1.0]).unwrap();
            assert!(rep.is_positive(), "spans {spans} patch {k}: {rep:?}");
            eprintln!(
                "spans {spans} refine {r} patch {k}: min scaled Jacobian {:.4}",
                rep.min_scaled_jacobian
            );
        }
    }
}

#[test]
fn json_round_trip() {
    let mp = dome_multipatch(3).refined(2).unwrap();
    let dir = temp_dir("json");
    let path = dir.join("dome.json");
    write_json(&path, &mp).unwrap();
    assert_eq!(read_json(&path).unwrap(), mp);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_is_well_formed() {
    let mp = dome_multipatch(3).refined(2).unwrap();
    let text = to_vtu_string(&mp).unwrap();
    // 4 patches × 6 × 6 Bézier elements, 16 nodes each.
    let cells = 4 * 36;
    assert!(text.contains(&format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{cells}\"",
        16 * cells
    )));
    let array = |name: &str| -> Vec<f64> {
        let start = text.find(&format!("Name=\"{name}\"")).unwrap();
        let body = &text[start..];
        let open = body.find('>').unwrap() + 1;
        let close = body.find("</DataArray>").unwrap();
        body[open..close]
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect()
    };
    let types = array("types");
    assert_eq!(types.len(), cells);
    assert!(types.iter().all(|&t| t == 77.0));
    let offsets = array("offsets");
    assert_eq!(offsets.last().copied(), Some((16 * cells) as f64));
    assert_eq!(array("connectivity").len(), 16 * cells);
    let deg = array("HigherOrderDegrees");
    assert_eq!(deg.len(), 3 * cells);
    assert!(deg.chunks(3).all(|d| d == [3.0, 3.0, 0.0]));
    assert_eq!(array("RationalWeights").len(), 16 * cells);
    // Corner nodes of the first cell are the patch corners' positions.
    let pts_start = text.find("<Points>").unwrap();
    let pts: Vec<f64> = text[pts_start..]
        .split_once("ascii\">")
        .unwrap()
        .1
        .split("</DataArray>")
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(pts.len(), 3 * 16 * cells);
    let p0 = mp.patch(0).unwrap();
    assert_eq!(&pts[..3], &p0.eval(0.0, 0.0));
    let dir = temp_dir("vtu");
    let path = dir.join("dome.vtu");
    write_vtu(&path, &mp).unwrap();
    // meshio (5.3) lists type 77 but not its node count, and VTK is not in
    // the test Python: the file is parsed as XML there instead.
    if python_module_available("xml.etree.ElementTree") {
        let script = "import sys, xml.etree.ElementTree as ET\nr = ET.parse(sys.argv[1]).getroot()\np = r.find('UnstructuredGrid/Piece')\nc = p.find('Cells')\nt = [int(x) for x in c.find(\"DataArray[@Name='types']\").text.split()]\nk = [int(x) for x in c.find(\"DataArray[@Name='connectivity']\").text.split()]\nx = p.find('Points/DataArray').text.split()\nprint(r.get('type'), p.get('NumberOfCells'), len(t), set(t) == {77}, len(k), len(x) // 3, max(k) + 1)";
        let out = Command::new(python())
            .args(["-c", script, path.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "XML parse failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s = String::from_utf8_lossy(&out.stdout);
        let want = format!(
            "UnstructuredGrid {cells} {cells} True {} {} {}",
            16 * cells,
            16 * cells,
            16 * cells
        );
        assert_eq!(s.trim(), want);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn iges_reads_back_in_gmsh() {
    let mp = dome_multipatch(3).refined(2).unwrap();
    let dir = temp_dir("iges");
    let path = dir.join("dome.igs");
    write_iges(&path, &mp).unwrap();
    if !python_module_available("gmsh") {
        std::fs::remove_dir_all(&dir).unwrap();
        return;
    }
    let uv = [(0.0, 0.0), (0.3, 0.7), (0.5, 0.5), (0.91, 0.13), (1.0, 1.0)];
    let uv_flat: Vec<String> = uv
        .iter()
        .flat_map(|(u, v)| [u.to_string(), v.to_string()])
        .collect();
    let script = r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.importShapes(sys.argv[1])
gmsh.model.occ.synchronize()
uv = [float(x) for x in sys.argv[2].split(",")]
faces = gmsh.model.getEntities(2)
print("faces", len(faces))
for _, tag in faces:
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    print("bounds", tag, *lo, *hi)
    print("values", tag, *gmsh.model.getValue(2, tag, uv))
    print("type", tag, gmsh.model.getType(2, tag))
gmsh.finalize()
"#;
    let out = Command::new(python())
        .args(["-c", script, path.to_str().unwrap(), &uv_flat.join(",")])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "gmsh failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split_whitespace().collect())
        .collect();
    let faces: usize = lines.iter().find(|l| l[0] == "faces").unwrap()[1]
        .parse()
        .unwrap();
    assert_eq!(faces, mp.patches().len(), "one face per type-128 entity");
    let mut worst: f64 = 0.0;
    for (k, (b, v)) in lines
        .iter()
        .filter(|l| l[0] == "bounds")
        .zip(lines.iter().filter(|l| l[0] == "values"))
        .enumerate()
    {
        let bounds: Vec<f64> = b[2..].iter().map(|x| x.parse().unwrap()).collect();
        assert_eq!(
            bounds,
            vec![0.0, 0.0, 1.0, 1.0],
            "face {k}: bounds = the knot range"
        );
        let vals: Vec<f64> = v[2..].iter().map(|x| x.parse().unwrap()).collect();
        let patch = mp.patch(k).unwrap();
        for (m, (u, w)) in uv.iter().enumerate() {
            let ours = patch.eval(*u, *w);
            for c in 0..3 {
                worst = worst.max((vals[3 * m + c] - ours[c]).abs());
            }
        }
    }
    eprintln!("IGES via Gmsh/OCC: {faces} faces, max evaluation difference {worst:.3e}");
    assert!(worst < 1e-9, "evaluation differs by {worst:e}");
    for l in lines.iter().filter(|l| l[0] == "type") {
        assert!(l[2..].join(" ").contains("BSpline"), "face type {:?}", l);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
