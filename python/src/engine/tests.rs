//! The engine without Python: options refused with the right kind, files
//! errors naming the file, a mesh through a [`Job`] equal to the library's,
//! cancellation, a panic turned into an error, writers and reader, the field.

use super::*;

fn cad(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/cad")
        .join(name)
}

/// Waits for a job's outcome (at most a few minutes).
fn finish<T: Send + 'static>(job: &Job<T>) -> Outcome<T> {
    job.wait(Duration::from_secs(300))
        .expect("the job ends within the timeout")
}

#[test]
fn methods_by_name() {
    for m in Method::ALL {
        assert_eq!(Method::parse(m.name()).unwrap(), m);
    }
    assert_eq!(
        Method::parse("Quasi_Structured").unwrap(),
        Method::QuasiStructured
    );
    let e = Method::parse("paving").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Option);
    assert!(e.message.contains("\"paving\""), "{e}");
}

#[test]
fn bad_options_are_option_errors() {
    for (size, factor) in [
        (Some(0.0), 1.0),
        (Some(-1.0), 1.0),
        (Some(f64::NAN), 1.0),
        (None, 0.0),
        (None, f64::INFINITY),
        (Some(2.0), 0.5),
    ] {
        let e = size_of(size, factor).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Option, "{size:?} {factor}");
    }
    assert_eq!(size_of(Some(2.0), 1.0).unwrap(), Size::Absolute(2.0));
    assert_eq!(size_of(None, 0.5).unwrap(), Size::Factor(0.5));

    let bad = [
        MeshRequest {
            threads: Some(0),
            ..Default::default()
        },
        MeshRequest {
            quads_per_turn: -1.0,
            ..Default::default()
        },
        MeshRequest {
            method: Method::Baseline,
            stages: Stages {
                cavities: false,
                ..Stages::ALL
            },
            ..Default::default()
        },
    ];
    for r in &bad {
        let e = r.to_library(None).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Option, "{r:?}");
    }
    let e = bad[2].to_library(None).unwrap_err();
    assert!(e.message.contains("cavities=False"), "{e}");
    // the stages are the quasi-structured method's
    let ok = MeshRequest {
        stages: Stages::NONE,
        ..Default::default()
    };
    let (_, method) = ok.to_library(None).unwrap();
    assert!(matches!(method, MeshMethod::QuasiStructured(s) if s == Stages::NONE));
}

#[test]
fn bad_files_are_file_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let empty_step = dir.path().join("empty.step");
    let empty_stl = dir.path().join("empty.stl");
    std::fs::write(&empty_step, b"").unwrap();
    std::fs::write(&empty_stl, b"").unwrap();
    let odd = dir.path().join("model.xyz");
    std::fs::write(&odd, b"solid").unwrap();
    for path in [
        dir.path().join("missing.step"),
        dir.path().join("missing.stl"),
        empty_step,
        empty_stl,
        odd,
    ] {
        let e = load(&path, 30.0).err().expect("refused");
        assert_eq!(e.kind, ErrorKind::File, "{e}");
        assert!(
            e.message
                .contains(&*path.file_name().unwrap().to_string_lossy()),
            "{e}"
        );
    }
    let e = load(&cad("s17o_sphere.stp"), 0.0).err().unwrap();
    assert_eq!(e.kind, ErrorKind::Option);
}

