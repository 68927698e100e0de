//! The **regular** method (Docampo-Sánchez & Haimes, "Towards Fully Regular
//! Quad Mesh Generation", AIAA 2019-1988): start from the triangle-split quad
//! mesh (about half its vertices irregular) and recover regularity with local
//! topological operations, each guarded by a geometric validity check,
//! repositioning and rollback; then redistribute the vertices so the quad
//! angles approach 90°.
//!
//! Stages (one module each):
//! - [`ops`]: swap, collapse, split with exact valence bookkeeping;
//! - [`validity`]: projected-angle / triangle-sign validity of a quad;
//! - [`reposition`]: Algorithm 1 and the local repair loop;
//! - [`driver`]: the sweep over quads, compositions and translations, the
//!   pair search (deeper sequences between a vertex and its nearest partner of
//!   opposite index), rollback (the translations and the pair search are in
//!   the private `pairs` module);
//! - [`redistribute`]: Algorithm 2 (tightening angle window);
//! - [`grid`]: structured patches of four- and three-sided faces.
//!
//! Faces are regularized independently (their boundary nodes never move, so
//! the mesh stays watertight), in parallel, with an output that does not depend
//! on the thread count.
//!
//! Beyond the paper, three things decide most of what is left:
//! - **structured patches** ([`grid`]): a four-sided face whose opposite
//!   sides have equal edge counts gets its `n1 × n2` grid, a three-sided face
//!   three grids around a valence-3 centre, an annulus with equal loop
//!   counts its ring grid, when every quad is valid (the
//!   operations do not reach them from the split, whose interior is often
//!   2–3 times denser than its boundary);
//! - the **quad count** ([`QuadTarget`]): the split's quads are about 1.5 times
//!   denser than squares of the boundary's edge length; a greedy search that
//!   keeps that density must end rows inside the face, each ending at an
//!   irregular vertex (a 3 beside a boundary vertex with an extra edge), so
//!   ties of the valence score go to operations that move the count toward
//!   the boundary's density;
//! - the **visiting order**: the greedy search ends in a local minimum that
//!   depends on it; each face is run in several orders (half of them without
//!   the count preference) and keeps the best result; faces stop early when
//!   regular up to their index sum, and faces whose input keeps invalid quads
//!   run one order with a short repair loop (their slow case).

pub mod driver;
pub mod grid;
pub mod ops;
mod pairs;
pub mod redistribute;
pub mod reposition;
pub mod validity;
mod whole_mesh;

use geometry::{Face, FaceId};

use crate::core::face_quads::FaceQuads;

pub use driver::OpCounts;
pub use validity::AngleWindow;
pub use whole_mesh::{
    regularize_mesh, regularize_mesh_with_progress, RegularizeError, RegularizeReport,
};

