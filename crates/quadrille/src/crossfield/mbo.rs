//! The multilevel MBO heat diffusion of Algorithm 1 (spec §2.4–2.6) and the
//! one-triangle boundary-condition extension.
//!
//! Per level `l` (α_l linear from `(0.1·d)²` down to `(3·h_min)²`), the
//! matrix `M + α_l K` restricted to the free edges is factorized once; then
//! backward-Euler steps `(M + α K) U⁺ = M U − α K_FB U_B` alternate with the
//! projection `u ← u / |u|` until the ∞-norm change between projected
//! iterates is at most the tolerance.

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
    (0..levels).map(|l| a0 + (a1 - a0) * l as f64 / (levels - 1) as f64).collect()
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
pub fn extend_boundary_conditions(topo: &FaceTopology, fixed: &mut [bool], u: &mut [Cplx]) -> Result<usize, CrossFieldError> {
    let active: Vec<bool> = topo.triangles.iter().map(|t| t.iter().any(|&v| topo.on_feature[v as usize])).collect();
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
    let dirs = [[0.8017837257372732, 0.5345224838248488, 0.2672612419124244], [-0.2672612419124244, 0.8017837257372732, -0.5345224838248488]];
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

/// Runs Algorithm 1 on the free edges (`fixed[e] == false`), updating `u`.
/// Returns per-level statistics.
pub fn diffuse(topo: &FaceTopology, fixed: &[bool], u: &mut [Cplx], opts: &CrossFieldOptions) -> Result<Vec<LevelStats>, CrossFieldError> {
    let active = vec![true; topo.triangles.len()];
    let sys = assemble(topo, &active, fixed, u)?;
    let n = sys.free.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let mut cur: Vec<c64> = sys.free.iter().map(|&e| c64::new(u[e as usize][0], u[e as usize][1])).collect();
    let mut rhs = vec![c64::new(0.0, 0.0); n];
    let mut vals = vec![c64::new(0.0, 0.0); sys.stiffness.len()];
    let mut stats = Vec::new();
    for alpha in level_alphas(topo.diagonal, topo.h_min, opts.levels) {
        let t0 = Instant::now();
        for (v, k) in vals.iter_mut().zip(&sys.stiffness) {
            *v = k * alpha;
        }
        for j in 0..n {
            vals[sys.spd.pattern.diag(j)] += c64::new(sys.mass[j], 0.0);
        }
        let f = sys.spd.factor(&vals)?;
        let factor_time = t0.elapsed().as_secs_f64();
        let mut iterations = 0;
        let mut change = f64::INFINITY;
        while iterations < opts.max_iterations {
            for j in 0..n {
                rhs[j] = cur[j] * sys.mass[j] - sys.coupling[j] * alpha;
            }
            f.solve_in_place(&mut rhs);
            iterations += 1;
            change = 0.0;
            for j in 0..n {
                let v = normalized(rhs[j]).unwrap_or(if cur[j].re == 0.0 && cur[j].im == 0.0 { c64::new(1.0, 0.0) } else { cur[j] });
                change = f64::max(change, f64::max((v.re - cur[j].re).abs(), (v.im - cur[j].im).abs()));
                cur[j] = v;
            }
            if change <= opts.tolerance {
                break;
            }
        }
        stats.push(LevelStats { alpha, iterations, final_change: change, factor_seconds: factor_time, seconds: t0.elapsed().as_secs_f64() });
    }
    for (j, &e) in sys.free.iter().enumerate() {
        u[e as usize] = [cur[j].re, cur[j].im];
    }
    Ok(stats)
}