#[test]
fn a_job_meshes_as_the_library_does() {
    let path = cad("s12o_cube_rounded_1.stp");
    let model = Arc::new(load(&path, 30.0).unwrap().model);
    let request = MeshRequest {
        threads: Some(2),
        ..Default::default()
    };
    let job = start_mesh(model.clone(), path.display().to_string(), &request).unwrap();
    let Outcome::Done((mesh, report)) = finish(&job) else {
        panic!("meshing failed")
    };
    // the progress reached every face
    assert_eq!(job.progress().get(), (model.faces.len(), model.faces.len()));
    // the same mesh as the library's own call, for any thread count
    let (opts, method) = MeshRequest {
        threads: Some(1),
        ..Default::default()
    }
    .to_library(None)
    .unwrap();
    let (direct, direct_report) = quadrille::mesh_model_with(&model, &opts, method).unwrap();
    assert_eq!(mesh.nodes, direct.nodes);
    assert_eq!(mesh.quads, direct.quads);
    assert_eq!(report, direct_report);

    // the arrays the NumPy ones are made of
    let n = mesh.nodes.len();
    assert_eq!(flat_nodes(&mesh).len(), 3 * n);
    let quads = flat_quads(&mesh);
    assert_eq!(quads.len(), 4 * mesh.quads.len());
    assert!(quads.iter().all(|&v| (0..n as i64).contains(&v)));
    let ent = flat_node_entity(&mesh);
    assert_eq!(ent.len(), 2 * n);
    for (pair, class) in ent.chunks(2).zip(&mesh.node_class) {
        match class {
            NodeClass::Corner(k) => assert_eq!(pair, [0, k.0 as i64 + 1]),
            NodeClass::Curve(k, _) => assert_eq!(pair, [1, k.0 as i64 + 1]),
            NodeClass::Face(k, _) => assert_eq!(pair, [2, k.0 as i64 + 1]),
            NodeClass::Unclassified => panic!("a mesh of ours classifies every node"),
        }
    }
    let faces = one_based(&mesh.quad_face);
    assert!(faces
        .iter()
        .all(|&f| (1..=model.faces.len() as i64).contains(&f)));

    let rep = report_json(&report, &request, model.faces.len(), &mesh);
    assert_eq!(rep["quads"], mesh.quads.len());
    assert_eq!(rep["method"], "quasi-structured");
    assert_eq!(
        rep["patterns"].as_array().unwrap().len(),
        report.patterns.len()
    );
    assert!(rep["times"]["total"].as_f64().unwrap() > 0.0);
    let stats: Value = serde_json::from_str(&stats_json(&mesh, Some(&model))).unwrap();
    assert_eq!(stats["quads"], mesh.quads.len());
    assert_eq!(stats["inverted_quads"], 0);
    assert_eq!(stats["inverted_quads_element_geometry"], 0);
    assert_eq!(stats["cad_normals"], true);
}

#[test]
fn a_cancelled_job_stops_at_the_next_progress_call() {
    let calls = Arc::new(AtomicUsize::new(0));
    let seen = calls.clone();
    let job = Job::spawn(move |progress| {
        for i in 0..10_000 {
            progress(i, 10_000);
            seen.fetch_add(1, Ordering::Relaxed);
            std::thread::sleep(Duration::from_millis(1));
        }
        Ok(())
    });
    // running: no outcome yet
    assert!(job.wait(Duration::from_millis(20)).is_none());
    job.cancel();
    assert!(matches!(finish(&job), Outcome::Cancelled));
    let at_cancel = calls.load(Ordering::Relaxed);
    assert!(at_cancel < 10_000, "{at_cancel}");
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(calls.load(Ordering::Relaxed), at_cancel, "the work stopped");
    // the outcome is handed out once
    assert!(job.wait(Duration::from_millis(1)).is_none());

    // a real mesh, cancelled before its first face is done
    let path = cad("i01o_m1.step");
    let model = Arc::new(load(&path, 30.0).unwrap().model);
    let job = start_mesh(model, "i01o_m1.step".into(), &MeshRequest::default()).unwrap();
    job.cancel();
    assert!(matches!(finish(&job), Outcome::Cancelled));
}

#[test]
fn a_panic_in_the_work_is_a_meshing_error() {
    let job: Job<()> = Job::spawn(|_| panic!("boom"));
    match finish(&job) {
        Outcome::Failed(e) => {
            assert_eq!(e.kind, ErrorKind::Meshing);
            assert!(e.message.contains("boom"), "{e}");
        }
        _ => panic!("expected a failure"),
    }
}

