//! The three basic topological operations of the regular method (paper §II.A)
//! on a [`FaceQuads`], with exact valence bookkeeping:
//!
//! - **swap** (Eq. 1): the shared edge `(h0, h3)` of two quads becomes
//!   `(h_k, h_{k+3})` of their hexagon; `h0, h3` lose one edge, `h_k, h_{k+3}` gain one;
//! - **collapse** (Eq. 2): quad `(v1, v2, v3, v4)` disappears by merging `v1`
//!   and `v3`; `val(v13) = val(v1) + val(v3) − 2`, `v2, v4` lose one edge;
//! - **split** (inverse of collapse): a movable vertex `c` of valence `k` and two
//!   of its links `n_p, n_q` at a distance of `d` sectors give `c'` with `d + 1`
//!   edges, `c` with `k − d + 1`, and `n_p, n_q` one more each.
//!
//! [`effect`] checks an operation's preconditions and predicts its valence
//! changes without touching the mesh; [`apply`] performs it (journaled, so the
//! caller can roll it back) and places new or merged vertices in (u, v).
//! Fixed (boundary) vertices are never moved or removed; edges between two
//! boundary-side quads are never swapped because they have a single quad.

use geometry::Face;

use crate::core::face_quads::{FaceQuads, QVertex};

/// One basic operation, named by stable ids.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Op {
    /// Swap the edge `quads[q][e] → quads[q][e+1]` to the hexagon diagonal `k` (1 or 2).
    Swap {
        /// One of the two quads.
        q: u32,
        /// Edge index in that quad (0..4).
        e: u8,
        /// Which new diagonal (1 or 2).
        k: u8,
    },
    /// Collapse quad `q` by merging its vertices `d` and `d + 2` (d = 0 or 1).
    Collapse {
        /// The quad removed.
        q: u32,
        /// Which diagonal is merged.
        d: u8,
    },
    /// Split vertex `c` through its links `a` and `b`; the new vertex takes the
    /// sectors from `a` counter-clockwise to `b`.
    Split {
        /// The vertex split (movable).
        c: u32,
        /// First link.
        a: u32,
        /// Second link.
        b: u32,
    },
}

/// Predicted valence changes of an operation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Effect {
    /// `(vertex, valence before, valence after)` for every existing vertex whose valence changes.
    pub changes: Vec<(u32, u32, u32)>,
    /// A vertex that disappears (collapse), with its valence before.
    pub removed: Option<(u32, u32)>,
    /// Valence of the vertex created (split).
    pub created: Option<u32>,
    /// The vertices around which geometry must be checked afterwards.
    pub region: Vec<u32>,
}

/// Smallest number of quads a vertex may keep (spec §5.1, `validSwap`):
/// - inside, 3 (valence ≥ 3: no doublets);
/// - on a curve (or a seam), 2 quads (≥ 3 edges): with 2 edges the vertex would
///   be the 180° corner of a single quad;
/// - at a CAD corner, or wherever the boundary angle asks for 2 edges, 1 quad (2 edges);
/// - at a pole with a closed fan (sphere pole, cone apex), 3 quads, as inside;
/// - at other fixed vertices (odd fans), 1 quad.
pub fn min_fan(v: &QVertex) -> usize {
    if !v.fixed {
        return 3;
    }
    if v.pole.is_some() && v.edge_offset == 0 {
        // a pole with a closed fan is a point of the surface: no doublets
        return 3;
    }
    let corner = matches!(v.class, mesh::NodeClass::Corner(_)) || v.ideal <= 2;
    if v.edge_offset == 1 && !corner && v.pole.is_none() {
        2
    } else {
        1
    }
}

/// The hexagon `(h0..h5)` of the quad pair sharing edge `e` of quad `q`, with
/// the other quad: quad `q` is `(h0, h1, h2, h3)`, the other `(h3, h4, h5, h0)`.
pub fn hexagon(fq: &FaceQuads, q: u32, e: u8) -> Option<([u32; 6], u32)> {
    if !*fq.quad_alive.get(q as usize)? || e > 3 {
        return None;
    }
    let r = fq.quads[q as usize];
    let i = e as usize;
    let (a, b) = (r[i], r[(i + 1) % 4]);
    let p = fq.across(q, a, b)?;
    // q has a → b, so h3 = a and h0 = b
    let h0 = b;
    let h1 = r[(i + 2) % 4];
    let h2 = r[(i + 3) % 4];
    let h3 = a;
    let s = fq.rotated(p, h3)?;
    if s[3] != h0 {
        return None;
    }
    let h = [h0, h1, h2, h3, s[1], s[2]];
    for x in 0..6 {
        if (0..x).any(|y| h[y] == h[x]) {
            return None;
        }
    }
    Some((h, p))
}

/// Checks the preconditions of `op` and predicts its valence changes, without
/// changing the mesh. `None` when the operation is not allowed here.
pub fn effect(fq: &FaceQuads, op: Op) -> Option<Effect> {
    effect_impl(fq, op, true)
}

