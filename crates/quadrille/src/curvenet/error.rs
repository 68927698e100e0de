//! Why a curve network could not be read or a cycle of it is not meshable
//! (issue 30, item 10): one line per error, naming the file (when known), the
//! cycle (and its CAD face) and the place.
//!
//! Numbering in messages: curves, cycles, loops and points are 0-based, as
//! they are indexed in the JSON format; CAD faces and curves are 1-based, as
//! in CAD files and every other Quadrille message.

use std::fmt;

use geometry::FaceId;

/// Where an error is: the file, the cycle and the cycle's CAD face, each when
/// known. Shown as `file: cycle 3 (CAD face 8)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Origin {
    /// The file the network was read from.
    pub file: Option<String>,
    /// The cycle (0-based).
    pub cycle: Option<usize>,
    /// The cycle's CAD face (0-based id; shown 1-based).
    pub cad_face: Option<FaceId>,
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut parts = Vec::new();
        if let Some(file) = &self.file {
            parts.push(file.clone());
        }
        match (self.cycle, self.cad_face) {
            (Some(c), Some(face)) => parts.push(format!("cycle {c} (CAD face {})", face.0 + 1)),
            (Some(c), None) => parts.push(format!("cycle {c}")),
            (None, Some(face)) => parts.push(format!("CAD face {}", face.0 + 1)),
            (None, None) => {}
        }
        if parts.is_empty() {
            parts.push("curve network".to_string());
        }
        write!(f, "{}", parts.join(": "))
    }
}

