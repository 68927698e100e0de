//! Global vertex redistribution (paper Algorithm 2): once the topology is
//! fixed, the admissible angle window is tightened one degree per step from
//! (5°, 175°) toward (85°, 95°), repositioning (Algorithm 1) the vertices of
//! the quads that violate the current window, until some quad cannot be
//! brought inside it ("the process stops once it cannot reduce the angle
//! interval any further").
//!
//! Reading of the undefined `validArea` (spec §8): a vertex move is kept only
//! when no quad of its fan gets further outside the current window (nor
//! becomes invalid for the base window), so the mesh stays valid and every
//! step is an improvement; a full move is tried, then a half move.

use geometry::Face;

use crate::core::face_quads::FaceQuads;

use super::reposition::weighted_average;
use super::validity::{fan_inverted, quad_violation, worst_movable_vertex, AngleWindow};

/// Rounds of repositioning per window before giving up on it.
const ROUNDS_PER_WINDOW: usize = 4;

fn fan_violation(fq: &FaceQuads, face: &Face, v: u32, w: AngleWindow) -> f64 {
    fq.verts[v as usize]
        .fan
        .iter()
        .map(|&q| quad_violation(fq, face, q, w))
        .fold(0.0, f64::max)
}

/// Moves `v` toward its Algorithm-1 position when that does not make its fan
/// worse for `w`; returns whether it moved.
fn guarded_move(fq: &mut FaceQuads, face: &Face, v: u32, w: AngleWindow) -> bool {
    let Some(target) = weighted_average(fq, v) else {
        return false;
    };
    let before = fan_violation(fq, face, v, w);
    let inverted = fan_inverted(fq, face, v);
    let start = fq.verts[v as usize].uv;
    for t in [1.0, 0.5, 0.25] {
        let uv = [
            start[0] + t * (target[0] - start[0]),
            start[1] + t * (target[1] - start[1]),
        ];
        let cp = fq.checkpoint();
        if !fq.move_vertex(face, v, uv) {
            return false;
        }
        let after = fan_violation(fq, face, v, w);
        if after.is_finite()
            && (after < before || (after == 0.0 && before == 0.0))
            && fan_inverted(fq, face, v) <= inverted
        {
            return true;
        }
        fq.rollback(cp);
    }
    false
}

/// Runs Algorithm 2 on one face from `base` toward `target` by `step` degrees.
/// Returns the tightest window every quad satisfies at the end (at movable
/// vertices), which is at least as tight as the window the face started in.
pub fn redistribute(
    fq: &mut FaceQuads,
    face: &Face,
    base: AngleWindow,
    target: AngleWindow,
    step: f64,
) -> AngleWindow {
    let step = if step.is_finite() && step > 0.0 {
        step
    } else {
        1.0
    };
    let mut reached = base;
    let mut w = base;
    // quads already invalid for the base window cannot stop (or block) the tightening
    let counts = |fq: &FaceQuads, q: u32| quad_violation(fq, face, q, base).is_finite();
    loop {
        w = AngleWindow {
            min_deg: (w.min_deg + step).min(target.min_deg),
            max_deg: (w.max_deg - step).max(target.max_deg),
        };
        let mut ok = false;
        for _ in 0..ROUNDS_PER_WINDOW {
            let bad: Vec<u32> = fq
                .live_quads()
                .filter(|&q| counts(fq, q) && quad_violation(fq, face, q, w) > 0.0)
                .collect();
            if bad.is_empty() {
                ok = true;
                break;
            }
            let mut moved = false;
            for q in bad {
                let Some(v) = worst_movable_vertex(fq, face, q, w) else {
                    continue;
                };
                moved |= guarded_move(fq, face, v, w);
                for l in fq.links(v) {
                    if !fq.verts[l as usize].fixed {
                        moved |= guarded_move(fq, face, l, w);
                    }
                }
                moved |= guarded_move(fq, face, v, w);
            }
            fq.commit();
            if !moved {
                break;
            }
        }
        if !ok
            && fq
                .live_quads()
                .any(|q| counts(fq, q) && quad_violation(fq, face, q, w) > 0.0)
        {
            break;
        }
        reached = w;
        if w.min_deg >= target.min_deg && w.max_deg <= target.max_deg {
            break;
        }
    }
    fq.commit();
    reached
}
