//! S6–S7 of `quadrille spline` (spec ricci-flow-iga-reconstruction §8): the
//! layout-inducing constrained minimisation. From ψ_R, the constraint sets
//! are classified once (`constraints`), then E1 (symmetric Dirichlet,
//! `dirichlet`) + λ·(E2 boundary + E3 features + E4 cut transitions) is
//! minimised by projected Newton with flip-free steps, λ from 1 to 1e8
//! (×100 per outer stage: the residuals fall ×100 with it, in half the
//! stages of ×10 and fewer Newton iterations), the reference of E1
//! alternating between the Ricci metric and the 3D triangles. It stops when every constraint residual is
//! below 1e-7 × the diagonal of ψ with every det J > 0, or earlier when the
//! exact snap (`snap`: the stage's map projected onto the constraints, tried
//! once the residuals are below 1e-5 × the diagonal) passes, then checks
//! Q1–Q4 (`verify`). E5 (the user's separatrix connections Γ_topo) is not built.

pub mod constraints;
pub mod dirichlet;
pub mod snap;
pub mod verify;

use thiserror::Error;

use crate::cut::CutMesh;
use crate::field::{LowerPattern, SparseSpd};
use crate::immersion::Immersion;
use crate::ricci::{Cone, RicciMetric};
use crate::shell::{Shell, ShellTopology};

use constraints::{aligned_terms, holonomy_terms, LinearTerm};
pub use constraints::{classify, AlignedEdge, ConstraintSets, HeldAxis, HolonomyPath};
use dirichlet::ReferenceTriangle;
pub use verify::{residuals, Residuals};

/// Settings of the minimisation (spec §8.4 reference defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutEnergyOptions {
    /// λ2..λ4 of the first outer stage.
    pub lambda_start: f64,
    /// Factor per outer stage (100; the spec's reference 10 took 8 stages
    /// and 218 iterations on n10o where 100 takes 5 and 120).
    pub lambda_factor: f64,
    /// Largest λ.
    pub lambda_max: f64,
    /// Newton iterations per outer stage at most.
    pub max_newton: usize,
    /// Residual tolerance as a share of the diagonal of ψ's bounding box.
    pub tolerance_share: f64,
    /// Q2: largest |angle sum − target| (radians).
    pub angle_tolerance: f64,
    /// The exact snap (`snap`) is tried after a stage whose residuals are
    /// below this share of ψ's diagonal (0: never) and ends the
    /// minimisation when the snapped map passes Q1–Q4.
    pub snap_share: f64,
}

impl Default for LayoutEnergyOptions {
    fn default() -> Self {
        LayoutEnergyOptions {
            lambda_start: 1.0,
            lambda_factor: 100.0,
            lambda_max: 1e8,
            max_newton: 200,
            tolerance_share: 1e-7,
            angle_tolerance: 1e-6,
            snap_share: 1e-5,
        }
    }
}

/// The reference geometry of E1 in one outer stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceMetric {
    /// The Ricci flat metric (scaled like ψ_R).
    Ricci,
    /// The 3D triangles.
    Euclidean,
}

/// What one outer stage did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageReport {
    /// λ2 = λ3 = λ4.
    pub lambda: f64,
    /// E1's reference.
    pub reference: ReferenceMetric,
    /// Newton iterations.
    pub iterations: usize,
    /// Total energy at its end.
    pub energy: f64,
    /// Residuals at its end.
    pub residuals: Residuals,
    /// Smallest det J (Ricci reference) at its end.
    pub min_det: f64,
    /// Largest |angle sum − target| at its end (radians).
    pub max_angle_error: f64,
}

/// The minimised map φ of Ω and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutMap {
    /// Plane position per child vertex of Ω.
    pub uv: Vec<[f64; 2]>,
    /// The constraint sets.
    pub constraints: ConstraintSets,
    /// One report per outer stage.
    pub stages: Vec<StageReport>,
    /// Newton iterations over all stages.
    pub iterations: usize,
    /// Final residuals.
    pub residuals: Residuals,
    /// Their tolerance (1e-7 × diagonal of ψ).
    pub tolerance: f64,
    /// Smallest det J against the Ricci reference (Q1).
    pub min_det: f64,
    /// Largest |angle sum − target| over the shell vertices (Q2, radians).
    pub max_angle_error: f64,
    /// When the exact snap ended it: the largest move of one coordinate.
    pub snap_shift: Option<f64>,
}

