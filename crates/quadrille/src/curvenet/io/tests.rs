use super::*;
use std::path::PathBuf;

/// `docs/curve-networks.md`, whose examples are tested.
const DOC: &str = include_str!("../../../../../docs/curve-networks.md");

/// The first code block of `DOC` after `heading` opening with `fence`.
fn doc_block(heading: &str, fence: &str) -> String {
    let rest = &DOC[DOC.find(heading).expect("heading")..];
    let start = rest.find(fence).expect("block") + fence.len();
    let end = start + rest[start..].find("```").expect("end of block");
    rest[start..end].to_string()
}

/// The JSON example of `docs/curve-networks.md`: a 2 × 1 rectangle with a
/// square hole, beside a unit square sharing its right side.
const EXAMPLE: &str = r#"{
  "curves": [
    {"points": [[0,0,0], [2,0,0]]},
    {"points": [[2,0,0], [2,1,0]]},
    {"points": [[2,1,0], [0,1,0], [0,0,0]]},
    {"points": [[0.5,0.25,0], [1,0.25,0], [1,0.75,0], [0.5,0.75,0], [0.5,0.25,0]]},
    {"points": [[2,0,0], [3,0,0], [3,1,0], [2,1,0]], "cad_curve": 7}
  ],
  "cycles": [
    {"loops": [[[0,1], [1,1], [2,1]], [[3,-1]]]},
    {"loops": [[[4,1], [1,-1]]], "cad_face": 2}
  ],
  "corners": [[1,0,0]],
  "units": "mm"
}"#;

/// A fresh path in the temporary directory.
fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("quadrille-curvenet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn the_documented_json_example_reads() {
    let doc = parse_json(&doc_block("## JSON", "```json\n"), None).unwrap();
    assert_eq!(doc, parse_json(EXAMPLE, None).unwrap());
    let net = parse_json(EXAMPLE, Some("ex.json")).unwrap();
    assert_eq!(net.curves().len(), 5);
    assert_eq!(net.cycles().len(), 2);
    assert_eq!(net.curves()[4].cad, Some(CurveId(6)));
    assert_eq!(net.cycles()[1].cad_face, Some(FaceId(1)));
    assert_eq!(net.file(), Some("ex.json"));
    assert!(net.validate().is_empty(), "{:?}", net.validate());
    let a = net.cycle_loops(0).unwrap();
    assert_eq!(a.outer.points.len(), 5); // the corner (1, 0, 0) inserted
    assert_eq!(a.holes.len(), 1);
    let fixed: Vec<Vec3> = a.outer.fixed.iter().map(|&i| a.outer.points[i]).collect();
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
    ] {
        assert!(fixed.contains(&p), "{p:?} in {fixed:?}");
    }
    let b = net.cycle_loops(1).unwrap();
    assert_eq!(b.outer.points.len(), 4);
}

#[test]
fn the_json_writer_reads_back_to_an_equal_network() {
    let net = parse_json(EXAMPLE, None).unwrap();
    let text = to_json(&net);
    let back = parse_json(&text, None).unwrap();
    assert_eq!(back, net);
    assert_eq!(to_json(&back), text);
    // through a file, with awkward numbers
    let mut curves = net.curves().to_vec();
    curves[2].points[1] = [0.1 + 0.2, 1.0 / 3.0, -1e-300];
    let net = CurveNetwork::new(curves, net.cycles().to_vec(), net.corners().to_vec()).unwrap();
    let path = temp("round_trip.json");
    write_network(&net, &path).unwrap();
    let back = read_network(&path).unwrap();
    assert_eq!(back, net);
    assert_eq!(back.file(), Some(path.display().to_string().as_str()));
}

