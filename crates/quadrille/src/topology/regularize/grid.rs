//! Structured patches of four- and three-sided faces (beyond the paper).
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
//! A three-sided face (3 corners, the rest straight, an even boundary, each
//! side shorter than the two others together) has a mesh with a single
//! irregular vertex, as few as its boundary allows: three grids, one per
//! corner, around a centre of valence 3 ([`three_sided_patch`]).
//!
//! An annulus (two loops, every boundary vertex straight, the same edge
//! count on both) has a fully regular ring grid ([`ring_grid`]); without it
//! the operations spent most of the regular method's time on such faces of
//! the industrial corpus (a flange's face around its bore, a washer's side)
//! and still left irregular vertices.
//!
//! The boundary vertices are the input's own (same local ids, untouched), so
//! the face stays watertight with its neighbours.

use std::collections::BTreeMap;

use geometry::{Face, FaceId};
use mesh::NodeClass;

use crate::core::face_quads::{FaceQuads, QVertex};

/// The boundary loops of `fq`'s live quads, each following the directed
/// boundary edges (the quads on the left) from its smallest vertex id, in
/// order of those ids; `None` when the boundary touches itself (a vertex
/// with two outgoing boundary edges) or a loop does not close.
pub fn boundary_loops(fq: &FaceQuads) -> Option<Vec<Vec<u32>>> {
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
    let mut loops = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for &start in next.keys() {
        if seen.contains(&start) {
            continue;
        }
        let mut lp = vec![start];
        seen.insert(start);
        let mut v = next[&start];
        while v != start {
            if lp.len() > next.len() || !seen.insert(v) {
                return None;
            }
            lp.push(v);
            v = *next.get(&v)?;
        }
        loops.push(lp);
    }
    Some(loops)
}

/// The boundary of `fq`'s live quads as one loop of local vertex ids,
/// following the directed boundary edges (the quads on the left), starting
/// at the smallest id; `None` when the boundary touches itself or is
/// several loops.
pub fn boundary_loop(fq: &FaceQuads) -> Option<Vec<u32>> {
    let mut loops = boundary_loops(fq)?;
    if loops.len() != 1 {
        return None;
    }
    loops.pop()
}

/// Edge counts of the 4 sides of a face whose boundary is one loop with 4
/// corners (ideal valence 2), from the corner after the smallest vertex id;
/// `None` otherwise.
pub fn four_side_counts(fq: &FaceQuads) -> Option<[usize; 4]> {
    let lp = boundary_loop(fq)?;
    let corners: Vec<usize> = (0..lp.len())
        .filter(|&i| fq.verts[lp[i] as usize].ideal == 2)
        .collect();
    if corners.len() != 4 {
        return None;
    }
    let side = |k: usize| (corners[(k + 1) % 4] + lp.len() - corners[k]) % lp.len();
    Some([side(0), side(1), side(2), side(3)])
}

/// [`boundary_loop`] when it holds every fixed vertex of `fq` (one simple
/// loop is the whole boundary).
pub fn single_boundary_loop(fq: &FaceQuads) -> Option<Vec<u32>> {
    let lp = boundary_loop(fq)?;
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
    let n = lp.len();
    // counter-clockwise loop: bottom from corner 0, right, top backwards, left backwards
    let bottom: Vec<u32> = (0..=n1).map(|i| lp[i]).collect();
    let right: Vec<u32> = (0..=n2).map(|j| lp[n1 + j]).collect();
    let top: Vec<u32> = (0..=n1).map(|i| lp[n1 + n2 + (n1 - i)]).collect();
    let left: Vec<u32> = (0..=n2).map(|j| lp[(2 * n1 + n2 + (n2 - j)) % n]).collect();
    let mut b = Builder::new(fq, face, fid);
    let quads = b.fill(&bottom, &right, &top, &left)?;
    FaceQuads::new(b.verts, quads)
}

