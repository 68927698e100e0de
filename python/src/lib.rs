//! The native half of the `quadrille` Python package (`quadrille._quadrille`):
//! Quadrille's library, not its command line, for Python.
//!
//! - [`engine`]: everything that needs no Python (loading, option checks,
//!   meshing on a worker thread that can be cancelled, reports as JSON, flat
//!   arrays, writers, the cross field). Built and tested by `cargo test`.
//! - `bindings` (feature `python`, which maturin turns on): the PyO3 module,
//!   classes `Model` and `QuadMesh`, functions `load`, `mesh`, `read_mesh`,
//!   `field`, exceptions `Error`, `FileError`, `OptionError`, `MeshingError`.
//!
//! `python/quadrille/__init__.py` re-exports the module; `python/README.md`
//! documents the package.

pub mod engine;

#[cfg(feature = "python")]
mod bindings;