impl LayoutMap {
    /// One line: "layout energy converged: …".
    pub fn describe(&self) -> String {
        let [u, v] = self.constraints.axis_counts();
        format!(
            "layout energy converged: residual {:.1e} (tolerance {:.1e}; boundary {:.1e}, features {:.1e}, cuts {:.1e}), min det J {:.3e}, max angle-sum error {:.1e} rad, iterations {} in {} stages (λ up to {:.0e}; per stage iterations/residual/angle: {}); {}; Γ_u {u}, Γ_v {v} edges, {} cut paths; E5 not built",
            self.residuals.max(),
            self.tolerance,
            self.residuals.boundary,
            self.residuals.features,
            self.residuals.holonomy,
            self.min_det,
            self.max_angle_error,
            self.iterations,
            self.stages.len(),
            self.stages.last().map_or(0.0, |s| s.lambda),
            self.stages
                .iter()
                .map(|s| format!(
                    "{}/{:.1e}/{:.1e}",
                    s.iterations,
                    s.residuals.max(),
                    s.max_angle_error
                ))
                .collect::<Vec<_>>()
                .join(", "),
            match self.snap_shift {
                Some(s) => format!("exact snap after the last stage (moves ≤ {s:.1e})"),
                None => "no snap".to_string(),
            },
            self.constraints.holonomy.len(),
        )
    }
}

/// Why the minimisation gave no valid map.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LayoutEnergyError {
    /// ψ_R folds: E1 is infinite at the start.
    #[error("layout energy: ψ_R has {count} triangles with det J ≤ 0 (first: triangle {face}); the energy needs a locally injective start")]
    InvertedStart {
        /// Triangles with det J ≤ 0.
        count: usize,
        /// The first one.
        face: usize,
    },
    /// A reference triangle breaks the triangle inequality.
    #[error("layout energy: triangle {face} has {reference:?} reference lengths {lengths:?} that break the triangle inequality")]
    DegenerateReference {
        /// The triangle.
        face: usize,
        /// Which reference.
        reference: ReferenceMetric,
        /// Its lengths.
        lengths: [f64; 3],
    },
    /// The sparse Cholesky failed.
    #[error("layout energy: linear solve failed in stage {stage}: {message}")]
    Solver {
        /// Outer stage.
        stage: usize,
        /// faer's message.
        message: String,
    },
    /// A constraint set (or Q1/Q2) still violated after the last stage.
    #[error("layout energy stalled after {stages} stages ({iterations} Newton iterations, λ = {lambda:.0e}): {set} violated by {value:.3e} > {limit:.3e} near {position:?}; residual per stage (boundary/features/cuts, angle sums): {history}")]
    Violated {
        /// The violated set or check.
        set: String,
        /// Its worst value.
        value: f64,
        /// Its limit.
        limit: f64,
        /// 3D point where it is worst.
        position: [f64; 3],
        /// Outer stages run.
        stages: usize,
        /// Newton iterations.
        iterations: usize,
        /// Last λ.
        lambda: f64,
        /// Residuals per stage.
        history: String,
    },
}

/// The quadratic penalty sets with their weights.
struct Penalties {
    boundary: Vec<LinearTerm>,
    features: Vec<LinearTerm>,
    holonomy: Vec<LinearTerm>,
}

impl Penalties {
    fn all(&self) -> impl Iterator<Item = &LinearTerm> {
        self.boundary
            .iter()
            .chain(&self.features)
            .chain(&self.holonomy)
    }
}

/// The Newton problem of one outer stage.
struct Problem<'a> {
    corners: &'a [[usize; 3]],
    reference: Vec<ReferenceTriangle>,
    penalties: &'a Penalties,
    lambda: f64,
    pinned: usize,
}