/// Options of [`regularize_mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct RegularizeOptions {
    /// Angle window every operation must respect (paper: (5°, 175°)).
    pub window: AngleWindow,
    /// Window Algorithm 2 tightens toward (paper: (85°, 95°)).
    pub target: AngleWindow,
    /// Tightening step of Algorithm 2 in degrees (paper: 1°).
    pub angle_step: f64,
    /// Maximum sweeps of the operation loop per face.
    pub max_sweeps: usize,
    /// Search two-operation compositions (swap-split, double collapse, …).
    pub compositions: bool,
    /// Longest operation sequence searched at one quad: 2 covers the paper's
    /// compositions, 3 and more add translations (valence-neutral moves
    /// before a composition).
    pub max_sequence: usize,
    /// Topological trial applications allowed per sequence search at one quad.
    pub search_budget: usize,
    /// Longest translation chain (valence-neutral swaps moving an irregular
    /// cluster toward another, paper Fig. 5; 0: no translations).
    pub translation_steps: usize,
    /// Pair search: hop radius within which an irregular vertex looks for a
    /// partner of opposite index to cancel with (0: off). See
    /// [`driver::Regularizer::cancel_pair_at`].
    pub pair_radius: usize,
    /// Pair search: longest operation sequence.
    pub pair_depth: usize,
    /// Pair search: operations expanded per search level, best score first.
    pub pair_beam: usize,
    /// Pair search: topological trial applications per searched pair.
    pub pair_budget: usize,
    /// Visiting orders tried per face (1: increasing quad ids; 2: also
    /// decreasing; more: seeded pseudo-random permutations), keeping the best
    /// result. The greedy sweeps end in different local minima; each order
    /// costs one more topological phase. Orders beyond the second run only on
    /// faces whose first result is valid, and only while orders × input quads
    /// stays within [`RegularizeOptions::order_budget`]. No further order runs
    /// on a face once its best result is valid with no interior irregular
    /// vertex and no more irregular vertices than the magnitude of its index
    /// sum Σ (ideal − valence) (which no operation changes), nor when the
    /// input kept invalid quads after the initial repair and the first result
    /// still has some. See also [`RegularizeOptions::order_patience`].
    /// 32 by default. With the structured grids, 16 orders left 16 of the 25
    /// CAD models at ≤ 5 % interior irregular vertices, 40 left 19
    /// (i01o_m1 5.9 → 4.9 %, i02o_m2 5.3 → 4.3 %, i11o_s1 5.5 → 4.4 %), at
    /// 2.3 times the CPU; the gains come from late orders (a patience of 12
    /// orders past the 16th keeps little of them). With
    /// [`RegularizeOptions::straight_ties`], 32 orders (budget 10 000) keep
    /// the same 22 models at ≤ 5 % as 40 (12 000) at 27 % less CPU.
    pub sweep_orders: usize,
    /// Stop trying visiting orders on a face once this many in a row (after
    /// the best so far) brought no better result (0: no such stop, the
    /// default: on the 25 CAD models even 7 costs models their ≤ 5 %, the
    /// best order is often a late one).
    pub order_patience: usize,
    /// Bound on (visiting orders × input quads) per face: large faces get
    /// fewer orders (never fewer than 2). 10 000 (32 orders up to 312 quads,
    /// 13 at 717). With 16 orders and 7 000, on the 25 CAD models no model's
    /// interior share changed from 12 000 to 7 000; with 40 orders, 12 000
    /// gives the same shares as 20 000 (i01o_m1 4.9 %, i02o_m2 4.3 %,
    /// i11o_s1 4.4 %) at 10 % less CPU.
    pub order_budget: usize,
    /// Keep an operation only when the quads around it end up all valid
    /// (default: no more invalid than before). [`regularize_mesh`] reruns a
    /// face in this mode when its result has more inverted quads than its input.
    pub strict_validity: bool,
    /// Quad count each face should approach ([`QuadTarget`]). Ties of the
    /// valence score go to operations that move the count toward it, and
    /// valence-neutral collapses (splits) that do are accepted. See
    /// [`driver::Regularizer::target_quads`]. Odd visiting orders run
    /// without it, so a face keeps the better of both behaviours.
    pub quad_target: QuadTarget,
    /// On a four-sided face whose opposite sides have equal edge counts, try
    /// the structured `n1 × n2` grid ([`grid::structured_grid`], fully
    /// regular) first, on a three-sided face the three grids around a
    /// valence-3 centre ([`grid::three_sided_patch`]), on an annulus with
    /// equal loop counts its ring grid ([`grid::ring_grid`]), and keep it when all
    /// its quads are valid and no more are inverted against the CAD normals
    /// than in the input; the topological phase then does not run on that
    /// face.
    pub structured_grids: bool,
    /// Among the results of the visiting orders, prefer the one with the
    /// fewest face-interior irregular vertices (then all irregular vertices)
    /// instead of the fewest irregular vertices (then interior ones). Off by
    /// default: on the 25 CAD models it lowers the interior share (i16o_s9
    /// 5.2 → 4.9 %, i13o_s6 5.8 → 5.3 %) but raises the share including the
    /// boundary (i13o_s6 4.7 → 5.3 %), and with 16 orders it lowered the
    /// worst SICN of i01o_m1 from 0.052 to 0.005.
    pub prefer_interior: bool,
    /// Give a pole on the face boundary (a degenerate edge seen as one
    /// corner of the face, with an open fan) the ideal valence of its
    /// interior angle, as any other corner ([`classify_pole_corners`]),
    /// instead of its input valence.
    pub pole_corners: bool,
    /// A boundary vertex whose interior angle lies within [`TIE_DEG`] of
    /// 225° (where the ideal boundary valence switches from 3 to 4) wants 3
    /// edges, as a straight boundary ([`straighten_ambiguous_ideals`]): on the
    /// 25 CAD models i13o_s6 5.8 → 4.2 %, i16o_s9 5.2 → 4.1 %, i02o_m2 4.3 →
    /// 1.5 % (the same band around 135° as well cost i10o_simp and i12o_s5
    /// some of their gain).
    pub straight_ties: bool,
    /// A face whose best result still leaves more than this share of its
    /// interior vertices irregular gets the visiting orders again with the
    /// pair search at [`RegularizeOptions::wide_pair_radius`], and keeps the
    /// better result (0.05, the top of the paper's range; `f64::INFINITY`: never).
    pub wide_above: f64,
    /// Pair-search hop radius of that second search. 4: i04o_m4 5.3 → 4.6 %
    /// interior irregular vertices; as the default radius for every face it
    /// cost two to four times the time.
    pub wide_pair_radius: usize,
    /// Visiting orders of that second search, at most (and never more than
    /// the first search ran). 8: i04o_m4 4.6 %, the four largest MAMBO
    /// models 20–40 % slower; 32: 4.5 %, twice as slow.
    pub wide_orders: usize,
    /// Only faces with at least this many interior irregular vertices get it.
    pub wide_min_irregular: usize,
    /// Work budget of one face, per quad of its input: the visiting orders
    /// (and the wide pair search) of a face share `work_per_quad × input
    /// quads` units of [`driver::Regularizer::work`]; a search stops when the
    /// face's budget is spent, no further order starts, and the face keeps
    /// its best result so far. Counted, never timed: the output does not
    /// depend on the machine or the thread count (0: no bound). The units
    /// count every evaluation of a candidate's valence effect (1), every
    /// topological trial (1) and every operation applied with repositioning
    /// (300): about 0.15–0.3 µs of CPU per unit on the 26 bundled models.
    /// 250 000: the largest use of any face of those models is 176 000 per
    /// input quad (i01o_m1 face 42), so none of them reaches it.
    pub work_per_quad: u64,
    /// Bound on one face's whole budget, whatever its quad count (0: none):
    /// the budget is `min(work_per_quad × input quads, work_per_face)`.
    /// Counted like [`RegularizeOptions::work_per_quad`], so the output does
    /// not depend on the machine or the thread count. [`WORK_PER_FACE`] by
    /// default.
    pub work_per_face: u64,
    /// Run Algorithm 2 after the topological phase.
    pub redistribute: bool,
    /// Worker threads (`None`: rayon's global pool). The output does not depend on it.
    pub threads: Option<usize>,
}

