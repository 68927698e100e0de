//! Smoothing: node placement with fixed topology.
//!
//! - [`kernels`]: the quasi-structured meshing paper's 3D kernels (§5.3:
//!   Winslow on regular nodes, angle-based on irregular ones) and the
//!   smoothing loop, with the average-SICN ascent (ours);
//! - [`repair`]: Laplacian smoothing with rollback and untangling (ours);
//! - [`curve_slide`]: curve nodes slid along their curves on the assembled
//!   mesh (ours).

pub(crate) mod curve_slide;
pub(crate) mod kernels;
pub(crate) mod repair;

pub use kernels::{optimize, optimize_nodes, raise_average, OptimizeOptions, OptimizeReport};
pub use repair::{
    lift_poor_quads, optimize_around, sharp_corner_weights, smooth, smooth_then_untangle, untangle,
    untangle_budget, untangle_counted, Untangled, POOR_SICN, SHARP_CORNER_WEIGHT, UNTANGLE_BELOW,
    UNTANGLE_EVALUATIONS_FIXED, UNTANGLE_EVALUATIONS_PER_NODE, UNTANGLE_MAX_NODES, UNTANGLE_PASSES,
};
