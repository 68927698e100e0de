//! STEP output of untrimmed B-spline patches (issue 31, `quadrille spline`):
//! each patch becomes a `Geom_BSplineSurface` and a face on its natural
//! bounds (four edges on the parameter bounds), the faces are sewn into one
//! shell (kept open when sewing leaves free edges), and the shell is written
//! as AP214 STEP. The input is checked here, before OCCT sees it, and the
//! file is written through a temporary file renamed at the end, so an error
//! never leaves a partial file behind.
//!
//! The patch data is a plain struct of this crate ([`BSplineSurfaceData`]):
//! `occt` does not depend on `spline`; the caller converts.

use std::ffi::CString;
use std::os::raw::c_int;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::ffi;

/// Highest degree OCCT's B-splines accept (`Geom_BSplineSurface::MaxDegree`).
pub const MAX_DEGREE: usize = 25;

/// Sewing tolerance relative to the diagonal of the control points' box.
pub const SEW_TOLERANCE: f64 = 1e-7;

/// One non-rational tensor-product B-spline patch: degrees, full clamped
/// knot vectors (first and last knot repeated degree + 1 times), and the
/// control net row-major with s fastest (`control[j * n_s + i]` is P_ij,
/// `n_s = knots_s.len() − degree_s − 1`). s becomes OCCT's u, t its v.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurfaceData {
    /// Degree in s (≥ 1).
    pub degree_s: usize,
    /// Degree in t (≥ 1).
    pub degree_t: usize,
    /// Full knot vector in s, non-decreasing and clamped.
    pub knots_s: Vec<f64>,
    /// Full knot vector in t, non-decreasing and clamped.
    pub knots_t: Vec<f64>,
    /// The n_s × n_t control points, s fastest.
    pub control: Vec<[f64; 3]>,
}

impl BSplineSurfaceData {
    /// Control points along s, as the knots ask (0 when they are too few).
    pub fn n_s(&self) -> usize {
        self.knots_s.len().saturating_sub(self.degree_s + 1)
    }

    /// Control points along t, as the knots ask (0 when they are too few).
    pub fn n_t(&self) -> usize {
        self.knots_t.len().saturating_sub(self.degree_t + 1)
    }
}

/// What [`write_bspline_step`] wrote, counted on the sewn shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WriteReport {
    /// Faces written (one per patch).
    pub faces: usize,
    /// Shells written: 1 when every patch joined one connected shell.
    pub shells: usize,
    /// Non-degenerate edges that bound a single face after sewing.
    pub free_edges: usize,
    /// Edges shared by two faces after sewing.
    pub shared_edges: usize,
    /// Edges shared by three faces or more (non-manifold), normally 0.
    pub multiple_edges: usize,
    /// The sewing tolerance used ([`SEW_TOLERANCE`] × the control box diagonal).
    pub sew_tolerance: f64,
}

/// Why the B-spline patches could not be written as STEP. Every message is
/// one line naming the patch or file and the numbers.
#[derive(Debug, thiserror::Error)]
pub enum StepWriteError {
    /// No patch was given.
    #[error("{}: no B-spline patch to write", .path.display())]
    NoPatch {
        /// The output file.
        path: PathBuf,
    },
    /// A patch is malformed (degree, knots, control-point count, NaN, …).
    #[error("{}: patch {patch}: {detail}", .path.display())]
    BadPatch {
        /// The output file.
        path: PathBuf,
        /// The patch's index in the input.
        patch: usize,
        /// What is wrong, with the numbers.
        detail: String,
    },
    /// The file could not be created, written or renamed into place.
    #[error("{}: cannot write the file: {detail}", .path.display())]
    Io {
        /// The output file.
        path: PathBuf,
        /// What the operating system said.
        detail: String,
    },
    /// OpenCASCADE failed to build, sew or write the shape.
    #[error("{}: OpenCASCADE could not write the patches as STEP: {detail}", .path.display())]
    Occt {
        /// The output file.
        path: PathBuf,
        /// What OCCT said.
        detail: String,
    },
}

/// A knot vector as OCCT wants it: distinct knots and their multiplicities.
#[derive(Debug)]
struct DistinctKnots {
    knots: Vec<f64>,
    mults: Vec<c_int>,
}

