//! Geometric smoothing kernels of the quasi-structured paper (§5.3, spec
//! §8.4–8.6), evaluated in 3D on the one-ring of a face-interior node and
//! mapped back onto the CAD surface through its (u, v) Jacobian:
//!
//! - [`winslow_point`]: the finite-difference Winslow kernel (Eq. 13 with the
//!   sign corrected) on a regular node, whose eight ring nodes `x₁..x₈`
//!   alternate edge neighbours (odd) and diagonals (even). Every affine grid
//!   is a fixed point.
//! - [`angle_based_point`]: on an irregular node, each edge neighbour `p_j`
//!   proposes `p_j + |x − p_j| b_j` where `b_j` bisects the one-ring polygon's
//!   angle at `p_j` in the tangent plane; the node goes to their mean.
//!
//! [`optimize`] runs them in Gauss–Seidel sweeps (node order, deterministic)
//! with a per-node rollback (a move is kept only if the worst SICN of the
//! quads around the node does not decrease; otherwise half the step is tried,
//! then the mean of the edge neighbours in 3D and half the step to it, and
//! the node is put back bit for bit when none passes) and a global
//! acceptance: the smoothed patch is kept only if its worst SICN did not drop
//! and its average rose, otherwise every position is restored exactly. A
//! node is visited again only when it or a ring node moved in the previous
//! sweep. The 3D target goes onto the surface by Gauss–Newton steps in
//! (u, v) from the node's own (u, v), so seams (the face's (u, v) is
//! continuous inside it) need no care; poles never move, and a move onto a
//! singular point of the parametrization is refused.

use geometry::vec3::{self, Vec3};
use geometry::{Face, SurfaceDerivs};

use crate::core::patch::NodeRef;
use crate::core::patch::QuadPatch;
use crate::core::quality::{keep_unfolded_curve_normals, quad_quality_with};

/// Gauss–Newton iterations mapping a 3D target onto the surface.
const MAP_ITERATIONS: usize = 3;
/// Gauss–Newton stops when its step is below this share of the shortest ring edge.
const MAP_TOLERANCE: f64 = 1e-9;

/// Options of [`optimize`].
#[derive(Clone, Copy, Debug)]
pub struct OptimizeOptions {
    /// Maximum Gauss–Seidel sweeps (spec §8.6: 10 in optimization phases, 30
    /// for the final smoothing of a face).
    pub max_sweeps: usize,
    /// A sweep in which every node moved less than this share of its
    /// shortest ring edge ends the loop.
    pub stop_displacement: f64,
}

impl Default for OptimizeOptions {
    fn default() -> Self {
        OptimizeOptions {
            max_sweeps: 30,
            stop_displacement: 0.01,
        }
    }
}

/// What [`optimize`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OptimizeReport {
    /// Sweeps run.
    pub sweeps: usize,
    /// Node moves kept by the per-node check.
    pub moves: usize,
    /// Moves rolled back by the per-node check.
    pub rejected: usize,
    /// Worst and average quad SICN before.
    pub before: (f64, f64),
    /// Worst and average quad SICN after (equal to `before` when not kept).
    pub after: (f64, f64),
    /// False when the global check restored the patch.
    pub kept: bool,
}

