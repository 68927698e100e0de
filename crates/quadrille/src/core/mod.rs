//! Core: the types and tools every stage shares, importing nothing from the
//! other folders.
//!
//! - [`fast_hash`]: the one-multiply hasher of the inner-loop maps (ours);
//! - [`work_queue`]: parallel map handing out work largest first, results in
//!   input order (ours: the output does not depend on the thread count);
//! - [`face_quads`]: the editable quads of one face with an edit journal and
//!   checkpoints (exact rollback), used by the topology stages.

pub mod error;
pub mod face_quads;
pub mod fast_hash;
pub mod options;
pub mod patch;
pub mod quality;
pub mod queries;
pub mod valence;
pub mod work_queue;
