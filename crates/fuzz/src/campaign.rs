//! A fuzzing campaign: worker processes run batches of cases and report each
//! case before running it, so a crash (a signal, an abort inside
//! OpenCASCADE, an allocation failure) or a hang is pinned to its case; the
//! driver saves the input of every defect and goes on with the next case.

use crate::mutate::mutant;
use crate::rng::Rng;
use crate::target::Target;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Address space a worker may use (bytes): a corrupted count that makes a
/// reader allocate more is a defect, found without exhausting the machine.
pub const WORKER_MEMORY: u64 = 4 << 30;

/// What went wrong with one case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DefectKind {
    /// A Rust panic (caught in the worker).
    Panic,
    /// The worker died: a signal, an abort or another exit status.
    Crash,
    /// The case ran past [`Target::hang_seconds`].
    Hang,
}

/// A defect: its case, kind, what the worker said and the saved input.
#[derive(Clone, Debug)]
pub struct Defect {
    /// Case number (with the campaign seed it makes the input again).
    pub case: u64,
    /// Panic, crash or hang.
    pub kind: DefectKind,
    /// The panic message or exit status.
    pub detail: String,
    /// The saved input.
    pub file: PathBuf,
}

/// What a campaign on one target did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The target.
    pub target: Target,
    /// Cases run (finished, refused or defective).
    pub cases: u64,
    /// Cases the reader accepted (the rest were refused with an error).
    pub accepted: u64,
    /// The defects.
    pub defects: Vec<Defect>,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// The seed files of a campaign and their bytes.
pub struct Seeds {
    /// Paths, sorted.
    pub paths: Vec<PathBuf>,
    /// Their contents.
    pub bytes: Vec<Vec<u8>>,
}

impl Seeds {
    /// Reads the seed files in `dir` (sorted by name).
    pub fn read(dir: &Path) -> Result<Seeds, String> {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file())
            .collect();
        paths.sort();
        if paths.is_empty() {
            return Err(format!("{}: no seed files", dir.display()));
        }
        let bytes = paths
            .iter()
            .map(|p| std::fs::read(p).map_err(|e| format!("{}: {e}", p.display())))
            .collect::<Result<_, _>>()?;
        Ok(Seeds { paths, bytes })
    }

    /// Case `case` of campaign `seed`: the extension of the seed it mutates,
    /// and the mutant.
    pub fn case(&self, seed: u64, case: u64) -> (String, Vec<u8>) {
        let mut rng = Rng::for_case(seed, case);
        let i = rng.below(self.paths.len());
        let ext = self.paths[i]
            .extension()
            .map(|e| e.to_string_lossy().to_string())
            .unwrap_or_default();
        (ext, mutant(&self.bytes[i], &self.bytes, &mut rng))
    }
}

/// The worker's side: runs cases `from..to`, printing `@case K` before each,
/// `@ok K` after an accepted one and `@panic K message` after a caught panic,
/// then `@done`; `@stop K` when the process reads no more CAD files after case
/// K (a read timed out or faulted inside OCCT: `occt::cad_reads_refused`), so
/// the driver starts a new worker after it.
pub fn work(target: Target, seeds: &Seeds, seed: u64, from: u64, to: u64, scratch: &Path) {
    limit_memory(WORKER_MEMORY);
    std::panic::set_hook(Box::new(|_| {}));
    let out = std::io::stdout();
    for case in from..to {
        let (ext, data) = seeds.case(seed, case);
        let _ = writeln!(out.lock(), "@case {case}");
        let _ = out.lock().flush();
        match std::panic::catch_unwind(|| target.run(&data, &ext, scratch)) {
            Ok(Ok(_)) => {
                let _ = writeln!(out.lock(), "@ok {case}");
            }
            Ok(Err(_)) => {}
            Err(payload) => {
                let msg = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic".into());
                let _ = writeln!(out.lock(), "@panic {case} {}", msg.replace('\n', " "));
            }
        }
        if occt::cad_reads_refused().is_some() {
            // a CAD read timed out (its thread still holds OCCT's lock) or
            // faulted inside OCCT (whose state is no longer trusted): later
            // cases would only be refused, so this worker ends
            let _ = writeln!(out.lock(), "@stop {case}");
            let _ = out.lock().flush();
            return;
        }
    }
    let _ = writeln!(out.lock(), "@done");
    let _ = out.lock().flush();
}

fn limit_memory(bytes: u64) {
    let lim = libc::rlimit {
        rlim_cur: bytes as libc::rlim_t,
        rlim_max: bytes as libc::rlim_t,
    };
    // SAFETY: setrlimit with a valid struct; failure only leaves the limit off.
    unsafe {
        libc::setrlimit(libc::RLIMIT_AS, &lim);
    }
}