impl Problem<'_> {
    fn corner_uv(&self, phi: &[f64], f: usize) -> [[f64; 2]; 3] {
        let c = self.corners[f];
        [0, 1, 2].map(|k| [phi[2 * c[k]], phi[2 * c[k] + 1]])
    }

    /// The total energy; `None` when a triangle has det J ≤ 0.
    fn energy(&self, phi: &[f64]) -> Option<f64> {
        let mut e = 0.0;
        for (f, r) in self.reference.iter().enumerate() {
            e += dirichlet::energy(&self.corner_uv(phi, f), r)?;
        }
        let pen: f64 = self
            .penalties
            .all()
            .map(|t| t.weight * t.value(phi).powi(2))
            .sum();
        Some(e + self.lambda * pen)
    }

    /// Energy, gradient and the lower triangle of the projected Hessian in
    /// the order of `scatter`'s pattern (the pinned vertex's rows are
    /// identity).
    fn assemble(
        &self,
        phi: &[f64],
        scatter: &Scatter,
        values: &mut [f64],
        grad: &mut [f64],
    ) -> Option<f64> {
        values.fill(0.0);
        grad.fill(0.0);
        let mut energy = 0.0;
        for (f, r) in self.reference.iter().enumerate() {
            let t = dirichlet::terms(&self.corner_uv(phi, f), r)?;
            energy += t.energy;
            let c = self.corners[f];
            let slots = &scatter.triangles[f];
            for m in 0..6 {
                grad[2 * c[m / 2] + m % 2] += t.gradient[m];
                for n in 0..6 {
                    let p = slots[6 * m + n];
                    if p != NO_SLOT {
                        values[p as usize] += t.hessian[m][n];
                    }
                }
            }
        }
        for (t, slots) in self.penalties.all().zip(&scatter.terms) {
            let r = t.value(phi);
            let w = self.lambda * t.weight;
            energy += w * r * r;
            for p in 0..t.len {
                grad[t.dofs[p]] += 2.0 * w * r * t.coefs[p];
                for q in 0..t.len {
                    let s = slots[6 * p + q];
                    if s != NO_SLOT {
                        values[s as usize] += 2.0 * w * t.coefs[p] * t.coefs[q];
                    }
                }
            }
        }
        for d in [2 * self.pinned, 2 * self.pinned + 1] {
            grad[d] = 0.0;
            values[scatter.pattern.diag(d)] = 1.0;
        }
        Some(energy)
    }

    /// The largest flip-free step along `dir`.
    fn max_step(&self, phi: &[f64], dir: &[f64]) -> f64 {
        let mut tau = f64::INFINITY;
        for f in 0..self.corners.len() {
            let x = self.corner_uv(phi, f);
            let d = self.corner_uv(dir, f);
            let sub = |p: [f64; 2], q: [f64; 2]| [p[0] - q[0], p[1] - q[1]];
            tau = tau.min(dirichlet::flip_free_step(
                sub(x[1], x[0]),
                sub(x[2], x[0]),
                sub(d[1], d[0]),
                sub(d[2], d[0]),
            ));
        }
        tau
    }
}

/// No Hessian entry: above the diagonal or in the pinned vertex's rows.
const NO_SLOT: u32 = u32::MAX;

/// Where each local Hessian entry goes in the lower pattern, looked up once
/// (the pattern is fixed over all stages): 6 × 6 slots per triangle and
/// per penalty term, row-major, [`NO_SLOT`] for entries left out.
struct Scatter {
    pattern: LowerPattern,
    triangles: Vec<[u32; 36]>,
    terms: Vec<[u32; 36]>,
}

impl Scatter {
    fn new(
        pattern: LowerPattern,
        corners: &[[usize; 3]],
        penalties: &Penalties,
        pinned: usize,
    ) -> Scatter {
        let slot = |r: usize, c: usize| -> u32 {
            if r < c || r / 2 == pinned || c / 2 == pinned {
                return NO_SLOT;
            }
            pattern.position(r, c).map_or(NO_SLOT, |p| p as u32)
        };
        let local = |dofs: &[usize]| {
            let mut out = [NO_SLOT; 36];
            for (m, &a) in dofs.iter().enumerate() {
                for (n, &b) in dofs.iter().enumerate() {
                    out[6 * m + n] = slot(a, b);
                }
            }
            out
        };
        let triangles = corners.iter().map(|c| local(&triangle_dofs(c))).collect();
        let terms = penalties.all().map(|t| local(&t.dofs[..t.len])).collect();
        Scatter {
            pattern,
            triangles,
            terms,
        }
    }
}

/// The six unknowns (u, v of each corner) of the triangle with `corners`.
fn triangle_dofs(c: &[usize; 3]) -> [usize; 6] {
    [
        2 * c[0],
        2 * c[0] + 1,
        2 * c[1],
        2 * c[1] + 1,
        2 * c[2],
        2 * c[2] + 1,
    ]
}

/// The pattern of the Hessian: every triangle's and every term's unknowns.
fn hessian_pattern(n: usize, corners: &[[usize; 3]], penalties: &Penalties) -> LowerPattern {
    let mut below = vec![Vec::new(); n];
    let mut couple = |dofs: &[usize]| {
        for &a in dofs {
            for &b in dofs {
                if a > b {
                    below[b].push(a);
                }
            }
        }
    };
    for c in corners {
        couple(&triangle_dofs(c));
    }
    for t in penalties.all() {
        couple(&t.dofs[..t.len]);
    }
    LowerPattern::from_columns(n, below)
}

