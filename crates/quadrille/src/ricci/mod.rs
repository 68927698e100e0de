//! S3 of `quadrille spline` (spec ricci-flow-iga-reconstruction §5, paper
//! Eq. 5–11): discrete Euclidean Ricci flow with the inversive-distance
//! circle-packing metric. Every vertex gets a conformal factor `u`; edge
//! lengths follow ℓ² = e^{2uᵢ} + e^{2uⱼ} + 2 ηᵢⱼ e^{uᵢ+uⱼ} with η fixed from
//! the input lengths, and Newton's method on the negated Eq. 10 drives the
//! curvature K to the targets K̄ = I·π/2 at cones and 0 elsewhere (boundary
//! included: a straight geodesic boundary between corner cones).
//!
//! The flow uses the mesh as given; [`refine_cone_rings`] splits the edges
//! at cones beforehand when the caller wants finer cone neighbourhoods (a
//! coarse one shows as a failed Newton step).

use thiserror::Error;

mod corners;
mod refine;
pub use corners::boundary_corner_cones;
pub use refine::refine_cone_rings;

use crate::field::crossfield::linsolve::Factor;
use crate::field::{LowerPattern, SparseSpd};
use crate::shell::{Shell, ShellTopology};

/// A cone singularity: a vertex and its integer index I (spec §1.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cone {
    /// The shell vertex.
    pub vertex: usize,
    /// Index I: target curvature K̄ = I·π/2.
    pub index: i32,
}

/// Stopping rules of the Newton iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RicciOptions {
    /// Stop at max |K̄ − K| below this (radians).
    pub tolerance: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
}

impl Default for RicciOptions {
    fn default() -> Self {
        RicciOptions {
            tolerance: 1e-9,
            max_iterations: 100,
        }
    }
}

/// The flat cone metric the flow converged to.
#[derive(Clone, Debug, PartialEq)]
pub struct RicciMetric {
    /// Conformal factor per vertex (log of the circle radius).
    pub u: Vec<f64>,
    /// Inversive distance per edge of [`ShellTopology::edges`] (fixed).
    pub eta: Vec<f64>,
    /// Final length per edge.
    pub lengths: Vec<f64>,
    /// Target curvature per vertex.
    pub target: Vec<f64>,
    /// Final curvature per vertex.
    pub curvature: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Final max |K̄ − K|.
    pub max_error: f64,
    /// max |K̄ − K| before each iteration and at the end.
    pub history: Vec<f64>,
}

impl RicciMetric {
    /// Lengths of triangle `f`'s sides, side `k` from corner `k` to `k + 1`.
    pub fn triangle_lengths(&self, topo: &ShellTopology, f: usize) -> [f64; 3] {
        let e = topo.triangle_edges[f];
        [self.lengths[e[0]], self.lengths[e[1]], self.lengths[e[2]]]
    }
}

/// Why the flow could not start or did not converge.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RicciError {
    /// A cone on a vertex that does not exist.
    #[error("cone on vertex {vertex}: no such vertex (the shell has {count})")]
    ConeVertex {
        /// The vertex.
        vertex: usize,
        /// Vertices of the shell.
        count: usize,
    },
    /// Two cones on one vertex.
    #[error("two cones on vertex {vertex} at {position:?}")]
    DuplicateCone {
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
    },
    /// A cone whose target angle sum is not positive.
    #[error("cone on vertex {vertex} at {position:?}: index {index} gives a target angle sum {angle:.4} ≤ 0 (interior I ≤ 3, boundary I ≤ 1)")]
    ConeAngle {
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
        /// The index.
        index: i32,
        /// Target angle sum.
        angle: f64,
    },
    /// The targets break discrete Gauss–Bonnet.
    #[error("cone indices sum to Σ I = {index_sum} (Σ K̄ = {target_sum:.6}) but Gauss–Bonnet needs Σ I = 4χ = {needed} (Σ K̄ = 2πχ = {gauss_bonnet:.6}, χ = {euler})")]
    IndexSum {
        /// Σ I of the cones.
        index_sum: i64,
        /// Σ K̄ = π/2 Σ I.
        target_sum: f64,
        /// 4χ.
        needed: i64,
        /// 2πχ.
        gauss_bonnet: f64,
        /// χ.
        euler: i64,
    },
    /// The flow needs one connected shell.
    #[error("Ricci flow: the shell has {0} connected components; run each on its own")]
    Components(usize),
    /// A zero-length edge.
    #[error("Ricci flow: edge between {a:?} and {b:?} has length {length:e}")]
    DegenerateEdge {
        /// One end.
        a: [f64; 3],
        /// The other end.
        b: [f64; 3],
        /// Its length.
        length: f64,
    },
    /// No step length keeps the triangles valid and lowers the residual.
    #[error("Ricci Newton step failed at iteration {iteration}: max|K̄ − K| = {residual:.3e} at vertex {vertex} {position:?}; {hint}")]
    StepFailed {
        /// Iteration.
        iteration: usize,
        /// Residual max |K̄ − K|.
        residual: f64,
        /// The worst vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
        /// What to try.
        hint: &'static str,
    },
    /// Out of iterations.
    #[error("Ricci flow did not converge in {iterations} iterations: max|K̄ − K| = {residual:.3e} at vertex {vertex} {position:?}; {hint}")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Residual max |K̄ − K|.
        residual: f64,
        /// The worst vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
        /// What to try.
        hint: &'static str,
    },
    /// The Hessian could not be factored.
    #[error("Ricci Newton iteration {iteration}: Hessian factorization failed ({message}); refine the one-rings of cones or the mesh")]
    Solver {
        /// Iteration.
        iteration: usize,
        /// Solver message.
        message: String,
    },
}

