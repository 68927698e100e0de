//! A curve network from the boundary loops of CAD faces (issue 30, item 1):
//! each face a cycle, each CAD curve one polyline shared by the faces using it.

use std::collections::HashMap;
use std::fmt;

use geometry::vec3::{self, Vec3};
use geometry::{CurveEntity, CurveId, FaceId, Model};

use super::error::CurveNetError;
use super::surface::CycleSurface;
use super::network::{turn, CurveNetwork, CycleUse, NetworkCurve, NetworkCycle};

/// CAD curves are sampled at spacings of at most this fraction of the model
/// diagonal …
pub const CAD_SPACING_FACTOR: f64 = 1.0 / 200.0;

/// … and turning at most this many degrees per segment, so that a small
/// circle keeps its shape and smooth curves show no corner (spec §1 looks for
/// 40° over ±2 samples).
pub const CAD_TURN_DEGREES: f64 = 5.0;

/// Why a face gave no cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkipReason {
    /// The face has no boundary loop (a closed surface), or an empty one.
    NoLoop,
    /// The face has a seam: this curve appears twice in its loops.
    Seam(CurveId),
    /// A boundary loop of the face has only degenerate curves (poles or
    /// apexes: points in 3D). A degenerate curve between others, as at the
    /// pole corner of a spherical triangle, is left out of its loop, which
    /// closes through the pole, and the face is kept.
    DegenerateCurve(CurveId),
}

/// A face [`network_from_model`] left out, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SkippedFace {
    /// The face.
    pub face: FaceId,
    /// Why.
    pub reason: SkipReason,
}

impl fmt::Display for SkippedFace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let why = match self.reason {
            SkipReason::NoLoop => "no boundary loop".to_string(),
            SkipReason::Seam(c) => format!("a seam (CAD curve {})", c.0 + 1),
            SkipReason::DegenerateCurve(c) => {
                format!(
                    "a loop of degenerate curves only (CAD curve {}, a pole or apex)",
                    c.0 + 1
                )
            }
        };
        write!(f, "CAD face {} skipped: {why}", self.face.0 + 1)
    }
}

/// The network of the boundary loops of `faces` (0-based ids; `None`: every
/// face): each face a cycle whose loops follow the face orientation (counter-
/// clockwise about the face's oriented normal, holes the other way), so the
/// quads face the way the face does, out of a solid. Each CAD curve is one
/// polyline, shared by the faces using it and keeping its id, sampled at
/// equal arc lengths no more than [`CAD_SPACING_FACTOR`] × the model diagonal
/// apart and turning no more than [`CAD_TURN_DEGREES`] per segment; its ends
/// are its CAD corners' points, so loops close exactly. Degenerate curves
/// (poles, apexes) are points in 3D and are left out of their loops. Faces
/// with a seam, no loop, or a loop of degenerate curves only are skipped and
/// listed.
pub fn network_from_model(
    model: &Model,
    faces: Option<&[usize]>,
) -> Result<(CurveNetwork, Vec<SkippedFace>), CurveNetError> {
    model.validate().map_err(|e| CurveNetError::Format {
        file: None,
        message: format!("invalid model: {e}"),
    })?;
    let mut list: Vec<usize> = match faces {
        Some(f) => f.to_vec(),
        None => (0..model.faces.len()).collect(),
    };
    let mut seen = std::collections::HashSet::new();
    list.retain(|f| seen.insert(*f));
    if let Some(&f) = list.iter().find(|&&f| f >= model.faces.len()) {
        return Err(CurveNetError::OutOfRange {
            what: "CAD face",
            index: f,
            count: model.faces.len(),
        });
    }
    let spacing = CAD_SPACING_FACTOR * model.diagonal();
    let mut curves: Vec<NetworkCurve> = Vec::new();
    let mut index: HashMap<CurveId, usize> = HashMap::new();
    let mut cycles = Vec::new();
    let mut skipped = Vec::new();
    for f in list {
        let face = &model.faces[f];
        let id = FaceId(f as u32);
        if let Some(reason) = skip_reason(model, f) {
            skipped.push(SkippedFace { face: id, reason });
            continue;
        }
        // the outer loop first, holes in their order
        let mut order: Vec<&geometry::Loop> = face.loops.iter().filter(|l| l.outer).collect();
        order.extend(face.loops.iter().filter(|l| !l.outer));
        let mut loops = Vec::with_capacity(order.len());
        for lp in order {
            // a degenerate curve (a pole at a corner of the face) is a point
            // in 3D: the loop closes through it without it
            let mut uses: Vec<CycleUse> = lp
                .uses
                .iter()
                .filter(|u| !degenerate(&model.curves[u.curve.idx()]))
                .map(|u| {
                    let curve = *index.entry(u.curve).or_insert_with(|| {
                        curves.push(NetworkCurve {
                            points: sample(model, &model.curves[u.curve.idx()], spacing),
                            cad: Some(u.curve),
                        });
                        curves.len() - 1
                    });
                    CycleUse {
                        curve,
                        forward: u.forward,
                    }
                })
                .collect();
            if face.reversed {
                // counter-clockwise about the oriented normal −(du × dv)
                uses.reverse();
                for u in &mut uses {
                    u.forward = !u.forward;
                }
            }
            loops.push(uses);
        }
        cycles.push(NetworkCycle {
            loops,
            cad_face: Some(id),
            surface: Some(CycleSurface::new(face.surface.clone(), face.reversed)),
        });
    }
    if cycles.is_empty() {
        let message = if skipped.is_empty() {
            "no CAD face".to_string()
        } else {
            let why: Vec<String> = skipped.iter().map(|s| s.to_string()).collect();
            format!("every CAD face was skipped ({})", why.join("; "))
        };
        return Err(CurveNetError::Empty {
            file: None,
            message,
        });
    }
    let net = CurveNetwork::new(curves, cycles, Vec::new())?;
    Ok((net, skipped))
}

