//! The residuals of the constraint sets and the checks after S7 (spec
//! §8.5): Q1 every det J > 0, Q2 every shell vertex's angle sum in φ at its
//! target, Q3 |Δu| on Γ_u and |Δv| on Γ_v (boundary and features), Q4 each
//! cut path's sides related by R_k to the tolerance. Q5 belongs to the
//! tracing (S8), which is not built.

use std::f64::consts::PI;

use super::constraints::{quarter_turn, ConstraintSets, HeldAxis};
use super::{LayoutEnergyError, LayoutEnergyOptions, LayoutMap};
use crate::cut::CutMesh;
use crate::ricci::RicciMetric;
use crate::shell::{Shell, ShellTopology};

/// Largest constraint residual per set (plane units), with the shell edge
/// where it is worst.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Residuals {
    /// max |Δu| on Γ_u, |Δv| on Γ_v over boundary edges (Q3).
    pub boundary: f64,
    /// The same over feature edges (Q3).
    pub features: f64,
    /// max ‖R_k d_left − d_right‖ over cut edges (Q4).
    pub holonomy: f64,
    /// Shell vertices of the worst edge per set.
    pub worst: [Option<[usize; 2]>; 3],
}

impl Residuals {
    /// The largest of the three.
    pub fn max(&self) -> f64 {
        self.boundary.max(self.features).max(self.holonomy)
    }
}

/// The residuals of `sets` at the map `uv`.
pub fn residuals(sets: &ConstraintSets, uv: &[[f64; 2]]) -> Residuals {
    let mut r = Residuals::default();
    let d = |p: [usize; 2]| [uv[p[1]][0] - uv[p[0]][0], uv[p[1]][1] - uv[p[0]][1]];
    for (k, edges) in [&sets.boundary, &sets.features].into_iter().enumerate() {
        for e in edges {
            let v = d(e.children);
            let value = match e.held {
                HeldAxis::U => v[0].abs(),
                HeldAxis::V => v[1].abs(),
            };
            let slot = if k == 0 {
                &mut r.boundary
            } else {
                &mut r.features
            };
            if value > *slot {
                *slot = value;
                r.worst[k] = Some(e.parents);
            }
        }
    }
    for p in &sets.holonomy {
        let (c, s) = quarter_turn(p.quarter_turns);
        for (sd, parents, _) in &p.edges {
            let (l, rt) = (d(sd.left), d(sd.right));
            let value = (c * l[0] - s * l[1] - rt[0]).hypot(s * l[0] + c * l[1] - rt[1]);
            if value > r.holonomy {
                r.holonomy = value;
                r.worst[2] = Some(*parents);
            }
        }
    }
    r
}

/// Diagonal of the bounding box of `uv`.
pub fn diagonal(uv: &[[f64; 2]]) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in uv {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// Per shell vertex: the sum of φ's corner angles over all its children's
/// triangles minus its target (2π or π minus the target curvature I·π/2).
pub fn angle_errors(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    metric: &RicciMetric,
    uv: &[[f64; 2]],
) -> Vec<f64> {
    let mut sum = vec![0.0; shell.vertices.len()];
    for (f, c) in cut.corners.iter().enumerate() {
        for k in 0..3 {
            let (p, q, r) = (uv[c[k]], uv[c[(k + 1) % 3]], uv[c[(k + 2) % 3]]);
            let (a, b) = ([q[0] - p[0], q[1] - p[1]], [r[0] - p[0], r[1] - p[1]]);
            let angle = (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]);
            sum[shell.triangles[f][k]] += angle;
        }
    }
    sum.iter()
        .enumerate()
        .map(|(v, s)| {
            let full = if topo.on_boundary[v] { PI } else { 2.0 * PI };
            s - (full - metric.target[v])
        })
        .collect()
}

fn midpoint(shell: &Shell, e: Option<[usize; 2]>) -> [f64; 3] {
    e.map_or([f64::NAN; 3], |[a, b]| {
        let (p, q) = (shell.vertices[a], shell.vertices[b]);
        [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]))
    })
}

/// Checks Q1–Q4 on `map`; fills its angle error or names the first check
/// that fails.
pub fn verify(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    metric: &RicciMetric,
    mut map: LayoutMap,
    opts: &LayoutEnergyOptions,
) -> Result<LayoutMap, LayoutEnergyError> {
    let history = map
        .stages
        .iter()
        .map(|s| {
            format!(
                "{:.1e}/{:.1e}/{:.1e} ({:.1e} rad)",
                s.residuals.boundary, s.residuals.features, s.residuals.holonomy, s.max_angle_error
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let lambda = map.stages.last().map_or(0.0, |s| s.lambda);
    let fail =
        |set: &str, value: f64, limit: f64, position: [f64; 3]| LayoutEnergyError::Violated {
            set: set.to_string(),
            value,
            limit,
            position,
            stages: map.stages.len(),
            iterations: map.iterations,
            lambda,
            history: history.clone(),
        };
    if !(map.min_det > 0.0) {
        return Err(fail("Q1 (det J > 0)", map.min_det, 0.0, [f64::NAN; 3]));
    }
    let r = &map.residuals;
    let sets = [
        ("Q3 boundary Γ_u/Γ_v (E2)", r.boundary, r.worst[0]),
        ("Q3 features Γ_u/Γ_v (E3)", r.features, r.worst[1]),
        ("Q4 cut transitions Γ_Hol (E4)", r.holonomy, r.worst[2]),
    ];
    for (name, value, worst) in sets {
        if !(value < map.tolerance) {
            return Err(fail(name, value, map.tolerance, midpoint(shell, worst)));
        }
    }
    let errors = angle_errors(shell, topo, cut, metric, &map.uv);
    let (worst, max) = errors
        .iter()
        .enumerate()
        .fold(
            (0, 0.0f64),
            |(w, m), (v, e)| if e.abs() > m { (v, e.abs()) } else { (w, m) },
        );
    map.max_angle_error = max;
    if !(max <= opts.angle_tolerance) {
        return Err(fail(
            "Q2 (angle sums)",
            max,
            opts.angle_tolerance,
            shell.vertices[worst],
        ));
    }
    Ok(map)
}
