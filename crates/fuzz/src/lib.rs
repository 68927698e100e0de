//! Mutation fuzzing of Quadrille's readers (STL, OBJ, PLY, MSH, and STEP,
//! IGES, BREP through OpenCASCADE) and of meshing mutated but loadable
//! models (issue 32, item 6). Stable Rust, no instrumentation: seed files are
//! mutated ([`mutate`]) and run in worker processes ([`campaign`]) so that a
//! crash inside C++ code is caught and pinned to its input. A panic, a crash
//! or a hang is a defect; a clean error is the right answer to a broken file.
//!
//! The command: `quadrille-fuzz [--targets stl,obj,...] [--seconds S]
//! [--seed N] [--out DIR]` (see `docs/fuzzing.md`).

pub mod campaign;
pub mod mutate;
pub mod rng;
pub mod target;

pub use campaign::{Campaign, Defect, DefectKind, Summary};
pub use target::{Target, ALL_TARGETS};
