//! Combinatorics: quad layouts of disks as pure tables, with no geometry.
//!
//! - [`patterns`]: the quasi-structured meshing paper's pattern library
//!   (§6.1, Fig. 6: quad patterns for 3–6 sided disks and their side counts);
//! - [`disk_quads`]: every quadrangulation of a small disk with given boundary
//!   valences (the paper's §6.3 disk quadrangulations, tabulated here).

pub(crate) mod disk_quads;
pub(crate) mod patterns;

pub use disk_quads::{enumerate, format_table, TABLE_MAX_BOUNDARY, TABLE_MAX_INTERIOR};
pub use patterns::library;
