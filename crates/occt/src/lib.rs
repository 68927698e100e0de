//! CAD import for Quadrille through the system OpenCASCADE 7.6 (OCCT).
//!
//! [`load`] reads a STEP, IGES or BREP file and returns a [`geometry::Model`]
//! whose corners, curves and faces are exactly OCCT's vertices, edges and
//! faces of the loaded shape (`TopExp::MapShapes` order, so entity id `i` is
//! OCCT index `i + 1`, and an MSH tag `id + 1` names the same entity as Gmsh
//! would). The shape is not healed or modified.
//!
//! Geometry stays in OCCT: [`OcctSurface`], [`OcctCurve`] and [`OcctCurve2d`]
//! call into a small C++ shim (`src/shim.cpp`); they are `Send + Sync` and safe
//! to evaluate from several threads at once. OCCT exceptions are caught in the
//! shim and never unwind into Rust; bad input gives an [`ImportError`] that
//! names the file and the problem.
//!
//! Orientation: loops are built from the face taken FORWARD, so that whatever
//! the face's orientation in its shell, the material lies to the left of each
//! loop in (u, v) (outer loop counter-clockwise); the face orientation is
//! carried by [`geometry::Face::reversed`] instead.

#![warn(missing_docs)]

mod bspline_step;
mod ffi;
mod geom;
mod import;
mod wires;
mod step_references;

use std::ffi::CString;
use std::io::Read;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};

pub use bspline_step::{
    write_bspline_step, BSplineSurfaceData, StepWriteError, WriteReport, MAX_DEGREE, SEW_TOLERANCE,
};
pub use geom::{OcctCurve, OcctCurve2d, OcctSurface, PcurveOnSurface};
pub use import::Import;
pub use wires::{load_wires, ClosedWire, WireUse, Wires};

use geometry::Model;

/// Why a CAD file could not be imported. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The path does not exist.
    #[error("{}: file not found", .path.display())]
    NotFound {
        /// The file asked for.
        path: PathBuf,
    },
    /// The file exists but could not be read (permissions, a directory, …).
    #[error("{}: cannot read the file: {detail}", .path.display())]
    Io {
        /// The file asked for.
        path: PathBuf,
        /// What the operating system said.
        detail: String,
    },
    /// The file is empty (or holds only white space).
    #[error("{}: the file is empty", .path.display())]
    Empty {
        /// The file asked for.
        path: PathBuf,
    },
    /// The extension names no format this importer reads.
    #[error("{}: unknown CAD file extension {ext:?} (expected .step, .stp, .iges, .igs, .brep or .brp)", .path.display())]
    UnknownExtension {
        /// The file asked for.
        path: PathBuf,
        /// The extension found (empty when there is none).
        ext: String,
    },
    /// The reader rejected the file: garbage, binary data, a truncated file, …
    #[error("{}: cannot be read as {format}: {detail}", .path.display())]
    Unreadable {
        /// The file asked for.
        path: PathBuf,
        /// The format the extension announced ("STEP", "IGES", "BREP").
        format: &'static str,
        /// What was wrong.
        detail: String,
    },
    /// The file was read but holds no face to mesh.
    #[error("{}: no face in the file ({detail})", .path.display())]
    NoFace {
        /// The file asked for.
        path: PathBuf,
        /// What the file held instead.
        detail: String,
    },
    /// The shape was read but its topology or geometry is unusable
    /// (an edge without vertices, a face edge without a pcurve, …).
    #[error("{}: invalid shape: {detail}", .path.display())]
    Invalid {
        /// The file asked for.
        path: PathBuf,
        /// What was wrong.
        detail: String,
    },
}

/// The CAD formats the importer reads, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// ISO 10303-21 (`.step`, `.stp`).
    Step,
    /// IGES 5.x (`.iges`, `.igs`).
    Iges,
    /// OCCT's native text BREP (`.brep`, `.brp`).
    Brep,
}

impl Format {
    /// The format for a path's extension (case-insensitive), if known.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "step" | "stp" => Some(Format::Step),
            "iges" | "igs" => Some(Format::Iges),
            "brep" | "brp" => Some(Format::Brep),
            _ => None,
        }
    }

    /// Short name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Format::Step => "STEP",
            Format::Iges => "IGES",
            Format::Brep => "BREP",
        }
    }

    fn code(self) -> i32 {
        match self {
            Format::Step => 0,
            Format::Iges => 1,
            Format::Brep => 2,
        }
    }
}

/// Reads a CAD file (STEP, IGES or BREP, by extension, case-insensitive)
/// into a [`Model`]: corners, curves and faces in OCCT `MapShapes` order.
pub fn load(path: &Path) -> Result<Model, ImportError> {
    import(path).map(|i| i.model)
}

