//! `quadrille-fuzz`: mutation fuzzing of the readers and of meshing (issue
//! 32). `quadrille-fuzz --help` for the options; `docs/fuzzing.md` for the
//! long run and how to turn a defect into a regression test.

use fuzz::campaign::{work, Campaign, Seeds};
use fuzz::{Target, ALL_TARGETS};
use std::path::PathBuf;
use std::process::ExitCode;

const HELP: &str = "quadrille-fuzz: mutation fuzzing of Quadrille's readers and of meshing

USAGE: quadrille-fuzz [--targets LIST] [--seconds S] [--cases N] [--seed N] [--out DIR]
       quadrille-fuzz replay TARGET FILE   (one saved input, in this process)

  --targets LIST  comma-separated: stl,obj,ply,msh,step,iges,brep,mesh (default: all)
  --seconds S     time per target (default 60)
  --cases N       at most N cases per target (default: no limit)
  --seed N        campaign seed (default 1); a case is made again from seed and number
  --out DIR       where seeds and defect inputs go (default: fuzz-out)

Exit status 0 when no case panicked, crashed or hung; 1 otherwise; 2 on bad usage.";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("worker") => return worker(&args[1..]),
        Some("replay") => return replay(&args[1..]),
        _ => {}
    }
    match drive(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `worker TARGET SEEDS SEED FROM TO SCRATCH` (run by the driver).
fn worker(args: &[String]) -> ExitCode {
    let parsed = (|| -> Option<(Target, PathBuf, u64, u64, u64, PathBuf)> {
        Some((
            Target::from_name(args.first()?)?,
            PathBuf::from(args.get(1)?),
            args.get(2)?.parse().ok()?,
            args.get(3)?.parse().ok()?,
            args.get(4)?.parse().ok()?,
            PathBuf::from(args.get(5)?),
        ))
    })();
    let Some((target, seeds, seed, from, to, scratch)) = parsed else {
        eprintln!("error: worker TARGET SEEDS SEED FROM TO SCRATCH");
        return ExitCode::from(2);
    };
    match Seeds::read(&seeds) {
        Ok(s) => {
            work(target, &s, seed, from, to, &scratch);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `replay TARGET FILE`: runs one saved input through its target in this
/// process and prints the answer (a panic or crash ends the process as it
/// would end a user's); exit status 0 when it answered, 2 on bad usage.
fn replay(args: &[String]) -> ExitCode {
    let (Some(target), Some(file)) = (args.first().and_then(|t| Target::from_name(t)), args.get(1))
    else {
        eprintln!("error: replay TARGET FILE");
        return ExitCode::from(2);
    };
    let path = PathBuf::from(file);
    let data = match std::fs::read(&path) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(2);
        }
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_string())
        .unwrap_or_default();
    let scratch =
        std::env::temp_dir().join(format!("quadrille-fuzz-replay-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&scratch);
    match target.run(&data, &ext, &scratch) {
        Ok(answer) => println!("ok: {answer}"),
        Err(why) => println!("error: {why}"),
    }
    let _ = std::fs::remove_dir_all(&scratch);
    ExitCode::SUCCESS
}

/// Runs the campaigns; `Ok(true)` when no defect was found.
fn drive(args: &[String]) -> Result<bool, String> {
    let mut targets: Vec<Target> = ALL_TARGETS.to_vec();
    let (mut seconds, mut cases, mut seed) = (60.0f64, u64::MAX, 1u64);
    let mut out = PathBuf::from("fuzz-out");
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || {
            it.next()
                .cloned()
                .ok_or_else(|| format!("{a} needs a value"))
        };
        match a.as_str() {
            "-h" | "--help" => {
                println!("{HELP}");
                return Ok(true);
            }
            "--targets" => {
                let v = value()?;
                targets = if v == "all" {
                    ALL_TARGETS.to_vec()
                } else {
                    v.split(',')
                        .map(|t| {
                            Target::from_name(t.trim())
                                .ok_or_else(|| format!("unknown target '{t}'"))
                        })
                        .collect::<Result<_, _>>()?
                };
            }
            "--seconds" => {
                seconds = value()?
                    .parse()
                    .map_err(|_| "--seconds takes a number".to_string())?
            }
            "--cases" => {
                cases = value()?
                    .parse()
                    .map_err(|_| "--cases takes a whole number".to_string())?
            }
            "--seed" => {
                seed = value()?
                    .parse()
                    .map_err(|_| "--seed takes a whole number".to_string())?
            }
            "--out" => out = PathBuf::from(value()?),
            other => {
                return Err(format!(
                    "unknown argument '{other}' (--help lists the options)"
                ))
            }
        }
    }
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let cad = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/cad");
    println!(
        "{:<6} {:>9} {:>9} {:>8} {:>8}",
        "target", "cases", "accepted", "defects", "seconds"
    );
    let mut clean = true;
    for t in targets {
        let seeds = out.join("seeds").join(t.name());
        let _ = std::fs::remove_dir_all(&seeds);
        t.write_seeds(&seeds, &cad)?;
        let campaign = Campaign {
            target: t,
            seed,
            seconds,
            max_cases: cases,
            seeds,
            out: out.join("defects"),
            exe: exe.clone(),
        };
        let sum = campaign.run(|_| {})?;
        println!(
            "{:<6} {:>9} {:>9} {:>8} {:>8.1}",
            t.name(),
            sum.cases,
            sum.accepted,
            sum.defects.len(),
            sum.seconds
        );
        for d in &sum.defects {
            println!(
                "  {:?} case {}: {} ({})",
                d.kind,
                d.case,
                d.detail,
                d.file.display()
            );
        }
        clean &= sum.defects.is_empty();
    }
    Ok(clean)
}