#[test]
fn writers_and_reader() {
    let dir = tempfile::tempdir().unwrap();
    let (model, mesh) = mesh::fixtures::cube(2.0, 3);
    for name in ["a.msh", "a.vtu", "a.obj"] {
        let p = dir.path().join(name);
        write_mesh(&mesh, Some(&model), &p, false, false).unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 0, "{name}");
    }
    let back = read_mesh(&dir.path().join("a.msh")).unwrap();
    assert_eq!(back.nodes, mesh.nodes);
    assert_eq!(back.quads, mesh.quads);
    // no parameters by default, with them on request
    assert!(back.node_class.iter().all(|c| !matches!(
        c,
        NodeClass::Curve(_, Some(_)) | NodeClass::Face(_, Some(_))
    )));
    let p = dir.path().join("p.msh");
    write_mesh(&mesh, Some(&model), &p, true, true).unwrap();
    assert_eq!(read_mesh(&p).unwrap().node_class, mesh.node_class);

    let e = write_mesh(&mesh, None, &dir.path().join("a.stl"), false, false).unwrap_err();
    assert_eq!(e.kind, ErrorKind::File);
    assert!(e.message.contains("a.stl"), "{e}");
    let e = write_mesh(&mesh, None, &dir.path().join("b.vtu"), true, false).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Option);
    let e = write_mesh(&mesh, None, &dir.path().join("no/such/c.msh"), false, false).unwrap_err();
    assert_eq!(e.kind, ErrorKind::File);
    assert!(e.message.contains("c.msh"), "{e}");
    assert!(!dir.path().join("b.vtu").exists());

    for bad in ["a.vtu", "missing.msh"] {
        let e = read_mesh(&dir.path().join(bad)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::File);
        assert!(e.message.contains(bad), "{e}");
    }
}

#[test]
fn the_sphere_field_has_eight_plus_one_singularities() {
    let path = cad("s17o_sphere.stp");
    let model = Arc::new(load(&path, 30.0).unwrap().model);
    let job = start_field(model, "s17o_sphere.stp".into(), None, 1.0, 20.0).unwrap();
    let Outcome::Done(f) = finish(&job) else {
        panic!("the field failed")
    };
    assert_eq!(f.singularities.len(), 8);
    assert!(f.singularities.iter().all(|s| s.1 == 1 && s.2 == 1));
    let m = f.triangles.len() / 3;
    assert!(m > 100);
    assert_eq!(f.triangle_face.len(), m);
    assert_eq!(f.cross.len(), 3 * m);
    assert_eq!(f.size.len(), m);
    let n = (f.points.len() / 3) as i64;
    assert!(f.triangles.iter().all(|&v| (0..n).contains(&v)));
    assert_eq!(f.report["totals"]["faces_euler_ok"], 1);
    assert!(start_field(
        Arc::new(Model::default()),
        "x".into(),
        Some(-1.0),
        1.0,
        20.0
    )
    .is_err());
}

#[test]
fn a_far_too_small_size_is_an_option_error_naming_the_python_options() {
    let path = cad("i01o_m1.step");
    let model = Arc::new(load(&path, 30.0).unwrap().model);
    let request = MeshRequest {
        size: Some(1e-5),
        ..Default::default()
    };
    let job = start_mesh(model, path.display().to_string(), &request).unwrap();
    let Outcome::Failed(e) = finish(&job) else {
        panic!("not refused")
    };
    assert_eq!(e.kind, ErrorKind::Option, "{e}");
    for part in [
        "i01o_m1.step",
        "quads estimated",
        "size_factor",
        "max_quads 0 lifts",
    ] {
        assert!(e.message.contains(part), "`{part}` missing: {e}");
    }
    assert!(!e.message.contains("--"), "no command-line flags: {e}");
}
