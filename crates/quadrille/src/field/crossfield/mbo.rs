//! The multilevel MBO heat diffusion of Algorithm 1 (spec §2.4–2.6) and the
//! one-triangle boundary-condition extension.
//!
//! Per level `l` (α_l linear from `(0.1·d)²` down to `(3·h_min)²`), the
//! matrix `M + α_l K` restricted to the free edges is factorized once (into
//! the same buffers, after one symbolic analysis); then backward-Euler steps
//! `(M + α K) U⁺ = M u − α K_FB U_B` alternate with the projection
//! `u ← U⁺ / |U⁺|` until the ∞-norm change between the solutions `U` of
//! successive solves (before projection) is at most the tolerance, or the
//! level reaches `max_iterations` (see [`diffuse`]).

use std::time::Instant;

use faer::c64;
use geometry::vec3;

use super::assembly::assemble;
use super::topology::{Cplx, FaceTopology, NONE};
use super::{CrossFieldError, CrossFieldOptions, LevelStats};

/// The diffusion coefficients of the levels: linear in α from
/// `(0.1·diagonal)²` to `(3·h_min)²`; a single level `(3·h_min)²` when the
/// face is so small or coarse that the final α is not below the initial one.
pub fn level_alphas(diagonal: f64, h_min: f64, levels: usize) -> Vec<f64> {
    let a0 = (0.1 * diagonal).powi(2);
    let a1 = (3.0 * h_min).powi(2);
    if a1 >= a0 || levels <= 1 {
        return vec![a1];
    }
    (0..levels)
        .map(|l| a0 + (a1 - a0) * l as f64 / (levels - 1) as f64)
        .collect()
}

/// Normalizes `v`; returns `None` when its norm is below 1e-12.
#[inline]
fn normalized(v: c64) -> Option<c64> {
    let n = (v.re * v.re + v.im * v.im).sqrt();
    if n > 1e-12 && n.is_finite() {
        Some(c64::new(v.re / n, v.im / n))
    } else {
        None
    }
}

/// Solves the one-triangle boundary layer (spec §2.6): every triangle with a
/// vertex on a feature curve gets its three edges fixed, valued by the
/// discrete Laplace equation on that layer with `u = 1` on feature edges and
/// natural conditions on the layer's inner side. Marks these edges fixed.
pub fn extend_boundary_conditions(
    topo: &FaceTopology,
    fixed: &mut [bool],
    u: &mut [Cplx],
) -> Result<usize, CrossFieldError> {
    let active: Vec<bool> = topo
        .triangles
        .iter()
        .map(|t| t.iter().any(|&v| topo.on_feature[v as usize]))
        .collect();
    let sys = assemble(topo, &active, fixed, u)?;
    let n = sys.free.len();
    if n == 0 {
        return Ok(0);
    }
    // A tiny mass shift guards against round-off; the layer Laplacian with
    // Dirichlet edges is positive definite in exact arithmetic.
    let mut vals = sys.stiffness.clone();
    for j in 0..n {
        let p = sys.spd.pattern.diag(j);
        let shift = 1e-10 * vals[p].re.abs() + 1e-300;
        vals[p] += c64::new(shift, 0.0);
    }
    let f = sys.spd.factor(&vals)?;
    let mut x: Vec<c64> = sys.coupling.iter().map(|c| -c).collect();
    f.solve_in_place(&mut x);
    for (j, &e) in sys.free.iter().enumerate() {
        let v = normalized(x[j]).unwrap_or(c64::new(1.0, 0.0));
        u[e as usize] = [v.re, v.im];
        fixed[e as usize] = true;
    }
    Ok(n)
}

/// A deterministic non-trivial start for a surface without any Dirichlet
/// edge: the cross containing the projection of a fixed generic 3D direction
/// onto the first triangle of each edge.
pub fn closed_surface_start(topo: &FaceTopology, u: &mut [Cplx]) {
    let dirs = [
        [0.8017837257372732, 0.5345224838248488, 0.2672612419124244],
        [-0.2672612419124244, 0.8017837257372732, -0.5345224838248488],
    ];
    for e in 0..topo.edges.len() {
        let t = topo.edge_tris[e][0];
        if t == NONE {
            continue;
        }
        let n = topo.normals[t as usize];
        let te = topo.edge_dir[e];
        let mut best = [1.0, 0.0];
        for d in dirs {
            let dt = vec3::sub(d, vec3::scale(n, vec3::dot(d, n)));
            if vec3::norm(dt) > 0.3 {
                let c = vec3::dot(dt, te);
                let s = vec3::dot(vec3::cross(te, dt), n);
                let th = 4.0 * s.atan2(c);
                best = [th.cos(), th.sin()];
                break;
            }
        }
        u[e] = best;
    }
}