/// Why a network could not be read, or why one of its cycles cannot be meshed.
#[derive(Clone, Debug, PartialEq)]
pub enum CurveNetError {
    /// The file could not be read (missing, unreadable, not UTF-8).
    Io {
        /// The file.
        file: String,
        /// The system's message.
        message: String,
    },
    /// The file is not valid JSON or OBJ at a line and column (1-based).
    Syntax {
        /// The file, when known.
        file: Option<String>,
        /// Line (1-based).
        line: usize,
        /// Column (1-based).
        column: usize,
        /// What is wrong there.
        message: String,
    },
    /// The file parses but does not describe a network (a direction other
    /// than ±1, a curve without points, an unknown extension, ids that are
    /// not positions).
    Format {
        /// The file, when known.
        file: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// Nothing to mesh: no curve, no cycle, every point the same, every
    /// CAD face skipped.
    Empty {
        /// The file, when known.
        file: Option<String>,
        /// What is missing.
        message: String,
    },
    /// An index past the end of its list (a cycle asked of
    /// [`crate::curvenet::CurveNetwork::cycle_loops`], a face asked of
    /// [`crate::curvenet::network_from_model`]).
    OutOfRange {
        /// What was indexed: "cycle", "CAD face".
        what: &'static str,
        /// The index asked for (0-based; a CAD face is shown 1-based).
        index: usize,
        /// How many there are.
        count: usize,
    },
    /// A cycle refers to a curve that does not exist.
    UnknownCurve {
        /// The cycle.
        origin: Origin,
        /// The loop (0 = outer).
        loop_index: usize,
        /// The position of the use in the loop.
        use_index: usize,
        /// The curve id given.
        curve: usize,
        /// How many curves there are.
        curves: usize,
    },
    /// A coordinate is NaN or infinite.
    NotFinite {
        /// The file, when known.
        file: Option<String>,
        /// The point: "curve 3 point 5 (used by cycle 1)", "corner 2",
        /// "vertex 7 (line 9)".
        item: String,
        /// The coordinates.
        value: [f64; 3],
    },
    /// Consecutive curve uses of a loop do not meet: a gap above the weld
    /// tolerance.
    Open {
        /// The cycle.
        origin: Origin,
        /// The loop (0 = outer).
        loop_index: usize,
        /// Where the gap starts (the end of one curve use) …
        from: [f64; 3],
        /// … and where it ends (the start of the next).
        to: [f64; 3],
        /// Its width.
        gap: f64,
        /// The weld tolerance.
        tolerance: f64,
    },
    /// Two segments of the cycle that are not neighbours come closer than
    /// the weld tolerance (3D segment–segment distance), or neighbours fold
    /// back onto each other.
    SelfIntersecting {
        /// The cycle.
        origin: Origin,
        /// The loops of the two segments (the same for a loop crossing itself).
        loops: (usize, usize),
        /// Midway between the closest points.
        at: [f64; 3],
        /// Their distance.
        distance: f64,
        /// The weld tolerance.
        tolerance: f64,
    },
    /// A loop with fewer than 3 distinct points (zero length when 1).
    TooFewPoints {
        /// The cycle.
        origin: Origin,
        /// The loop (0 = outer).
        loop_index: usize,
        /// Distinct points after welding.
        distinct: usize,
        /// One of them, if any.
        at: Option<[f64; 3]>,
    },
    /// A loop's Newell area is below 1e-6 d² (d its bounding-box diagonal):
    /// folded flat or a figure-eight, no side to put quads on.
    NoInwardSide {
        /// The cycle.
        origin: Origin,
        /// The loop (0 = outer).
        loop_index: usize,
        /// The Newell area.
        area: f64,
        /// The least area accepted.
        minimum: f64,
        /// The loop's centroid.
        at: [f64; 3],
    },
    /// The cycle and another one (or the cycle itself) use a curve they
    /// share in the same direction: no orientation makes both surfaces face
    /// the same side.
    NonOrientable {
        /// The cycle.
        origin: Origin,
        /// The other cycle (may be the same cycle).
        other_cycle: usize,
        /// The other cycle's CAD face.
        other_face: Option<FaceId>,
        /// The shared curve.
        curve: usize,
        /// A point of the curve.
        at: [f64; 3],
    },
}

/// A number in 6 significant digits, trailing zeros cut.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let e = x.abs().log10().floor();
    if (-4.0..9.0).contains(&e) {
        let decimals = (5.0 - e).max(0.0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{x:.5e}");
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

/// A point as `(x, y, z)` in 6 significant digits.
pub(crate) fn pt(p: [f64; 3]) -> String {
    format!("({}, {}, {})", num(p[0]), num(p[1]), num(p[2]))
}

fn file_prefix(file: &Option<String>) -> String {
    match file {
        Some(f) => format!("{f}: "),
        None => String::new(),
    }
}

fn loop_name(l: usize) -> String {
    if l == 0 {
        "the outer loop".to_string()
    } else {
        format!("hole {l}")
    }
}

impl fmt::Display for CurveNetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveNetError::Io { file, message } => write!(f, "{file}: cannot read: {message}"),
            CurveNetError::Syntax {
                file,
                line,
                column,
                message,
            } => {
                let file = file.as_deref().unwrap_or("input");
                write!(f, "{file}:{line}:{column}: {message}")
            }
            CurveNetError::Format { file, message } => {
                write!(f, "{}{message}", file_prefix(file))
            }
            CurveNetError::Empty { file, message } => {
                write!(f, "{}nothing to mesh: {message}", file_prefix(file))
            }
            CurveNetError::OutOfRange { what, index, count } => {
                // CAD faces are numbered from 1 in messages, as in files
                let (shown, first) = if what.starts_with("CAD") {
                    (index + 1, 1)
                } else {
                    (*index, 0)
                };
                write!(
                    f,
                    "no {what} {shown}: they are {first} to {}",
                    (*count + first).saturating_sub(1)
                )
            }
            CurveNetError::UnknownCurve {
                origin,
                loop_index,
                use_index,
                curve,
                curves,
            } => write!(
                f,
                "{origin}: unknown curve: use {use_index} of {} names curve {curve}, \
                 but the curves are 0 to {}",
                loop_name(*loop_index),
                curves.saturating_sub(1)
            ),
            CurveNetError::NotFinite { file, item, value } => write!(
                f,
                "{}not a finite number: {item} is {}",
                file_prefix(file),
                pt(*value)
            ),
            CurveNetError::Open {
                origin,
                loop_index,
                from,
                to,
                gap,
                tolerance,
            } => write!(
                f,
                "{origin}: open cycle: {} has a gap of {} from {} to {} (weld tolerance {})",
                loop_name(*loop_index),
                num(*gap),
                pt(*from),
                pt(*to),
                num(*tolerance)
            ),
            CurveNetError::SelfIntersecting {
                origin,
                loops,
                at,
                distance,
                tolerance,
            } => {
                let which = if loops.0 == loops.1 {
                    format!("{} crosses or touches itself", loop_name(loops.0))
                } else {
                    format!(
                        "{} and {} cross or touch",
                        loop_name(loops.0),
                        loop_name(loops.1)
                    )
                };
                write!(
                    f,
                    "{origin}: self-intersecting cycle: {which} at {} (segments {} apart, \
                     weld tolerance {})",
                    pt(*at),
                    num(*distance),
                    num(*tolerance)
                )
            }
            CurveNetError::TooFewPoints {
                origin,
                loop_index,
                distinct,
                at,
            } => {
                let place = at.map(|p| format!(" at {}", pt(p))).unwrap_or_default();
                let zero = if *distinct <= 1 { ", zero length" } else { "" };
                write!(
                    f,
                    "{origin}: degenerate cycle: {} has {distinct} distinct point{}{zero}{place} \
                     (3 needed)",
                    loop_name(*loop_index),
                    if *distinct == 1 { "" } else { "s" }
                )
            }
            CurveNetError::NoInwardSide {
                origin,
                loop_index,
                area,
                minimum,
                at,
            } => write!(
                f,
                "{origin}: no inward side: {} around {} has Newell area {}, below {} \
                 (folded flat or a figure-eight)",
                loop_name(*loop_index),
                pt(*at),
                num(*area),
                num(*minimum)
            ),
            CurveNetError::NonOrientable {
                origin,
                other_cycle,
                other_face,
                curve,
                at,
            } => {
                let other = Origin {
                    file: None,
                    cycle: Some(*other_cycle),
                    cad_face: *other_face,
                };
                let same = origin.cycle == Some(*other_cycle);
                let whom = if same {
                    "twice".to_string()
                } else {
                    format!("as {other} does")
                };
                write!(
                    f,
                    "{origin}: non-orientable network: uses curve {curve} (through {}) in the \
                     same direction {whom}",
                    pt(*at)
                )
            }
        }
    }
}