impl Default for RegularizeOptions {
    fn default() -> Self {
        RegularizeOptions {
            window: AngleWindow::BASE,
            target: AngleWindow {
                min_deg: 85.0,
                max_deg: 95.0,
            },
            angle_step: 1.0,
            max_sweeps: 100,
            compositions: true,
            max_sequence: 3,
            search_budget: 600,
            translation_steps: 8,
            pair_radius: 2,
            pair_depth: 4,
            pair_beam: 5,
            pair_budget: 600,
            strict_validity: false,
            sweep_orders: 32,
            order_budget: 10_000,
            order_patience: 0,
            quad_target: QuadTarget::BoundarySpacing,
            structured_grids: true,
            prefer_interior: false,
            pole_corners: true,
            straight_ties: true,
            wide_above: 0.05,
            wide_pair_radius: 4,
            wide_orders: 8,
            wide_min_irregular: 1,
            work_per_quad: WORK_PER_QUAD,
            work_per_face: WORK_PER_FACE,
            redistribute: true,
            threads: None,
        }
    }
}

/// Default [`RegularizeOptions::work_per_quad`].
pub const WORK_PER_QUAD: u64 = 250_000;

/// Default [`RegularizeOptions::work_per_face`]: 24 M units, about 5 s of CPU
/// (0.22 µs per unit on ball_bearing_8_22_7). The twelve balls of that part
/// (sphere faces of 430–520 quads with two poles) used 30–33 M each, 83 s of
/// CPU for the part; the largest use of any other face measured on the
/// industrial corpus is 21.7 M (button_head_collar_screw_m5x12 face 12).
/// Yet one default-method mesh of the 74 measured changed with this bound's
/// branch (i05o_m5: 3734 → 3714 quads, irregular 2.58 → 1.86 %), by this
/// bound or by the star's index: not isolated (BENCHMARKS.md, ninth session).
pub const WORK_PER_FACE: u64 = 24_000_000;