/// Every how many iterations of a level [`diffuse`] tries an extrapolation.
pub const EXTRAPOLATION_PERIOD: usize = 3;

/// Largest extrapolation weight: the extrapolated step is at most this many
/// times the last change.
pub const MAX_EXTRAPOLATION: f64 = 4.0;

/// Weight ω of the extrapolation `U + ω (U − U_prev)` of the last solution
/// `U` (see [`diffuse`]), or 0 when the last two changes `Δ₁ = U − U_prev`,
/// `Δ₀ = U_prev − U_prev2` do not look like the geometric convergence of one
/// slow mode: ω = ρ / (1 − ρ) with ρ = ‖Δ₁‖ / ‖Δ₀‖ (mass-weighted norms),
/// used when ρ < 1 and the two changes are nearly parallel (cosine ≥ 0.9),
/// capped at [`MAX_EXTRAPOLATION`].
pub fn extrapolation_weight(sol: &[c64], prev: &[c64], prev2: &[c64], mass: &[f64]) -> f64 {
    let (mut n1, mut n0, mut dot) = (0.0, 0.0, 0.0);
    for j in 0..sol.len() {
        let d1 = sol[j] - prev[j];
        let d0 = prev[j] - prev2[j];
        n1 += d1.norm_sqr() * mass[j];
        n0 += d0.norm_sqr() * mass[j];
        dot += (d1.conj() * d0).re * mass[j];
    }
    if !(n0 > 0.0 && n1 > 0.0 && dot >= 0.9 * (n1 * n0).sqrt()) {
        return 0.0;
    }
    let rho = (n1 / n0).sqrt();
    if rho < 1.0 {
        (rho / (1.0 - rho)).min(MAX_EXTRAPOLATION)
    } else {
        0.0
    }
}