/// Reference triangles of `which` metric.
fn references(
    shell: &Shell,
    topo: &ShellTopology,
    metric: &RicciMetric,
    scale: f64,
    which: ReferenceMetric,
) -> Result<Vec<ReferenceTriangle>, LayoutEnergyError> {
    (0..shell.triangles.len())
        .map(|f| {
            let lengths = match which {
                ReferenceMetric::Ricci => metric.triangle_lengths(topo, f).map(|l| l * scale),
                ReferenceMetric::Euclidean => {
                    let t = shell.triangles[f];
                    [0, 1, 2].map(|k| {
                        let (p, q) = (shell.vertices[t[k]], shell.vertices[t[(k + 1) % 3]]);
                        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                            .sqrt()
                    })
                }
            };
            ReferenceTriangle::from_lengths(lengths).ok_or(LayoutEnergyError::DegenerateReference {
                face: f,
                reference: which,
                lengths,
            })
        })
        .collect()
}

/// Projected Newton on one stage's problem from `phi` (in place); returns
/// the iterations taken and the final energy.
fn newton(
    problem: &Problem,
    phi: &mut [f64],
    spd: &SparseSpd,
    scatter: &Scatter,
    max_newton: usize,
    stage: usize,
) -> Result<(usize, f64), LayoutEnergyError> {
    let n = phi.len();
    let mut values = vec![0.0; spd.pattern.nnz()];
    let mut grad = vec![0.0; n];
    let solver = |message: String| LayoutEnergyError::Solver { stage, message };
    let mut factor = None;
    let mut energy = problem.energy(phi).unwrap_or(f64::INFINITY);
    for it in 0..max_newton {
        let Some(e) = problem.assemble(phi, scatter, &mut values, &mut grad) else {
            return Ok((it, energy));
        };
        energy = e;
        let gmax = grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        if gmax <= 1e-12 * energy.max(f64::MIN_POSITIVE) {
            return Ok((it, energy));
        }
        match factor.as_mut() {
            None => factor = Some(spd.factor(&values).map_err(|e| solver(e.to_string()))?),
            Some(f) => spd
                .refactor(&values, f)
                .map_err(|e| solver(e.to_string()))?,
        }
        let mut dir: Vec<f64> = grad.iter().map(|g| -g).collect();
        if let Some(f) = factor.as_ref() {
            f.solve_in_place(&mut dir);
        }
        let slope: f64 = dir.iter().zip(&grad).map(|(d, g)| d * g).sum();
        if !(slope < 0.0) {
            return Ok((it, energy));
        }
        let mut tau = (0.8 * problem.max_step(phi, &dir)).min(1.0);
        let mut trial = vec![0.0; n];
        let mut accepted = None;
        for _ in 0..60 {
            for k in 0..n {
                trial[k] = phi[k] + tau * dir[k];
            }
            if let Some(et) = problem.energy(&trial) {
                if et <= energy + 1e-4 * tau * slope {
                    accepted = Some(et);
                    break;
                }
            }
            tau *= 0.5;
        }
        let Some(new_energy) = accepted else {
            return Ok((it + 1, energy));
        };
        phi.copy_from_slice(&trial);
        let decrease = (energy - new_energy) / energy.abs().max(f64::MIN_POSITIVE);
        energy = new_energy;
        if decrease < 1e-12 {
            return Ok((it + 1, energy));
        }
    }
    Ok((max_newton, energy))
}