/// The loop of a three-sided face rotated to start at a corner, with the side
/// edge counts `[n0, n1, n2]` (corners at positions 0, `n0`, `n0 + n1`).
/// `None` unless the face has one boundary loop holding every fixed vertex,
/// exactly 3 vertices of ideal valence 2 and every other one of
/// ideal valence 3, an even boundary, and each side shorter than the other
/// two together (so that [`three_sided_patch`] exists).
pub fn three_sided_sides(fq: &FaceQuads) -> Option<(Vec<u32>, [usize; 3])> {
    let lp = single_boundary_loop(fq)?;
    if lp.iter().any(|&v| {
        let x = &fq.verts[v as usize];
        x.edge_offset != 1 || !(x.ideal == 2 || x.ideal == 3)
    }) {
        return None;
    }
    let corners: Vec<usize> = (0..lp.len())
        .filter(|&i| fq.verts[lp[i] as usize].ideal == 2)
        .collect();
    if corners.len() != 3 {
        return None;
    }
    let n = lp.len();
    let side = |k: usize| (corners[(k + 1) % 3] + n - corners[k]) % n;
    let sides = [side(0), side(1), side(2)];
    let sum: usize = sides.iter().sum();
    if sum % 2 == 1 || sides.iter().any(|&s| 2 * s >= sum) {
        return None;
    }
    let mut rot = lp[corners[0]..].to_vec();
    rot.extend_from_slice(&lp[..corners[0]]);
    Some((rot, sides))
}

/// The patch of a three-sided face ([`three_sided_sides`]) made of three
/// structured grids, one per corner, meeting at a centre vertex of valence 3
/// (the only irregular vertex when the boundary valences are ideal). With
/// sides `n_k` and `P = (n0 + n1 + n2) / 2`, the spoke from side `k` to the
/// centre has `P − n_k` edges; side `k` is cut `P − n_(k−1)` edges after its
/// first corner. The spokes are straight in (u, v); the rest is filled by
/// transfinite interpolation (a pole, often a corner of such a face, at the
/// (u, v) it was given). Vertex slots as [`structured_grid`]. `None` when
/// the face is not three-sided as required or a position cannot be evaluated.
/// The result is not checked for validity.
pub fn three_sided_patch(fq: &FaceQuads, face: &Face, fid: FaceId) -> Option<FaceQuads> {
    let (lp, n) = three_sided_sides(fq)?;
    let half = (n[0] + n[1] + n[2]) / 2;
    let p = [half - n[0], half - n[1], half - n[2]];
    let start = [0, n[0], n[0] + n[1]];
    let len = lp.len();
    // the cut point of side k, x_k = p_(k−1) edges after its first corner
    let cut = |k: usize| start[k] + p[(k + 2) % 3];
    let mut b = Builder::new(fq, face, fid);
    let mids: Vec<[f64; 2]> = (0..3).map(|k| b.uv(lp[cut(k)])).collect();
    let centre_uv = [
        (mids[0][0] + mids[1][0] + mids[2][0]) / 3.0,
        (mids[0][1] + mids[1][1] + mids[2][1]) / 3.0,
    ];
    let centre = b.add(centre_uv)?;
    // spoke k: from the cut point of side k to the centre, p_k edges
    let mut spokes: Vec<Vec<u32>> = Vec::new();
    for k in 0..3 {
        let m = mids[k];
        let mut sp = vec![lp[cut(k)]];
        for t in 1..p[k] {
            let s = t as f64 / p[k] as f64;
            sp.push(b.add([
                m[0] + s * (centre_uv[0] - m[0]),
                m[1] + s * (centre_uv[1] - m[1]),
            ])?);
        }
        sp.push(centre);
        spokes.push(sp);
    }
    let mut quads = Vec::new();
    for k in 0..3 {
        let prev = (k + 2) % 3;
        let (n1, n2) = (p[prev], p[k]);
        // corner k → cut of side k, along the boundary
        let bottom: Vec<u32> = (0..=n1).map(|i| lp[(start[k] + i) % len]).collect();
        let right = spokes[k].clone();
        let top = spokes[prev].clone();
        // corner k ← cut of side k − 1, backwards along the boundary
        let left: Vec<u32> = (0..=n2).map(|j| lp[(start[k] + len - j) % len]).collect();
        quads.extend(b.fill(&bottom, &right, &top, &left)?);
    }
    FaceQuads::new(b.verts, quads)
}