/// Winslow update of a regular node (spec §8.4, Eq. 13 corrected): `ring` is
/// `x₁..x₈` in cyclic order around the node, odd entries (`ring[0]`,
/// `ring[2]`, …) its edge neighbours, even entries the diagonal nodes.
/// Returns `None` when the stencil is degenerate (`α₀ + α₁` ≈ 0).
pub fn winslow_point(ring: &[Vec3; 8]) -> Option<Vec3> {
    let [x1, x2, x3, x4, x5, x6, x7, x8] = *ring;
    let d15 = vec3::sub(x1, x5);
    let d37 = vec3::sub(x3, x7);
    let a0 = vec3::dot(d37, d37);
    let a1 = vec3::dot(d15, d15);
    let beta = vec3::dot(d15, d37);
    let den = 2.0 * (a0 + a1);
    if !(den > 0.0 && den.is_finite()) {
        return None;
    }
    let mut out = [0.0; 3];
    for c in 0..3 {
        let cross = x2[c] - x4[c] + x6[c] - x8[c];
        out[c] = (a0 * (x1[c] + x5[c]) + a1 * (x3[c] + x7[c]) - 0.5 * beta * cross) / den;
    }
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// Angle-based update of an irregular node at `x` with unit normal `n`
/// (spec §8.5): `ring` alternates edge neighbours (even indices) and the
/// diagonal nodes between them, counter-clockwise about `n`. Each edge
/// neighbour `p` proposes the point at distance `|x − p|` along the bisector
/// of the ring polygon's interior angle at `p` (measured in the tangent
/// plane); the result is the mean of the proposals. `None` when the ring is
/// degenerate.
pub fn angle_based_point(x: Vec3, n: Vec3, ring: &[Vec3]) -> Option<Vec3> {
    let m = ring.len();
    if m < 4 || m % 2 != 0 {
        return None;
    }
    let tangent = |v: Vec3| vec3::sub(v, vec3::scale(n, vec3::dot(v, n)));
    let mut sum = [0.0; 3];
    let k = m / 2;
    for j in 0..k {
        let p = ring[2 * j];
        let next = ring[(2 * j + 1) % m];
        let prev = ring[(2 * j + m - 1) % m];
        let t1 = vec3::normalize(tangent(vec3::sub(next, p)))?;
        let ep = tangent(vec3::sub(prev, p));
        let t2 = vec3::cross(n, t1);
        // interior angle of a counter-clockwise polygon: from `next` to `prev`, counter-clockwise
        let mut theta = vec3::dot(ep, t2).atan2(vec3::dot(ep, t1));
        if theta < 0.0 {
            theta += 2.0 * std::f64::consts::PI;
        }
        let h = 0.5 * theta;
        let b = vec3::add(vec3::scale(t1, h.cos()), vec3::scale(t2, h.sin()));
        let r = vec3::dist(x, p);
        sum = vec3::add(sum, vec3::add(p, vec3::scale(b, r)));
    }
    let out = vec3::scale(sum, 1.0 / k as f64);
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// The one-ring of node `v` (its quads `star`) in the quads' own cyclic
/// order: edge neighbour, diagonal, edge neighbour, …; `None` when the star
/// is not a closed disk around `v`.
pub fn one_ring(quads: &[[u32; 4]], v: u32, star: &[u32]) -> Option<Vec<u32>> {
    if star.len() < 2 {
        return None;
    }
    let mut step: Vec<(u32, u32, u32)> = Vec::with_capacity(star.len());
    for &qi in star {
        let q = quads.get(qi as usize)?;
        let k = q.iter().position(|&x| x == v)?;
        if q.iter().filter(|&&x| x == v).count() != 1 {
            return None;
        }
        step.push((q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]));
    }
    let mut ring = Vec::with_capacity(2 * star.len());
    let start = step[0].0;
    let mut a = start;
    for _ in 0..star.len() {
        let mut it = step.iter().filter(|s| s.0 == a);
        let &(_, b, c) = it.next()?;
        if it.next().is_some() {
            return None;
        }
        ring.push(a);
        ring.push(b);
        a = c;
    }
    if a != start {
        return None;
    }
    let mut seen = ring.clone();
    seen.sort_unstable();
    seen.dedup();
    (seen.len() == ring.len() && !ring.contains(&v)).then_some(ring)
}

/// The (u, v) near `uv` whose surface point is closest to `target`
/// (Gauss–Newton on the surface's Jacobian, stopped when the step is below
/// `tol` in 3D), with that point and the oriented normal there; `None` at a
/// singular point or when the iteration fails.
pub(crate) fn map_to_surface(
    face: &Face,
    uv: [f64; 2],
    target: Vec3,
    tol: f64,
) -> Option<([f64; 2], Vec3, Vec3)> {
    map_to_surface_from(face, uv, face.surface.first_derivs(uv), target, tol)
}

/// [`map_to_surface`] with the surface's first derivatives at the start
/// `uv` given (`d`, from `first_derivs(uv)`): the smoothing maps several
/// trial targets of one node from the same start, and evaluates it once.
fn map_to_surface_from(
    face: &Face,
    uv: [f64; 2],
    d: SurfaceDerivs,
    target: Vec3,
    tol: f64,
) -> Option<([f64; 2], Vec3, Vec3)> {
    let mut cur = uv;
    let mut d = d;
    for _ in 0..MAP_ITERATIONS {
        let r = vec3::sub(target, d.point);
        let (a, b, c) = (
            vec3::dot(d.du, d.du),
            vec3::dot(d.du, d.dv),
            vec3::dot(d.dv, d.dv),
        );
        let (ru, rv) = (vec3::dot(d.du, r), vec3::dot(d.dv, r));
        let det = a * c - b * b;
        if det.is_nan() || det <= 1e-30 * (a * c).max(1e-300) {
            return None;
        }
        let du = (c * ru - b * rv) / det;
        let dv = (a * rv - b * ru) / det;
        if !(du.is_finite() && dv.is_finite()) {
            return None;
        }
        if (du * du * a + 2.0 * du * dv * b + dv * dv * c).sqrt() <= tol {
            break;
        }
        cur = [cur[0] + du, cur[1] + dv];
        d = face.surface.first_derivs(cur);
    }
    if !d.point.iter().all(|v| v.is_finite()) {
        return None;
    }
    let n = face.regular_normal_from(&d)?;
    Some((cur, d.point, n))
}

/// Smooths the face-interior nodes of `p` with the Winslow kernel (regular
/// nodes) and the angle-based kernel (irregular ones), see the module
/// documentation. Nodes on curves, corners and poles never move; a node
/// whose star is not a closed disk is left alone.
pub fn optimize(face: &Face, p: &mut QuadPatch, opts: &OptimizeOptions) -> OptimizeReport {
    optimize_nodes(face, p, None, opts)
}

/// [`optimize`] restricted to the nodes of `only` (all face-interior nodes
/// when `None`); the global check is made on the quads around them.
pub fn optimize_nodes(
    face: &Face,
    p: &mut QuadPatch,
    only: Option<&[u32]>,
    opts: &OptimizeOptions,
) -> OptimizeReport {
    sweep_nodes(face, p, only, opts, Objective::Kernels)
}

/// Raises the average SICN of `p`'s quads: each face-interior node steps
/// along the gradient (finite differences in its tangent plane) of the sum
/// of the SICN of its quads; the step, a share of its shortest edge between
/// [`ASCENT_STEP`] and [`ASCENT_MIN_STEP`], grows after a kept move and
/// shrinks after a refused one. A move must raise that sum and keep each
/// of the node's quads above its floor ([`ascent_floor`]: a quad below
/// [`ASCENT_SAFE`] never gets worse). The Winslow and angle-based kernels
/// aim at evenly spaced grids; this aims at square quads and lets their
/// size vary. A patch whose average is already [`ASCENT_DONE`] is left
/// as it is (at fine sizes most faces: i01o_m1 at size factor 0.0625 takes
/// 6.8 s instead of 7.6 s, the same average). The result is kept only if
/// the average rose; otherwise every position is restored exactly.
pub fn raise_average(face: &Face, p: &mut QuadPatch, max_sweeps: usize) -> OptimizeReport {
    let opts = OptimizeOptions {
        max_sweeps,
        ..Default::default()
    };
    sweep_nodes(face, p, None, &opts, Objective::Average)
}

/// Largest (and first) step of [`raise_average`], as a share of the node's shortest edge.
pub const ASCENT_STEP: f64 = 0.05;
/// [`raise_average`] leaves a node when its step falls below this share of its shortest edge.
pub const ASCENT_MIN_STEP: f64 = 0.0005;
/// Probe of [`raise_average`]'s finite-difference gradient, as a share of the node's shortest edge.
pub const ASCENT_PROBE: f64 = 1e-3;
/// [`raise_average`] keeps a good quad's SICN at least this share of what it
/// was (see [`ascent_floor`]).
pub const ASCENT_KEEP: f64 = 0.95;
/// [`raise_average`] never lowers a quad below this SICN, nor one already
/// below it.
pub const ASCENT_SAFE: f64 = 0.5;
/// [`raise_average`] leaves a patch whose average SICN is at least this
/// (on the 25 shared models the averages move by at most 0.0013 against
/// no such test).
pub const ASCENT_DONE: f64 = 0.97;
/// [`raise_average`] stops after a sweep whose kept moves raised the average
/// SICN of the patch by less than this. At the default size the gains fall from about
/// 5e-3 in the first sweep to 1e-5 after 20 to 30 (the 10 to 20 sweeps
/// beyond add 1e-4 together); on i01o_m1 at size factor 0.0625 every sweep
/// of the 16 faces not already square gains below 1e-5, 40 sweeps 1e-4 in
/// all, for 15 % of the run's time.
pub const ASCENT_STALL: f64 = 1e-5;
/// [`raise_average`] passes over a node whose quads are all at least this
/// good (0.98 froze the well-shaped middle of a sphere's cube faces, so the
/// nodes near its corners could not make room: s17o 0.979 against 0.986).
pub const ASCENT_GOOD: f64 = 0.995;

/// The eight compass directions (unit, in a tangent frame) of the steps of
/// [`raise_average`] at a kink of its objective, of the face nodes of
/// [`crate::smoothing::curve_slide`], and (in (u, v)) of the regular method's last
/// repair ([`crate::topology::regularize::reposition::polish_invalid`]).
pub(crate) const COMPASS: [(f64, f64); 8] = {
    let d = std::f64::consts::FRAC_1_SQRT_2;
    [
        (1.0, 0.0),
        (-1.0, 0.0),
        (0.0, 1.0),
        (0.0, -1.0),
        (d, d),
        (-d, -d),
        (d, -d),
        (-d, d),
    ]
};

/// The lowest SICN [`raise_average`] lets a quad take, given its SICN
/// before the sweeps: a quad below [`ASCENT_SAFE`] never gets worse; a
/// better one keeps [`ASCENT_KEEP`] of its value and stays above
/// [`ASCENT_SAFE`].
pub(crate) fn ascent_floor(initial: f64) -> f64 {
    if initial < ASCENT_SAFE {
        initial
    } else {
        (ASCENT_KEEP * initial).max(ASCENT_SAFE)
    }
}

/// What a sweep of [`sweep_nodes`] moves nodes toward.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Objective {
    /// The Winslow / angle-based kernel's point; a node's worst quad must not drop.
    Kernels,
    /// Compass steps raising the sum of the node's quads' SICN.
    Average,
}

