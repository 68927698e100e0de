//! The size guard (ours): before any curve is sampled at the target size,
//! the quad count the method would make is estimated from its size map
//! ([`crate::field::quad_estimate`], on a background of bounded resolution)
//! and the run is refused when it is above [`MeshOptions::max_quads`]
//! ([`MeshError::TooManyQuads`]: the estimate, the memory it would take,
//! a size that would fit). Without it a size far too small ran until the
//! machine ran out of memory (`--size 1e-5` on i01o_m1 held 18.7 GB before
//! it was stopped).
//!
//! The estimate is `K · Σ_faces max(∫ dA / s², grid)`: the field-guided
//! methods' size map `s` (bounds, curvature, small features) or the uniform
//! target size for the baseline and regular methods, or, where the curve
//! plan is finer than the map, the face as a grid of its curves' mean
//! planned spacing ([`crate::field::SizeIntegral::grid_quads`]: pattern
//! faces follow their curves' counts, and every method refines around a
//! curve refined at tight bends; without it wing_surface, an airfoil loft,
//! was estimated at 0.02–0.04 of its count), times a per-method constant
//! `K` (quads per `s²` of area) calibrated on the bundled models
//! (`data/cad`) at the default size; see the constants.

use geometry::Model;

use crate::core::error::{MeshError, TooManyQuads};
use crate::core::options::default_size;
use crate::field::quad_estimate::size_integral;
use crate::field::size_map::SizeMapOptions;
use crate::methods::options::{MeshOptions, Stages};
use crate::methods::quasi_structured::size_map_options;
use crate::methods::MeshMethod;

/// Default of [`MeshOptions::max_quads`]: 50 million quads, about
/// 50e6 × [`BYTES_PER_QUAD`] of memory.
pub const DEFAULT_MAX_QUADS: u64 = 50_000_000;

/// Peak memory of a run per quad of its mesh, in bytes: the peak resident
/// set size of `quadrille mesh` with the default method over its quad count,
/// rounded up. Measured on i01o_m1, two threads (2026-12-06): 953 k quads
/// (`--size-factor 0.03125`) in 546 MB, 587 B a quad (472 B a quad more
/// than at 238 k quads in 216 MB, the fixed part being about 50 MB).
pub const BYTES_PER_QUAD: f64 = 600.0;

// The constants: the geometric mean of estimate / made over the 26
// bundled models at the default size set to about 1 (`examples/
// estimate_calibration.rs`, 2026-12-06; ratios with K = 1 in brackets).

/// Quads per `s²` of area of the quasi-structured method (the default):
/// 1.13 (with K = 1: geometric mean 0.887, from 0.64 on twisted_body, whose
/// twisted grids are finer than their size map, to 1.09 on i04o_m4), so
/// every model is within 0.72–1.23 of its count.
const K_QUASI_STRUCTURED: f64 = 1.13;
/// Quads per `s²` of area of the plain unstructured method (K = 1: mean
/// 0.906, 0.69–1.30).
const K_UNSTRUCTURED: f64 = 1.10;
/// Quads per `h²` of area of the baseline (K = 1.732, `√3`, the count of
/// equilateral triangles of side `2h` split in three: mean 0.691,
/// 0.51–1.57; its triangles come out smaller than `2h`).
const K_BASELINE: f64 = 2.5;
/// Quads per `h²` of area of the regular method, the baseline's quads
/// after collapses and splits (K = 1.732: mean 1.395, 0.89–1.92).
const K_REGULAR: f64 = 1.24;

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
        MeshMethod::QuasiStructured(s) if *s == Stages::NONE => {
            (size_map_options(model, h, opts, *s), K_UNSTRUCTURED)
        }
        MeshMethod::QuasiStructured(s) => {
            // without the width rule: on the estimate's coarser background
            // it reads strips as even that the meshing run does not (i04o_m4:
            // 2,904 estimated against 2,231 made with it, 2,756 without); the
            // gears come closer without it too (helical gear 10,120 → 5,880
            // for 6,459 made)
            let map = SizeMapOptions {
                floor_narrow: false,
                ..size_map_options(model, h, opts, *s)
            };
            (map, K_QUASI_STRUCTURED)
        }
        MeshMethod::Unstructured => (size_map_options(model, h, opts, Stages::NONE), K_UNSTRUCTURED),
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
    Ok(k * size_integral(model, h, &map)?.total_with_grids())
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