/// The two boundary loops of an annulus whose every boundary vertex is
/// straight (ideal valence 3, an open fan, no pole), with the same edge
/// count `n ≥ 3` on both and every fixed vertex on them; `None` otherwise.
pub fn ring_sides(fq: &FaceQuads) -> Option<[Vec<u32>; 2]> {
    let mut loops = boundary_loops(fq)?;
    if loops.len() != 2 || loops[0].len() != loops[1].len() || loops[0].len() < 3 {
        return None;
    }
    let fixed_alive = fq.verts.iter().filter(|x| x.alive && x.fixed).count();
    if fixed_alive != 2 * loops[0].len() {
        return None; // a fixed vertex off the loops (a pole, a hard point)
    }
    if loops.iter().flatten().any(|&v| {
        let x = &fq.verts[v as usize];
        x.pole.is_some() || x.edge_offset != 1 || x.ideal != 3
    }) {
        return None;
    }
    let b = loops.pop()?;
    let a = loops.pop()?;
    Some([a, b])
}

/// The ring grid of an annulus ([`ring_sides`]): `n` sectors joining the
/// loops' vertices one to one, `m` rows between them, every vertex regular
/// (ours, as `direct::ring_face` meshes such a face from its curves). Loop
/// `b` is walked forward and loop `a` backward (both run with the quads on
/// their left), from the offset that puts matched vertices nearest in
/// (u, v); the rows' geometric spacing is `direct::ring_face::row_fraction`,
/// `m` is `direct::ring_face::ring_rows` (square cells on a circular annulus)
/// but at least the input's quads over `n`; interior (u, v) on the straight (u, v) segment between matched
/// vertices. Vertex slots as [`structured_grid`]. `None` when the face is
/// not such an annulus or a position cannot be evaluated. The result is not
/// checked for validity.
pub fn ring_grid(fq: &FaceQuads, face: &Face, fid: FaceId) -> Option<FaceQuads> {
    use crate::direct::ring_face::{ring_rows, row_fraction};
    let [a, b] = ring_sides(fq)?;
    let n = a.len();
    let x = |v: u32| &fq.verts[v as usize];
    // loop a's vertex matched with b[k] at offset r
    let at = |r: usize, k: usize| a[(r + n - k % n) % n];
    let dist2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let cost = |r: usize| -> f64 {
        (0..n)
            .map(|k| dist2(x(b[k]).uv, x(at(r, k)).uv_toward(x(b[k]).uv)))
            .sum()
    };
    let rotation = (0..n)
        .map(|r| (r, cost(r)))
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .map_or(0, |(r, _)| r);
    let closed = |lp: &[u32]| -> f64 {
        (0..lp.len())
            .map(|k| geometry::vec3::dist(x(lp[k]).xyz, x(lp[(k + 1) % lp.len()]).xyz))
            .sum()
    };
    let (len_a, len_b) = (closed(&a), closed(&b));
    let width = (0..n)
        .map(|k| geometry::vec3::dist(x(b[k]).xyz, x(at(rotation, k)).xyz))
        .sum::<f64>()
        / n as f64;
    if !(len_a > 0.0 && len_b > 0.0 && width > 0.0) {
        return None;
    }
    // square cells, but never fewer rows than the input's quads fill (a
    // coarser ring lowers no irregular count, only the interior vertices)
    let m = ring_rows(n, len_a, len_b, width).max((fq.num_quads() + n / 2) / n);
    let ratio = len_b / len_a;
    let mut bld = Builder::new(fq, face, fid);
    // row j (0: loop a, m: loop b), sector k
    let mut id = vec![u32::MAX; (m + 1) * n];
    for k in 0..n {
        let (pa, pb) = (at(rotation, k), b[k]);
        let (ua, ub) = (x(pa).uv_toward(x(pb).uv), x(pb).uv);
        id[k] = pa;
        id[m * n + k] = pb;
        for j in 1..m {
            let t = row_fraction(j, m, ratio);
            id[j * n + k] = bld.add([ua[0] + t * (ub[0] - ua[0]), ua[1] + t * (ub[1] - ua[1])])?;
        }
    }
    let quads = (0..m)
        .flat_map(|j| {
            let id = &id;
            (0..n).map(move |k| {
                let k1 = (k + 1) % n;
                [
                    id[(j + 1) * n + k],
                    id[(j + 1) * n + k1],
                    id[j * n + k1],
                    id[j * n + k],
                ]
            })
        })
        .collect();
    FaceQuads::new(bld.verts, quads)
}

