//! The regular method's operations as the last topological pass of the
//! quasi-structured method.
//!
//! Cavity remeshing (paper §6.2) only removes an irregular vertex when a
//! convex cavity around it can be remeshed by a pattern; it leaves pairs of
//! opposite index that are a few quads apart, and concave corners with a
//! quad too many (n12o_limit_cycle_genus0's 270° corner with 4 quads and a
//! valence-3 vertex beside it). The swaps, collapses, splits and pair search
//! of [`crate::topology::regularize`] (Docampo-Sánchez & Haimes) reach those: they move
//! irregular vertices one quad at a time and cancel pairs.
//!
//! This pass converts a face's patch, after the cavities and before the
//! last average ascent, to [`FaceQuads`]; runs the regular method's
//! operation loop on it (one visiting order, single operations, the pair
//! search and translations with small budgets, no quad count target and no
//! redistribution: the quasi-structured mesh's spacing is already right); converts it back and smooths it with the §5.3
//! kernels. The result is kept only when it has fewer irregular
//! face-interior vertices, no more irregular boundary vertices, a worst SICN
//! at or above the method's bar (or the input's, if lower) and an average
//! SICN at most [`RegularPassOptions::average_loss`] below the input's.
//! Otherwise the patch is left exactly as it was. A face still above 5 %
//! irregular after a kept result gets a second round from it, with a
//! larger pair search budget.
//!
//! Boundary vertices (curve nodes with other than two quads) count in the
//! operations' score, so a valence-3 vertex can cancel against a curve node
//! with an extra edge; those farther than
//! [`RegularPassOptions::boundary_reach`] links from every irregular
//! interior vertex count as regular, so the search spends no time on them
//! (on i01o_m1 all of them counted took 0.126 s, against 0.10 s).
//!
//! Measured on the 26 CAD models: see BENCHMARKS.md, "The regular method's
//! operations after the cavities".

pub use crate::core::quality::patch_quality;
use geometry::{CornerId, Face, FaceId};
use mesh::NodeClass;

use crate::core::face_quads::{FaceQuads, QVertex};
use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::smoothing::{lift_poor_quads, optimize, OptimizeOptions, POOR_SICN};
use crate::topology::regularize::reposition::polish_invalid;
use crate::topology::regularize::{
    classify_pole_corners, straighten_ambiguous_ideals, topological_phase, RegularizeOptions,
};

/// Options of [`reduce_irregular`].
#[derive(Clone, Debug, PartialEq)]
pub struct RegularPassOptions {
    /// The attempts, each the operation loop run on the face's input in
    /// one visiting order; the best that passes the checks is kept.
    pub attempts: Vec<Attempt>,
    /// Pair search radius in links ([`RegularizeOptions::pair_radius`]).
    pub pair_radius: usize,
    /// Depth of the pair search: operations in one cancelling sequence (the
    /// regular method: 4). n12o_limit_cycle_genus0's 270° corner with a quad
    /// too many cancels with the valence-3 vertex two links away in 6.
    pub pair_depth: usize,
    /// Expansions of the pair search per irregular vertex (the regular method: 600).
    pub pair_budget: usize,
    /// Branches kept at each level of the pair search (the regular method: 5).
    pub pair_beam: usize,
    /// Sequences examined per vertex by the operation search (the regular method: 600).
    pub search_budget: usize,
    /// A face whose kept result still has more than this share of its
    /// interior vertices irregular gets a second round from that result,
    /// with [`RegularPassOptions::dense_pair_budget`].
    pub dense_above: f64,
    /// Pair search budget of the second round (i04o_m4: 72 → 65 irregular
    /// vertices for 0.08 s more; on every face, budget 100 cost twice the
    /// time of budget 30 for 652 instead of 674 vertices on the 25 models).
    pub dense_pair_budget: usize,
    /// Irregular boundary vertices farther than this many links from every
    /// irregular interior vertex count as regular.
    pub boundary_reach: usize,
    /// How far the face's average SICN may fall for a result to be kept.
    pub average_loss: f64,
    /// Faces with more quads than this are left as they are: the search's
    /// time grows faster than the face (wing_surface's 21 846-quad face,
    /// 21 % of its vertices irregular, took 340 s).
    pub max_quads: usize,
}

impl Default for RegularPassOptions {
    fn default() -> Self {
        RegularPassOptions {
            attempts: vec![Attempt {
                order: 0,
                max_sequence: 1,
            }],
            pair_radius: 2,
            pair_depth: 6,
            pair_budget: 30,
            pair_beam: 3,
            search_budget: 100,
            dense_above: 0.05,
            dense_pair_budget: 100,
            boundary_reach: 3,
            average_loss: 0.05,
            max_quads: 5000,
        }
    }
}

