//! `quadrille field`: the VTU file holds what the JSON report says, the
//! singularities obey relation (2) of the paper on a sphere (Σ indices = 4χ = 8)
//! and on four-sided faces (no singularity, four +1 corners), the picture is a
//! PNG of the default size, and bad input leaves no file behind.

mod common;

use std::path::Path;

use common::{assert_clean_failure, cad, quadrille};
use serde_json::Value;

/// The `<Piece …>…</Piece>` elements of a VTU file, in order.
fn pieces(xml: &str) -> Vec<&str> {
    xml.split("<Piece ")
        .skip(1)
        .map(|p| &p[..p.find("</Piece>").expect("closed Piece")])
        .collect()
}

/// An integer attribute of a piece's opening tag.
fn attr(piece: &str, name: &str) -> usize {
    let key = format!("{name}=\"");
    let start = piece.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len();
    piece[start..start + piece[start..].find('"').unwrap()]
        .parse()
        .unwrap()
}

/// The values of the `DataArray` called `name` in `piece`.
fn array(piece: &str, name: &str) -> Vec<f64> {
    let key = format!("Name=\"{name}\"");
    let start = piece
        .find(&key)
        .unwrap_or_else(|| panic!("no array {name}"));
    let body = start + piece[start..].find('>').unwrap() + 1;
    let end = body + piece[body..].find("</DataArray>").unwrap();
    piece[body..end]
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

/// Runs `quadrille field MODEL -o DIR/field.vtu --json --quiet [extra]`;
/// returns the JSON report and the VTU text.
fn field(model: &str, dir: &Path, extra: &[&str]) -> (Value, String) {
    let out = dir.join("field.vtu");
    let m = cad(model);
    let mut args = vec![
        "field",
        m.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let r = quadrille(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: Value = serde_json::from_slice(&r.stdout).expect("JSON on stdout");
    (json, std::fs::read_to_string(&out).unwrap())
}

/// Checks the VTU against the JSON report: one piece with one triangle cell
/// per background triangle (unit or zero cross vectors, valid faces, positive
/// sizes), then one vertex cell per singularity with its index.
fn vtu_matches_report(json: &Value, xml: &str) {
    let triangles = json["totals"]["triangles"].as_u64().unwrap() as usize;
    let per_face: u64 = json["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["triangles"].as_u64().unwrap())
        .sum();
    assert_eq!(triangles as u64, per_face);
    let listed: Vec<f64> = json["faces"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|f| {
            f["singularities"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| s["index"].as_f64().unwrap())
        })
        .collect();
    let ns = listed.len();
    assert!(xml.starts_with("<?xml") && xml.trim_end().ends_with("</VTKFile>"));
    let p = pieces(xml);
    assert_eq!(p.len(), 1);
    let p = p[0];
    assert_eq!(
        attr(p, "NumberOfCells"),
        triangles + ns,
        "one cell per background triangle and per singularity"
    );
    let types = array(p, "types");
    assert_eq!(types.len(), triangles + ns);
    assert_eq!(
        types.iter().filter(|&&t| t == 5.0).count(),
        triangles,
        "VTK triangles"
    );
    assert!(
        types[triangles..].iter().all(|&t| t == 1.0),
        "then VTK vertices"
    );
    assert_eq!(array(p, "offsets").len(), triangles + ns);
    let points = attr(p, "NumberOfPoints");
    assert_eq!(array(p, "Points").len(), 3 * points);
    assert!(array(p, "connectivity")
        .iter()
        .all(|&v| v >= 0.0 && (v as usize) < points));
    let cross = array(p, "cross");
    assert_eq!(cross.len(), 3 * (triangles + ns));
    let cross = &cross[..3 * triangles];
    for d in cross.chunks(3) {
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        assert!((n - 1.0).abs() < 1e-6 || n == 0.0, "cross vector {d:?}");
    }
    assert!(
        cross
            .chunks(3)
            .filter(|d| d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0)
            .count()
            * 100
            < triangles,
        "few vanishing crosses"
    );
    let faces = json["totals"]["faces"].as_u64().unwrap() as f64;
    assert!(array(p, "cad_face")
        .iter()
        .all(|&f| (1.0..=faces).contains(&f)));
    let sizes = array(p, "size");
    assert_eq!(sizes.len(), triangles + ns);
    assert!(
        sizes[..triangles].iter().all(|&s| s > 0.0),
        "the size map is positive"
    );
    let index = array(p, "singularity_index");
    assert!(index[..triangles].iter().all(|&k| k == 0.0));
    assert_eq!(
        index[triangles..],
        listed[..],
        "singularity cells carry the indices of the report"
    );
}

#[test]
fn sphere_indices_add_up_to_eight() {
    let dir = tempfile::tempdir().unwrap();
    let (json, xml) = field("s17o_sphere.stp", dir.path(), &[]);
    let faces = json["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 1);
    let f = &faces[0];
    assert_eq!(f["face"], 1);
    assert_eq!(f["euler_characteristic"], 2);
    assert!(
        f["corner_indices"].as_array().unwrap().is_empty(),
        "a closed sphere has no boundary corner"
    );
    let sum: i64 = f["singularities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["index"].as_i64().unwrap())
        .sum();
    assert_eq!(sum, 8, "Σ indices = 4χ = 8");
    for s in f["singularities"].as_array().unwrap() {
        let p: Vec<f64> = s["position"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        assert!(
            (r - 5.0).abs() < 0.05,
            "singularity off the sphere of radius 5: {p:?}"
        );
    }
    assert_eq!(f["euler_ok"], true);
    assert_eq!(json["totals"]["faces_euler_ok"], 1);
    assert_eq!(json["totals"]["euler_ok_share"], 1.0);
    vtu_matches_report(&json, &xml);
}

#[test]
fn four_sided_faces_are_regular_and_the_picture_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("field.png");
    let (json, xml) = field(
        "twisted_body.step",
        dir.path(),
        &["--png", png.to_str().unwrap(), "--size-factor", "1.5"],
    );
    let faces = json["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 6);
    for f in faces {
        assert_eq!(f["euler_characteristic"], 1, "{f}");
        assert_eq!(
            f["corner_indices"],
            serde_json::json!([1, 1, 1, 1]),
            "four 90° corners: {f}"
        );
        assert!(
            f["singularities"].as_array().unwrap().is_empty(),
            "a four-sided face needs no singularity: {f}"
        );
        assert_eq!(f["euler_ok"], true);
    }
    assert_eq!(json["totals"]["faces_euler_ok"], 6);
    vtu_matches_report(&json, &xml);
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let (w, h) = (
        u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
        u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
    );
    assert_eq!((w, h), (1600, 1200));
}

#[test]
fn a_larger_size_gives_fewer_background_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let (fine, _) = field("twisted_body.step", dir.path(), &[]);
    let (coarse, _) = field("twisted_body.step", dir.path(), &["--size-factor", "2"]);
    let t = |j: &Value| j["totals"]["triangles"].as_u64().unwrap();
    assert!(t(&coarse) * 2 < t(&fine), "{} vs {}", t(&coarse), t(&fine));
    assert!((coarse["size"].as_f64().unwrap() / fine["size"].as_f64().unwrap() - 2.0).abs() < 1e-9);
}

/// `quadrille field` on the sphere into `out` (and `png`) must be refused,
/// naming `name`, and leave neither file.
fn field_refused(out: &Path, png: Option<&Path>, name: &str) {
    let model = cad("s17o_sphere.stp");
    let mut args = vec![
        "field",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ];
    if let Some(p) = png {
        args.extend(["--png", p.to_str().unwrap()]);
    }
    assert_clean_failure(&quadrille(&args), name);
    assert!(!out.exists(), "no field file may be left behind");
    if let Some(p) = png {
        assert!(!p.exists(), "no picture may be left behind");
    }
}

#[test]
fn bad_outputs_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    // the parent of the output is a regular file
    let blocker = dir.path().join("blocker");
    std::fs::write(&blocker, b"x").unwrap();
    field_refused(&blocker.join("field.vtu"), None, "field.vtu");
    // wrong extensions for the field and for the picture
    field_refused(&dir.path().join("field.msh"), None, "field.msh");
    field_refused(
        &dir.path().join("field.vtu"),
        Some(&dir.path().join("field.jpg")),
        "field.jpg",
    );
    field_refused(
        &dir.path().join("field.vtu"),
        Some(&blocker.join("field.png")),
        "field.png",
    );
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(left, ["blocker"], "files left behind: {left:?}");
}

#[test]
fn missing_model_and_bad_size_give_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("field.vtu");
    let r = quadrille(&[
        "field",
        dir.path().join("nope.step").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_clean_failure(&r, "nope.step");
    assert!(!out.exists());
    let model = cad("s17o_sphere.stp");
    let r = quadrille(&[
        "field",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--size=0",
        "--quiet",
    ]);
    let err = assert_clean_failure(&r, "s17o_sphere.stp");
    assert!(err.contains("size"), "{err}");
    assert!(!out.exists());
}

#[test]
fn json_alone_writes_no_file_and_no_output_at_all_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let model = cad("s17o_sphere.stp");
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_quadrille"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap()
    };
    let r = run(&["field", model.to_str().unwrap(), "--json", "--quiet"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: Value = serde_json::from_slice(&r.stdout).expect("JSON on stdout");
    // the same report as with -o: the sphere's eight +1 singularities
    assert_eq!(json["totals"]["singularities_plus"], 8);
    assert_eq!(json["totals"]["faces_euler_ok"], 1);
    // nothing asked for but the computation: refused before any work
    let r = run(&["field", model.to_str().unwrap(), "--quiet"]);
    let err = assert_clean_failure(&r, "s17o_sphere.stp");
    assert!(err.contains("nothing to do"), "{err}");
    let left = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(left, 0, "no file may be written");
}

#[test]
fn help_has_an_example() {
    let r = quadrille(&["field", "--help"]);
    assert!(r.status.success());
    let help = String::from_utf8_lossy(&r.stdout);
    assert!(
        help.contains("quadrille field part.step -o field.vtu --png field.png"),
        "{help}"
    );
    assert!(
        help.contains("--size-factor") && help.contains("--json"),
        "{help}"
    );
    let top = quadrille(&["--help"]);
    assert!(String::from_utf8_lossy(&top.stdout).contains("field"));
}

/// The JSON lists every curve's quantization: an even edge count near its
/// ideal ∫ dl / s, and a size range; a user size on one curve of the twisted
/// body raises its count (and its chord's) and lowers its sizes.
#[test]
fn curves_are_quantized_against_the_size_map() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("size.png");
    let (plain, xml) = field(
        "twisted_body.step",
        dir.path(),
        &["--size-png", png.to_str().unwrap()],
    );
    assert_eq!(&std::fs::read(&png).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    vtu_matches_report(&plain, &xml);
    let curves = plain["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 12);
    for c in curves {
        let edges = c["edges"].as_u64().unwrap();
        let ideal = c["ideal_edges"].as_f64().unwrap();
        assert!(edges % 2 == 0 && edges >= 2, "{c}");
        assert!(
            (edges as f64 - ideal).abs() <= 0.5 * ideal.max(2.0),
            "count far from its ideal: {c}"
        );
        let r = c["size_range"].as_array().unwrap();
        assert!(
            r[0].as_f64().unwrap() > 0.0 && r[0].as_f64() <= r[1].as_f64(),
            "{c}"
        );
    }
    let range = plain["size_range"].as_array().unwrap();
    let h = plain["size"].as_f64().unwrap();
    assert!(
        range[0].as_f64().unwrap() > 0.3 * h && range[1].as_f64().unwrap() < 3.0 * h,
        "{range:?} for size {h}"
    );
    let small = 0.25 * h;
    let (sized, _) = field(
        "twisted_body.step",
        dir.path(),
        &["--entity-size", &format!("curve:1={small}")],
    );
    let c1 = &sized["curves"][0];
    assert!(
        c1["edges"].as_u64().unwrap() >= 3 * plain["curves"][0]["edges"].as_u64().unwrap(),
        "{c1} vs {}",
        plain["curves"][0]
    );
    assert!(
        (c1["size_range"][0].as_f64().unwrap() - small).abs() < 1e-9 * h,
        "{c1}"
    );
}

#[test]
fn bad_size_options_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("field.vtu");
    let model = cad("s17o_sphere.stp");
    for (opt, says) in [
        ("--entity-size=curve:0=1", "start at 1"),
        ("--entity-size=edge:1=1", "unknown entity kind"),
        ("--entity-size=curve:1=-2", "positive"),
        ("--entity-size=curve1", "KIND:ID=SIZE"),
        ("--entity-size=curve:99=1", "does not have"),
        ("--size-gradient=0", "gradient"),
        ("--min-size=-1", "minimum size"),
    ] {
        let r = quadrille(&[
            "field",
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            opt,
            "--quiet",
        ]);
        assert!(!r.status.success(), "{opt} accepted");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(says), "{opt}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists());
    }
}