const HINT: &str = "refine the one-rings of cones (or the mesh), or move cones away from each other and the boundary";

/// Target curvature per vertex: I·π/2 at cones, 0 elsewhere. Checks the
/// cones (vertex exists, once each, positive target angle) and Σ K̄ = 2πχ.
pub fn target_curvature(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
) -> Result<Vec<f64>, RicciError> {
    let n = shell.vertices.len();
    let mut target = vec![0.0; n];
    let mut has_cone = vec![false; n];
    let mut index_sum = 0i64;
    for c in cones {
        if c.vertex >= n {
            return Err(RicciError::ConeVertex {
                vertex: c.vertex,
                count: n,
            });
        }
        let position = shell.vertices[c.vertex];
        if has_cone[c.vertex] {
            return Err(RicciError::DuplicateCone {
                vertex: c.vertex,
                position,
            });
        }
        has_cone[c.vertex] = true;
        let full = if topo.on_boundary[c.vertex] { 2 } else { 4 };
        let angle = f64::from(full - c.index) * std::f64::consts::FRAC_PI_2;
        if full - c.index <= 0 {
            return Err(RicciError::ConeAngle {
                vertex: c.vertex,
                position,
                index: c.index,
                angle,
            });
        }
        target[c.vertex] = f64::from(c.index) * std::f64::consts::FRAC_PI_2;
        index_sum += i64::from(c.index);
    }
    if index_sum != 4 * topo.euler {
        return Err(RicciError::IndexSum {
            index_sum,
            target_sum: index_sum as f64 * std::f64::consts::FRAC_PI_2,
            needed: 4 * topo.euler,
            gauss_bonnet: 2.0 * std::f64::consts::PI * topo.euler as f64,
            euler: topo.euler,
        });
    }
    Ok(target)
}

/// Angles of a triangle with side lengths `l` (side `k` from corner `k` to
/// `k + 1`), or `None` unless every triangle inequality holds strictly.
/// Corner `k` is opposite side `k + 1`.
fn corner_angles(l: [f64; 3]) -> Option<[f64; 3]> {
    let s = 0.5 * (l[0] + l[1] + l[2]);
    let d = [s - l[0], s - l[1], s - l[2]];
    if d.iter().any(|&x| x <= 0.0) {
        return None;
    }
    // Corner k: opposite side o = k+1, adjacent sides k and k+2. Half-angle
    // formula: tan(θ/2) = sqrt((s−p)(s−q) / (s (s−o))).
    Some(std::array::from_fn(|k| {
        let o = (k + 1) % 3;
        let (p, q) = (k, (k + 2) % 3);
        2.0 * (d[p] * d[q]).sqrt().atan2((s * d[o]).sqrt())
    }))
}

/// Lengths from the conformal factors.
fn lengths_from(u: &[f64], eta: &[f64], topo: &ShellTopology, out: &mut [f64]) {
    for (e, [a, b]) in topo.edges.iter().enumerate() {
        let (ga, gb) = (u[*a].exp(), u[*b].exp());
        out[e] = (ga * ga + gb * gb + 2.0 * eta[e] * ga * gb).max(0.0).sqrt();
    }
}

