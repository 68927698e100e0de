//! Quad meshes from closed 3D curve cycles, with no surface inside (paper
//! curve-network-quadrangulation; spec `curve-network-quadrangulation.md`).
//!
//! The stages hand these types to each other:
//!
//! - a cycle to mesh is a [`CycleLoops`]: its outer loop and its holes, each a
//!   closed polyline ([`LoopPolyline`]) with the points that must stay segment
//!   endpoints;
//! - segmentation and matching (§1–§4) turn it into a [`PairedCycle`]: one
//!   closed polyline (holes joined by connectors) cut into segments, and the
//!   segments paired, each pair the two ends of one poly-chord;
//! - layout and geometry (§5–§6) turn a [`PairedCycle`] into quads.
//!
//! The input side (issue 30, items 1 and 10):
//! - [`network`]: the welded [`CurveNetwork`] and, per cycle, its checked and
//!   oriented [`CycleLoops`] ([`CurveNetwork::cycle_loops`]);
//! - [`io`]: the JSON and OBJ readers and the JSON writer
//!   (`docs/curve-networks.md`);
//! - [`from_model`]: a network from the boundary loops of CAD faces;
//! - [`error`]: [`CurveNetError`], one line naming file, cycle and place;
//! - [`check`]: segment distances through a grid, Newell areas, welding.
//!
//! The network stage (§7), after every cycle is meshed on its own:
//! - [`tjunction`]: T-junctions on shared curves merged or split (chords
//!   split in two), secondary vertices snapped onto the shared sampling;
//! - [`intervals`]: one interval count per poly-chord by an integer program,
//!   equal on both sides of every shared primary segment.

pub(crate) mod check;
pub(crate) mod error;
pub(crate) mod from_model;
pub(crate) mod from_wires;
pub(crate) mod io;
pub(crate) mod network;
pub mod surface;

pub use error::{CurveNetError, Origin};
pub use from_model::{
    network_from_model, SkipReason, SkippedFace, CAD_SPACING_FACTOR, CAD_TURN_DEGREES,
};
pub use from_wires::{network_from_wires, WireCurveUse};
pub use io::{parse_json, parse_obj, read_network, to_json, write_network};
pub use surface::CycleSurface;
pub use network::{
    CurveNetwork, CycleUse, NetworkCurve, NetworkCycle, INWARD_AREA_FACTOR, JUNCTION_TURN_DEGREES,
    WELD_FACTOR,
};

pub mod cost;
pub mod midpoint;
pub mod pairing;
pub mod polyline;
pub mod refine;
pub mod roommates;
pub mod ring;
pub mod segment;

#[cfg(test)]
pub(crate) mod fixtures;
#[cfg(test)]
mod figure_tests;

pub use pairing::{pair_cycle, PairingError, PairingOptions, PairingReport};

/// A closed polyline: one loop of a cycle.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopPolyline {
    /// The points in order; the loop closes from the last point back to the
    /// first, which is not repeated.
    pub points: Vec<[f64; 3]>,
    /// Indices into `points` that must stay segment endpoints: the input's
    /// corners and T-junctions, and junctions where the curves meet at an
    /// angle (spec §1, §7.2). Ascending, no repeats.
    pub fixed: Vec<usize>,
}

/// One cycle marked for surfacing: an outer loop and its holes.
///
/// The outer loop runs counter-clockwise seen from the side the quads face;
/// holes run the other way, so the surface is always on the left.
#[derive(Clone, Debug, PartialEq)]
pub struct CycleLoops {
    /// The outer loop.
    pub outer: LoopPolyline,
    /// The holes, in input order.
    pub holes: Vec<LoopPolyline>,
    /// The CAD surface the cycle bounds (a network from CAD faces), else
    /// `None`: bridge directions, the inversion judge and the patch
    /// interiors then follow it.
    pub surface: Option<CycleSurface>,
}

/// A cycle cut into segments with its segments paired (the output of §1–§4,
/// the input of §5).
#[derive(Clone, Debug, PartialEq)]
pub struct PairedCycle {
    /// The closed polyline the segments are cut from. Holes are joined to the
    /// outer loop by connectors traversed once on each side, so a position may
    /// appear twice under two indices.
    pub points: Vec<[f64; 3]>,
    /// The first point of each segment, ascending: segment `s` runs from
    /// `starts[s]` to `starts[s + 1]`, the last one around to `starts[0]`.
    /// Always an even count.
    pub starts: Vec<usize>,
    /// The matched segments `(i, j)` with `i < j`, one per poly-chord, every
    /// segment in exactly one pair.
    pub pairs: Vec<(usize, usize)>,
    /// The matching cost of each pair (spec §2), in `pairs` order.
    pub costs: Vec<f64>,
    /// Per segment: a connector or cut that must not be split (spec §1, §5.1).
    pub unsplittable: Vec<bool>,
    /// The cycle's diameter D, the largest distance between two of its points;
    /// every length in the method is measured in D.
    pub diameter: f64,
}

pub mod cut;
pub mod dislocation;
pub mod geometry;
pub mod intervals;
pub mod layout;
pub mod sample;
pub mod tjunction;
pub mod untangle;

pub use layout::LayoutError;
pub use sample::{quadrangulate, CycleQuads};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod pipeline_tests;