/// The Gauss–Seidel sweeps of [`optimize_nodes`] and [`raise_average`].
fn sweep_nodes(
    face: &Face,
    p: &mut QuadPatch,
    only: Option<&[u32]>,
    opts: &OptimizeOptions,
    objective: Objective,
) -> OptimizeReport {
    let n = p.nodes.len();
    let mut quads_of: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (qi, q) in p.quads.iter().enumerate() {
        for &a in q {
            if (a as usize) < n {
                quads_of[a as usize].push(qi as u32);
            }
        }
    }
    let candidates: Vec<u32> = match only {
        Some(list) => {
            let mut l: Vec<u32> = list.iter().copied().filter(|&i| (i as usize) < n).collect();
            l.sort_unstable();
            l.dedup();
            l
        }
        None => (0..n as u32).collect(),
    };
    // free nodes with their rings
    let mut free: Vec<(u32, Vec<u32>)> = Vec::new();
    for &i in &candidates {
        let nd = &p.nodes[i as usize];
        if nd.node != NodeRef::Interior || nd.pole.is_some() || quads_of[i as usize].is_empty() {
            continue;
        }
        if let Some(ring) = one_ring(&p.quads, i, &quads_of[i as usize]) {
            free.push((i, ring));
        }
    }
    let mut report = OptimizeReport {
        kept: true,
        ..Default::default()
    };
    // the quads the optimization can change
    let mut touched: Vec<u32> = free
        .iter()
        .flat_map(|(i, _)| quads_of[*i as usize].iter().copied())
        .collect();
    touched.sort_unstable();
    touched.dedup();
    // cached normals of the ordinary nodes of the quads it can change (poles
    // and singular points: computed per quad)
    let mut nrm: Vec<Option<Vec3>> = vec![None; n];
    let mut known = vec![false; n];
    for &q in &touched {
        for &v in &p.quads[q as usize] {
            let v = v as usize;
            if !known[v] {
                known[v] = true;
                if p.nodes[v].pole.is_none() {
                    nrm[v] = face.regular_normal(p.nodes[v].uv);
                }
            }
        }
    }
    let qual = |p: &QuadPatch, nrm: &[Option<Vec3>], q: u32| {
        let quad = &p.quads[q as usize];
        let mut known = [
            nrm[quad[0] as usize],
            nrm[quad[1] as usize],
            nrm[quad[2] as usize],
            nrm[quad[3] as usize],
        ];
        keep_unfolded_curve_normals(&p.nodes, quad, &mut known);
        quad_quality_with(face, &p.nodes, &p.pos, quad, &known)
    };
    let mut qv: Vec<f64> = vec![f64::NAN; p.quads.len()];
    for &q in &touched {
        qv[q as usize] = qual(p, &nrm, q);
    }
    let stats = |qv: &[f64]| {
        let (mut mn, mut s) = (f64::INFINITY, 0.0);
        for &q in &touched {
            mn = mn.min(qv[q as usize]);
            s += qv[q as usize];
        }
        (
            mn,
            if touched.is_empty() {
                0.0
            } else {
                s / touched.len() as f64
            },
        )
    };
    report.before = stats(&qv);
    if tracing::enabled!(tracing::Level::TRACE) {
        tracing::trace!("qv {:?} touched {}", &qv, touched.len());
    }
    report.after = report.before;
    if free.is_empty() || opts.max_sweeps == 0 {
        return report;
    }
    // a patch whose quads are about square on average has little to gain
    if objective == Objective::Average && report.before.1 >= ASCENT_DONE {
        return report;
    }
    let saved: Vec<([f64; 2], Vec3)> = free
        .iter()
        .map(|(i, _)| (p.nodes[*i as usize].uv, p.pos[*i as usize]))
        .collect();
    let saved_nrm: Vec<Option<Vec3>> = free.iter().map(|(i, _)| nrm[*i as usize]).collect();
    let saved_qv: Vec<f64> = touched.iter().map(|&q| qv[q as usize]).collect();
    let mut ring_pos: Vec<Vec3> = Vec::with_capacity(16);
    let mut new_q: Vec<f64> = Vec::with_capacity(8);
    // a node is smoothed again only when it or a ring node moved by more
    // than `stop_displacement` in the previous sweep
    // the quads' SICN before the sweeps (the floor of the Average objective)
    let initial_q = qv.clone();
    let mut active = vec![true; free.len()];
    // per-node compass step of the Average objective (0: not started)
    let mut step = vec![0.0f64; free.len()];
    let mut moved = vec![false; n];
    for _ in 0..opts.max_sweeps {
        report.sweeps += 1;
        let mut converged = true;
        let mut sweep_gain = 0.0f64;
        let sweep_moves = report.moves;
        for (f, (i, ring)) in free.iter().enumerate() {
            if !active[f] {
                continue;
            }
            let i = *i as usize;
            let x = p.pos[i];
            ring_pos.clear();
            ring_pos.extend(ring.iter().map(|&r| p.pos[r as usize]));
            let Some(n_i) = nrm[i] else { continue };
            if objective == Objective::Average {
                let edge = (0..ring_pos.len())
                    .step_by(2)
                    .map(|j| vec3::dist(ring_pos[j], x))
                    .fold(f64::INFINITY, f64::min);
                if !(edge > 0.0 && edge.is_finite()) {
                    continue;
                }
                if step[f] == 0.0 {
                    step[f] = ASCENT_STEP;
                }
                if step[f] < ASCENT_MIN_STEP {
                    continue;
                }
                converged = false;
                let sum_before: f64 = quads_of[i].iter().map(|&q| qv[q as usize]).sum();
                // quads about square already: nothing to gain here
                if quads_of[i].iter().all(|&q| qv[q as usize] >= ASCENT_GOOD) {
                    continue;
                }
                // the derivatives at the node: its tangent frame and the
                // start of every trial placement below
                let d0 = face.surface.first_derivs(p.nodes[i].uv);
                let Some(t1) = vec3::normalize(d0.du) else {
                    continue;
                };
                let t2 = vec3::cross(n_i, t1);
                let (old_uv, old_n) = (p.nodes[i].uv, nrm[i]);
                // the node at `t` (3D, mapped onto the surface): the sum and
                // the worst of its quads' SICN; the node stays there
                let place = |p: &mut QuadPatch,
                             nrm: &mut Vec<Option<Vec3>>,
                             new_q: &mut Vec<f64>,
                             t: Vec3| {
                    let (uv, nx, nn) =
                        map_to_surface_from(face, old_uv, d0, t, MAP_TOLERANCE * edge)?;
                    p.nodes[i].uv = uv;
                    p.pos[i] = nx;
                    nrm[i] = Some(nn);
                    new_q.clear();
                    new_q.extend(quads_of[i].iter().map(|&q| qual(p, nrm, q)));
                    let sum: f64 = new_q.iter().sum();
                    let floor_ok = quads_of[i]
                        .iter()
                        .zip(new_q.iter())
                        .all(|(&q, &v)| v >= ascent_floor(initial_q[q as usize]));
                    Some((sum, floor_ok))
                };
                // a finite-difference gradient in the tangent frame
                let h = ASCENT_PROBE * edge;
                let mut g = [0.0; 2];
                for (k, t) in [t1, t2].into_iter().enumerate() {
                    if let Some((sum, _)) =
                        place(p, &mut nrm, &mut new_q, vec3::add(x, vec3::scale(t, h)))
                    {
                        g[k] = (sum - sum_before) / h;
                    }
                }
                let gn = (g[0] * g[0] + g[1] * g[1]).sqrt();
                let mut kept = false;
                if gn > 0.0 && gn.is_finite() {
                    let dir = vec3::add(vec3::scale(t1, g[0] / gn), vec3::scale(t2, g[1] / gn));
                    for shrink in [1.0, 0.5, 0.25] {
                        let t = vec3::add(x, vec3::scale(dir, shrink * step[f] * edge));
                        let Some((sum, floor_ok)) = place(p, &mut nrm, &mut new_q, t) else {
                            continue;
                        };
                        if sum > sum_before + 1e-12 && floor_ok {
                            for (&q, &v) in quads_of[i].iter().zip(&new_q) {
                                qv[q as usize] = v;
                            }
                            sweep_gain += sum - sum_before;
                            report.moves += 1;
                            kept = true;
                            step[f] = (shrink * step[f] * 1.5).min(ASCENT_STEP);
                            break;
                        }
                    }
                }
                // at a kink of the sum (two corners of a quad tie for its
                // worst) the gradient misleads: compass steps instead
                if !kept {
                    for (a, b) in COMPASS {
                        let dir = vec3::add(vec3::scale(t1, a), vec3::scale(t2, b));
                        let t = vec3::add(x, vec3::scale(dir, step[f] * edge));
                        let Some((sum, floor_ok)) = place(p, &mut nrm, &mut new_q, t) else {
                            continue;
                        };
                        if sum > sum_before + 1e-12 && floor_ok {
                            for (&q, &v) in quads_of[i].iter().zip(&new_q) {
                                qv[q as usize] = v;
                            }
                            sweep_gain += sum - sum_before;
                            report.moves += 1;
                            kept = true;
                            break;
                        }
                    }
                }
                if !kept {
                    p.nodes[i].uv = old_uv;
                    p.pos[i] = x;
                    nrm[i] = old_n;
                    report.rejected += 1;
                    step[f] *= 0.25;
                }
                continue;
            }
            let target = if ring.len() == 8 {
                let r: [Vec3; 8] = [
                    ring_pos[0],
                    ring_pos[1],
                    ring_pos[2],
                    ring_pos[3],
                    ring_pos[4],
                    ring_pos[5],
                    ring_pos[6],
                    ring_pos[7],
                ];
                winslow_point(&r)
            } else {
                // the ring's orientation about the normal
                let k = ring_pos.len();
                let mut turn = 0.0;
                for j in 0..k {
                    turn += vec3::dot(
                        vec3::cross(
                            vec3::sub(ring_pos[j], x),
                            vec3::sub(ring_pos[(j + 1) % k], x),
                        ),
                        n_i,
                    );
                }
                let n_ring = if turn >= 0.0 {
                    n_i
                } else {
                    vec3::scale(n_i, -1.0)
                };
                angle_based_point(x, n_ring, &ring_pos)
            };
            let edge = (0..ring_pos.len())
                .step_by(2)
                .map(|j| vec3::dist(ring_pos[j], x))
                .fold(f64::INFINITY, f64::min);
            if edge.is_nan()
                || edge <= 0.0
                || target.is_some_and(|t| vec3::dist(t, x) < 1e-12 * edge)
            {
                continue;
            }
            let before = quads_of[i]
                .iter()
                .map(|&q| qv[q as usize])
                .fold(f64::INFINITY, f64::min);
            let (old_uv, old_x, old_n) = (p.nodes[i].uv, x, nrm[i]);
            let mut done = false;
            // the kernel's point, half way to it, then the mean of the edge
            // neighbours (a 3D Laplacian) and half way to that
            let k = ring_pos.len() / 2;
            let mut mean = [0.0; 3];
            for j in 0..k {
                mean = vec3::add(mean, ring_pos[2 * j]);
            }
            let mean = vec3::scale(mean, 1.0 / k as f64);
            let half = |t: Vec3| vec3::scale(vec3::add(t, x), 0.5);
            let tries = [target, target.map(half), Some(mean), Some(half(mean))];
            // every try starts from the node's (u, v): its derivatives once
            let d0 = face.surface.first_derivs(old_uv);
            for t in tries.into_iter().flatten() {
                let Some((uv, nx, nn)) =
                    map_to_surface_from(face, old_uv, d0, t, MAP_TOLERANCE * edge)
                else {
                    continue;
                };
                p.nodes[i].uv = uv;
                p.pos[i] = nx;
                nrm[i] = Some(nn);
                new_q.clear();
                new_q.extend(quads_of[i].iter().map(|&q| qual(p, &nrm, q)));
                let after = new_q.iter().cloned().fold(f64::INFINITY, f64::min);
                if after >= before {
                    for (&q, &v) in quads_of[i].iter().zip(&new_q) {
                        qv[q as usize] = v;
                    }
                    // only a move above the stop displacement wakes the
                    // ring up for the next sweep (on a 130k-quad face most
                    // nodes settle after a few sweeps; the rest need not be
                    // visited 30 times)
                    if vec3::dist(nx, old_x) > opts.stop_displacement * edge {
                        converged = false;
                        moved[i] = true;
                    }
                    report.moves += 1;
                    done = true;
                    break;
                }
                // rollback, bit for bit
                p.nodes[i].uv = old_uv;
                p.pos[i] = old_x;
                nrm[i] = old_n;
            }
            if !done {
                report.rejected += 1;
            }
        }
        // a sweep whose kept moves raised the average by less than
        // ASCENT_STALL: the ascent has stalled (a sweep without a kept move
        // goes on: its nodes try again with smaller steps)
        if objective == Objective::Average
            && sweep_moves < report.moves
            && sweep_gain < ASCENT_STALL * touched.len() as f64
        {
            break;
        }
        if converged {
            break;
        }
        if objective == Objective::Kernels {
            for (f, (i, ring)) in free.iter().enumerate() {
                active[f] = moved[*i as usize] || ring.iter().any(|&r| moved[r as usize]);
            }
        }
        for (i, _) in &free {
            moved[*i as usize] = false;
        }
    }
    let after = stats(&qv);
    let worst_kept = match objective {
        Objective::Kernels => after.0 >= report.before.0,
        Objective::Average => after.0 >= ascent_floor(report.before.0),
    };
    if worst_kept && after.1 > report.before.1 {
        report.after = after;
    } else {
        for ((i, _), &(uv, x)) in free.iter().zip(&saved) {
            p.nodes[*i as usize].uv = uv;
            p.pos[*i as usize] = x;
        }
        for ((i, _), &nn) in free.iter().zip(&saved_nrm) {
            nrm[*i as usize] = nn;
        }
        for (&q, &v) in touched.iter().zip(&saved_qv) {
            qv[q as usize] = v;
        }
        report.kept = false;
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::patch::LocalNode;
    use crate::core::quality::quad_quality;
    use crate::smoothing::untangle;
    use geometry::{primitives, CornerId, CurveId};

    /// Ring `x₁..x₈` of the node at grid point (0, 0) under the map `f`.
    fn grid_ring(f: impl Fn(f64, f64) -> Vec3) -> [Vec3; 8] {
        // x₁ at +ξ, then counter-clockwise: edge neighbours odd, diagonals even
        let ij = [
            (1, 0),
            (1, 1),
            (0, 1),
            (-1, 1),
            (-1, 0),
            (-1, -1),
            (0, -1),
            (1, -1),
        ];
        ij.map(|(i, j)| f(i as f64, j as f64))
    }

    fn close(a: Vec3, b: Vec3, tol: f64) -> bool {
        vec3::dist(a, b) <= tol
    }

    #[test]
    fn winslow_fixes_affine_grids() {
        let maps: [Box<dyn Fn(f64, f64) -> Vec3>; 4] = [
            Box::new(|i, j| [i, j, 0.0]),
            // stretched 5:1
            Box::new(|i, j| [5.0 * i, j, 0.0]),
            // sheared and stretched, in a tilted plane of 3D, off the origin
            Box::new(|i, j| {
                [
                    2.0 + 3.0 * i + 1.2 * j,
                    -1.0 + 0.4 * i + 0.7 * j,
                    0.5 + 0.3 * i - 0.9 * j,
                ]
            }),
            // tiny scale
            Box::new(|i, j| [1e-6 * (i + 0.5 * j), 1e-6 * j, 0.0]),
        ];
        for f in &maps {
            let centre = f(0.0, 0.0);
            let x = winslow_point(&grid_ring(f)).expect("a regular stencil");
            let scale = vec3::dist(f(1.0, 0.0), centre);
            assert!(
                close(x, centre, 1e-12 * scale.max(1.0)),
                "{x:?} vs {centre:?}"
            );
        }
    }

    #[test]
    fn winslow_returns_a_perturbed_centre_in_one_step() {
        // the update does not depend on the centre: any start lands on the grid point
        let f = |i: f64, j: f64| [1.0 + 2.0 * i + 0.5 * j, 3.0 + 1.5 * j, 0.0];
        let ring = grid_ring(f);
        let x = winslow_point(&ring).unwrap();
        assert!(close(x, f(0.0, 0.0), 1e-12), "{x:?}");
        // a degenerate stencil is refused
        assert!(winslow_point(&[[1.0, 2.0, 3.0]; 8]).is_none());
    }

    #[test]
    fn angle_based_kernel_keeps_a_symmetric_star_at_its_centre() {
        // a regular star of valence k: edge neighbours on a circle, diagonals further out
        for k in [3usize, 4, 5, 6] {
            let mut ring = Vec::new();
            for j in 0..k {
                let a = 2.0 * std::f64::consts::PI * j as f64 / k as f64;
                let b = a + std::f64::consts::PI / k as f64;
                ring.push([a.cos(), a.sin(), 0.0]);
                ring.push([1.6 * b.cos(), 1.6 * b.sin(), 0.0]);
            }
            let x = angle_based_point([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], &ring).unwrap();
            assert!(close(x, [0.0, 0.0, 0.0], 1e-12), "valence {k}: {x:?}");
            // a displaced centre moves back toward it
            let x = angle_based_point([0.1, -0.2, 0.0], [0.0, 0.0, 1.0], &ring).unwrap();
            assert!(
                vec3::norm(x) < 0.5 * vec3::norm([0.1, -0.2, 0.0]),
                "valence {k}: {x:?}"
            );
        }
        // on a uniform grid (valence 4) the bisectors point straight at the centre
        let ring = grid_ring(|i, j| [i, j, 0.0]);
        let x = angle_based_point([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], &ring).unwrap();
        assert!(close(x, [0.0, 0.0, 0.0], 1e-12), "{x:?}");
    }

    /// An n × n grid of quads on the unit square face, nodes at `at(i, j)` in (u, v).
    fn grid_patch(face: &Face, n: usize, at: impl Fn(usize, usize) -> [f64; 2]) -> QuadPatch {
        let mut p = QuadPatch {
            nodes: Vec::new(),
            pos: Vec::new(),
            quads: Vec::new(),
            quad_tri: Vec::new(),
        };
        for j in 0..=n {
            for i in 0..=n {
                let inner = i > 0 && j > 0 && i < n && j < n;
                let node = if inner {
                    NodeRef::Interior
                } else {
                    NodeRef::Curve(CurveId(0), p.nodes.len() as u32 + 1)
                };
                let uv = at(i, j);
                p.nodes.push(LocalNode {
                    uv,
                    node,
                    pole: None,
                });
                p.pos.push(face.surface.eval(uv));
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                p.quads
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                p.quad_tri.push(p.quad_tri.len() as u32);
            }
        }
        // counter-clockwise about the face's oriented normal
        if quad_quality(face, &p.nodes, &p.pos, &p.quads[0]) < 0.0 {
            for q in &mut p.quads {
                q.reverse();
            }
        }
        p
    }

    fn qualities(face: &Face, p: &QuadPatch) -> Vec<f64> {
        p.quads
            .iter()
            .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
            .collect()
    }

    fn same_bits(a: &QuadPatch, b: &QuadPatch) -> bool {
        a.nodes
            .iter()
            .zip(&b.nodes)
            .all(|(x, y)| x.uv.map(f64::to_bits) == y.uv.map(f64::to_bits))
            && a.pos
                .iter()
                .zip(&b.pos)
                .all(|(x, y)| x.map(f64::to_bits) == y.map(f64::to_bits))
    }

    #[test]
    fn one_ring_walks_the_star_in_order() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let p = grid_patch(face, 2, |i, j| [i as f64 * 0.5, j as f64 * 0.5]);
        let star: Vec<u32> = (0..4).collect();
        let ring = one_ring(&p.quads, 4, &star).unwrap();
        assert_eq!(ring.len(), 8);
        // edge neighbours at even positions, diagonals at odd ones
        for (k, &r) in ring.iter().enumerate() {
            let edge = [1u32, 3, 5, 7].contains(&r);
            assert_eq!(edge, k % 2 == 0, "{ring:?}");
        }
        // a boundary node's star is not a disk
        assert!(one_ring(&p.quads, 1, &[0, 1]).is_none());
    }

    #[test]
    fn raising_the_average_squares_a_sheared_grid_and_keeps_its_boundary() {
        // a 4 × 4 grid of the unit square whose interior nodes are sheared
        // toward +u: its quads are parallelograms; the boundary is fixed
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let n = 4;
        let h = 1.0 / n as f64;
        let mut p = grid_patch(face, n, |i, j| {
            let inner = i > 0 && j > 0 && i < n && j < n;
            let shear = if inner {
                0.3 * h * (j as f64 - 2.0)
            } else {
                0.0
            };
            [i as f64 * h + shear, j as f64 * h]
        });
        let boundary: Vec<([f64; 2], Vec3)> = (0..p.nodes.len())
            .filter(|&i| p.nodes[i].node != NodeRef::Interior)
            .map(|i| (p.nodes[i].uv, p.pos[i]))
            .collect();
        let before = qualities(face, &p);
        let avg = |q: &[f64]| q.iter().sum::<f64>() / q.len() as f64;
        let r = raise_average(face, &mut p, 20);
        let after = qualities(face, &p);
        assert!(r.kept && r.moves > 0, "{r:?}");
        // the average rises to where nodes count as done (ASCENT_GOOD)
        assert!(
            avg(&before) < 0.95 && avg(&after) > ASCENT_GOOD,
            "{} → {}",
            avg(&before),
            avg(&after)
        );
        assert!((r.after.1 - avg(&after)).abs() < 1e-12);
        // no quad falls below its floor
        for (b, a) in before.iter().zip(&after) {
            assert!(*a >= ascent_floor(*b), "{b} → {a}");
        }
        // boundary nodes bit-identical, interior ones on the plane
        let still: Vec<([f64; 2], Vec3)> = (0..p.nodes.len())
            .filter(|&i| p.nodes[i].node != NodeRef::Interior)
            .map(|i| (p.nodes[i].uv, p.pos[i]))
            .collect();
        assert_eq!(boundary, still);
        assert!(p.pos.iter().all(|x| x[2] == 0.0));
        // on the square grid itself nothing moves
        let mut square = grid_patch(face, n, |i, j| [i as f64 * h, j as f64 * h]);
        let copy = square.clone();
        let r = raise_average(face, &mut square, 20);
        assert_eq!(r.moves, 0);
        assert!(same_bits(&square, &copy));
    }

    #[test]
    fn the_ascent_stops_after_a_sweep_that_gains_almost_nothing() {
        // a uniform 6 × 6 grid of 2:1 rectangles (SICN 0.8, below
        // ASCENT_DONE) is a maximum of the sum of the SICN: no move is kept,
        // and the steps shrink until every node gives up
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let n = 6;
        let h = 1.0 / n as f64;
        let at = |i: usize, j: usize| [i as f64 * h, 0.5 * j as f64 * h];
        let mut p = grid_patch(face, n, at);
        let copy = p.clone();
        let r = raise_average(face, &mut p, 40);
        assert!((r.before.1 - 0.8).abs() < 1e-9, "{r:?}");
        assert_eq!(r.moves, 0, "{r:?}");
        assert!(r.sweeps >= 4, "{r:?}");
        assert!(same_bits(&p, &copy));
        // the same grid 40 × 40 with one node a twentieth of its shortest
        // edge off: the first sweep's gradient step takes it back, which
        // raises the average of the 1 600 quads by about 5e-6, below
        // ASCENT_STALL; the ascent ends there (the other nodes, at the
        // maximum, would shrink their steps for three more sweeps)
        let (n40, h40) = (40, 1.0 / 40.0);
        let mut near = grid_patch(face, n40, |i, j| {
            let off = if (i, j) == (20, 20) {
                0.05 * 0.5 * h40
            } else {
                0.0
            };
            [i as f64 * h40 + off, 0.5 * j as f64 * h40]
        });
        let r = raise_average(face, &mut near, 40);
        let gain = r.after.1 - r.before.1;
        assert!(r.moves >= 1 && r.sweeps == 1, "{r:?}");
        assert!(gain > 0.0 && gain < ASCENT_STALL, "{r:?}");
        // a sheared grid gains more than that per sweep and runs on
        let mut sheared = grid_patch(face, n, |i, j| {
            let inner = i > 0 && j > 0 && i < n && j < n;
            let shear = if inner {
                0.3 * h * (j as f64 - 3.0)
            } else {
                0.0
            };
            [i as f64 * h + shear, 0.5 * j as f64 * h]
        });
        let r = raise_average(face, &mut sheared, 40);
        assert!(r.sweeps > 1 && r.after.1 > r.before.1 + 1e-3, "{r:?}");
    }

    #[test]
    fn the_floor_never_lowers_a_poor_quad_and_keeps_good_ones_above_half() {
        assert_eq!(ascent_floor(0.2), 0.2);
        assert_eq!(ascent_floor(0.5), 0.5);
        assert_eq!(ascent_floor(0.52), 0.5);
        assert!((ascent_floor(0.9) - 0.855).abs() < 1e-12);
    }

    #[test]
    fn a_perturbed_grid_returns_to_the_uniform_grid() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let n = 6;
        let h = 1.0 / n as f64;
        let mut p = grid_patch(face, n, |i, j| {
            let inner = i > 0 && j > 0 && i < n && j < n;
            // deterministic wobble of the interior nodes
            let d = if inner {
                0.3 * h * ((3 * i + 5 * j) as f64).sin()
            } else {
                0.0
            };
            [i as f64 * h + d, j as f64 * h - 0.7 * d]
        });
        let before = qualities(face, &p);
        let r = optimize(
            face,
            &mut p,
            &OptimizeOptions {
                max_sweeps: 200,
                stop_displacement: 1e-9,
            },
        );
        let after = qualities(face, &p);
        let (mn0, mn1) = (
            before.iter().cloned().fold(1.0, f64::min),
            after.iter().cloned().fold(1.0, f64::min),
        );
        assert!(r.kept && r.moves > 0, "{r:?}");
        assert!(mn1 >= mn0 && mn1 > 0.999, "min {mn0} → {mn1}");
        for (k, nd) in p.nodes.iter().enumerate() {
            let (i, j) = (k % (n + 1), k / (n + 1));
            assert!(
                (nd.uv[0] - i as f64 * h).abs() < 1e-6 && (nd.uv[1] - j as f64 * h).abs() < 1e-6,
                "node {k}: {:?}",
                nd.uv
            );
        }
    }

    #[test]
    fn a_uniform_grid_is_left_bit_for_bit() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let mut p = grid_patch(face, 4, |i, j| [i as f64 * 0.25, j as f64 * 0.25]);
        let orig = p.clone();
        let r = optimize(face, &mut p, &OptimizeOptions::default());
        assert!(same_bits(&p, &orig), "{r:?}");
    }

    #[test]
    fn rollback_restores_exact_positions() {
        // a 2 × 2 grid whose top middle node is pushed down into a notch: the
        // Winslow point of the centre is not where its worst quad is best, so
        // with the centre put at the best point of a fine search, both the
        // kernel's step and its half step lower the worst SICN and are refused
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let xy = |x: f64, y: f64| [0.5 + 0.4 * x, 0.5 + 0.4 * y];
        let at = |i: usize, j: usize| match (i, j) {
            (1, 2) => xy(0.0, 0.2),
            (i, j) => xy(i as f64 - 1.0, j as f64 - 1.0),
        };
        let mut p = grid_patch(face, 2, at);
        let worst = |p: &QuadPatch| qualities(face, p).into_iter().fold(f64::INFINITY, f64::min);
        let put = |p: &mut QuadPatch, uv: [f64; 2]| {
            p.nodes[4].uv = uv;
            p.pos[4] = face.surface.eval(uv);
        };
        let mut best = (f64::NEG_INFINITY, [0.5, 0.5]);
        for a in 0..=200 {
            for b in 0..=200 {
                let uv = [0.1 + 0.8 * a as f64 / 200.0, 0.1 + 0.8 * b as f64 / 200.0];
                put(&mut p, uv);
                let w = worst(&p);
                if w > best.0 {
                    best = (w, uv);
                }
            }
        }
        put(&mut p, best.1);
        let w0 = worst(&p);
        assert!(w0 > 0.0);
        let ring: Vec<Vec3> = one_ring(&p.quads, 4, &[0, 1, 2, 3])
            .unwrap()
            .iter()
            .map(|&r| p.pos[r as usize])
            .collect();
        let target = winslow_point(&[
            ring[0], ring[1], ring[2], ring[3], ring[4], ring[5], ring[6], ring[7],
        ])
        .unwrap();
        for frac in [1.0, 0.5] {
            let t = vec3::add(p.pos[4], vec3::scale(vec3::sub(target, p.pos[4]), frac));
            let mut q = p.clone();
            put(&mut q, [t[0], t[1]]);
            assert!(worst(&q) < w0 - 1e-3, "step {frac}: {} vs {w0}", worst(&q));
        }
        let orig = p.clone();
        let r = optimize(face, &mut p, &OptimizeOptions::default());
        assert_eq!(r.moves, 0, "{r:?}");
        assert!(r.rejected > 0 && !r.kept, "{r:?}");
        assert!(same_bits(&p, &orig));
        assert_eq!(worst(&p).to_bits(), w0.to_bits());
    }

    #[test]
    fn the_global_check_keeps_a_patch_whose_average_rose() {
        // a uniform grid except one node a hair off: the per-node checks allow the
        // moves, and the global check keeps them only because the average rose
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let mut p = grid_patch(face, 3, |i, j| {
            [
                i as f64 / 3.0 + if (i, j) == (1, 1) { 0.05 } else { 0.0 },
                j as f64 / 3.0,
            ]
        });
        let r = optimize(face, &mut p, &OptimizeOptions::default());
        assert!(
            r.kept && r.after.1 > r.before.1 && r.after.0 >= r.before.0,
            "{r:?}"
        );
        // no sweeps: nothing moves and the report says so
        let orig = p.clone();
        let r = optimize(
            face,
            &mut p,
            &OptimizeOptions {
                max_sweeps: 0,
                ..Default::default()
            },
        );
        assert_eq!(r.moves, 0);
        assert!(same_bits(&p, &orig));
    }

    /// An n × n grid of the unit square whose interior nodes are moved by
    /// up to `amp` in a fixed pattern.
    fn perturbed_grid(face: &Face, n: usize, amp: f64) -> QuadPatch {
        grid_patch(face, n, |i, j| {
            let inner = i > 0 && j > 0 && i < n && j < n;
            let d = if inner {
                amp * ((i + 2 * j) as f64).cos()
            } else {
                0.0
            };
            [i as f64 / n as f64 + d, j as f64 / n as f64 - d]
        })
    }

    #[test]
    fn optimize_nodes_moves_only_the_listed_nodes() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let mut p = perturbed_grid(face, 4, 0.05);
        let orig = p.clone();
        let r = optimize_nodes(face, &mut p, Some(&[6, 12]), &OptimizeOptions::default());
        assert!(r.kept && r.moves > 0, "{r:?}");
        for k in 0..p.nodes.len() {
            let same = p.nodes[k].uv.map(f64::to_bits) == orig.nodes[k].uv.map(f64::to_bits);
            assert_eq!(same, k != 6 && k != 12, "node {k}");
        }
    }

    #[test]
    fn optimize_around_moves_only_the_changed_vertices_and_their_neighbours() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let n = 6;
        let mut p = perturbed_grid(face, n, 0.04);
        let orig = p.clone();
        crate::smoothing::optimize_around(face, &mut p, &[]);
        assert!(same_bits(&p, &orig), "nothing changed, nothing moves");
        // node (2, 2): the quads around it span (1..=3, 1..=3)
        let id = |i: usize, j: usize| j * (n + 1) + i;
        crate::smoothing::optimize_around(face, &mut p, &[id(2, 2) as u32]);
        let mut moved = 0;
        for j in 0..=n {
            for i in 0..=n {
                let k = id(i, j);
                let same = p.nodes[k].uv.map(f64::to_bits) == orig.nodes[k].uv.map(f64::to_bits);
                if !same {
                    moved += 1;
                    assert!(
                        (1..=3).contains(&i) && (1..=3).contains(&j),
                        "node ({i}, {j}) moved"
                    );
                }
            }
        }
        assert!(moved > 0, "the perturbed vertices near (2, 2) are smoothed");
    }

    #[test]
    fn poor_quads_are_lifted_or_the_face_is_left_alone() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        let worst = |p: &QuadPatch| qualities(face, p).into_iter().fold(f64::INFINITY, f64::min);
        // the centre of a 2 × 2 grid pushed close to a corner: poor but not inverted
        let mut p = grid_patch(face, 2, |i, j| {
            if (i, j) == (1, 1) {
                [0.76, 0.73]
            } else {
                [i as f64 * 0.5, j as f64 * 0.5]
            }
        });
        assert!(worst(&p) > 0.0 && worst(&p) < 0.1, "{}", worst(&p));
        assert!(crate::smoothing::lift_poor_quads(face, &mut p, 0.1, &[]));
        assert!(worst(&p) >= 0.1, "{}", worst(&p));
        // nothing to move (a single quad, all its nodes on the boundary): unchanged
        let mut q = grid_patch(face, 1, |i, j| {
            if (i, j) == (1, 1) {
                [0.05, 1.0]
            } else {
                [i as f64, j as f64]
            }
        });
        let orig = q.clone();
        let before = worst(&q);
        assert!(before < 0.1, "{before}");
        assert!(!crate::smoothing::lift_poor_quads(face, &mut q, 0.1, &[]));
        assert!(same_bits(&q, &orig));
    }

    #[test]
    fn the_untangler_repairs_a_folded_quad() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        // the centre of a 2 × 2 grid pushed past the far corner: quads fold over
        let mut p = grid_patch(face, 2, |i, j| {
            if (i, j) == (1, 1) {
                [0.97, 0.93]
            } else {
                [i as f64 * 0.5, j as f64 * 0.5]
            }
        });
        assert!(
            qualities(face, &p).iter().any(|&q| q < 0.0),
            "{:?}",
            qualities(face, &p)
        );
        untangle(face, &mut p, 0.1, 8, 10, &[]);
        let q = qualities(face, &p);
        assert!(q.iter().all(|&s| s > 0.1), "{q:?}");
    }

    #[test]
    fn a_cusp_tip_quad_is_weighted_so_the_quads_beyond_it_open_up() {
        let m = primitives::square(1.0);
        let face = &m.faces[0];
        // a wedge of half-slope 0.04 from a corner at the origin, with curve
        // nodes at x = 0.5 and 0.625: the split tip triangle's centre C sits
        // almost at the far end, so the two quads beyond the tip quad are
        // slivers at R1 and L1
        let slope = 0.04;
        let at = [
            ([0.0, 0.0], NodeRef::Corner(CornerId(0))),           // T
            ([0.5, -0.5 * slope], NodeRef::Curve(CurveId(0), 1)), // R1
            ([0.625, -0.625 * slope], NodeRef::Curve(CurveId(0), 2)), // R2
            ([0.625, 0.0], NodeRef::Curve(CurveId(1), 1)),        // M
            ([0.625, 0.625 * slope], NodeRef::Curve(CurveId(2), 2)), // L2
            ([0.5, 0.5 * slope], NodeRef::Curve(CurveId(2), 1)),  // L1
            ([0.62, 0.0], NodeRef::Interior),                     // C
        ];
        let mut p = QuadPatch {
            nodes: at
                .iter()
                .map(|&(uv, node)| LocalNode {
                    uv,
                    node,
                    pole: None,
                })
                .collect(),
            pos: at.iter().map(|&(uv, _)| face.surface.eval(uv)).collect(),
            quads: vec![[0, 1, 6, 5], [1, 2, 3, 6], [6, 3, 4, 5]],
            quad_tri: vec![0, 0, 0],
        };
        if quad_quality(face, &p.nodes, &p.pos, &p.quads[0]) < 0.0 {
            p.quads.iter_mut().for_each(|q| q.reverse());
        }
        let beyond = |p: &QuadPatch| {
            qualities(face, p)[1..]
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min)
        };
        // the tip quad's corner at T caps it near sin(2 atan 0.04) ≈ 0.08
        let tip = qualities(face, &p)[0];
        assert!(tip > 0.0 && tip < 0.09, "{tip}");
        assert!(beyond(&p) < 0.05, "{}", beyond(&p));
        // counted at face value, the tip quad pins C: the quads beyond stay poor
        let mut plain = p.clone();
        untangle(face, &mut plain, 0.1, 8, 10, &[]);
        assert!(beyond(&plain) < 0.1, "{}", beyond(&plain));
        // weighted, C moves back toward R1 and L1 and the quads beyond open up
        untangle(face, &mut p, 0.1, 8, 10, &[CornerId(0)]);
        let q = qualities(face, &p);
        assert!(beyond(&p) > 0.25, "{q:?}");
        assert!(q[0] > 0.0, "the tip quad stays valid: {q:?}");
        // only C moved
        assert!(p.nodes[..6].iter().zip(&at).all(|(n, a)| n.uv == a.0));
    }
}
