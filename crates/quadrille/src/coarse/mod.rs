//! The coarse method (coarse high-order quads paper; `quadrille mesh --method
//! coarse`): the default method's quads, a T-mesh of traces on them (§III.A),
//! an integer program over the T-mesh arc lengths (§III.B–C), the coarse block
//! layout it implies (§IV.A–C), a fine block-structured mesh (§IV.D–E) and one
//! curved Lagrange quad per block (§IV.F).
//!
//! Stages, one module each:
//! - [`block_layout`]: the coarse layout placed on the input mesh — the
//!   hand-over between the layout stages and the geometry stages.

pub(crate) mod block_layout;
