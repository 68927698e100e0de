//! Core: the types and tools every stage shares, importing nothing from the
//! other folders.
//!
//! - [`fast_hash`]: the one-multiply hasher of the inner-loop maps (ours);
//! - [`work_queue`]: parallel map handing out work largest first, results in
//!   input order (ours: the output does not depend on the thread count);
//! - [`face_quads`]: the editable quads of one face with an edit journal and
//!   checkpoints (exact rollback), used by the topology stages;
//! - [`union_find`]: disjoint sets (curve chords, quad loops).

pub(crate) mod error;
pub(crate) mod face_quads;
pub(crate) mod fast_hash;
pub(crate) mod options;
pub(crate) mod patch;
pub(crate) mod quality;
pub(crate) mod queries;
pub(crate) mod union_find;
pub(crate) mod valence;
pub(crate) mod work_queue;

pub use face_quads::extract::{extract_face, quads_by_face};
pub use face_quads::FaceQuads;
pub use patch::{NodeRef, QuadPatch};
pub use quality::quad_quality;