/// Why face `f` gives no cycle, if it does not.
fn skip_reason(model: &Model, f: usize) -> Option<SkipReason> {
    let face = &model.faces[f];
    if face.loops.is_empty() || face.loops.iter().any(|l| l.uses.is_empty()) {
        return Some(SkipReason::NoLoop);
    }
    let mut count: HashMap<CurveId, usize> = HashMap::new();
    for u in face.curve_uses() {
        *count.entry(u.curve).or_default() += 1;
    }
    if let Some(u) = face.curve_uses().find(|u| u.seam || count[&u.curve] > 1) {
        return Some(SkipReason::Seam(u.curve));
    }
    // a loop of poles only has no 3D extent
    face.loops
        .iter()
        .find(|l| {
            l.uses
                .iter()
                .all(|u| degenerate(&model.curves[u.curve.idx()]))
        })
        .map(|l| SkipReason::DegenerateCurve(l.uses[0].curve))
}

/// A curve without 3D extent: a pole or an apex.
fn degenerate(c: &CurveEntity) -> bool {
    c.degenerate || c.geom.is_none()
}

/// The polyline of a CAD curve: equal arc lengths at most `spacing` apart,
/// at most [`CAD_TURN_DEGREES`] of turn per segment, from its start corner's
/// point to its end corner's.
fn sample(model: &Model, ce: &CurveEntity, spacing: f64) -> Vec<Vec3> {
    let start = model.corners[ce.start.idx()].point;
    let end = model.corners[ce.end.idx()].point;
    let Some(g) = &ce.geom else {
        return vec![start, end];
    };
    let (t0, t1) = ce.range;
    let closed = ce.start == ce.end;
    let max_turn = CAD_TURN_DEGREES.to_radians();
    let mut m = 256usize;
    loop {
        let ts: Vec<f64> = (0..=m)
            .map(|i| t0 + (t1 - t0) * i as f64 / m as f64)
            .collect();
        let ps: Vec<Vec3> = ts.iter().map(|&t| g.eval(t)).collect();
        let mut cum = vec![0.0; m + 1];
        for i in 1..=m {
            cum[i] = cum[i - 1] + vec3::dist(ps[i - 1], ps[i]);
        }
        let length = cum[m];
        let total_turn: f64 = (1..m).map(|i| turn(ps[i - 1], ps[i], ps[i + 1])).sum();
        let by_length = if spacing > 0.0 {
            (length / spacing).ceil()
        } else {
            1.0
        };
        let n = by_length
            .max((total_turn / max_turn).ceil())
            .max(if closed { 3.0 } else { 1.0 })
            .clamp(1.0, 1e6) as usize;
        if 4 * n > m && m < (1 << 20) {
            m = 8 * n;
            continue;
        }
        if !(length > 0.0) || !length.is_finite() {
            return vec![start, end];
        }
        let mut out = Vec::with_capacity(n + 1);
        out.push(start);
        let mut seg = 0;
        for k in 1..n {
            let s = length * k as f64 / n as f64;
            while seg + 1 < m && cum[seg + 1] < s {
                seg += 1;
            }
            let span = cum[seg + 1] - cum[seg];
            let a = if span > 0.0 {
                (s - cum[seg]) / span
            } else {
                0.0
            };
            out.push(g.eval(ts[seg] + a * (ts[seg + 1] - ts[seg])));
        }
        out.push(end);
        return out;
    }
}

#[cfg(test)]
mod tests;