/// Curvature per vertex from edge lengths, or `None` when a triangle
/// inequality fails.
fn curvature_from(shell: &Shell, topo: &ShellTopology, lengths: &[f64]) -> Option<Vec<f64>> {
    let mut k: Vec<f64> = topo
        .on_boundary
        .iter()
        .map(|&b| {
            if b {
                std::f64::consts::PI
            } else {
                2.0 * std::f64::consts::PI
            }
        })
        .collect();
    for (f, t) in shell.triangles.iter().enumerate() {
        let e = topo.triangle_edges[f];
        let a = corner_angles([lengths[e[0]], lengths[e[1]], lengths[e[2]]])?;
        for c in 0..3 {
            k[t[c]] -= a[c];
        }
    }
    Some(k)
}

fn max_error(target: &[f64], k: &[f64]) -> (f64, usize) {
    let mut worst = (0.0, 0);
    for (i, (a, b)) in target.iter().zip(k).enumerate() {
        let d = (a - b).abs();
        if d > worst.0 {
            worst = (d, i);
        }
    }
    worst
}

fn norm2(target: &[f64], k: &[f64]) -> f64 {
    target
        .iter()
        .zip(k)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// Runs the flow from the input metric to the cone targets (spec §5.3–5.4).
pub fn ricci_flow(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
    options: &RicciOptions,
) -> Result<RicciMetric, RicciError> {
    if topo.components != 1 {
        return Err(RicciError::Components(topo.components));
    }
    let target = target_curvature(shell, topo, cones)?;
    let n = shell.vertices.len();
    let ne = topo.edges.len();
    // Initial radii: a third of the shortest incident edge; η from the input.
    let input: Vec<f64> = topo
        .edges
        .iter()
        .map(|&[a, b]| shell.edge_length(a, b))
        .collect();
    let mut shortest = vec![f64::INFINITY; n];
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        if input[e] <= 0.0 || !input[e].is_finite() {
            return Err(RicciError::DegenerateEdge {
                a: shell.vertices[a],
                b: shell.vertices[b],
                length: input[e],
            });
        }
        shortest[a] = shortest[a].min(input[e]);
        shortest[b] = shortest[b].min(input[e]);
    }
    let mut u: Vec<f64> = shortest.iter().map(|&l| (l / 3.0).ln()).collect();
    let eta: Vec<f64> = topo
        .edges
        .iter()
        .enumerate()
        .map(|(e, &[a, b])| {
            let (ga, gb) = (u[a].exp(), u[b].exp());
            (input[e] * input[e] - ga * ga - gb * gb) / (2.0 * ga * gb)
        })
        .collect();
    let mut lengths = vec![0.0; ne];
    lengths_from(&u, &eta, topo, &mut lengths);
    let worst_position = |v: usize| shell.vertices[v];
    let mut k = curvature_from(shell, topo, &lengths).ok_or(RicciError::StepFailed {
        iteration: 0,
        residual: f64::NAN,
        vertex: 0,
        position: worst_position(0),
        hint: "a degenerate input triangle",
    })?;

    // Pin vertex 0: unknown j is vertex j + 1.
    let pinned = 0usize;
    let unknown = |v: usize| if v == pinned { None } else { Some(v - 1) };
    let m = n - 1;
    let mut below = vec![Vec::new(); m];
    for &[a, b] in &topo.edges {
        if let (Some(i), Some(j)) = (unknown(a), unknown(b)) {
            below[i.min(j)].push(i.max(j));
        }
    }
    let pattern = LowerPattern::from_columns(m, below);
    let edge_position: Vec<Option<usize>> = topo
        .edges
        .iter()
        .map(|&[a, b]| match (unknown(a), unknown(b)) {
            (Some(i), Some(j)) => pattern.position(i.max(j), i.min(j)),
            _ => None,
        })
        .collect();
    let coords: Vec<[f64; 3]> = shell.vertices[1..].to_vec();
    let solver_error = |iteration: usize| {
        move |e: crate::field::crossfield::CrossFieldError| RicciError::Solver {
            iteration,
            message: e.to_string(),
        }
    };
    let spd = SparseSpd::analyze(pattern, Some(&coords)).map_err(solver_error(0))?;
    let mut factor: Option<Factor<'_, f64>> = None;
    let mut values = vec![0.0; spd.pattern.nnz()];
    let mut history = Vec::new();
    let mut iteration = 0;
    loop {
        let (err, worst) = max_error(&target, &k);
        history.push(err);
        if err < options.tolerance {
            break;
        }
        if iteration >= options.max_iterations {
            return Err(RicciError::NotConverged {
                iterations: iteration,
                residual: err,
                vertex: worst,
                position: worst_position(worst),
                hint: HINT,
            });
        }
        iteration += 1;
        assemble_hessian(
            shell,
            topo,
            &u,
            &eta,
            &lengths,
            &spd,
            &edge_position,
            &mut values,
        );
        match factor.as_mut() {
            None => factor = Some(spd.factor(&values).map_err(solver_error(iteration))?),
            Some(f) => spd.refactor(&values, f).map_err(solver_error(iteration))?,
        }
        let mut rhs: Vec<f64> = (1..n).map(|v| target[v] - k[v]).collect();
        if let Some(f) = factor.as_ref() {
            f.solve_in_place(&mut rhs);
        }
        let mut du = vec![0.0; n];
        du[1..].copy_from_slice(&rhs);
        // Backtracking: valid triangles and a smaller 2-norm residual.
        let current = norm2(&target, &k);
        let mut step = 1.0;
        let mut trial_u = vec![0.0; n];
        let mut trial_lengths = vec![0.0; ne];
        let mut accepted = None;
        for _ in 0..40 {
            for v in 0..n {
                trial_u[v] = u[v] + step * du[v];
            }
            lengths_from(&trial_u, &eta, topo, &mut trial_lengths);
            if let Some(tk) = curvature_from(shell, topo, &trial_lengths) {
                if norm2(&target, &tk) < current {
                    accepted = Some(tk);
                    break;
                }
            }
            step *= 0.5;
        }
        match accepted {
            Some(tk) => {
                std::mem::swap(&mut u, &mut trial_u);
                std::mem::swap(&mut lengths, &mut trial_lengths);
                k = tk;
            }
            None => {
                return Err(RicciError::StepFailed {
                    iteration,
                    residual: err,
                    vertex: worst,
                    position: worst_position(worst),
                    hint: HINT,
                })
            }
        }
    }
    let (max_err, _) = max_error(&target, &k);
    Ok(RicciMetric {
        u,
        eta,
        lengths,
        target,
        curvature: k,
        iterations: iteration,
        max_error: max_err,
        history,
    })
}