/// Like [`load`], and also returns OCCT's tolerances of every corner and
/// curve (useful for merging nodes and for checking pcurves).
pub fn import(path: &Path) -> Result<Import, ImportError> {
    let owned = path.to_path_buf();
    open_with(path, move |shape| import::build(&shape, &owned))
}

/// Numbers of faces, edges and vertices of the file's shape, as counted by
/// OCCT itself (`TopExp::MapShapes`): the reference [`load`] must match.
pub fn topology_counts(path: &Path) -> Result<(usize, usize, usize), ImportError> {
    open_with(path, |shape| Ok(import::counts(&shape)))
}

/// Why [`convert`] could not write its output.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// The input could not be imported.
    #[error(transparent)]
    Import(#[from] ImportError),
    /// The output could not be written.
    #[error("{}: cannot write {format}: {detail}", .path.display())]
    Write {
        /// The output file.
        path: PathBuf,
        /// The format its extension asked for.
        format: &'static str,
        /// What went wrong.
        detail: String,
    },
}

/// Reads a CAD file and writes its shape, unchanged, to `output` in the
/// format of `output`'s extension (STEP, IGES in B-rep mode, or BREP): a
/// format converter, and a way to test every reader on the same shape.
pub fn convert(input: &Path, output: &Path) -> Result<(), ConvertError> {
    let write_err = |format: &'static str, detail: String| ConvertError::Write {
        path: output.to_path_buf(),
        format,
        detail,
    };
    let format =
        Format::from_path(output).ok_or_else(|| write_err("CAD", "unknown extension".into()))?;
    let shape = open_with(input, Ok)?;
    let cpath = CString::new(output.as_os_str().as_bytes())
        .map_err(|_| write_err(format.name(), "the path holds a NUL byte".into()))?;
    let mut err = vec![0u8; 1024];
    ffi::hand_over_iges();
    // SAFETY: live model, NUL-terminated path, err valid for its length.
    let rc = unsafe {
        ffi::occt_write(
            shape.ptr(),
            cpath.as_ptr(),
            format.code(),
            err.as_mut_ptr().cast(),
            err.len(),
        )
    };
    if rc == ffi::OK {
        Ok(())
    } else {
        Err(write_err(format.name(), c_message(&err)))
    }
}

/// The NUL-terminated message in an error buffer.
fn c_message(err: &[u8]) -> String {
    let n = err.iter().position(|&b| b == 0).unwrap_or(err.len());
    String::from_utf8_lossy(&err[..n]).into_owned()
}

/// How many bytes of the head and tail of a file are checked before OCCT sees it.
const PEEK: u64 = 4096;