/// Minimises the layout energy on Ω = `cut` of `shell` from ψ_R
/// (`immersion`), with the Ricci `metric`, the `cones` (boundary runs break
/// at them) and `features` (per shell edge; empty for none); see the module
/// docs. The result passed Q1–Q4.
#[allow(clippy::too_many_arguments)]
pub fn minimise(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    cones: &[Cone],
    metric: &RicciMetric,
    immersion: &Immersion,
    features: &[bool],
    opts: &LayoutEnergyOptions,
) -> Result<LayoutMap, LayoutEnergyError> {
    let uv0 = &immersion.uv;
    let constraints = classify(shell, topo, cut, cones, uv0, features);
    let penalties = Penalties {
        boundary: aligned_terms(&constraints.boundary),
        features: aligned_terms(&constraints.features),
        holonomy: holonomy_terms(&constraints.holonomy),
    };
    let n = 2 * uv0.len();
    let ricci_ref = references(shell, topo, metric, immersion.scale, ReferenceMetric::Ricci)?;
    let mut phi: Vec<f64> = uv0.iter().flat_map(|p| [p[0], p[1]]).collect();
    let det_of = |phi: &[f64]| -> (f64, Option<usize>, usize) {
        let mut min = f64::INFINITY;
        let (mut first, mut count) = (None, 0);
        for (f, r) in ricci_ref.iter().enumerate() {
            let c = cut.corners[f];
            let x = [0, 1, 2].map(|k| [phi[2 * c[k]], phi[2 * c[k] + 1]]);
            let d = dirichlet::det_j(&x, r);
            min = min.min(d);
            if !(d > 0.0) {
                count += 1;
                first.get_or_insert(f);
            }
        }
        (min, first, count)
    };
    if let (_, Some(face), count) = det_of(&phi) {
        return Err(LayoutEnergyError::InvertedStart { count, face });
    }
    let diagonal = verify::diagonal(uv0);
    let tolerance = opts.tolerance_share * diagonal;
    let pattern = hessian_pattern(n, &cut.corners, &penalties);
    let scatter = Scatter::new(pattern.clone(), &cut.corners, &penalties, 0);
    let spd = SparseSpd::analyze(pattern, None).map_err(|e| LayoutEnergyError::Solver {
        stage: 0,
        message: e.to_string(),
    })?;
    let mut stages = Vec::new();
    let mut iterations = 0;
    let mut lambda = opts.lambda_start;
    let mut euclid_ref = None;
    loop {
        let s = stages.len();
        let reference = if s % 2 == 0 {
            ReferenceMetric::Ricci
        } else {
            ReferenceMetric::Euclidean
        };
        let refs = match reference {
            ReferenceMetric::Ricci => ricci_ref.clone(),
            ReferenceMetric::Euclidean => match &euclid_ref {
                Some(r) => Vec::clone(r),
                None => {
                    let r = references(shell, topo, metric, 1.0, reference)?;
                    euclid_ref = Some(r.clone());
                    r
                }
            },
        };
        let problem = Problem {
            corners: &cut.corners,
            reference: refs,
            penalties: &penalties,
            lambda,
            pinned: 0,
        };
        let (its, energy) = newton(&problem, &mut phi, &spd, &scatter, opts.max_newton, s)?;
        iterations += its;
        let uv: Vec<[f64; 2]> = phi.chunks(2).map(|p| [p[0], p[1]]).collect();
        let res = residuals(&constraints, &uv);
        let (min_det, _, _) = det_of(&phi);
        stages.push(StageReport {
            lambda,
            reference,
            iterations: its,
            energy,
            residuals: res,
            min_det,
            max_angle_error: f64::NAN,
        });
        // Q2 too: the penalty leaves angle-sum errors of about residual / ℓ
        // (2.8e-5 rad on n10o at λ = 1e5 with every residual under the
        // tolerance), so λ grows until they are within theirs as well.
        let angle = verify::angle_errors(shell, topo, cut, metric, &uv)
            .iter()
            .fold(0.0f64, |m, e| m.max(e.abs()));
        if let Some(last) = stages.last_mut() {
            last.max_angle_error = angle;
        }
        let done = res.max() < tolerance && min_det > 0.0 && angle <= opts.angle_tolerance;
        // The exact snap (spec §8.4): kept when the projected map passes.
        let mut snapped = None;
        if !done && res.max() < opts.snap_share * diagonal {
            let rows: Vec<&LinearTerm> = penalties.all().collect();
            if let Some((sphi, shift)) = snap::snap(&rows, &phi, 20 * rows.len() + 100) {
                let suv: Vec<[f64; 2]> = sphi.chunks(2).map(|p| [p[0], p[1]]).collect();
                let sres = residuals(&constraints, &suv);
                let (sdet, _, _) = det_of(&sphi);
                let sangle = verify::angle_errors(shell, topo, cut, metric, &suv)
                    .iter()
                    .fold(0.0f64, |m, e| m.max(e.abs()));
                if sres.max() < tolerance && sdet > 0.0 && sangle <= opts.angle_tolerance {
                    snapped = Some((suv, sres, sdet, shift));
                }
            }
        }
        let last = lambda * opts.lambda_factor > opts.lambda_max * (1.0 + 1e-9);
        if done || last || snapped.is_some() {
            let (uv, res, min_det, snap_shift) = match snapped {
                Some((suv, sres, sdet, shift)) => (suv, sres, sdet, Some(shift)),
                None => (uv, res, min_det, None),
            };
            let map = LayoutMap {
                uv,
                constraints,
                stages,
                iterations,
                residuals: res,
                tolerance,
                min_det,
                max_angle_error: 0.0,
                snap_shift,
            };
            return verify::verify(shell, topo, cut, metric, map, opts);
        }
        lambda *= opts.lambda_factor;
    }
}

#[cfg(test)]
pub(crate) mod tests;