/// One attempt of the pass: a visiting order and a search depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Attempt {
    /// Visiting order ([`crate::topology::regularize::driver::visiting_order`]).
    pub order: u32,
    /// Longest sequence of operations tried at a vertex by the operation
    /// search (the pair search has its own depth). On the 25 CAD models
    /// (wing out), with the pair search at depth 4, 1 removed as many
    /// irregular vertices as 3 in 60 % of the time.
    pub max_sequence: usize,
}

/// What [`reduce_irregular`] did on one face.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RegularPassReport {
    /// False when the face had no irregular interior vertex, was too large
    /// or could not be converted.
    pub tried: bool,
    /// True when a result replaced the input.
    pub kept: bool,
    /// Irregular face-interior vertices before and after (after = before when not kept).
    pub irregular: (usize, usize),
    /// Irregular boundary vertices (corners and curve nodes off their ideal
    /// valence) before and after.
    pub boundary: (usize, usize),
    /// Worst and average SICN of the input.
    pub before: (f64, f64),
    /// Worst and average SICN of the kept result (zero when none was kept).
    pub after: (f64, f64),
}

/// The [`FaceQuads`] of patch `p` of face `fid`: boundary nodes (corners,
/// curve nodes, poles) fixed, each vertex's `global` its node index in `p`.
/// `None` when the patch is not a manifold set of quads.
pub fn to_face_quads(fid: FaceId, p: &QuadPatch) -> Option<FaceQuads> {
    let verts: Vec<QVertex> = p
        .nodes
        .iter()
        .zip(&p.pos)
        .enumerate()
        .map(|(i, (n, &xyz))| {
            let fixed = n.node != NodeRef::Interior;
            let class = match n.node {
                NodeRef::Corner(c) => NodeClass::Corner(c),
                NodeRef::Curve(c, _) => NodeClass::Curve(c, None),
                NodeRef::Interior => NodeClass::Face(fid, Some(n.uv)),
            };
            QVertex {
                fixed,
                global: Some(i as u32),
                pole: n.pole,
                edge_offset: u32::from(fixed),
                ..QVertex::interior(n.uv, xyz, class)
            }
        })
        .collect();
    let mut fq = FaceQuads::new(verts, p.quads.clone())?;
    fq.classify_fixed();
    fq.check().ok()?;
    Some(fq)
}

/// The patch of `fq`'s live quads; fixed vertices that came from
/// `original` (their `global`) keep its node (identity, pole segment), the
/// others are face-interior nodes at their (u, v).
pub fn to_patch(fq: &FaceQuads, original: &QuadPatch) -> QuadPatch {
    let mut index = vec![u32::MAX; fq.verts.len()];
    let mut nodes: Vec<LocalNode> = Vec::new();
    let mut pos = Vec::new();
    for (i, v) in fq.verts.iter().enumerate() {
        if !v.alive || v.fan.is_empty() {
            continue;
        }
        index[i] = nodes.len() as u32;
        let node = match v.global {
            Some(g) if v.fixed => original.nodes[g as usize],
            _ => LocalNode {
                uv: v.uv,
                node: NodeRef::Interior,
                pole: None,
            },
        };
        nodes.push(LocalNode { uv: v.uv, ..node });
        pos.push(v.xyz);
    }
    let quads: Vec<[u32; 4]> = fq
        .live_quads()
        .map(|q| fq.quads[q as usize].map(|v| index[v as usize]))
        .collect();
    QuadPatch {
        quad_tri: (0..quads.len() as u32).collect(),
        nodes,
        pos,
        quads,
    }
}

/// Makes every irregular boundary vertex of `fq` farther than `reach`
/// links from all irregular interior vertices count as regular (its ideal
/// becomes its valence).
fn ignore_far_boundary(fq: &mut FaceQuads, reach: usize) {
    let n = fq.verts.len();
    let mut near = vec![false; n];
    let mut front: Vec<u32> = (0..n as u32)
        .filter(|&v| !fq.verts[v as usize].fixed && fq.is_irregular(v))
        .collect();
    for &v in &front {
        near[v as usize] = true;
    }
    for _ in 0..reach {
        let mut next = Vec::new();
        for &a in &front {
            for l in fq.links(a) {
                if !near[l as usize] {
                    near[l as usize] = true;
                    next.push(l);
                }
            }
        }
        front = next;
    }
    for (v, &is_near) in near.iter().enumerate() {
        if fq.verts[v].alive && fq.verts[v].fixed && !is_near {
            fq.verts[v].ideal = fq.valence(v as u32);
        }
    }
}