/// Checks the file (exists, not empty, known extension, plausibly of its
/// format) and reads it with OCCT.
fn open_with<T: Send + 'static>(
    path: &Path,
    after: impl FnOnce(ffi::ModelPtr) -> Result<T, ImportError> + Send + 'static,
) -> Result<T, ImportError> {
    let owned = || path.to_path_buf();
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(ImportError::NotFound { path: owned() })
        }
        Err(e) => {
            return Err(ImportError::Io {
                path: owned(),
                detail: e.to_string(),
            })
        }
    };
    if meta.is_dir() {
        return Err(ImportError::Io {
            path: owned(),
            detail: "it is a directory".into(),
        });
    }
    let format = Format::from_path(path).ok_or_else(|| ImportError::UnknownExtension {
        path: owned(),
        ext: path
            .extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default(),
    })?;
    let (head, tail) = peek(path, meta.len()).map_err(|e| ImportError::Io {
        path: owned(),
        detail: e.to_string(),
    })?;
    if head.iter().all(|b| b.is_ascii_whitespace()) && meta.len() <= PEEK {
        return Err(ImportError::Empty { path: owned() });
    }
    let unreadable = |detail: String| ImportError::Unreadable {
        path: owned(),
        format: format.name(),
        detail,
    };
    if head.contains(&0) || tail.contains(&0) {
        return Err(unreadable("it holds binary data, not text".into()));
    }
    if format == Format::Step {
        let start = String::from_utf8_lossy(&head);
        if !start
            .trim_start_matches('\u{feff}')
            .trim_start()
            .starts_with("ISO-10303-21")
        {
            return Err(unreadable(
                "it does not start with the ISO-10303-21 header".into(),
            ));
        }
        if !String::from_utf8_lossy(&tail).contains("END-ISO-10303-21") {
            return Err(unreadable(
                "it is truncated: no END-ISO-10303-21 terminator".into(),
            ));
        }
        let text = std::fs::read(path).map_err(|e| ImportError::Io {
            path: owned(),
            detail: e.to_string(),
        })?;
        if let Some(why) = step_references::reference_error(&text) {
            return Err(unreadable(why));
        }
    }
    let cpath = CString::new(path.as_os_str().as_bytes())
        .map_err(|_| unreadable("the path holds a NUL byte".into()))?;
    if let Some(why) = cad_reads_refused() {
        return Err(unreadable(why));
    }
    let limit = read_time_limit(meta.len());
    let timed_out = unreadable(format!(
        "OpenCASCADE did not finish reading it in {} s, so it is most likely damaged \
         (QUADRILLE_CAD_READ_SECONDS sets the limit)",
        limit.as_secs()
    ));
    let owned_path = owned();
    let read = move || {
        let unreadable = |detail: String| ImportError::Unreadable {
            path: owned_path.clone(),
            format: format.name(),
            detail,
        };
        let mut err = vec![0u8; 1024];
        let mut out: *mut ffi::OcctModel = std::ptr::null_mut();
        ffi::hand_over_iges();
        // SAFETY: cpath is NUL-terminated, out and err are valid for the call.
        let rc = unsafe {
            ffi::occt_load(
                cpath.as_ptr(),
                format.code(),
                &mut out,
                err.as_mut_ptr().cast(),
                err.len(),
            )
        };
        let msg = c_message(&err);
        match (rc, ffi::ModelPtr::new(out)) {
            (ffi::OK, Some(m)) => after(m),
            (ffi::ERR_TRANSFER, _) => Err(ImportError::NoFace {
                path: owned_path.clone(),
                detail: msg,
            }),
            (ffi::ERR_OPEN, _) | (ffi::ERR_EXCEPTION, _) => Err(unreadable(msg)),
            (rc, _) => Err(unreadable(format!(
                "the OCCT shim failed with code {rc} {msg}"
            ))),
        }
    };
    let faults_before = faults_caught();
    let answer = match read_with_deadline(read, limit) {
        Ok(answer) => answer,
        Err(NoAnswer::TimedOut) => {
            if let Ok(mut g) = STUCK_READ.lock() {
                *g = Some(path.to_path_buf());
            }
            return Err(timed_out);
        }
        Err(NoAnswer::Lost(why)) => Err(ImportError::Unreadable {
            path: owned(),
            format: format.name(),
            detail: why.into(),
        }),
    };
    if faults_caught() == faults_before {
        return answer;
    }
    // OCCT faulted on this file (perhaps recovering by itself): the jump out
    // of the fault skipped OCCT's destructors and unlocks, so neither the
    // shape nor OCCT's state after it can be trusted
    if let Ok(mut g) = FAULTED_READ.lock() {
        g.get_or_insert_with(|| path.to_path_buf());
    }
    const NOTE: &str = "a memory fault inside OpenCASCADE was caught while reading it, \
                        so this process reads no more CAD files (restart it to read more)";
    Err(match answer {
        Ok(_) => unreadable(format!("OpenCASCADE recovered from a fault on it; {NOTE}")),
        Err(e) => e.with_note(NOTE),
    })
}

impl ImportError {
    /// The same error with `note` appended to its detail.
    fn with_note(self, note: &str) -> ImportError {
        let add = |detail: String| format!("{detail}; {note}");
        match self {
            ImportError::Io { path, detail } => ImportError::Io {
                path,
                detail: add(detail),
            },
            ImportError::Unreadable {
                path,
                format,
                detail,
            } => ImportError::Unreadable {
                path,
                format,
                detail: add(detail),
            },
            ImportError::NoFace { path, detail } => ImportError::NoFace {
                path,
                detail: add(detail),
            },
            ImportError::Invalid { path, detail } => ImportError::Invalid {
                path,
                detail: add(detail),
            },
            other => other,
        }
    }
}

/// Faults inside OCCT caught in this process so far.
fn faults_caught() -> u64 {
    // SAFETY: reads an atomic counter.
    unsafe { ffi::occt_faults_caught() as u64 }
}

/// Why this process reads and writes no more CAD files, or `None` when it
/// still does. Two things end OCCT's use in a process: a read that timed out
/// (its thread still runs inside OCCT and holds its lock), and a fault inside
/// OCCT caught during a read or write (the jump out of the fault skips OCCT's
/// destructors and unlocks: later reads in the same process crashed at
/// random, in `free` or on a null pointer, so the fuzzer found). A program
/// that reads many untrusted files should start a new process when this
/// answers `Some`.
pub fn cad_reads_refused() -> Option<String> {
    if let Some(earlier) = STUCK_READ.lock().ok().and_then(|g| g.clone()) {
        return Some(format!(
            "OpenCASCADE is still busy with {}, whose reading did not finish: \
             restart the program to read more CAD files",
            earlier.display()
        ));
    }
    let faulted = FAULTED_READ.lock().ok().and_then(|g| g.clone());
    if faulted.is_some() || faults_caught() > 0 {
        let which = faulted.map_or_else(
            || "an earlier CAD file".to_string(),
            |p| p.display().to_string(),
        );
        return Some(format!(
            "OpenCASCADE faulted while reading {which}, which may have damaged its state: \
             restart the program to read more CAD files"
        ));
    }
    None
}