/// The quad count a face should approach during regularization.
///
/// The split makes quads about 1.5 times smaller in area than squares with the
/// boundary's edge length (a triangle of side h gives 3 quads of area ≈ 0.14 h²,
/// while the split boundary edges are h / 2 long, squares of 0.25 h²). A
/// regular mesh needs an interior density that matches its boundary spacing:
/// where the interior is denser, rows must end inside the face, each ending an
/// irregular vertex (in practice a 3 beside a boundary vertex with an extra
/// edge). Steering the count toward the boundary's density removes that cause.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum QuadTarget {
    /// No preference (the count follows the valence score alone).
    Off,
    /// A fraction of the face's input quad count (the authors' code uses 2/3).
    Ratio(f64),
    /// On a face whose single boundary loop has 4 corners (vertices whose
    /// ideal valence is 2), the grid `n1 × n2` its sides allow (`n1`, `n2`:
    /// the larger edge counts of the opposite sides, as the authors' code);
    /// elsewhere the face's area over the square of its mean boundary edge
    /// length, clamped to [0.4, 1.2] times the input count.
    BoundarySpacing,
}

impl QuadTarget {
    /// The target count for `fq` (0 when off).
    pub fn quads_for(&self, fq: &FaceQuads) -> usize {
        let q0 = fq.num_quads() as f64;
        let t = match *self {
            QuadTarget::Off => return 0,
            QuadTarget::Ratio(r) => r * q0,
            QuadTarget::BoundarySpacing => {
                if let Some(n) = four_sided_grid(fq) {
                    return n;
                }
                let (area, mean) = (face_area(fq), mean_boundary_edge(fq));
                if !(area > 0.0 && mean > 0.0) {
                    return 0;
                }
                (area / (mean * mean)).clamp(0.4 * q0, 1.2 * q0)
            }
        };
        if t.is_finite() && t > 0.0 {
            t.round() as usize
        } else {
            0
        }
    }
}

/// `n1 × n2` for a face with one boundary loop and 4 corners (ideal valence
/// 2); `None` otherwise.
fn four_sided_grid(fq: &FaceQuads) -> Option<usize> {
    let side = grid::four_side_counts(fq)?;
    Some(side[0].max(side[2]) * side[1].max(side[3]))
}

/// 3D area of the live quads (each as two triangles).
fn face_area(fq: &FaceQuads) -> f64 {
    use geometry::vec3::{cross, norm, sub};
    fq.live_quads()
        .map(|q| {
            let p = fq.quads[q as usize].map(|v| fq.verts[v as usize].xyz);
            0.5 * norm(cross(sub(p[2], p[0]), sub(p[3], p[1])))
        })
        .sum()
}