/// [`effect`] without [`Effect::region`] (left empty): the valence bookkeeping
/// alone, cheaper, for scoring candidates during searches.
pub fn effect_valences(fq: &FaceQuads, op: Op) -> Option<Effect> {
    effect_impl(fq, op, false)
}

fn effect_impl(fq: &FaceQuads, op: Op, with_region: bool) -> Option<Effect> {
    let val = |v: u32| fq.valence(v);
    match op {
        Op::Swap { q, e, k } => {
            if k != 1 && k != 2 {
                return None;
            }
            let (h, _) = hexagon(fq, q, e)?;
            for &v in &[h[0], h[3]] {
                let x = &fq.verts[v as usize];
                if x.fan.len() <= min_fan(x) {
                    return None;
                }
            }
            let (n1, n2) = (h[k as usize], h[k as usize + 3]);
            if fq.linked(n1, n2) {
                return None;
            }
            Some(Effect {
                changes: vec![
                    (h[0], val(h[0]), val(h[0]) - 1),
                    (h[3], val(h[3]), val(h[3]) - 1),
                    (n1, val(n1), val(n1) + 1),
                    (n2, val(n2), val(n2) + 1),
                ],
                removed: None,
                created: None,
                region: if with_region { h.to_vec() } else { Vec::new() },
            })
        }
        Op::Collapse { q, d } => {
            if !*fq.quad_alive.get(q as usize)? || d > 1 {
                return None;
            }
            let r = fq.quads[q as usize];
            let i = d as usize;
            let (v1, v2, v3, v4) = (r[i], r[i + 1], r[(i + 2) % 4], r[(i + 3) % 4]);
            let (f1, f3) = (fq.verts[v1 as usize].fixed, fq.verts[v3 as usize].fixed);
            if f1 && f3 {
                return None;
            }
            for &v in &[v2, v4] {
                let x = &fq.verts[v as usize];
                if x.fan.len() <= min_fan(x) {
                    return None;
                }
            }
            // link condition: v1 and v3 share exactly the neighbours v2 and v4,
            // and no other quad holds both
            if fq.linked(v1, v3) {
                return None;
            }
            let l1 = fq.links(v1);
            let l3 = fq.links(v3);
            let common = l3.iter().filter(|x| l1.binary_search(x).is_ok()).count();
            if common != 2 {
                return None;
            }
            if fq.verts[v1 as usize]
                .fan
                .iter()
                .any(|&p| p != q && fq.quads[p as usize].contains(&v3))
            {
                return None;
            }
            let (keep, gone) = if f1 { (v1, v3) } else { (v3, v1) };
            let merged = (val(v1) + val(v3)).checked_sub(2)?;
            let mut region = Vec::new();
            if with_region {
                region = l1;
                region.extend(l3);
                region.push(keep);
                region.sort_unstable();
                region.dedup();
                region.retain(|&x| x != gone);
            }
            Some(Effect {
                changes: vec![
                    (v2, val(v2), val(v2) - 1),
                    (v4, val(v4), val(v4) - 1),
                    (keep, val(keep), merged),
                ],
                removed: Some((gone, val(gone))),
                created: None,
                region,
            })
        }
        Op::Split { c, a, b } => {
            let x = fq.verts.get(c as usize)?;
            if x.fixed || !x.alive || a == b {
                return None;
            }
            let star = fq.ordered_star(c)?;
            let k = star.len();
            let ia = star.iter().position(|s| s.1[1] == a)?;
            let ib = star.iter().position(|s| s.1[1] == b)?;
            let dist = (ib + k - ia) % k;
            if dist < 2 || dist + 2 > k {
                return None;
            }
            let mut region: Vec<u32> = Vec::new();
            if with_region {
                region = star.iter().flat_map(|s| [s.1[1], s.1[2]]).collect();
                region.push(c);
                region.sort_unstable();
                region.dedup();
            }
            Some(Effect {
                changes: vec![
                    (c, val(c), (k - dist + 1) as u32),
                    (a, val(a), val(a) + 1),
                    (b, val(b), val(b) + 1),
                ],
                removed: None,
                created: Some(dist as u32 + 1),
                region,
            })
        }
    }
}

/// Performs `op` (journaled: roll back with [`FaceQuads::rollback`]) and places
/// the vertices it creates or merges in (u, v). Returns the vertices whose
/// neighbourhood must be checked and repaired (the operation's region, plus the
/// vertex created by a split), or `None` (mesh unchanged) when the
/// preconditions fail.
pub fn apply(fq: &mut FaceQuads, face: &Face, op: Op) -> Option<Vec<u32>> {
    apply_impl(fq, Some(face), op)
}

/// [`apply`] without placing vertices (topology only, no surface evaluation):
/// for searching sequences of operations that are rolled back afterwards.
pub fn apply_topology(fq: &mut FaceQuads, op: Op) -> Option<Vec<u32>> {
    apply_impl(fq, None, op)
}

