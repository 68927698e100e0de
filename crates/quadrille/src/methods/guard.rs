//! The size guard (ours): before any curve is sampled at the target size,
//! the quad count the method would make is estimated from its size map
//! ([`crate::field::quad_estimate`], on a background of bounded resolution)
//! and the run is refused when it is above [`MeshOptions::max_quads`]
//! ([`MeshError::TooManyQuads`]: the estimate, the memory it would take,
//! a size that would fit). Without it a size far too small ran until the
//! machine ran out of memory (`--size 1e-5` on i01o_m1 held 18.7 GB before
//! it was stopped).
//!
//! The estimate is `K · ∫ dA / s²`: the field-guided methods' size map `s`
//! (bounds, curvature, small features) or the uniform target size for the
//! baseline and regular methods, times a per-method constant `K` (quads per
//! `s²` of area) calibrated on the bundled models (`data/cad`) at the
//! default size; see the constants.

use geometry::Model;

use crate::core::error::{MeshError, TooManyQuads};
use crate::core::options::default_size;
use crate::field::quad_estimate::size_integral;
use crate::field::size_map::SizeMapOptions;
use crate::methods::options::MeshOptions;
use crate::methods::quasi_structured::size_map_options;
use crate::methods::MeshMethod;

/// Default of [`MeshOptions::max_quads`]: 50 million quads, about
/// 50e6 × [`BYTES_PER_QUAD`] of memory.
pub const DEFAULT_MAX_QUADS: u64 = 50_000_000;

/// Peak memory of a run per quad of its mesh, in bytes (peak resident set
/// size over the quad count of `quadrille mesh` with the default method).
pub const BYTES_PER_QUAD: f64 = 2000.0;

/// Quads per `s²` of area of the quasi-structured method (the default).
const K_QUASI_STRUCTURED: f64 = 1.0;
/// Quads per `s²` of area of the plain unstructured method.
const K_UNSTRUCTURED: f64 = 1.0;
/// Quads per `h²` of area of the baseline: triangles of side `2h` (area
/// `√3 h²`), three quads each, `√3` in theory.
const K_BASELINE: f64 = 1.732;
/// Quads per `h²` of area of the regular method (the baseline, then
/// collapses and splits).
const K_REGULAR: f64 = 1.732;

/// Rounds of the search for a size that fits under the limit.
const FIT_ROUNDS: usize = 6;

/// The size map `method` meshes `model` against at target size `h`, and
/// its constant `K`.
fn sizing(model: &Model, h: f64, opts: &MeshOptions, method: &MeshMethod) -> (SizeMapOptions, f64) {
    let uniform = SizeMapOptions {
        min_size: Some(h),
        max_size: Some(h),
        small_features: false,
        ..Default::default()
    };
    match method {
        MeshMethod::QuasiStructured(s) if *s == crate::methods::options::Stages::NONE => {
            (size_map_options(model, h, opts), K_UNSTRUCTURED)
        }
        MeshMethod::QuasiStructured(_) => (size_map_options(model, h, opts), K_QUASI_STRUCTURED),
        MeshMethod::Unstructured => (size_map_options(model, h, opts), K_UNSTRUCTURED),
        MeshMethod::Baseline => (uniform, K_BASELINE),
        MeshMethod::Regular(_) => (uniform, K_REGULAR),
    }
}

/// The estimated quad count of `method` on `model` at target size `h`
/// (model units), on the current rayon pool.
pub(crate) fn estimate_at(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    method: &MeshMethod,
) -> Result<f64, MeshError> {
    let (map, k) = sizing(model, h, opts, method);
    Ok(k * size_integral(model, h, &map)?.total())
}

/// The estimate at `h`, and the refusal when it is above `opts.max_quads`
/// (0: no limit): the size guard of [`crate::mesh_model_with`].
pub(crate) fn check(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    method: &MeshMethod,
) -> Result<u64, MeshError> {
    let n = estimate_at(model, h, opts, method)?;
    let limit = opts.max_quads;
    if limit == 0 || n <= limit as f64 {
        return Ok(n.round() as u64);
    }
    // the area term goes as 1 / h²; the bounds and features make coarser
    // sizes cost relatively more, so the first guess is checked and grown
    let mut size = h * (n / limit as f64).sqrt();
    let mut fit = None;
    for _ in 0..FIT_ROUNDS {
        let m = estimate_at(model, size, opts, method)?;
        if m <= limit as f64 {
            fit = Some((size, size / default_size(model)));
            break;
        }
        size *= (m / limit as f64).sqrt() * 1.02;
    }
    Err(MeshError::TooManyQuads(TooManyQuads {
        estimate: n.round() as u64,
        limit,
        size: h,
        memory: n * BYTES_PER_QUAD,
        fit,
    }))
}