/// Builds the vertices of a new patch of a face: the input's slots (fixed
/// ones kept, movable ones dead), then new movable vertices.
struct Builder<'a> {
    face: &'a Face,
    fid: FaceId,
    verts: Vec<QVertex>,
}

impl<'a> Builder<'a> {
    fn new(fq: &FaceQuads, face: &'a Face, fid: FaceId) -> Self {
        let mut verts = fq.verts.clone();
        for x in &mut verts {
            if !x.fixed {
                x.alive = false;
            }
        }
        Builder { face, fid, verts }
    }

    fn uv(&self, v: u32) -> [f64; 2] {
        self.verts[v as usize].uv
    }

    /// A new movable vertex at `uv` (`None` when S(uv) is not finite).
    fn add(&mut self, uv: [f64; 2]) -> Option<u32> {
        let xyz = self.face.surface.eval(uv);
        if !(uv.iter().chain(xyz.iter()).all(|c| c.is_finite())) {
            return None;
        }
        self.verts.push(QVertex::interior(
            uv,
            xyz,
            NodeClass::Face(self.fid, Some(uv)),
        ));
        Some(self.verts.len() as u32 - 1)
    }

    /// The quads of the grid whose sides are the given vertex rows (each
    /// from its lower-index corner: `bottom` and `top` by i, `left` and
    /// `right` by j; corners shared), counter-clockwise when bottom → right
    /// → top (backwards) → left (backwards) is; interior vertices added by
    /// transfinite interpolation of the sides' (u, v), by node index.
    fn fill(
        &mut self,
        bottom: &[u32],
        right: &[u32],
        top: &[u32],
        left: &[u32],
    ) -> Option<Vec<[u32; 4]>> {
        let (n1, n2) = (bottom.len().checked_sub(1)?, left.len().checked_sub(1)?);
        if n1 == 0 || n2 == 0 || top.len() != n1 + 1 || right.len() != n2 + 1 {
            return None;
        }
        if bottom[n1] != right[0]
            || top[n1] != right[n2]
            || left[0] != bottom[0]
            || left[n2] != top[0]
        {
            return None;
        }
        let (c00, c10, c11, c01) = (
            self.uv(bottom[0]),
            self.uv(bottom[n1]),
            self.uv(top[n1]),
            self.uv(top[0]),
        );
        let idx = |i: usize, j: usize| j * (n1 + 1) + i;
        let mut id = vec![u32::MAX; (n1 + 1) * (n2 + 1)];
        for j in 0..=n2 {
            for i in 0..=n1 {
                let on_side = if j == 0 {
                    Some(bottom[i])
                } else if j == n2 {
                    Some(top[i])
                } else if i == 0 {
                    Some(left[j])
                } else if i == n1 {
                    Some(right[j])
                } else {
                    None
                };
                if let Some(v) = on_side {
                    id[idx(i, j)] = v;
                    continue;
                }
                let (s, t) = (i as f64 / n1 as f64, j as f64 / n2 as f64);
                let (b, r, tp, l) = (
                    self.uv(bottom[i]),
                    self.uv(right[j]),
                    self.uv(top[i]),
                    self.uv(left[j]),
                );
                let mut p = [0.0; 2];
                for k in 0..2 {
                    p[k] = (1.0 - t) * b[k] + t * tp[k] + (1.0 - s) * l[k] + s * r[k]
                        - ((1.0 - s) * (1.0 - t) * c00[k]
                            + s * (1.0 - t) * c10[k]
                            + s * t * c11[k]
                            + (1.0 - s) * t * c01[k]);
                }
                id[idx(i, j)] = self.add(p)?;
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
        Some(quads)
    }
}