impl std::error::Error for CurveNetError {}

impl CurveNetError {
    /// The error's origin with the file set (readers attach the file name to
    /// the errors a network's checks return).
    pub fn in_file(mut self, name: &str) -> Self {
        let set = |f: &mut Option<String>| {
            if f.is_none() {
                *f = Some(name.to_string());
            }
        };
        match &mut self {
            CurveNetError::Io { .. } | CurveNetError::OutOfRange { .. } => {}
            CurveNetError::Syntax { file, .. }
            | CurveNetError::Format { file, .. }
            | CurveNetError::Empty { file, .. }
            | CurveNetError::NotFinite { file, .. } => set(file),
            CurveNetError::UnknownCurve { origin, .. }
            | CurveNetError::Open { origin, .. }
            | CurveNetError::SelfIntersecting { origin, .. }
            | CurveNetError::TooFewPoints { origin, .. }
            | CurveNetError::NoInwardSide { origin, .. }
            | CurveNetError::NonOrientable { origin, .. } => set(&mut origin.file),
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(0.1 + 0.2), "0.3");
        assert_eq!(num(-2.5), "-2.5");
        assert_eq!(num(1234567.0), "1234567");
        assert_eq!(num(1e-12), "1e-12");
        assert_eq!(num(-2.5e-7), "-2.5e-7");
        assert_eq!(num(1.5e12), "1.5e12");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(pt([0.0, 1.0, -0.5]), "(0, 1, -0.5)");
    }

    #[test]
    fn origin_names_file_cycle_and_face() {
        let o = Origin {
            file: Some("a.json".into()),
            cycle: Some(3),
            cad_face: Some(FaceId(7)),
        };
        assert_eq!(o.to_string(), "a.json: cycle 3 (CAD face 8)");
        assert_eq!(Origin::default().to_string(), "curve network");
    }
}
