//! The curve network of a CAD file with curves and no face (issue 30, item 1:
//! "No face: its closed wires"), from the closed wires `occt::load_wires`
//! found (the CLI reads the file; this crate does not depend on `occt`).
//!
//! Each closed wire is one cycle of one loop. Each CAD curve of a closed wire
//! is one network polyline, its samples in the curve's own direction and its
//! CAD id kept (so `stats --cad` can measure the mesh against it); the cycle
//! has no CAD face, so the side its quads face is the loop's Newell normal,
//! as for a JSON or OBJ network. Curves in no closed wire (dead ends, or
//! junctions of three or more curves, where the cycles are ambiguous without
//! faces) are left out and named in one note.

use geometry::vec3::Vec3;
use geometry::CurveId;

use super::error::CurveNetError;
use super::network::{CurveNetwork, CycleUse, NetworkCurve, NetworkCycle};

/// One curve use of a closed wire: the CAD curve (0-based), true when the
/// wire runs it from its start to its end, and its samples in the wire's
/// direction (the first is the previous use's last).
pub type WireCurveUse<'a> = (usize, bool, &'a [Vec3]);

/// The network of the closed wires `closed` (each its curve uses in order)
/// and, when `open_curves` (0-based) is not empty, a note naming them
/// (1-based, as CAD files number them). An error when no wire is closed.
pub fn network_from_wires(
    closed: &[Vec<WireCurveUse<'_>>],
    open_curves: &[usize],
) -> Result<(CurveNetwork, Option<String>), CurveNetError> {
    let note = (!open_curves.is_empty()).then(|| {
        let ids: Vec<String> = open_curves
            .iter()
            .map(|c| (c + 1).to_string())
            .collect();
        let (what, verb) = if ids.len() == 1 {
            ("curve", "is")
        } else {
            ("curves", "are")
        };
        format!(
            "{what} {} {verb} in no closed wire (a dead end, or a junction of 3 or more curves): left out",
            ids.join(", ")
        )
    });
    if closed.is_empty() {
        return Err(CurveNetError::Empty {
            file: None,
            message: format!(
                "the file has no face and no closed wire{}",
                note.as_ref().map(|n| format!(" ({n})")).unwrap_or_default()
            ),
        });
    }
    let mut curves = Vec::new();
    let mut cycles = Vec::with_capacity(closed.len());
    for wire in closed {
        let mut uses = Vec::with_capacity(wire.len());
        for &(cad, forward, samples) in wire {
            // the curve's own direction: a backward use's samples reversed
            let mut points = samples.to_vec();
            if !forward {
                points.reverse();
            }
            uses.push(CycleUse {
                curve: curves.len(),
                forward,
            });
            curves.push(NetworkCurve {
                points,
                cad: Some(CurveId(cad as u32)),
            });
        }
        cycles.push(NetworkCycle {
            loops: vec![uses],
            cad_face: None,
            surface: None,
        });
    }
    Ok((CurveNetwork::new(curves, cycles, Vec::new())?, note))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square's sides as the samples of one wire of 4 line uses,
    /// the 2nd and 4th backward.
    fn square_sides() -> Vec<[Vec3; 2]> {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        (0..4).map(|i| [p[i], p[(i + 1) % 4]]).collect()
    }

    #[test]
    fn each_wire_is_a_cycle_and_each_use_a_curve_in_its_own_direction() {
        let sides = square_sides();
        let wire: Vec<WireCurveUse<'_>> = sides
            .iter()
            .enumerate()
            .map(|(i, s)| (i, i % 2 == 0, &s[..]))
            .collect();
        let (net, note) = network_from_wires(&[wire], &[6]).unwrap();
        assert_eq!(net.cycles().len(), 1);
        assert_eq!(net.curves().len(), 4);
        let loops = &net.cycles()[0].loops;
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].len(), 4);
        // the backward use of curve 1 runs (1,0) → (1,1) in the wire; the
        // network curve keeps the CAD direction, (1,1) → (1,0)
        let c1 = &net.curves()[1];
        assert_eq!(c1.cad, Some(CurveId(1)));
        assert_eq!(c1.points, vec![[1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]);
        assert!(!loops[0][1].forward);
        assert_eq!(note.as_deref().map(|n| n.contains("curve 7 is")), Some(true));
        // the cycle closes: its polyline is the square's 4 corners, each a
        // fixed point (the lines meet at 90°)
        let cl = net.cycle_loops(0).unwrap();
        assert!(cl.holes.is_empty());
        assert_eq!(cl.outer.points.len(), 4, "{:?}", cl.outer.points);
        assert_eq!(cl.outer.fixed, vec![0, 1, 2, 3]);
    }

    #[test]
    fn no_closed_wire_is_an_error_naming_the_open_curves() {
        let e = network_from_wires(&[], &[0, 2]).unwrap_err().to_string();
        assert!(e.contains("no closed wire") && e.contains("curves 1, 3"), "{e}");
    }
}
