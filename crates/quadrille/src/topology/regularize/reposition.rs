//! Vertex repositioning (paper Algorithm 1) and the local repair loop run
//! after every topological operation (paper §II.B).
//!
//! Algorithm 1 moves a vertex to the average of its links' (u, v) weighted by
//! the length of each link edge (`u = Σ L_j s_j / Σ L_j`, with the printed typo
//! `v = u/Γ` read as `v/Γ`). Weighting by length pulls the vertex toward far
//! neighbours, which evens out edge lengths. L is the 3D chord length (the
//! spec allows it instead of the arc length). Movement happens in (u, v), so
//! the vertex stays on the surface without projection.
//!
//! The repair loop: while some quad of the region is invalid, take each invalid
//! quad, largest angle first, move its worst movable vertex, then its links,
//! then it again; at most [`REPAIR_ITERATIONS`] rounds.

use geometry::vec3;
use geometry::Face;

use crate::core::face_quads::FaceQuads;

use super::validity::{fan_inverted, quad_angles, quad_valid, worst_movable_vertex, AngleWindow};

/// Rounds of the local repair loop (the authors' code uses 20).
pub const REPAIR_ITERATIONS: usize = 20;

/// The (u, v) Algorithm 1 gives for vertex `v` (`None` for a fixed vertex or
/// when all its links coincide with it).
pub fn weighted_average(fq: &FaceQuads, v: u32) -> Option<[f64; 2]> {
    let x = &fq.verts[v as usize];
    if x.fixed || !x.alive {
        return None;
    }
    let (mut u, mut w, mut gamma) = (0.0, 0.0, 0.0);
    for l in fq.links(v) {
        let y = &fq.verts[l as usize];
        let st = y.uv_toward(x.uv);
        let arc = vec3::dist(x.xyz, y.xyz);
        u += arc * st[0];
        w += arc * st[1];
        gamma += arc;
    }
    if !(gamma > 0.0) {
        return None;
    }
    Some([u / gamma, w / gamma])
}

/// Moves vertex `v` by Algorithm 1 (journaled). Returns whether it moved.
pub fn reposition(fq: &mut FaceQuads, face: &Face, v: u32) -> bool {
    match weighted_average(fq, v) {
        Some(uv) => fq.move_vertex(face, v, uv),
        None => false,
    }
}

/// Tries to make every quad around `region` valid for `w` by repositioning
/// movable vertices (journaled; the caller decides to keep or roll back).
/// Returns true when the quads around the region and around every moved
/// vertex are all valid.
pub fn repair(fq: &mut FaceQuads, face: &Face, region: &[u32], w: AngleWindow) -> bool {
    repair_rounds(fq, face, region, w, REPAIR_ITERATIONS)
}

/// [`repair`] with at most `rounds` rounds (each round also grows the region
/// by the links of the vertices it moved).
pub fn repair_rounds(
    fq: &mut FaceQuads,
    face: &Face,
    region: &[u32],
    w: AngleWindow,
    rounds: usize,
) -> bool {
    let mut verts: Vec<u32> = region
        .iter()
        .copied()
        .filter(|&v| fq.verts[v as usize].alive)
        .collect();
    for _ in 0..rounds {
        verts.sort_unstable();
        verts.dedup();
        let quads = fq.quads_around(&verts);
        let mut bad: Vec<(f64, u32)> = quads
            .into_iter()
            .filter(|&q| !quad_valid(fq, face, q, w))
            .map(|q| {
                let m = quad_angles(fq, face, q)
                    .map(|a| a.0.iter().fold(0.0f64, |s, &x| s.max(x)))
                    .unwrap_or(360.0);
                (m, q)
            })
            .collect();
        if bad.is_empty() {
            return true;
        }
        bad.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let mut moved_any = false;
        for (_, q) in bad {
            if !fq.quad_alive[q as usize] {
                continue;
            }
            let Some(v) = worst_movable_vertex(fq, face, q, w) else {
                continue;
            };
            moved_any |= reposition(fq, face, v);
            for l in fq.links(v) {
                if !fq.verts[l as usize].fixed && reposition(fq, face, l) {
                    moved_any = true;
                    verts.push(l);
                }
            }
            moved_any |= reposition(fq, face, v);
            verts.push(v);
        }
        if !moved_any {
            break;
        }
    }
    verts.sort_unstable();
    verts.dedup();
    fq.quads_around(&verts)
        .into_iter()
        .all(|q| quad_valid(fq, face, q, w))
}

/// Compass-search rounds of [`polish_invalid`] at most.
pub const POLISH_ROUNDS: usize = 60;
/// [`polish_invalid`] stops refining a vertex's step below this share of its
/// shortest link (in (u, v)).
const POLISH_MIN_STEP: f64 = 1e-4;