#[test]
fn json_errors_give_line_and_column() {
    // truncated
    let cut = &EXAMPLE[..EXAMPLE.len() / 2];
    let e = parse_json(cut, Some("cut.json")).unwrap_err();
    match &e {
        CurveNetError::Syntax { line, message, .. } => {
            assert!(*line >= 5, "{line}");
            assert!(message.contains("truncated"), "{message}");
        }
        _ => panic!("{e:?}"),
    }
    assert!(e.to_string().starts_with("cut.json:"), "{e}");
    // a syntax error: line 2, column 22 (the `}` closing no array)
    let e = parse_json("{\"curves\": [\n  {\"points\": [[0,0,0]}]}", Some("x.json")).unwrap_err();
    assert!(
        matches!(
            e,
            CurveNetError::Syntax {
                line: 2,
                column: 22,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("x.json:2:22: "), "{e}");
    // wrong types and missing keys
    let e = parse_json(r#"{"curves": [{"points": [[0,0]]}], "cycles": []}"#, None).unwrap_err();
    assert!(matches!(e, CurveNetError::Syntax { line: 1, .. }), "{e:?}");
    let e = parse_json("42", None).unwrap_err();
    assert!(
        e.to_string()
            .contains("expected a curve network: {\"curves\": [...], \"cycles\": [...]}"),
        "{e}"
    );
    let e = parse_json(r#"{"curves": []}"#, None).unwrap_err();
    assert!(e.to_string().contains("missing field `cycles`"), "{e}");
    // a direction other than ±1, ids that are not positions
    let bad = EXAMPLE.replace("[[4,1], [1,-1]]", "[[4,1], [1,2]]");
    let e = parse_json(&bad, None).unwrap_err();
    assert_eq!(
        e.to_string(),
        "cycle 1, loop 0, use 1: direction 2 (1 or -1 expected)"
    );
    let bad = EXAMPLE.replace("\"cad_curve\": 7", "\"id\": 9");
    assert!(matches!(
        parse_json(&bad, None),
        Err(CurveNetError::Format { .. })
    ));
    // NaN is not JSON; a number out of range is refused
    let bad = EXAMPLE.replace("[0.5,0.25,0]", "[1e999,0.25,0]");
    assert!(matches!(
        parse_json(&bad, None),
        Err(CurveNetError::Syntax { .. })
    ));
    // unknown curve
    let bad = EXAMPLE.replace("[[3,-1]]", "[[5,-1]]");
    let e = parse_json(&bad, Some("u.json")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("u.json: cycle 0: unknown curve: use 0 of hole 1 names curve 5"),
        "{e}"
    );
}

#[test]
fn empty_missing_and_unknown_files_are_clear_errors() {
    assert!(matches!(
        parse_json("  \n", None),
        Err(CurveNetError::Empty { .. })
    ));
    assert!(matches!(
        parse_json(r#"{"curves": [], "cycles": []}"#, None),
        Err(CurveNetError::Empty { .. })
    ));
    assert!(matches!(
        parse_obj("", None),
        Err(CurveNetError::Empty { .. })
    ));
    let e = read_network(Path::new("/nonexistent/net.json")).unwrap_err();
    assert!(matches!(e, CurveNetError::Io { .. }), "{e:?}");
    assert!(
        e.to_string()
            .starts_with("/nonexistent/net.json: cannot read: "),
        "{e}"
    );
    let e = read_network(Path::new("model.step")).unwrap_err();
    assert!(e.to_string().contains("occt::load"), "{e}");
    let e = read_network(Path::new("net.txt")).unwrap_err();
    assert!(matches!(e, CurveNetError::Format { .. }), "{e:?}");
    let path = temp("binary.obj");
    std::fs::write(&path, [0x76, 0x20, 0xff, 0xfe]).unwrap();
    assert!(matches!(read_network(&path), Err(CurveNetError::Io { .. })));
    // cycle errors from a file name it
    let path = temp("open.json");
    std::fs::write(
        &path,
        r#"{"curves":[{"points":[[0,0,0],[1,0,0],[1,1,0]]}],"cycles":[{"loops":[[[0,1]]]}]}"#,
    )
    .unwrap();
    let net = read_network(&path).unwrap();
    let e = net.cycle_loops(0).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}: cycle 0: open cycle", path.display())),
        "{e}"
    );
}

/// Two unit squares sharing the side x = 1, each its own vertices, the right
/// one given clockwise… then corrected: adjacent cycles run opposite ways
/// along the shared side.
const TWO_SQUARES: &str = "\
# left square
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
l 1 2 3 4 1
# right square, its own copies of the shared vertices
v 1 0 0
v 2 0 0
v 2 1 0
v 1 1 0
l -4 -3 -2 -1 -4
p 2
";

#[test]
fn the_documented_obj_example_reads() {
    let net = parse_obj(&doc_block("## OBJ", "```\n"), None).unwrap();
    // the curves as the document lists them: 2–3, 3–4–1–2, 2–5–6–3
    let v = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let (v5, v6) = ([2.0, 0.0, 0.0], [2.0, 1.0, 0.0]);
    let want = vec![
        vec![v[1], v[2]],
        vec![v[2], v[3], v[0], v[1]],
        vec![v[1], v5, v6, v[2]],
    ];
    let got: Vec<Vec<Vec3>> = net.curves().iter().map(|c| c.points.clone()).collect();
    assert_eq!(got, want);
    assert_eq!(net.corners(), &[v[1]]);
    assert!(net.validate().is_empty(), "{:?}", net.validate());
}

#[test]
fn obj_cycles_and_their_curves() {
    let net = parse_obj(TWO_SQUARES, Some("sq.obj")).unwrap();
    assert_eq!(net.cycles().len(), 2);
    // curves: the left square's three sides, the shared side, the right
    // square's three sides
    assert_eq!(net.curves().len(), 3);
    let shared: Vec<usize> = (0..3)
        .filter(|&c| net.curves()[c].points.len() == 2)
        .collect();
    assert_eq!(shared.len(), 1);
    assert_eq!(net.corners(), &[[1.0, 0.0, 0.0]]);
    assert!(net.validate().is_empty(), "{:?}", net.validate());
    for c in 0..2 {
        let l = net.cycle_loops(c).unwrap();
        assert_eq!(l.outer.points.len(), 4);
        assert_eq!(l.outer.fixed.len(), 2, "{:?}", l.outer.fixed);
    }
    // the same through JSON
    let back = parse_json(&to_json(&net), None).unwrap();
    assert_eq!(back, net);
}

#[test]
fn obj_same_direction_on_a_shared_side_is_not_orientable() {
    // the right square clockwise: both use the shared side upward
    let text = TWO_SQUARES.replace("l -4 -3 -2 -1 -4", "l -4 -1 -2 -3 -4");
    let net = parse_obj(&text, None).unwrap();
    let errors = net.validate();
    assert_eq!(errors.len(), 2);
    assert!(errors
        .iter()
        .all(|e| matches!(e, CurveNetError::NonOrientable { .. })));
}

#[test]
fn obj_single_loops_and_errors() {
    // one closed loop with no junction: one closed curve from its least vertex
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nl 3 4 1 2 3\nl 1 2\n";
    let net = parse_obj(text, None).unwrap();
    assert_eq!(net.curves().len(), 1);
    assert_eq!(net.curves()[0].points.len(), 5);
    assert_eq!(net.curves()[0].points[0], [0.0, 0.0, 0.0]);
    net.cycle_loops(0).unwrap();
    // errors with line and column
    let e = parse_obj("v 0 0 0\nv 1 x 0\n", Some("a.obj")).unwrap_err();
    assert_eq!(e.to_string(), "a.obj:2:5: \"x\" is not a number");
    let e = parse_obj("v 0 0 0\nl 1 2 1\n", Some("a.obj")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "a.obj:2:5: vertex 2 does not exist (1 vertices)"
    );
    let e = parse_obj("v 0 0 0\nl 1 0 1\n", None).unwrap_err();
    assert!(
        matches!(
            e,
            CurveNetError::Syntax {
                line: 2,
                column: 5,
                ..
            }
        ),
        "{e:?}"
    );
    let e = parse_obj("v 0 0 0\nv 1 0 0\nl 1 2\n", None).unwrap_err();
    assert!(matches!(e, CurveNetError::Empty { .. }), "{e:?}");
    // NaN parses as a number and is refused by name
    let e = parse_obj("v 0 0 0\nv 1 0 0\nv nan 1 0\nl 1 2 3 1\n", Some("n.obj")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "n.obj: not a finite number: vertex 3 (line 3) is (NaN, 1, 0)"
    );
    let e = parse_obj("v 0 0 0\nv 1 0 0\nv inf 1 0\nl 1 2 3 1\n", None).unwrap_err();
    assert!(matches!(e, CurveNetError::NotFinite { .. }), "{e:?}");
}

#[test]
fn obj_curves_break_at_junctions_of_three_cycles() {
    // three triangles around the origin (a fan), each counter-clockwise: the
    // spokes are shared, the origin joins 3 spokes
    let text = "\
v 0 0 0
v 1 0 0
v 0 1 0
v -1 -1 0
l 1 2 3 1
l 1 3 4 1
l 1 4 2 1
";
    let net = parse_obj(text, None).unwrap();
    // 3 spokes + 3 rim sides
    assert_eq!(net.curves().len(), 6);
    assert!(net.validate().is_empty(), "{:?}", net.validate());
    for c in 0..3 {
        let l = net.cycle_loops(c).unwrap();
        assert_eq!(l.outer.fixed, vec![0, 1, 2]);
    }
}

/// The error messages `docs/curve-networks.md` shows are the real ones.
#[test]
fn the_documented_messages_are_the_real_ones() {
    let cycle_error = |json: &str, c: usize| {
        parse_json(json, Some("net.json"))
            .unwrap()
            .cycle_loops(c)
            .unwrap_err()
    };
    let msgs = [
        cycle_error(
            r#"{"curves":[{"points":[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0.01,0]]}],
                "cycles":[{"loops":[[[0,1]]]}]}"#,
            0,
        ),
        cycle_error(
            r#"{"curves":[{"points":[[0,0,0],[2,2,0],[2,0,0],[0,2,0],[0,0,0]]}],
                "cycles":[{"loops":[[[0,1]]]}]}"#,
            0,
        ),
        cycle_error(
            r#"{"curves":[{"points":[[0,0,0],[1,0,0],[1,1,0],[0,0,0]]},{"points":[[5,5,0]]}],
                "cycles":[{"loops":[[[0,1]]]},{"loops":[[[1,1]]]}]}"#,
            1,
        ),
        cycle_error(
            r#"{"curves":[{"points":[[0,0,0],[1,0,0],[2,1e-7,0],[0,0,0]]}],
                "cycles":[{"loops":[[[0,1]]]}]}"#,
            0,
        ),
        parse_json(&EXAMPLE.replace("[[3,-1]]", "[[5,-1]]"), Some("net.json")).unwrap_err(),
        parse_obj("v 0 0 0\nv 1 0 0\nv nan 1 0\nl 1 2 3 1\n", Some("net.obj")).unwrap_err(),
        parse_obj(
            &TWO_SQUARES.replace("l -4 -3 -2 -1 -4", "l -4 -1 -2 -3 -4"),
            Some("net.obj"),
        )
        .unwrap()
        .cycle_loops(1)
        .unwrap_err(),
        parse_json(&EXAMPLE[..EXAMPLE.len() / 2], Some("net.json")).unwrap_err(),
        parse_json(" ", Some("net.json")).unwrap_err(),
        read_network(Path::new("net.json")).unwrap_err(),
    ];
    for m in msgs {
        let line = m.to_string();
        assert!(!line.contains('\n'), "{line}");
        assert!(
            DOC.contains(&format!("`{line}`")),
            "not in the document: {line}"
        );
    }
}
