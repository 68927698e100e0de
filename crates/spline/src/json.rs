//! The multipatch JSON format, written and read back.
//!
//! ```text
//! {
//!   "format": "quadrille-multipatch",
//!   "version": 1,
//!   "control_points": [[x, y, z], ...],          // global, shared by index
//!   "patches": [
//!     {
//!       "degree": [p, q],                          // in s and t (3, 3)
//!       "knots_s": [...], "knots_t": [...],        // clamped, full multiplicity
//!       "size": [n_s, n_t],                        // control points per direction
//!       "indices": [...]                           // n_s * n_t, row-major, s fastest:
//!     }                                            //   indices[j * n_s + i] = P_ij
//!   ]
//! }
//! ```
//! Weights are all 1 (non-rational). Numbers are written with the shortest
//! representation that reads back to the same `f64`, so a round trip is exact.

use crate::atomic::write_atomically;
use crate::error::{Result, SplineError};
use crate::knots::KnotVector;
use crate::multipatch::{Multipatch, PatchGrid};
use crate::vec3::Point3;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `format` tag of the file.
pub const FORMAT: &str = "quadrille-multipatch";

#[derive(Serialize, Deserialize)]
struct FilePatch {
    degree: [usize; 2],
    knots_s: Vec<f64>,
    knots_t: Vec<f64>,
    size: [usize; 2],
    indices: Vec<usize>,
}

#[derive(Serialize, Deserialize)]
struct File {
    format: String,
    version: u32,
    control_points: Vec<Point3>,
    patches: Vec<FilePatch>,
}

/// The multipatch as JSON text.
pub fn to_json_string(mp: &Multipatch) -> String {
    let file = File {
        format: FORMAT.into(),
        version: 1,
        control_points: mp.points().to_vec(),
        patches: mp
            .patches()
            .iter()
            .map(|g| FilePatch {
                degree: [g.knots_s.degree(), g.knots_t.degree()],
                knots_s: g.knots_s.knots().to_vec(),
                knots_t: g.knots_t.knots().to_vec(),
                size: [g.n_s(), g.n_t()],
                indices: g.indices.clone(),
            })
            .collect(),
    };
    serde_json::to_string_pretty(&file).expect("serialising plain numbers cannot fail")
}

/// Reads a multipatch from JSON text, checking the format tag, the knots,
/// the sizes and the indices.
pub fn from_json_str(text: &str) -> Result<Multipatch> {
    let file: File = serde_json::from_str(text).map_err(|e| SplineError::Json(e.to_string()))?;
    if file.format != FORMAT || file.version != 1 {
        return Err(SplineError::Json(format!(
            "format \"{}\" version {}, expected \"{FORMAT}\" version 1",
            file.format, file.version
        )));
    }
    let mut patches = Vec::with_capacity(file.patches.len());
    for (k, p) in file.patches.into_iter().enumerate() {
        let ks = KnotVector::new(p.degree[0], p.knots_s)
            .map_err(|e| SplineError::Json(format!("patch {k} knots_s: {e}")))?;
        let kt = KnotVector::new(p.degree[1], p.knots_t)
            .map_err(|e| SplineError::Json(format!("patch {k} knots_t: {e}")))?;
        if [ks.num_control_points(), kt.num_control_points()] != p.size {
            return Err(SplineError::Json(format!(
                "patch {k}: size {:?} but the knots give {} × {}",
                p.size,
                ks.num_control_points(),
                kt.num_control_points()
            )));
        }
        patches.push(PatchGrid {
            knots_s: ks,
            knots_t: kt,
            indices: p.indices,
        });
    }
    Multipatch::from_parts(file.control_points, patches)
}

/// Writes the multipatch to `path` as JSON (atomically).
pub fn write_json(path: &Path, mp: &Multipatch) -> Result<()> {
    Ok(write_atomically(path, to_json_string(mp).as_bytes())?)
}

/// Reads a multipatch JSON file.
pub fn read_json(path: &Path) -> Result<Multipatch> {
    from_json_str(&std::fs::read_to_string(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multipatch::tests::two_squares;

    #[test]
    fn round_trip_is_exact() {
        let mp = two_squares(3).refined(2).unwrap();
        let dir = std::env::temp_dir().join(format!("spline-json-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("mp.json");
        write_json(&path, &mp).unwrap();
        let back = read_json(&path).unwrap();
        assert_eq!(back, mp);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_files_are_errors() {
        let text = to_json_string(&two_squares(1));
        assert!(from_json_str("{").is_err());
        let e = from_json_str(&text.replace(FORMAT, "other"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected"), "{e}");
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["patches"][0]["size"] = serde_json::json!([5, 4]);
        let e = from_json_str(&v.to_string()).unwrap_err().to_string();
        assert!(e.contains("patch 0: size"), "{e}");
    }
}