/// Checks a full knot vector of `degree` for `n` control points: finite,
/// non-decreasing, clamped at both ends (degree + 1 equal knots), interior
/// multiplicities ≤ degree, distinct knots well apart; returns them distinct.
fn distinct_knots(knots: &[f64], degree: usize, dir: &str) -> Result<DistinctKnots, String> {
    if !(1..=MAX_DEGREE).contains(&degree) {
        return Err(format!(
            "degree in {dir} is {degree}, expected 1 to {MAX_DEGREE}"
        ));
    }
    if knots.len() < 2 * (degree + 1) {
        return Err(format!(
            "{} knots in {dir} for degree {degree}, at least {} needed",
            knots.len(),
            2 * (degree + 1)
        ));
    }
    if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
        return Err(format!("knot {i} in {dir} is {}", knots[i]));
    }
    if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
        return Err(format!(
            "knots in {dir} decrease at {}: {} then {}",
            i + 1,
            knots[i],
            knots[i + 1]
        ));
    }
    let (lo, hi) = (knots[0], knots[knots.len() - 1]);
    let range = hi - lo;
    if range <= 0.0 {
        return Err(format!("knots in {dir} span an empty range [{lo}, {hi}]"));
    }
    let mut out = DistinctKnots {
        knots: Vec::new(),
        mults: Vec::new(),
    };
    for &k in knots {
        match out.knots.last() {
            Some(&last) if k == last => {
                if let Some(m) = out.mults.last_mut() {
                    *m += 1;
                }
            }
            Some(&last) if k - last <= 1e-12 * range => {
                return Err(format!(
                    "knots {last} and {k} in {dir} are distinct but closer than 1e-12 of the range"
                ))
            }
            _ => {
                out.knots.push(k);
                out.mults.push(1);
            }
        }
    }
    let (first, last) = (
        out.mults[0] as usize,
        out.mults[out.mults.len() - 1] as usize,
    );
    if first != degree + 1 || last != degree + 1 {
        return Err(format!(
            "knots in {dir} are not clamped: end multiplicities {first} and {last}, expected {} (degree {degree} + 1)",
            degree + 1
        ));
    }
    let n = out.mults.len();
    if let Some(i) = out.mults[1..n - 1]
        .iter()
        .position(|&m| m as usize > degree)
    {
        return Err(format!(
            "interior knot {} in {dir} has multiplicity {}, more than the degree {degree}",
            out.knots[i + 1],
            out.mults[i + 1]
        ));
    }
    Ok(out)
}

/// A patch checked and in OCCT's layout.
struct CheckedPatch {
    s: DistinctKnots,
    t: DistinctKnots,
    poles: Vec<f64>,
}

/// Checks one patch (see [`BSplineSurfaceData`]).
fn check_patch(p: &BSplineSurfaceData) -> Result<CheckedPatch, String> {
    let s = distinct_knots(&p.knots_s, p.degree_s, "s")?;
    let t = distinct_knots(&p.knots_t, p.degree_t, "t")?;
    let (ns, nt) = (p.n_s(), p.n_t());
    if p.control.len() != ns * nt {
        return Err(format!(
            "the knots need {ns} × {nt} = {} control points, got {}",
            ns * nt,
            p.control.len()
        ));
    }
    if let Some(i) = p
        .control
        .iter()
        .position(|c| c.iter().any(|x| !x.is_finite()))
    {
        return Err(format!(
            "control point {i} is not finite: {:?}",
            p.control[i]
        ));
    }
    Ok(CheckedPatch {
        s,
        t,
        poles: p.control.iter().flatten().copied().collect(),
    })
}