/// How far inside its bounds quad `q` is, in degrees: the smallest of
/// `angle − min` and `max − angle` at movable vertices and `max − angle` at
/// fixed ones (the bounds of [`super::validity::quad_valid`]); negative when
/// the quad is invalid for `w`. A folded quad (a reflex or crossed corner)
/// keeps the margin of its angles, which stays continuous as a vertex moves
/// (so a search can climb out of it), capped at −1; −360 without a normal.
pub fn quad_margin(fq: &FaceQuads, face: &Face, q: u32, w: AngleWindow) -> f64 {
    let Some((ang, signs)) = quad_angles(fq, face, q) else {
        return -360.0;
    };
    let vs = fq.quads[q as usize];
    let fixed_max = AngleWindow::BASE.max_deg.max(w.max_deg);
    let m = (0..4)
        .map(|i| {
            if fq.verts[vs[i] as usize].fixed {
                fixed_max - ang[i]
            } else {
                (ang[i] - w.min_deg).min(w.max_deg - ang[i])
            }
        })
        .fold(f64::INFINITY, f64::min);
    if signs {
        m
    } else {
        m.min(-1.0)
    }
}

/// The last resort for quads still invalid for `w` after the repair loop
/// (a thin wedge at a cusp, where Algorithm 1's averages pull a vertex
/// along the wedge and leave 176–180° angles): each movable vertex of those
/// quads and of their links takes compass steps in (u, v) that raise the
/// smallest [`quad_margin`] of its own quads, the step halving when no
/// direction helps. A vertex only moves when its quads' worst margin rises,
/// so no quad gets worse than the worst around it was. Returns the number of
/// quads of `fq` invalid for `w` afterwards (journaled moves).
pub fn polish_invalid(fq: &mut FaceQuads, face: &Face, w: AngleWindow) -> usize {
    let invalid = |fq: &FaceQuads| -> Vec<u32> {
        fq.live_quads()
            .filter(|&q| !quad_valid(fq, face, q, w))
            .collect()
    };
    let bad = invalid(fq);
    if bad.is_empty() {
        return 0;
    }
    let mut verts: Vec<u32> = bad
        .iter()
        .flat_map(|&q| fq.quads[q as usize])
        .flat_map(|v| std::iter::once(v).chain(fq.links(v)))
        .filter(|&v| !fq.verts[v as usize].fixed && fq.verts[v as usize].alive)
        .collect();
    verts.sort_unstable();
    verts.dedup();
    // each vertex's step starts at half its shortest link in (u, v)
    let mut step: Vec<f64> = verts
        .iter()
        .map(|&v| {
            let x = &fq.verts[v as usize];
            fq.links(v)
                .iter()
                .map(|&l| {
                    let uv = fq.verts[l as usize].uv_toward(x.uv);
                    ((uv[0] - x.uv[0]).powi(2) + (uv[1] - x.uv[1]).powi(2)).sqrt()
                })
                .filter(|d| *d > 0.0)
                .fold(f64::INFINITY, f64::min)
                * 0.5
        })
        .collect();
    let floor: Vec<f64> = step.iter().map(|s| s * 2.0 * POLISH_MIN_STEP).collect();
    let worst_at = |fq: &FaceQuads, v: u32| -> f64 {
        fq.verts[v as usize]
            .fan
            .iter()
            .map(|&q| quad_margin(fq, face, q, w))
            .fold(f64::INFINITY, f64::min)
    };
    for _ in 0..POLISH_ROUNDS {
        let mut moved = false;
        for (k, &v) in verts.iter().enumerate() {
            if !step[k].is_finite() || step[k] <= floor[k] {
                continue;
            }
            let here = fq.verts[v as usize].uv;
            let mut best = (worst_at(fq, v), here);
            let inverted = fan_inverted(fq, face, v);
            for (a, b) in crate::smoothing::kernels::COMPASS {
                let uv = [here[0] + step[k] * a, here[1] + step[k] * b];
                if !fq.move_vertex(face, v, uv) {
                    continue;
                }
                let m = worst_at(fq, v);
                // no step may invert a quad by either judge of the final check
                if m > best.0 + 1e-9 && fan_inverted(fq, face, v) > inverted {
                    continue;
                }
                if m > best.0 + 1e-9 {
                    best = (m, uv);
                }
            }
            fq.move_vertex(face, v, best.1);
            if best.1 == here {
                step[k] *= 0.5;
            } else {
                moved = true;
            }
        }
        let all_fine = step
            .iter()
            .zip(&floor)
            .all(|(s, f)| s.partial_cmp(f) != Some(std::cmp::Ordering::Greater));
        if !moved && all_fine {
            break;
        }
        if invalid(fq).is_empty() {
            break;
        }
    }
    invalid(fq).len()
}
