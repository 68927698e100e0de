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

use crate::face_quads::FaceQuads;

use super::validity::{quad_angles, quad_valid, worst_movable_vertex, AngleWindow};

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
