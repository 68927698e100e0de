//! The coarse method (coarse high-order quads paper; `quadrille mesh --method
//! coarse`): the default method's quads, a T-mesh of traces on them (§III.A),
//! an integer program over the T-mesh arc lengths (§III.B–C), the coarse block
//! layout it implies (§IV.A–C), a fine block-structured mesh (§IV.D–E) and one
//! curved Lagrange quad per block (§IV.F).
//!
//! Stages, one module each:
//! - [`block_layout`]: the coarse layout placed on the input mesh — the
//!   hand-over between the layout stages and the geometry stages;
//! - [`layout_check`]: the identity layout (every input quad a block, q = l)
//!   and the validity check of a layout;
//! - [`quad_loops`]: the quad loops of a layout and their widths (§IV.D);
//! - [`fine_mesh`]: the fine block-structured mesh, placed by transfinite
//!   interpolation and smoothed (§IV.D–E);
//! - [`high_order_extraction`]: one Lagrange quad of order N per block, its
//!   Jacobian checked (§IV.F);
//! - [`loop_split`]: the quad loops of elements that stay invalid split in
//!   two, and the extraction run again (issue 29; not in the paper).
//!
//! Helpers of the geometry stages: [`face_patches`] (per-face (u, v) views of
//! a mesh) and [`resample`] (equal-arc-length resampling, curve parameters,
//! transfinite interpolation).

pub(crate) mod block_layout;
pub(crate) mod face_patches;
pub(crate) mod fine_mesh;
pub(crate) mod high_order_extraction;
pub(crate) mod layout_check;
pub(crate) mod loop_split;
pub(crate) mod quad_loops;
pub(crate) mod resample;