/// Why the reader thread gave no answer.
enum NoAnswer {
    /// It ran past the time limit (and still runs).
    TimedOut,
    /// It could not start, or ended without answering.
    Lost(&'static str),
}

/// The file whose reading timed out: its thread still runs and holds OCCT's
/// reader lock, so later reads are refused at once rather than waiting.
static STUCK_READ: std::sync::Mutex<Option<std::path::PathBuf>> = std::sync::Mutex::new(None);

/// The first file whose reading caught a fault inside OCCT: later reads are
/// refused ([`cad_reads_refused`]).
static FAULTED_READ: std::sync::Mutex<Option<std::path::PathBuf>> = std::sync::Mutex::new(None);

/// Seconds OCCT may take to read a file of `len` bytes before the file counts
/// as damaged: 5 s plus 20 s per MB (a damaged IGES or BREP file can send
/// OCCT's reader into an endless loop; sound files read at well over 1 MB/s),
/// or `QUADRILLE_CAD_READ_SECONDS`.
fn read_time_limit(len: u64) -> std::time::Duration {
    let from_env = std::env::var("QUADRILLE_CAD_READ_SECONDS")
        .ok()
        .and_then(|s| s.parse::<f64>().ok());
    let secs = match from_env {
        Some(s) if s > 0.0 => s,
        _ => 5.0 + 20.0 * len as f64 / 1e6,
    };
    std::time::Duration::from_secs_f64(secs)
}

/// Runs `read` (OCCT's reader, then what is built from its shape) on a
/// reader thread, with faults inside OCCT turned into errors throughout
/// (`occt_signals_begin`), and waits at most `limit`. When it did not
/// finish, that thread is left to itself (OCCT's loops cannot be
/// interrupted) and the caller refuses later reads ([`STUCK_READ`]).
fn read_with_deadline<T: Send + 'static>(
    read: impl FnOnce() -> T + Send + 'static,
    limit: std::time::Duration,
) -> Result<T, NoAnswer> {
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = move || {
        // SAFETY: begin and end pair up on this thread.
        let scope = unsafe { ffi::occt_signals_begin() };
        let answer = read();
        unsafe { ffi::occt_signals_end(scope) };
        // nobody waits any more when this fails: the answer is dropped
        let _ = tx.send(answer);
    };
    // OCCT recurses deeply on big assemblies: a large stack (reserved, not
    // committed)
    let spawned = std::thread::Builder::new()
        .name("occt-read".into())
        .stack_size(256 << 20)
        .spawn(reader);
    if spawned.is_err() {
        return Err(NoAnswer::Lost("could not start the reader thread"));
    }
    rx.recv_timeout(limit).map_err(|e| match e {
        std::sync::mpsc::RecvTimeoutError::Timeout => NoAnswer::TimedOut,
        std::sync::mpsc::RecvTimeoutError::Disconnected => {
            NoAnswer::Lost("the reader thread ended without an answer (a bug)")
        }
    })
}

/// The first and last `PEEK` bytes of a file of `len` bytes.
fn peek(path: &Path, len: u64) -> std::io::Result<(Vec<u8>, Vec<u8>)> {
    use std::io::{Seek, SeekFrom};
    let mut f = std::fs::File::open(path)?;
    let mut head = Vec::new();
    (&mut f).take(PEEK).read_to_end(&mut head)?;
    if len <= PEEK {
        return Ok((head.clone(), head));
    }
    f.seek(SeekFrom::Start(len - PEEK))?;
    let mut tail = Vec::new();
    f.take(PEEK).read_to_end(&mut tail)?;
    Ok((head, tail))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_from_extension_is_case_insensitive() {
        assert_eq!(Format::from_path(Path::new("a/b.STEP")), Some(Format::Step));
        assert_eq!(Format::from_path(Path::new("b.stp")), Some(Format::Step));
        assert_eq!(Format::from_path(Path::new("b.IgS")), Some(Format::Iges));
        assert_eq!(Format::from_path(Path::new("b.iges")), Some(Format::Iges));
        assert_eq!(Format::from_path(Path::new("b.Brp")), Some(Format::Brep));
        assert_eq!(Format::from_path(Path::new("b.brep")), Some(Format::Brep));
        assert_eq!(Format::from_path(Path::new("b.stl")), None);
        assert_eq!(Format::from_path(Path::new("step")), None);
    }

    #[test]
    fn a_directory_is_an_io_error_naming_it() {
        let dir = std::env::temp_dir().join("occt_test_dir.step");
        std::fs::create_dir_all(&dir).unwrap();
        let e = load(&dir).unwrap_err();
        assert!(matches!(e, ImportError::Io { .. }), "{e:?}");
        assert!(e.to_string().contains("occt_test_dir.step"));
    }
}