/// The driver's options.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The target.
    pub target: Target,
    /// Campaign seed.
    pub seed: u64,
    /// Stop starting batches after this many seconds.
    pub seconds: f64,
    /// Stop after this many cases (whichever comes first).
    pub max_cases: u64,
    /// The folder of seed files (written by [`Target::write_seeds`]).
    pub seeds: PathBuf,
    /// Where defect inputs are saved.
    pub out: PathBuf,
    /// The `quadrille-fuzz` executable (workers run `EXE worker ...`).
    pub exe: PathBuf,
}

/// One line of a worker, or its end.
enum Event {
    Line(String),
    Eof,
}

impl Campaign {
    /// Runs the campaign: batches of workers until the time or case budget is
    /// spent; every defect's input is saved in `out`.
    pub fn run(&self, mut progress: impl FnMut(&Summary)) -> Result<Summary, String> {
        let seeds = Seeds::read(&self.seeds)?;
        std::fs::create_dir_all(&self.out).map_err(|e| format!("{}: {e}", self.out.display()))?;
        let started = Instant::now();
        let mut sum = Summary {
            target: self.target,
            cases: 0,
            accepted: 0,
            defects: Vec::new(),
            seconds: 0.0,
        };
        let mut next = 0u64;
        while started.elapsed().as_secs_f64() < self.seconds && next < self.max_cases {
            let to = (next + self.target.batch()).min(self.max_cases);
            let resume = self.batch(&seeds, next, to, &mut sum)?;
            next = resume;
            sum.seconds = started.elapsed().as_secs_f64();
            progress(&sum);
        }
        sum.seconds = started.elapsed().as_secs_f64();
        Ok(sum)
    }

    /// Runs cases `from..to` in one worker; returns the case to go on from.
    fn batch(&self, seeds: &Seeds, from: u64, to: u64, sum: &mut Summary) -> Result<u64, String> {
        let scratch = tempfile::tempdir().map_err(|e| e.to_string())?;
        // the worker's stderr, whose last line names what a crash was (an
        // allocation that failed, an OCCT message) when the worker dies
        let stderr_path = scratch.path().join("worker-stderr.txt");
        let stderr_file = std::fs::File::create(&stderr_path).map_err(|e| e.to_string())?;
        let mut child = Command::new(&self.exe)
            .args(["worker", self.target.name()])
            .arg(&self.seeds)
            .args([self.seed.to_string(), from.to_string(), to.to_string()])
            .arg(scratch.path())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::from(stderr_file))
            .spawn()
            .map_err(|e| format!("{}: {e}", self.exe.display()))?;
        let stdout = child.stdout.take().expect("piped stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                match line {
                    Ok(l) => {
                        if tx.send(Event::Line(l)).is_err() {
                            return;
                        }
                    }
                    Err(_) => break,
                }
            }
            let _ = tx.send(Event::Eof);
        });
        let hang = Duration::from_secs(self.target.hang_seconds());
        let poll = hang.min(Duration::from_secs(1));
        let pid = child.id();
        let mut current: Option<u64> = None;
        let mut done = false;
        // the clock of the worker's last line: wall time and its CPU time
        let mut since = (Instant::now(), cpu_seconds(pid));
        loop {
            match rx.recv_timeout(poll) {
                Ok(Event::Line(l)) => {
                    since = (Instant::now(), cpu_seconds(pid));
                    if let Some(k) = l.strip_prefix("@case ") {
                        current = k.trim().parse().ok();
                        sum.cases += 1;
                    } else if l.starts_with("@ok ") {
                        sum.accepted += 1;
                    } else if let Some(rest) = l.strip_prefix("@panic ") {
                        let (k, msg) = rest.split_once(' ').unwrap_or((rest, ""));
                        let case = k.parse().unwrap_or(0);
                        self.record(seeds, case, DefectKind::Panic, msg.to_string(), sum)?;
                    } else if l == "@done" {
                        done = true;
                    } else if let Some(k) = l.strip_prefix("@stop ") {
                        let _ = child.wait();
                        return Ok(k.trim().parse::<u64>().map_or(to, |k| k + 1));
                    }
                }
                Ok(Event::Eof) => break,
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    let wall = since.0.elapsed();
                    let cpu = match (since.1, cpu_seconds(pid)) {
                        (Some(a), Some(b)) => Some(b - a),
                        _ => None,
                    };
                    if !is_hang(hang, wall, cpu) {
                        continue;
                    }
                    let _ = child.kill();
                    let _ = child.wait();
                    let case = current.unwrap_or(from);
                    let detail = match cpu {
                        Some(c) => format!(
                            "no answer after {c:.1} s of CPU time ({:.1} s wall; limit {} s of CPU, {} s wall)",
                            wall.as_secs_f64(),
                            hang.as_secs(),
                            WALL_FACTOR * hang.as_secs()
                        ),
                        None => format!("no answer in {} s", hang.as_secs()),
                    };
                    self.record(seeds, case, DefectKind::Hang, detail, sum)?;
                    return Ok(case + 1);
                }
            }
        }
        let status = child.wait().map_err(|e| e.to_string())?;
        if done && status.success() {
            return Ok(to);
        }
        let case = current.unwrap_or(from);
        let mut detail = describe(status);
        // a crash may need the state earlier cases left in the worker
        if case > from {
            detail.push_str(&format!(" (worker began at case {from})"));
        }
        if let Some(last) = last_line(&stderr_path) {
            detail.push_str(&format!("; stderr: {last}"));
        }
        self.record(seeds, case, DefectKind::Crash, detail, sum)?;
        Ok(case + 1)
    }

    fn record(
        &self,
        seeds: &Seeds,
        case: u64,
        kind: DefectKind,
        detail: String,
        sum: &mut Summary,
    ) -> Result<(), String> {
        let (ext, data) = seeds.case(self.seed, case);
        let tag = match kind {
            DefectKind::Panic => "panic",
            DefectKind::Crash => "crash",
            DefectKind::Hang => "hang",
        };
        let file = self.out.join(format!(
            "{}-{tag}-{}-{case}.{ext}",
            self.target.name(),
            self.seed
        ));
        std::fs::write(&file, data).map_err(|e| format!("{}: {e}", file.display()))?;
        sum.defects.push(Defect {
            case,
            kind,
            detail,
            file,
        });
        Ok(())
    }
}

