//! A structured-grid candidate for four-sided faces (beyond the paper).
//!
//! A face whose single boundary loop has exactly 4 corners (ideal valence 2),
//! every other boundary vertex straight (ideal 3), and opposite sides with the
//! same edge counts `n1` and `n2` has a fully regular quad mesh: the
//! `n1 × n2` grid joining the boundary nodes side to side. The greedy local
//! operations rarely reach it from the triangle split (the split's interior
//! is denser than its boundary, and every row ending inside the face leaves an
//! irregular vertex), so [`structured_grid`] builds it directly: the interior
//! (u, v) by transfinite (Coons) interpolation of the boundary's (u, v), by
//! node index; positions on the surface. [`super::regularize_face`] keeps it
//! only when every quad passes the base validity check and no more quads are
//! inverted against the CAD normals than in the input; Algorithm 2 then
//! redistributes it like any other result.
//!
//! The boundary vertices are the input's own (same local ids, untouched), so
//! the face stays watertight with its neighbours.

use std::collections::BTreeMap;

use geometry::{Face, FaceId};
use mesh::NodeClass;

use crate::face_quads::{FaceQuads, QVertex};

/// The boundary loop of `fq` as local vertex ids, following the directed
/// boundary edges (the quads on the left), starting at the smallest id.
/// `None` unless the boundary is one simple loop holding every fixed vertex.
pub fn single_boundary_loop(fq: &FaceQuads) -> Option<Vec<u32>> {
    let mut directed = std::collections::BTreeSet::new();
    for q in fq.live_quads() {
        let r = fq.quads[q as usize];
        for i in 0..4 {
            directed.insert((r[i], r[(i + 1) % 4]));
        }
    }
    let mut next = BTreeMap::new();
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) && next.insert(a, b).is_some() {
            return None; // the boundary touches itself at a
        }
    }
    let start = *next.keys().next()?;
    let mut lp = vec![start];
    let mut v = next[&start];
    while v != start {
        if lp.len() > next.len() {
            return None;
        }
        lp.push(v);
        v = *next.get(&v)?;
    }
    if lp.len() != next.len() {
        return None; // several loops
    }
    let fixed_alive = fq.verts.iter().filter(|x| x.alive && x.fixed).count();
    if fixed_alive != lp.len() {
        return None; // a fixed vertex off the loop (a pole, a hard point)
    }
    Some(lp)
}

/// The loop of a four-sided face rotated to start at a corner, with the side
/// edge counts `(n1, n2)` (sides 0 and 2 have `n1` edges, sides 1 and 3 have
/// `n2`). `None` unless the face has one boundary loop, exactly 4 vertices of
/// ideal valence 2, every other boundary vertex of ideal valence 3, no pole,
/// and opposite sides of equal edge counts.
pub fn four_sided_sides(fq: &FaceQuads) -> Option<(Vec<u32>, usize, usize)> {
    let lp = single_boundary_loop(fq)?;
    if lp.iter().any(|&v| {
        let x = &fq.verts[v as usize];
        x.pole.is_some() || x.edge_offset != 1 || !(x.ideal == 2 || x.ideal == 3)
    }) {
        return None;
    }
    let corners: Vec<usize> = (0..lp.len())
        .filter(|&i| fq.verts[lp[i] as usize].ideal == 2)
        .collect();
    if corners.len() != 4 {
        return None;
    }
    let n = lp.len();
    let side = |k: usize| (corners[(k + 1) % 4] + n - corners[k]) % n;
    let (n1, n2) = (side(0), side(1));
    if n1 == 0 || n2 == 0 || side(2) != n1 || side(3) != n2 {
        return None;
    }
    let mut rot = lp[corners[0]..].to_vec();
    rot.extend_from_slice(&lp[..corners[0]]);
    Some((rot, n1, n2))
}

/// The `n1 × n2` structured grid of a four-sided face ([`four_sided_sides`]),
/// as a new [`FaceQuads`] that keeps every input vertex slot (boundary
/// vertices unchanged, the old interior ones dead) and appends the new
/// interior vertices, classified on face `fid`. `None` when the face is not
/// four-sided with matching sides or a position cannot be evaluated. The
/// result is not checked for validity.
pub fn structured_grid(fq: &FaceQuads, face: &Face, fid: FaceId) -> Option<FaceQuads> {
    let (lp, n1, n2) = four_sided_sides(fq)?;
    // grid node (i, j), 0 ≤ i ≤ n1, 0 ≤ j ≤ n2, counter-clockwise loop:
    // bottom j = 0 from corner 0, right i = n1, top j = n2 backwards, left i = 0 backwards
    let at = |i: usize, j: usize| -> Option<u32> {
        if j == 0 {
            Some(lp[i])
        } else if i == n1 {
            Some(lp[n1 + j])
        } else if j == n2 {
            Some(lp[n1 + n2 + (n1 - i)])
        } else if i == 0 {
            Some(lp[(2 * n1 + n2 + (n2 - j)) % lp.len()])
        } else {
            None
        }
    };
    let uv = |v: u32| fq.verts[v as usize].uv;
    let mut verts: Vec<QVertex> = fq.verts.clone();
    for x in &mut verts {
        if !x.fixed {
            x.alive = false;
        }
    }
    let mut id = vec![u32::MAX; (n1 + 1) * (n2 + 1)];
    let idx = |i: usize, j: usize| j * (n1 + 1) + i;
    let (c00, c10, c11, c01) = (
        uv(at(0, 0)?),
        uv(at(n1, 0)?),
        uv(at(n1, n2)?),
        uv(at(0, n2)?),
    );
    for j in 0..=n2 {
        for i in 0..=n1 {
            if let Some(v) = at(i, j) {
                id[idx(i, j)] = v;
                continue;
            }
            let (s, t) = (i as f64 / n1 as f64, j as f64 / n2 as f64);
            let (b, r, tp, l) = (uv(at(i, 0)?), uv(at(n1, j)?), uv(at(i, n2)?), uv(at(0, j)?));
            let mut p = [0.0; 2];
            for k in 0..2 {
                p[k] = (1.0 - t) * b[k] + t * tp[k] + (1.0 - s) * l[k] + s * r[k]
                    - ((1.0 - s) * (1.0 - t) * c00[k]
                        + s * (1.0 - t) * c10[k]
                        + s * t * c11[k]
                        + (1.0 - s) * t * c01[k]);
            }
            let xyz = face.surface.eval(p);
            if !(p.iter().chain(xyz.iter()).all(|c| c.is_finite())) {
                return None;
            }
            id[idx(i, j)] = verts.len() as u32;
            verts.push(QVertex::interior(p, xyz, NodeClass::Face(fid, Some(p))));
        }
    }
    let mut quads = Vec::with_capacity(n1 * n2);
    for j in 0..n2 {
        for i in 0..n1 {
            quads.push([
                id[idx(i, j)],
                id[idx(i + 1, j)],
                id[idx(i + 1, j + 1)],
                id[idx(i, j + 1)],
            ]);
        }
    }
    FaceQuads::new(verts, quads)
}