/// The operations of one [`Attempt`] on a copy of `fq0`, turned back into
/// a patch and smoothed, with its irregular boundary vertex count; `None`
/// when quads are left outside the operations' angle window.
fn attempt(
    face: &Face,
    fq0: &FaceQuads,
    original: &QuadPatch,
    sharp: &[CornerId],
    opts: &RegularPassOptions,
    a: Attempt,
) -> Option<(QuadPatch, usize)> {
    let ropts = RegularizeOptions {
        max_sequence: a.max_sequence,
        search_budget: opts.search_budget,
        pair_radius: opts.pair_radius,
        pair_depth: opts.pair_depth,
        pair_budget: opts.pair_budget,
        pair_beam: opts.pair_beam,
        ..Default::default()
    };
    let mut fq = fq0.clone();
    let (_, _, invalid, _) = topological_phase(face, &mut fq, &ropts, a.order, 0, 0);
    if invalid > 0 && polish_invalid(&mut fq, face, ropts.window) > 0 {
        return None;
    }
    let mut cand = to_patch(&fq, original);
    let boundary = fq
        .irregular_count()
        .saturating_sub(cand.interior_irregular());
    optimize(face, &mut cand, &OptimizeOptions::default());
    lift_poor_quads(face, &mut cand, POOR_SICN, sharp);
    Some((cand, boundary))
}

/// Runs the pass on face `fid`'s patch `p` (see the module documentation);
/// `sharp` are the face's sharp CAD corners (for the untangling weights).
/// `p` is changed only when a result is kept: of the attempts that pass the
/// checks, the one with the fewest irregular face-interior vertices, then
/// the highest average SICN. A face left dense with irregular vertices
/// after a kept result gets a second round from it
/// ([`RegularPassOptions::dense_above`]).
pub fn reduce_irregular(
    face: &Face,
    fid: FaceId,
    p: &mut QuadPatch,
    sharp: &[CornerId],
    opts: &RegularPassOptions,
) -> RegularPassReport {
    let mut rep = one_round(face, fid, p, sharp, opts);
    let interior = p
        .nodes
        .iter()
        .filter(|n| n.node == NodeRef::Interior)
        .count();
    if rep.kept && rep.irregular.1 as f64 > opts.dense_above * interior as f64 {
        let dense = RegularPassOptions {
            pair_budget: opts.dense_pair_budget,
            ..opts.clone()
        };
        let second = one_round(face, fid, p, sharp, &dense);
        if second.kept {
            rep.irregular.1 = second.irregular.1;
            rep.boundary.1 = second.boundary.1;
            rep.after = second.after;
        }
    }
    rep
}

/// One round of [`reduce_irregular`]: the attempts from `p` as it is.
fn one_round(
    face: &Face,
    fid: FaceId,
    p: &mut QuadPatch,
    sharp: &[CornerId],
    opts: &RegularPassOptions,
) -> RegularPassReport {
    let inside0 = p.interior_irregular();
    let mut rep = RegularPassReport {
        irregular: (inside0, inside0),
        ..Default::default()
    };
    if inside0 == 0 || p.quads.len() > opts.max_quads {
        return rep;
    }
    let Some(mut fq0) = to_face_quads(fid, p) else {
        return rep;
    };
    classify_pole_corners(&mut fq0);
    straighten_ambiguous_ideals(&mut fq0);
    ignore_far_boundary(&mut fq0, opts.boundary_reach);
    rep.tried = true;
    let boundary0 = fq0.irregular_count().saturating_sub(inside0);
    rep.boundary = (boundary0, boundary0);
    rep.before = patch_quality(face, p);
    let floor = rep.before.0.min(POOR_SICN);
    let mut best: Option<(QuadPatch, usize, usize, (f64, f64))> = None;
    for &a in &opts.attempts {
        let Some((cand, boundary)) = attempt(face, &fq0, p, sharp, opts, a) else {
            continue;
        };
        let inside = cand.interior_irregular();
        let q = patch_quality(face, &cand);
        if tracing::enabled!(tracing::Level::DEBUG) {
            tracing::debug!(
                "face {}: attempt {a:?}: interior {inside0} → {inside}, boundary {boundary0} → {boundary}, worst/average {:.3}/{:.3} → {:.3}/{:.3}",
                fid.0 + 1,
                rep.before.0,
                rep.before.1,
                q.0,
                q.1
            );
        }
        if inside >= inside0 || boundary > boundary0 {
            continue;
        }
        if q.0 < floor || q.1 < rep.before.1 - opts.average_loss {
            continue;
        }
        let better = match &best {
            None => true,
            Some((_, i, _, bq)) => inside < *i || (inside == *i && q.1 > bq.1),
        };
        if better {
            best = Some((cand, inside, boundary, q));
        }
    }
    if let Some((cand, inside, boundary, q)) = best {
        *p = cand;
        rep.kept = true;
        rep.irregular.1 = inside;
        rep.boundary.1 = boundary;
        rep.after = q;
    }
    rep
}

#[cfg(test)]
mod tests;
