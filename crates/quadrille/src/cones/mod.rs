//! S2 of `quadrille spline` (spec ricci-flow-iga-reconstruction §4, paper
//! Eq. 2–4): the cone singularities the Ricci flow flattens the shell to.
//! A proposal from the boundary-aligned cross field of the whole shell
//! ([`propose_cones`]: its singularities snapped to shell vertices, boundary
//! corners at I = 2 − n̄), or the user's cone file ([`parse_cones`], lines
//! `x y z index`), written back by [`format_cones`] for hand edits. Every
//! set is checked the same way ([`check_cones`]): Σ I = 4χ (Gauss–Bonnet,
//! χ = 2 − 2g − b), interior I ≤ 3, boundary I ≤ 1, one cone per vertex.

use thiserror::Error;

use crate::ricci::Cone;
use crate::shell::{Shell, ShellTopology};

mod file;
mod propose;

pub use file::{format_cones, parse_cones, write_cones, FAR_TRIANGLE_SIZES};
pub use propose::{propose_cones, CREASE_ANGLE_DEGREES};

/// The counts of a cone set, for reports and error lines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ConeSummary {
    /// Interior cones of index +1 (valence 3).
    pub plus: usize,
    /// Interior cones of index −1 (valence 5).
    pub minus: usize,
    /// Interior cones of another index (−2: valence 6, merged clusters).
    pub other_interior: usize,
    /// Boundary cones (corners).
    pub boundary: usize,
    /// Σ I over the interior cones.
    pub interior_sum: i64,
    /// Σ I over the boundary cones.
    pub boundary_sum: i64,
    /// χ of the shell.
    pub euler: i64,
}

impl ConeSummary {
    /// Counts `cones` on `topo` (cones of index 0 count nowhere).
    pub fn of(topo: &ShellTopology, cones: &[Cone]) -> ConeSummary {
        let mut s = ConeSummary {
            euler: topo.euler,
            ..ConeSummary::default()
        };
        for c in cones.iter().filter(|c| c.index != 0) {
            let boundary = topo.on_boundary.get(c.vertex).copied().unwrap_or(false);
            if boundary {
                s.boundary += 1;
                s.boundary_sum += i64::from(c.index);
            } else {
                match c.index {
                    1 => s.plus += 1,
                    -1 => s.minus += 1,
                    _ => s.other_interior += 1,
                }
                s.interior_sum += i64::from(c.index);
            }
        }
        s
    }

    /// Interior cones.
    pub fn interior(&self) -> usize {
        self.plus + self.minus + self.other_interior
    }

    /// Σ I over all cones.
    pub fn index_sum(&self) -> i64 {
        self.interior_sum + self.boundary_sum
    }

    /// 4χ, what Gauss–Bonnet needs of Σ I.
    pub fn needed(&self) -> i64 {
        4 * self.euler
    }
}

impl std::fmt::Display for ConeSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} interior cones (+1: {}, −1: {}, other: {}; Σ I = {}) and {} boundary cones (Σ I = {}); Σ I = {}, 4χ = {} (χ = {})",
            self.interior(),
            self.plus,
            self.minus,
            self.other_interior,
            self.interior_sum,
            self.boundary,
            self.boundary_sum,
            self.index_sum(),
            self.needed(),
            self.euler
        )
    }
}

/// Why a cone set was not made or is not usable.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConeError {
    /// The cross field of the proposal failed.
    #[error("cone proposal: cross field failed ({0})")]
    Field(String),
    /// Σ I ≠ 4χ.
    #[error("{source_name}: cone indices break Gauss–Bonnet: Σ I = {index_sum} ({interior_sum} interior + {boundary_sum} boundary) but 4χ = {needed} (χ = {euler})")]
    IndexSum {
        /// Where the cones came from (the proposal or a file).
        source_name: String,
        /// Σ I.
        index_sum: i64,
        /// Σ I over interior cones.
        interior_sum: i64,
        /// Σ I over boundary cones.
        boundary_sum: i64,
        /// 4χ.
        needed: i64,
        /// χ.
        euler: i64,
    },
    /// An index above the cap (interior 3, boundary 1).
    #[error("{source_name}: cone at {position:?} (vertex {vertex}) has index {index}, above the {where_} cap {cap}")]
    TooLarge {
        /// Where the cones came from.
        source_name: String,
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
        /// The index.
        index: i32,
        /// "interior" or "boundary".
        where_: &'static str,
        /// 3 or 1.
        cap: i32,
    },
    /// Two cones on one vertex, or a vertex that does not exist.
    #[error("{source_name}: {message}")]
    BadVertex {
        /// Where the cones came from.
        source_name: String,
        /// What is wrong.
        message: String,
    },
    /// A bad line of a cone file.
    #[error("{file}:{line}: {message}")]
    Line {
        /// The file.
        file: String,
        /// Line number from 1.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The cone file could not be read or written.
    #[error("{file}: {message}")]
    Io {
        /// The file.
        file: String,
        /// The system's message.
        message: String,
    },
}

/// Largest interior index (target angle sum 2π − 3π/2 = π/2 > 0).
pub const MAX_INTERIOR_INDEX: i32 = 3;
/// Largest boundary index (target angle sum π − π/2 = π/2 > 0).
pub const MAX_BOUNDARY_INDEX: i32 = 1;

/// Checks `cones` on the shell: vertices exist and hold one cone each,
/// interior I ≤ 3, boundary I ≤ 1, Σ I = 4χ. `source_name` starts every
/// error line (the proposal or the cone file).
pub fn check_cones(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
    source_name: &str,
) -> Result<ConeSummary, ConeError> {
    let n = shell.vertices.len();
    let mut seen = vec![false; n];
    for c in cones {
        if c.vertex >= n {
            return Err(ConeError::BadVertex {
                source_name: source_name.into(),
                message: format!("cone on vertex {}: the shell has {n} vertices", c.vertex),
            });
        }
        if std::mem::replace(&mut seen[c.vertex], true) {
            return Err(ConeError::BadVertex {
                source_name: source_name.into(),
                message: format!(
                    "two cones on vertex {} at {:?}",
                    c.vertex, shell.vertices[c.vertex]
                ),
            });
        }
        let (where_, cap) = if topo.on_boundary[c.vertex] {
            ("boundary", MAX_BOUNDARY_INDEX)
        } else {
            ("interior", MAX_INTERIOR_INDEX)
        };
        if c.index > cap {
            return Err(ConeError::TooLarge {
                source_name: source_name.into(),
                vertex: c.vertex,
                position: shell.vertices[c.vertex],
                index: c.index,
                where_,
                cap,
            });
        }
    }
    let s = ConeSummary::of(topo, cones);
    if s.index_sum() != s.needed() {
        return Err(ConeError::IndexSum {
            source_name: source_name.into(),
            index_sum: s.index_sum(),
            interior_sum: s.interior_sum,
            boundary_sum: s.boundary_sum,
            needed: s.needed(),
            euler: s.euler,
        });
    }
    Ok(s)
}

#[cfg(test)]
mod tests;