/// The Hessian ∂K/∂u by the chain rule (spec §5.4), lower triangle of the
/// unknowns (vertex 0 pinned) in `spd`'s pattern order.
#[allow(clippy::too_many_arguments)]
fn assemble_hessian(
    shell: &Shell,
    topo: &ShellTopology,
    u: &[f64],
    eta: &[f64],
    lengths: &[f64],
    spd: &SparseSpd,
    edge_position: &[Option<usize>],
    values: &mut [f64],
) {
    values.fill(0.0);
    for (f, t) in shell.triangles.iter().enumerate() {
        let te = topo.triangle_edges[f];
        // Side k joins corners k and k+1; the corner opposite is k+2.
        let l = [lengths[te[0]], lengths[te[1]], lengths[te[2]]];
        let Some(ang) = corner_angles(l) else {
            continue;
        };
        let area = 0.5 * l[0] * l[2] * ang[0].sin();
        // Relabel as in §5.4: side `a` opposite corner a is side (a + 1) % 3.
        let opp = |a: usize| l[(a + 1) % 3];
        // [corner][opposite side of corner]
        let dtheta_dl: [[f64; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                if a == b {
                    opp(a) / (2.0 * area)
                } else {
                    -opp(a) * ang[3 - a - b].cos() / (2.0 * area)
                }
            })
        });
        // dℓ/du: the side opposite corner a joins corners a+1 and a+2.
        let mut dl_du = [[0.0; 3]; 3];
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let e = te[(a + 1) % 3];
            let (gb, gc) = (u[t[b]].exp(), u[t[c]].exp());
            dl_du[a][b] = (gb * gb + eta[e] * gb * gc) / opp(a);
            dl_du[a][c] = (gc * gc + eta[e] * gb * gc) / opp(a);
        }
        let mut m = [[0.0; 3]; 3];
        for a in 0..3 {
            for v in 0..3 {
                m[a][v] = (0..3).map(|s| dtheta_dl[a][s] * dl_du[s][v]).sum();
            }
        }
        // H = −Σ dΘ/du, symmetrised; diagonal = −Σ off-diagonal (rows sum to 0).
        for a in 0..3 {
            let b = (a + 1) % 3;
            let h = -0.5 * (m[a][b] + m[b][a]);
            let e = te[a];
            if let Some(p) = edge_position[e] {
                values[p] += h;
            }
            for v in [t[a], t[b]] {
                if v != 0 {
                    values[spd.pattern.diag(v - 1)] -= h;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