/// Runs Algorithm 1 on the free edges (`fixed[e] == false`), starting from
/// and updating `u`. Returns per-level statistics.
///
/// Convergence test of a level: `‖U_{i+1} − U_i‖_∞ ≤ tolerance`, where `U_i`
/// is the solution of the i-th linear solve **before** the projection (the
/// first solve of a level is compared with the last one of the previous
/// level). The projected iterates are not suitable: at a singularity the
/// diffused field is nearly zero and its direction is arbitrary, so a shift
/// of the singularity by a fraction of a triangle turns the normalized value
/// of its few edges by up to 45° (a change of up to 2 in `u`), and their
/// ∞-norm change stays of order 0.1–1 as long as a singularity moves at all
/// (at the final level, `α = (3 h_min)²`, singularities creep by about a
/// triangle per 10–20 iterations, so it never drops to 1e-3). Before the
/// projection the same edges carry values of norm ≈ 0.01, and the test
/// measures the field where it is defined. The Gmsh implementation by the
/// paper's authors tests the same quantity through its norms (largest
/// increase of `|U|` between solves, threshold 1e-3).
///
/// After the first solve of a level, the change must be below the tolerance
/// on two successive solves, the second no larger than the first: a change
/// that is small but grows means that the iterate is leaving an unstable
/// fixed point, not converging. This happens on symmetric faces: from
/// `U₀ = 0` the first solve on a disk vanishes at the centre, an index +4
/// zero that the iteration leaves only as the mesh's asymmetry grows, over
/// several solves that change the field by less than 1e-4 each (the third
/// solve on the 100k disk: 6e-5, then 7e-5, 9e-5, 2e-4, 2e-3, … as the zero
/// splits into four +1 that move out to r ≈ 0.75).
///
/// Extrapolation. Within a level the iteration converges linearly, and
/// slowly where a singularity has far to travel: its distance to its place
/// shrinks by a factor ρ ≈ 0.8–0.95 per solve (the 100k pentagon's −1 needs
/// 26, 21 and 41 solves at the first three levels). Every
/// [`EXTRAPOLATION_PERIOD`]-th solve of a level (not the last one allowed),
/// when the last two changes are nearly parallel and shrinking — one slow
/// mode dominates — the solution is moved to the limit of that geometric
/// sequence, `U + ρ/(1−ρ) (U − U_prev)` (at most [`MAX_EXTRAPOLATION`] times
/// the last change, see [`extrapolation_weight`]), before the projection.
/// The fixed points are those of Algorithm 1, the convergence test and the
/// stored solutions use the plain solves, and the next solves correct any
/// overshoot. The same pentagon then converges in 15, 9 and 21 solves, and
/// with 8 solves per level its −1 ends 0.016 from its place with converged
/// levels (without extrapolation: 0.074, and 0.048 with 10 solves per
/// level).
pub fn diffuse(
    topo: &FaceTopology,
    fixed: &[bool],
    u: &mut [Cplx],
    opts: &CrossFieldOptions,
) -> Result<Vec<LevelStats>, CrossFieldError> {
    let active = vec![true; topo.triangles.len()];
    let sys = assemble(topo, &active, fixed, u)?;
    let n = sys.free.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    // projected iterate; solutions of the current solve and of the two before
    let mut cur: Vec<c64> = sys
        .free
        .iter()
        .map(|&e| c64::new(u[e as usize][0], u[e as usize][1]))
        .collect();
    let mut sol = vec![c64::new(0.0, 0.0); n];
    let mut prev = vec![c64::new(0.0, 0.0); n];
    let mut prev2 = vec![c64::new(0.0, 0.0); n];
    let mut vals = vec![c64::new(0.0, 0.0); sys.stiffness.len()];
    let mut factor = None;
    let mut stats = Vec::new();
    for alpha in level_alphas(topo.diagonal, topo.h_min, opts.levels) {
        let t0 = Instant::now();
        for (v, k) in vals.iter_mut().zip(&sys.stiffness) {
            *v = k * alpha;
        }
        for j in 0..n {
            vals[sys.spd.pattern.diag(j)] += c64::new(sys.mass[j], 0.0);
        }
        let f = match factor.as_mut() {
            None => factor.insert(sys.spd.factor(&vals)?),
            Some(f) => {
                sys.spd.refactor(&vals, f)?;
                f
            }
        };
        let factor_time = t0.elapsed().as_secs_f64();
        let mut iterations = 0;
        let mut change = f64::INFINITY;
        let mut last_change = f64::INFINITY;
        while iterations < opts.max_iterations {
            for j in 0..n {
                sol[j] = cur[j] * sys.mass[j] - sys.coupling[j] * alpha;
            }
            f.solve_in_place(&mut sol);
            iterations += 1;
            change = 0.0;
            for j in 0..n {
                let (y, p) = (sol[j], prev[j]);
                change = f64::max(change, f64::max((y.re - p.re).abs(), (y.im - p.im).abs()));
            }
            let converged = change <= opts.tolerance
                && (iterations == 1 || (last_change <= opts.tolerance && change <= last_change));
            let omega = if !converged
                && iterations % EXTRAPOLATION_PERIOD == 0
                && iterations < opts.max_iterations
            {
                extrapolation_weight(&sol, &prev, &prev2, &sys.mass)
            } else {
                0.0
            };
            for j in 0..n {
                let y = sol[j] + (sol[j] - prev[j]) * omega;
                // an exact zero keeps the previous direction ((1, 0) after a zero start)
                cur[j] = normalized(y)
                    .or_else(|| normalized(cur[j]))
                    .unwrap_or(c64::new(1.0, 0.0));
            }
            // prev2 ← prev ← sol (the raw solutions, not extrapolated)
            std::mem::swap(&mut prev, &mut prev2);
            std::mem::swap(&mut sol, &mut prev);
            if converged {
                break;
            }
            last_change = change;
        }
        stats.push(LevelStats {
            alpha,
            iterations,
            final_change: change,
            factor_seconds: factor_time,
            seconds: t0.elapsed().as_secs_f64(),
        });
    }
    for (j, &e) in sys.free.iter().enumerate() {
        u[e as usize] = [cur[j].re, cur[j].im];
    }
    Ok(stats)
}