/// The last non-empty line of a worker's stderr file, at most 300 characters.
fn last_line(path: &std::path::Path) -> Option<String> {
    let text = std::fs::read(path).ok()?;
    let text = String::from_utf8_lossy(&text);
    let line = text.lines().rev().find(|l| !l.trim().is_empty())?;
    Some(line.trim().chars().take(300).collect())
}

#[cfg(unix)]
fn describe(status: std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (_, Some(sig)) => format!("killed by signal {sig}"),
        (Some(c), _) => format!("exit status {c}"),
        _ => "ended".into(),
    }
}

/// A case that waits without computing (a deadlock, a blocked read) is a
/// hang after this many times the CPU limit in wall time.
const WALL_FACTOR: u64 = 10;

/// Whether a worker silent for `wall`, having used `cpu` seconds of CPU in
/// that time (`None`: not measurable), has hung. The limit `hang` counts the
/// worker's CPU time, so a worker starved of CPU by a loaded machine (the
/// fuzzer runs at low priority beside builds) is not called hung; one that
/// does not compute at all is, after [`WALL_FACTOR`] × `hang` of wall time.
fn is_hang(hang: Duration, wall: Duration, cpu: Option<f64>) -> bool {
    match cpu {
        Some(c) => c >= hang.as_secs_f64() || wall >= hang * WALL_FACTOR as u32,
        None => wall >= hang,
    }
}

/// CPU time (user and system, every thread) process `pid` has used, from
/// `/proc/PID/stat`; `None` where that cannot be read.
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // after "pid (command) ": state is field 3; utime and stime are 14 and 15
    let fields: Vec<&str> = stat.get(stat.rfind(')')? + 2..)?.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    // SAFETY: sysconf only reads a configuration value
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    (hz > 0).then(|| ticks / hz as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_starved_worker_is_no_hang_but_a_computing_or_idle_one_is() {
        let hang = Duration::from_secs(10);
        // 30 s silent on a loaded machine with 2 s of CPU: starved, not hung
        assert!(!is_hang(hang, Duration::from_secs(30), Some(2.0)));
        // 10 s of CPU without a line: hung
        assert!(is_hang(hang, Duration::from_secs(12), Some(10.0)));
        // 100 s without computing (a deadlock): hung
        assert!(is_hang(hang, Duration::from_secs(100), Some(0.0)));
        // no /proc: wall time alone
        assert!(is_hang(hang, Duration::from_secs(10), None));
        assert!(!is_hang(hang, Duration::from_secs(9), None));
    }

    #[test]
    fn this_process_cpu_time_grows_with_work() {
        let pid = std::process::id();
        let before = cpu_seconds(pid).expect("/proc on Linux");
        // busy until the clock ticks (it counts in 1/100 s), at most 20 s
        // of wall time on a loaded machine
        let started = Instant::now();
        let mut x = 0u64;
        let mut after = before;
        while after <= before && started.elapsed() < Duration::from_secs(20) {
            for _ in 0..1_000_000 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
            after = cpu_seconds(pid).expect("/proc on Linux");
        }
        std::hint::black_box(x);
        assert!(after > before, "{before} → {after}");
    }
}