fn apply_impl(fq: &mut FaceQuads, face: Option<&Face>, op: Op) -> Option<Vec<u32>> {
    let eff = effect(fq, op)?;
    let mut region = eff.region.clone();
    match op {
        Op::Swap { q, e, k } => {
            let (h, p) = hexagon(fq, q, e)?;
            let (a, b) = if k == 1 {
                ([h[1], h[2], h[3], h[4]], [h[4], h[5], h[0], h[1]])
            } else {
                ([h[2], h[3], h[4], h[5]], [h[5], h[0], h[1], h[2]])
            };
            fq.set_quad(q, a);
            fq.set_quad(p, b);
        }
        Op::Collapse { q, d } => {
            let r = fq.quads[q as usize];
            let i = d as usize;
            let (v1, v3) = (r[i], r[(i + 2) % 4]);
            let (keep, gone) = if fq.verts[v1 as usize].fixed {
                (v1, v3)
            } else {
                (v3, v1)
            };
            let uv = fq.quad_uv_centre(q);
            fq.kill_quad(q);
            let fan = fq.verts[gone as usize].fan.clone();
            for p in fan {
                let s = fq.quads[p as usize].map(|x| if x == gone { keep } else { x });
                fq.set_quad(p, s);
            }
            fq.kill_vertex(gone);
            if let Some(face) = face {
                fq.move_vertex(face, keep, uv);
            }
        }
        Op::Split { c, a, b } => {
            let star = fq.ordered_star(c)?;
            let k = star.len();
            let ia = star.iter().position(|s| s.1[1] == a)?;
            let x = fq.verts[c as usize].clone();
            let c2 = fq.add_vertex(QVertex {
                global: None,
                ..QVertex::interior(x.uv, x.xyz, x.class)
            });
            let dist = eff.created? as usize - 1;
            for j in 0..dist {
                let (sq, _) = star[(ia + j) % k];
                let s = fq.quads[sq as usize].map(|y| if y == c { c2 } else { y });
                fq.set_quad(sq, s);
            }
            let newq = fq.add_quad([c, a, c2, b]);
            region.push(c2);
            let Some(face) = face else {
                return Some(region);
            };
            // each of c, c' to the mean of its quads' centres (the new quad excluded)
            for v in [c, c2] {
                let fan: Vec<u32> = fq.verts[v as usize]
                    .fan
                    .iter()
                    .copied()
                    .filter(|&p| p != newq)
                    .collect();
                if fan.is_empty() {
                    continue;
                }
                let mut s = [0.0, 0.0];
                for &p in &fan {
                    let m = fq.quad_uv_centre(p);
                    s[0] += m[0];
                    s[1] += m[1];
                }
                let n = fan.len() as f64;
                fq.move_vertex(face, v, [s[0] / n, s[1] / n]);
            }
        }
    }
    Some(region)
}

/// Irregularity score of one vertex: (irregular?, |valence − ideal|).
pub fn vertex_score(valence: u32, ideal: u32) -> (i64, i64) {
    let d = (valence as i64 - ideal as i64).abs();
    ((d != 0) as i64, d)
}

/// Change of the total score `(N_irr, Σ|val − ideal|)` that `eff` would cause.
pub fn score_delta(fq: &FaceQuads, eff: &Effect) -> (i64, i64) {
    let mut d = (0i64, 0i64);
    let mut add = |s: (i64, i64), sign: i64| {
        d.0 += sign * s.0;
        d.1 += sign * s.1;
    };
    for &(v, before, after) in &eff.changes {
        let ideal = fq.verts[v as usize].ideal;
        add(vertex_score(before, ideal), -1);
        add(vertex_score(after, ideal), 1);
    }
    if let Some((v, before)) = eff.removed {
        add(vertex_score(before, fq.verts[v as usize].ideal), -1);
    }
    if let Some(after) = eff.created {
        add(vertex_score(after, 4), 1);
    }
    d
}

/// Every operation whose valence changes involve quad `q`'s neighbourhood: the
/// swaps of its 4 edges, its 2 collapses, and the splits of its movable
/// vertices of valence ≥ 5 through any two links at distance 2..k−2. In a fixed order.
pub fn candidates_at(fq: &FaceQuads, q: u32) -> Vec<Op> {
    let mut out = Vec::new();
    if !fq.quad_alive[q as usize] {
        return out;
    }
    for d in 0..2u8 {
        out.push(Op::Collapse { q, d });
    }
    for e in 0..4u8 {
        for k in 1..=2u8 {
            out.push(Op::Swap { q, e, k });
        }
    }
    for &c in &fq.quads[q as usize] {
        let x = &fq.verts[c as usize];
        if x.fixed || fq.valence(c) < 5 {
            continue;
        }
        if let Some(star) = fq.ordered_star(c) {
            let k = star.len();
            for i in 0..k {
                for dist in 2..=k - 2 {
                    let j = (i + dist) % k;
                    // (a, b) at distance d and (b, a) at k − d are mirror images: keep one
                    if dist * 2 < k || (dist * 2 == k && i < j) {
                        out.push(Op::Split {
                            c,
                            a: star[i].1[1],
                            b: star[j].1[1],
                        });
                    }
                }
            }
        }
    }
    out
}