/// Mean 3D length of the boundary edges (edges of a single live quad), summed
/// in a fixed order (the result must not depend on hashing).
fn mean_boundary_edge(fq: &FaceQuads) -> f64 {
    let mut directed = std::collections::BTreeSet::new();
    for q in fq.live_quads() {
        let r = fq.quads[q as usize];
        for i in 0..4 {
            directed.insert((r[i], r[(i + 1) % 4]));
        }
    }
    let (mut sum, mut n) = (0.0, 0usize);
    for &(a, b) in &directed {
        if !directed.contains(&(b, a)) {
            sum += geometry::vec3::dist(fq.verts[a as usize].xyz, fq.verts[b as usize].xyz);
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

/// What regularization did to one face.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceReport {
    /// The face.
    pub face: FaceId,
    /// Quads before / after.
    pub quads: (usize, usize),
    /// Local vertices (seam nodes counted once per side) before / after.
    pub verts: (usize, usize),
    /// Vertices whose valence differs from the ideal one (4 inside, from the
    /// corner angle on the boundary), before / after.
    pub irregular: (usize, usize),
    /// Quads invalid for the base window, before / after.
    pub invalid: (usize, usize),
    /// Operations accepted and rejected.
    pub ops: OpCounts,
    /// Work done by the topological searches of every visiting order
    /// ([`driver::Regularizer::work`]), at most about
    /// [`RegularizeOptions::work_per_quad`] × input quads (0 on a grid).
    pub work: u64,
    /// Tightest angle window reached by Algorithm 2 (the base window if it did not run).
    pub window: AngleWindow,
    /// True when the result was discarded and the face's input quads kept,
    /// because it had more quads inverted against the CAD normals (the
    /// statistics' criterion, corner SICN < 0) than the input. The "after"
    /// figures are then the input's.
    pub reverted: bool,
    /// True when the face was redone with [`RegularizeOptions::strict_validity`]
    /// because the first result had more inverted quads than the input.
    pub strict: bool,
}

/// Regularizes one face in place: initial repair of invalid quads, the
/// operation loop, then (optionally) Algorithm 2. Fixed vertices are never
/// moved or removed.
pub fn regularize_face(
    face: &Face,
    fid: FaceId,
    fq: &mut FaceQuads,
    opts: &RegularizeOptions,
) -> FaceReport {
    if opts.pole_corners {
        classify_pole_corners(fq);
    }
    if opts.straight_ties {
        straighten_ambiguous_ideals(fq);
    }
    let before = (fq.num_quads(), fq.num_verts(), fq.irregular_count());
    // (not in strict mode: the rerun of a face whose result had more inverted
    // quads than its input, by the global check, uses the operations alone)
    if opts.structured_grids && !opts.strict_validity {
        if let Some((g, invalid_before)) = grid_candidate(face, fid, fq) {
            *fq = g;
            tracing::debug!(
                "regularize face {}: {} quads in, a structured patch of {} quads",
                fid.0 + 1,
                before.0,
                fq.num_quads()
            );
            let window = if opts.redistribute {
                redistribute::redistribute(fq, face, opts.window, opts.target, opts.angle_step)
            } else {
                opts.window
            };
            let invalid_after = fq
                .live_quads()
                .filter(|&q| !validity::quad_valid(fq, face, q, opts.window))
                .count();
            return FaceReport {
                face: fid,
                quads: (before.0, fq.num_quads()),
                verts: (before.1, fq.num_verts()),
                irregular: (before.2, fq.irregular_count()),
                invalid: (invalid_before, invalid_after),
                ops: OpCounts::default(),
                work: 0,
                window,
                reverted: false,
                strict: opts.strict_validity,
            };
        }
    }
    // the topological phase once per sweep order; the result with the fewest
    // invalid quads, then irregular vertices, is kept (ties: the first)
    let orders = opts
        .sweep_orders
        .min((opts.order_budget / fq.num_quads().max(1)).max(2))
        .max(1);
    let input = if orders > 1 { Some(fq.clone()) } else { None };
    // odd orders run without the quad-count preference: each face keeps the
    // better of the two behaviours
    let target = opts.quad_target.quads_for(fq);
    // a result with more quads inverted against the CAD normals than the input
    // is never preferred (regularize_mesh would revert the whole face)
    let inverted0 = if orders > 1 {
        validity::inverted_count(fq, face)
    } else {
        0
    };
    let key = |fq: &FaceQuads, invalid: usize| {
        let worse = orders > 1 && validity::inverted_count(fq, face) > inverted0;
        let (all, inside) = (fq.irregular_count(), interior_irregular(fq));
        if opts.prefer_interior {
            (worse, invalid, inside, all)
        } else {
            (worse, invalid, all, inside)
        }
    };
    let index_floor = index_sum(fq).abs();
    // inverted quads (both judges) in, after the operations, Algorithm 2 and
    // the polish, for the log alone
    let logged = tracing::enabled!(tracing::Level::DEBUG);
    let inverted_at = |fq: &FaceQuads| {
        if logged {
            validity::inverted_count(fq, face)
        } else {
            0
        }
    };
    let inverted_in = inverted_at(fq);
    let started = std::time::Instant::now();
    let mut tally = driver::WorkTally::default();
    // the face's work budget, shared by every order (0: none)
    let budget = opts.work_per_quad.saturating_mul(fq.num_quads() as u64);
    let budget = match (budget, opts.work_per_face) {
        (b, 0) => b,
        (0, f) => f,
        (b, f) => b.min(f),
    };
    let mut spent = 0u64;
    let left = |spent: u64| -> Option<u64> {
        if budget == 0 {
            Some(0)
        } else if spent < budget {
            Some(budget - spent)
        } else {
            None
        }
    };
    let (invalid_before, ops, invalid_mid, work) =
        topological_phase(face, fq, opts, 0, target, budget);
    spent += work.0;
    tally = tally.plus(work.1);
    let mut orders_run = 1usize;
    let (mut ops, mut invalid_mid) = (ops, invalid_mid);
    let mut best = key(fq, invalid_mid);
    let mut last_gain = 0usize;
    if let Some(input) = &input {
        for order in 1..orders as u32 {
            // orders beyond the second only where the first ended valid (a face
            // with quads left invalid is the slow case: repairs at every
            // trial); none at all when the input's invalid quads stayed (on the
            // 25 CAD models another order never did better there)
            if invalid_mid > 0 && (order >= 2 || invalid_before > 0) {
                break;
            }
            // as regular as the boundary allows: no interior irregular vertex
            // and no more irregular vertices than the index sum's magnitude
            let (all, inside) = if opts.prefer_interior {
                (best.3, best.2)
            } else {
                (best.2, best.3)
            };
            if !best.0 && invalid_mid == 0 && all as i64 <= index_floor && inside == 0 {
                break;
            }
            // optional: no better result for a while (off by default, see the option)
            if opts.order_patience > 0 && order as usize - last_gain > opts.order_patience {
                break;
            }
            // the face's work budget is spent
            let Some(cap) = left(spent) else {
                break;
            };
            let mut other = input.clone();
            let (_, ops2, invalid2, work) = topological_phase(
                face,
                &mut other,
                opts,
                order,
                if order % 2 == 1 { 0 } else { target },
                cap,
            );
            spent += work.0;
            tally = tally.plus(work.1);
            orders_run += 1;
            let k = key(&other, invalid2);
            if k < best {
                last_gain = order as usize;
                *fq = other;
                ops = ops2;
                invalid_mid = invalid2;
                best = k;
            }
        }
    }
    // a face left well above the paper's range: the orders again, with a
    // wider pair search (slow, so only here)
    let interior = (0..fq.verts.len())
        .filter(|&v| fq.verts[v].alive && !fq.verts[v].fixed)
        .count();
    if let Some(input) = &input {
        if invalid_mid == 0
            && opts.wide_pair_radius > opts.pair_radius
            && interior_irregular(fq) >= opts.wide_min_irregular
            && interior_irregular(fq) as f64 > opts.wide_above * interior as f64
        {
            let wide = RegularizeOptions {
                pair_radius: opts.wide_pair_radius,
                ..opts.clone()
            };
            for order in 0..orders.min(opts.wide_orders) as u32 {
                let Some(cap) = left(spent) else {
                    break;
                };
                let mut other = input.clone();
                let (_, ops2, invalid2, work) = topological_phase(
                    face,
                    &mut other,
                    &wide,
                    order,
                    if order % 2 == 1 { 0 } else { target },
                    cap,
                );
                spent += work.0;
                tally = tally.plus(work.1);
                orders_run += 1;
                let k = key(&other, invalid2);
                if k < best {
                    *fq = other;
                    ops = ops2;
                    invalid_mid = invalid2;
                    best = k;
                }
            }
        }
    }
    let inverted_topology = inverted_at(fq);
    let window = if opts.redistribute && invalid_mid == 0 {
        redistribute::redistribute(fq, face, opts.window, opts.target, opts.angle_step)
    } else {
        opts.window
    };
    let inverted_redistributed = inverted_at(fq);
    let invalid_after = reposition::polish_invalid(fq, face, opts.window);
    tracing::debug!(
        "regularize face {}: inverted (both judges) {inverted_in} in, {inverted_topology} after \
         the operations, {inverted_redistributed} after Algorithm 2, {} after the polish",
        fid.0 + 1,
        inverted_at(fq)
    );
    // (the time is for the log alone: nothing decided depends on it)
    tracing::debug!(
        "regularize face {}: {} quads in, {} orders, work {spent} of {budget} \
         ({} evaluations, {} trials, {} geometric), {:.0} ms",
        fid.0 + 1,
        before.0,
        orders_run,
        tally.evaluations,
        tally.trials,
        tally.geometric,
        started.elapsed().as_secs_f64() * 1e3
    );
    FaceReport {
        face: fid,
        quads: (before.0, fq.num_quads()),
        verts: (before.1, fq.num_verts()),
        irregular: (before.2, fq.irregular_count()),
        invalid: (invalid_before, invalid_after),
        ops,
        work: spent,
        window,
        reverted: false,
        strict: opts.strict_validity,
    }
}

/// The structured grid of a four-sided face ([`grid::structured_grid`]), or
/// else the three-grid patch of a three-sided face
/// ([`grid::three_sided_patch`]), or else the ring grid of an annulus
/// ([`grid::ring_grid`]), with the input's invalid quad count, when
/// it is worth keeping: fewer irregular vertices than the input and no more
/// than the magnitude of the face's index sum (as regular as the boundary
/// allows), every quad valid for the base window (after the initial repair by
/// repositioning), and no more quads inverted against the CAD normals than
/// the input.
fn grid_candidate(face: &Face, fid: FaceId, fq: &FaceQuads) -> Option<(FaceQuads, usize)> {
    let mut g = grid::structured_grid(fq, face, fid)
        .or_else(|| grid::three_sided_patch(fq, face, fid))
        .or_else(|| grid::ring_grid(fq, face, fid))?;
    if g.irregular_count() >= fq.irregular_count()
        || g.irregular_count() as i64 > index_sum(fq).abs()
    {
        return None;
    }
    let mut r = driver::Regularizer::new(face, &mut g);
    if r.invalid_count() > 0 {
        r.initial_repair();
        if r.invalid_count() > 0 {
            return None;
        }
    }
    if validity::inverted_count(&g, face) > validity::inverted_count(fq, face) {
        return None;
    }
    let invalid_before = fq
        .live_quads()
        .filter(|&q| !validity::quad_valid(fq, face, q, AngleWindow::BASE))
        .count();
    Some((g, invalid_before))
}

/// Sets the ideal valence of every pole on the face boundary (fixed, with a
/// pole segment and an open fan: one edge more than quads) from the face's
/// interior angle there ([`crate::core::valence::ideal_boundary_valence`]), as
/// for any corner. [`FaceQuads::classify_fixed`] gives such a vertex its input
/// valence (never irregular), which makes the triangle split's fan at the
/// pole (often 5 or more edges at a 90° corner) a constraint: on a
/// three-sided face with a pole corner it forces 3 more irregular vertices.
pub fn classify_pole_corners(fq: &mut FaceQuads) {
    for v in 0..fq.verts.len() as u32 {
        let x = &fq.verts[v as usize];
        if !(x.alive && x.fixed && x.pole.is_some() && x.edge_offset == 1) {
            continue;
        }
        if !matches!(
            x.class,
            mesh::NodeClass::Corner(_) | mesh::NodeClass::Curve(..)
        ) {
            continue;
        }
        let angle = fq.angle_sum(v);
        if angle.is_finite() && angle > 0.0 {
            fq.verts[v as usize].ideal = crate::core::valence::ideal_boundary_valence(angle);
        }
    }
}

/// Half-width (degrees) of the band around 225° (a threshold of
/// [`crate::core::valence::ideal_boundary_valence`]) within which
/// [`straighten_ambiguous_ideals`] rounds toward a straight boundary.
pub const TIE_DEG: f64 = 3.0;

/// Gives ideal valence 3 (a straight boundary) to every boundary vertex
/// (fixed, open fan, a curve or corner node, not a pole) whose interior angle
/// is within [`TIE_DEG`] of 225°, where
/// [`crate::core::valence::ideal_boundary_valence`] switches from 3 to 4. A circle cut into 8 segments (a common hole) has chordal
/// angles of exactly 225° on the face around it, so rounding noise gave some
/// of its vertices 4 and others 3: every face around such a hole had
/// irregular vertices forced by its classification (i16o_s9: index sums 4–6
/// on faces with one hole).
pub fn straighten_ambiguous_ideals(fq: &mut FaceQuads) {
    for v in 0..fq.verts.len() as u32 {
        let x = &fq.verts[v as usize];
        if !(x.alive && x.fixed && x.pole.is_none() && x.edge_offset == 1)
            || !matches!(
                x.class,
                mesh::NodeClass::Corner(_) | mesh::NodeClass::Curve(..)
            )
        {
            continue;
        }
        let a = fq.angle_sum(v);
        if (a - 225.0).abs() < TIE_DEG {
            fq.verts[v as usize].ideal = 3;
        }
    }
}

/// Σ (ideal − valence) over the live vertices: no operation changes it, so
/// at least `|Σ| / 2` vertices stay irregular (usually `|Σ|`: one edge too
/// many or too few each).
fn index_sum(fq: &FaceQuads) -> i64 {
    (0..fq.verts.len() as u32)
        .filter(|&v| fq.verts[v as usize].alive)
        .map(|v| fq.verts[v as usize].ideal as i64 - fq.valence(v) as i64)
        .sum()
}

/// Movable (face-interior) vertices whose valence is not 4.
fn interior_irregular(fq: &FaceQuads) -> usize {
    (0..fq.verts.len() as u32)
        .filter(|&v| !fq.verts[v as usize].fixed && fq.is_irregular(v))
        .count()
}

/// Initial repair and the operation loop of one face ([`driver::Regularizer::run`]),
/// visiting quads and vertices in `order` ([`driver::Regularizer::order`]),
/// steering the quad count toward `target` (0: off), stopping searches once
/// `work_cap` units of work are done (0: no bound). Returns the invalid
/// quads before, the operation counts, the invalid quads after and the work
/// done (units, and the events counted).
pub(crate) fn topological_phase(
    face: &Face,
    fq: &mut FaceQuads,
    opts: &RegularizeOptions,
    order: u32,
    target: usize,
    work_cap: u64,
) -> (usize, OpCounts, usize, (u64, driver::WorkTally)) {
    let mut r = driver::Regularizer::new(face, fq);
    r.compositions = opts.compositions;
    r.max_ops = opts.max_sequence;
    r.budget = opts.search_budget;
    r.translation_steps = opts.translation_steps;
    r.strict = opts.strict_validity;
    r.pair_radius = opts.pair_radius;
    r.pair_depth = opts.pair_depth;
    r.pair_beam = opts.pair_beam;
    r.pair_budget = opts.pair_budget;
    r.order = order;
    r.target_quads = target;
    r.work_cap = work_cap;
    let invalid_before = r.invalid_count();
    r.initial_repair();
    r.run(opts.max_sweeps);
    (
        invalid_before,
        r.counts,
        r.invalid_count(),
        (r.work, r.tally),
    )
}

#[cfg(test)]
mod tests;
