//! Issue 32, item 6: the readers and the mesher under mutated inputs. A short
//! campaign per target runs in `./run-tests` (`QUADRILLE_FUZZ_SECONDS`, the
//! whole budget, default 60 s); every saved defect input in `regressions/`
//! is run again here.

use fuzz::campaign::{Campaign, Seeds};
use fuzz::{Target, ALL_TARGETS};
use std::path::{Path, PathBuf};

fn cad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/cad")
}

/// Every seed is a good file: the reader (or the mesher) accepts it, so the
/// mutants start from inputs that exercise the whole reader.
#[test]
fn every_seed_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    for t in ALL_TARGETS {
        let seeds = t
            .write_seeds(&dir.path().join(t.name()), &cad_dir())
            .unwrap();
        assert!(!seeds.is_empty());
        for p in seeds {
            let data = std::fs::read(&p).unwrap();
            let ext = p.extension().unwrap().to_string_lossy().to_string();
            let r = t.run(&data, &ext, dir.path());
            assert!(r.is_ok(), "{:?} seed {} refused: {r:?}", t, p.display());
        }
    }
}

/// A budgeted campaign on every target: no panic, crash or hang; enough
/// cases ran to mean something, and the mutants were neither all accepted
/// nor all refused.
#[test]
fn a_fuzzing_campaign_finds_no_defect() {
    let total: f64 = std::env::var("QUADRILLE_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60.0);
    let seed: u64 = std::env::var("QUADRILLE_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let out = tempfile::tempdir().unwrap();
    let mut report = String::new();
    let mut defects = Vec::new();
    for t in ALL_TARGETS {
        let seeds = out.path().join("seeds").join(t.name());
        t.write_seeds(&seeds, &cad_dir()).unwrap();
        let c = Campaign {
            target: t,
            seed,
            seconds: total / ALL_TARGETS.len() as f64,
            max_cases: u64::MAX,
            seeds,
            out: out.path().join("defects"),
            exe: PathBuf::from(env!("CARGO_BIN_EXE_quadrille-fuzz")),
        };
        let s = c.run(|_| {}).unwrap();
        report += &format!(
            "{}: {} cases, {} accepted, {} defects\n",
            t.name(),
            s.cases,
            s.accepted,
            s.defects.len()
        );
        let least = if t == Target::Mesh { 3 } else { 20 };
        assert!(s.cases >= least, "{report}");
        for d in &s.defects {
            // keep the input for the log (the temporary folder goes away)
            let data = std::fs::read(&d.file).unwrap();
            defects.push(format!(
                "{:?} {:?} case {} seed {seed}: {} ({} bytes)",
                t,
                d.kind,
                d.case,
                d.detail,
                data.len()
            ));
        }
        if t != Target::Mesh {
            assert!(
                s.accepted < s.cases,
                "{t:?}: every mutant accepted?\n{report}"
            );
        }
    }
    eprintln!("{report}");
    assert!(defects.is_empty(), "{}\n{report}", defects.join("\n"));
}

/// Inputs that once panicked, crashed or hung (`regressions/<target>/`)
/// now give an answer, an error or a mesh: each replayed in a process of its
/// own (a CAD read that times out leaves OCCT busy in its process), which
/// must end normally, within three times the fuzzer's hang limit (the CAD
/// read limit is 5 s for files this small; the rest is room for a loaded
/// machine).
#[test]
fn regression_inputs_get_an_answer() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut n = 0;
    for t in ALL_TARGETS {
        let Ok(seeds) = Seeds::read(&root.join(t.name())) else {
            continue;
        };
        for p in &seeds.paths {
            let started = std::time::Instant::now();
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_quadrille-fuzz"))
                .args(["replay", t.name()])
                .arg(p)
                .output()
                .unwrap();
            let secs = started.elapsed().as_secs_f64();
            let said = String::from_utf8_lossy(&out.stdout);
            assert!(
                out.status.success(),
                "{}: {:?} {said}",
                p.display(),
                out.status
            );
            assert!(
                said.starts_with("ok: ") || said.starts_with("error: "),
                "{}: {said}",
                p.display()
            );
            assert!(
                secs < 3.0 * t.hang_seconds() as f64,
                "{} took {secs:.1} s",
                p.display()
            );
            n += 1;
        }
    }
    assert!(n >= 10, "only {n} regression inputs found");
}