/// The diagonal of the box around every control point (0 for none).
fn control_diagonal(patches: &[BSplineSurfaceData]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for c in patches.iter().flat_map(|p| &p.control) {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let d2: f64 = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum();
    if d2.is_finite() {
        d2.sqrt()
    } else {
        0.0
    }
}

/// Writes the patches as one sewn shell of untrimmed B-spline faces to a
/// STEP file (AP214, `STEPControl_AsIs`), through a temporary file beside
/// `path` renamed onto it at the end. Faces are sewn with a tolerance of
/// [`SEW_TOLERANCE`] × the control-point box diagonal; a free edge is not an
/// error (an open shell is written), and the report counts them.
pub fn write_bspline_step(
    patches: &[BSplineSurfaceData],
    path: &Path,
) -> Result<WriteReport, StepWriteError> {
    let owned = || path.to_path_buf();
    if patches.is_empty() {
        return Err(StepWriteError::NoPatch { path: owned() });
    }
    let checked = patches
        .iter()
        .enumerate()
        .map(|(k, p)| {
            check_patch(p).map_err(|detail| StepWriteError::BadPatch {
                path: owned(),
                patch: k,
                detail,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let diagonal = control_diagonal(patches);
    if diagonal <= 0.0 {
        return Err(StepWriteError::BadPatch {
            path: owned(),
            patch: 0,
            detail: "every control point is the same point: the patches have no extent".into(),
        });
    }
    let sew_tolerance = SEW_TOLERANCE * diagonal;
    let raw: Vec<ffi::BSplinePatchRaw> = checked
        .iter()
        .zip(patches)
        .map(|(c, p)| ffi::BSplinePatchRaw {
            degree_u: p.degree_s as c_int,
            degree_v: p.degree_t as c_int,
            n_u: p.n_s(),
            n_v: p.n_t(),
            knots_u: c.s.knots.as_ptr(),
            mults_u: c.s.mults.as_ptr(),
            nk_u: c.s.knots.len(),
            knots_v: c.t.knots.as_ptr(),
            mults_v: c.t.mults.as_ptr(),
            nk_v: c.t.knots.len(),
            poles: c.poles.as_ptr(),
        })
        .collect();

    if let Some(why) = crate::cad_reads_refused() {
        return Err(StepWriteError::Occt {
            path: owned(),
            detail: why,
        });
    }
    let tmp = temporary_beside(path);
    let ctmp = CString::new(tmp.as_os_str().as_bytes()).map_err(|_| StepWriteError::Io {
        path: owned(),
        detail: "the path holds a NUL byte".into(),
    })?;
    let mut err = vec![0u8; 1024];
    let mut sew = ffi::SewReport::default();
    // SAFETY: `raw` points into `checked`, alive for the call; the counts
    // match the buffers (checked above); path NUL-terminated; err valid.
    let rc = unsafe {
        ffi::occt_write_bspline_step(
            raw.as_ptr(),
            raw.len(),
            sew_tolerance,
            ctmp.as_ptr(),
            &mut sew,
            err.as_mut_ptr().cast(),
            err.len(),
        )
    };
    let finished = if rc != ffi::OK {
        Err(StepWriteError::Occt {
            path: owned(),
            detail: format!("{} (code {rc})", crate::c_message(&err)),
        })
    } else if !tmp.is_file() {
        Err(StepWriteError::Io {
            path: owned(),
            detail: "the STEP writer reported success but wrote no file".into(),
        })
    } else {
        std::fs::rename(&tmp, path).map_err(|e| StepWriteError::Io {
            path: owned(),
            detail: e.to_string(),
        })
    };
    if let Err(e) = finished {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    Ok(WriteReport {
        faces: sew.faces,
        shells: sew.shells,
        free_edges: sew.free_edges,
        shared_edges: sew.shared_edges,
        multiple_edges: sew.multiple_edges,
        sew_tolerance,
    })
}

/// A fresh temporary name in `path`'s directory (same file system, so the
/// final rename is atomic), unique per process and call.
fn temporary_beside(path: &Path) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{name}.{}.{k}.partial", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knots_become_distinct_with_multiplicities() {
        let d =
            distinct_knots(&[0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0], 3, "s").unwrap();
        assert_eq!(d.knots, vec![0.0, 0.5, 1.0]);
        assert_eq!(d.mults, vec![4, 2, 4]);
    }

    #[test]
    fn bad_knots_are_named() {
        let e = distinct_knots(&[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], 3, "t").unwrap_err();
        assert!(e.contains("at least 8"), "{e}");
        let e = distinct_knots(&[0.0, 0.0, 0.0, 0.2, 1.0, 1.0, 1.0, 1.0], 3, "t").unwrap_err();
        assert!(e.contains("not clamped") && e.contains("3 and 4"), "{e}");
        let e = distinct_knots(&[0.0, 0.0, 1.0, 0.5, 1.0, 1.0], 1, "s").unwrap_err();
        assert!(e.contains("decrease at 3"), "{e}");
        let e = distinct_knots(&[0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0], 2, "s").unwrap_err();
        assert!(e.contains("multiplicity 3"), "{e}");
        let e = distinct_knots(&[0.0, 0.0, 1.0, 1.0], 0, "s").unwrap_err();
        assert!(e.contains("degree in s is 0"), "{e}");
        let e = distinct_knots(&[0.0, 0.0, f64::NAN, 1.0], 1, "s").unwrap_err();
        assert!(e.contains("knot 2 in s is NaN"), "{e}");
    }
}
