//! Conformal scaling of a cross field (paper §3.3, spec §4).
//!
//! Scaling both branches of the unit cross field by `h = e^H` makes them
//! commute (integrable) when `∇H = −∇^⊥θ` (the paper's Eq. 8 with the sign
//! corrected, spec §4.1 / errata 4; checked by the annulus test: `h ∝ r`).
//! Per triangle `(i, j, k)`, the angle steps `Δθ_jk = diff(θ_jk, θ_ij)` and
//! `Δθ_ki = diff(θ_ki, θ_ij)` — both crosses re-expressed in the frame of the
//! triangle and brought to the nearest representative modulo π/2 — give the
//! constant gradient of the CR-linear θ; the target is
//! `G_T = −n_T × ∇θ_T = −(Δθ_jk e_jk + Δθ_ki e_ki) / |T|` (`e` the triangle's
//! oriented edge vectors). `H` minimizes `∫ |∇H − G|²` over P1 functions
//! (Eq. 9): the cotangent Laplacian system `K H = b`, pinned to 0 at the
//! lowest vertex of each connected component. Triangles whose medial loop
//! holds a singularity get `G_T = 0` (their gradient is meaningless).
//!
//! A field from [`crate::field::crossfield::parallel_field`] does not turn, so its
//! `H` is 0 without a solve.
//!
//! `H` is defined up to a constant `C`; [`scaling_constant`] picks it so that
//! `∫ e^{−2(H + C)} = N`, the target number of quads on the face.

use geometry::vec3;

use crate::field::crossfield::linsolve::{LowerPattern, SparseSpd};
use crate::field::crossfield::topology::{arg_ratio, FaceTopology, NONE};
use crate::field::crossfield::CrossField;
use crate::field::singularities::triangle_indices;

/// Why a scaling could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScalingError {
    /// The sparse solver failed.
    #[error("linear solver: {0}")]
    Solver(String),
    /// The target quad count is not a positive finite number, or the
    /// integral of e^{−2H} is not.
    #[error("invalid quad-count target: {0}")]
    InvalidTarget(String),
}

/// The conformal scaling `H` of a cross field, per welded vertex.
#[derive(Clone, Debug)]
pub struct ConformalScaling {
    /// `H` at each welded vertex of the field's topology (0 at one pinned
    /// vertex per connected component).
    pub h: Vec<f64>,
    /// Number of triangles left out of the fit because they hold a singularity.
    pub singular_triangles: usize,
}

impl ConformalScaling {
    /// The size `h = e^{H + c}` at welded vertex `v`, with `c` from [`scaling_constant`].
    pub fn size(&self, v: usize, c: f64) -> f64 {
        (self.h[v] + c).exp()
    }
}

/// The integrability target `G_T = −n_T × ∇θ_T` of triangle `t` (a tangent
/// vector), from the CR angle steps of its three edge crosses.
pub fn target_gradient(field: &CrossField, t: usize) -> [f64; 3] {
    let topo = &field.topology;
    // local edge 2 = (i, j), 0 = (j, k), 1 = (k, i)
    let w = [
        field.in_triangle(t, 0),
        field.in_triangle(t, 1),
        field.in_triangle(t, 2),
    ];
    let d_jk = arg_ratio(w[2], w[0]) / 4.0;
    let d_ki = arg_ratio(w[2], w[1]) / 4.0;
    let (e0, e1) = (
        topo.opposite_edge_vector(t, 0),
        topo.opposite_edge_vector(t, 1),
    );
    let inv = -1.0 / topo.areas[t];
    vec3::scale(vec3::add(vec3::scale(e0, d_jk), vec3::scale(e1, d_ki)), inv)
}

/// Solves Eq. 9 for `H` (see the module documentation).
pub fn conformal_scaling(field: &CrossField) -> Result<ConformalScaling, ScalingError> {
    let topo = &field.topology;
    let nv = topo.positions.len();
    let nt = topo.triangles.len();
    if field.parallel {
        // a parallel field does not turn: ∇θ = 0, so G = 0 and H = 0
        return Ok(ConformalScaling {
            h: vec![0.0; nv],
            singular_triangles: 0,
        });
    }
    // connected components: pin the lowest vertex of each
    let mut parent: Vec<u32> = (0..nv as u32).collect();
    fn find(p: &mut [u32], mut i: u32) -> u32 {
        while p[i as usize] != i {
            p[i as usize] = p[p[i as usize] as usize];
            i = p[i as usize];
        }
        i
    }
    for tri in &topo.triangles {
        for a in 0..3 {
            let (x, y) = (
                find(&mut parent, tri[a]),
                find(&mut parent, tri[(a + 1) % 3]),
            );
            if x != y {
                parent[x.max(y) as usize] = x.min(y);
            }
        }
    }
    let mut index = vec![NONE; nv];
    let mut n = 0usize;
    for v in 0..nv as u32 {
        if find(&mut parent, v) != v {
            index[v as usize] = n as u32;
            n += 1;
        }
    }
    let tri_index = triangle_indices(field);
    let mut below = vec![Vec::new(); n];
    for tri in &topo.triangles {
        for a in 0..3 {
            for b in 0..3 {
                let (i, j) = (index[tri[a] as usize], index[tri[b] as usize]);
                if i != NONE && j != NONE && i > j {
                    below[j as usize].push(i as usize);
                }
            }
        }
    }
    let pattern = LowerPattern::from_columns(n, below);
    let mut vals = vec![0.0f64; pattern.nnz()];
    let mut rhs = vec![0.0f64; n];
    let mut singular = 0;
    for t in 0..nt {
        let tri = topo.triangles[t];
        let nrm = topo.normals[t];
        let e = [
            topo.opposite_edge_vector(t, 0),
            topo.opposite_edge_vector(t, 1),
            topo.opposite_edge_vector(t, 2),
        ];
        let g = if tri_index[t] != 0 {
            singular += 1;
            [0.0; 3]
        } else {
            target_gradient(field, t)
        };
        let area = topo.areas[t];
        for a in 0..3 {
            let i = index[tri[a] as usize];
            if i == NONE {
                continue;
            }
            // b_v = |T| G·∇λ_v with ∇λ_v = n × e_v / (2|T|)
            rhs[i as usize] += 0.5 * vec3::dot(g, vec3::cross(nrm, e[a]));
            for b in 0..3 {
                let j = index[tri[b] as usize];
                if j != NONE && i >= j {
                    let p = pattern.position(i as usize, j as usize).ok_or_else(|| {
                        ScalingError::Solver("pattern is missing an entry".into())
                    })?;
                    vals[p] += vec3::dot(e[a], e[b]) / (4.0 * area);
                }
            }
        }
    }
    let mut h = vec![0.0; nv];
    if n > 0 {
        // AMD ordering (less fill than the geometric nested dissection here)
        let spd =
            SparseSpd::analyze(pattern, None).map_err(|e| ScalingError::Solver(e.to_string()))?;
        let f = spd
            .factor(&vals)
            .map_err(|e| ScalingError::Solver(e.to_string()))?;
        f.solve_in_place(&mut rhs);
        for v in 0..nv {
            if index[v] != NONE {
                h[v] = rhs[index[v] as usize];
            }
        }
    }
    if h.iter().any(|x| !x.is_finite()) {
        return Err(ScalingError::Solver("non-finite scaling".into()));
    }
    Ok(ConformalScaling {
        h,
        singular_triangles: singular,
    })
}

/// `∫_S e^{−2H}` with the per-triangle mean of the vertex values.
pub fn integral_exp_minus_2h(topo: &FaceTopology, h: &[f64]) -> f64 {
    topo.triangles
        .iter()
        .zip(&topo.areas)
        .map(|(tri, &a)| {
            a * tri
                .iter()
                .map(|&v| (-2.0 * h[v as usize]).exp())
                .sum::<f64>()
                / 3.0
        })
        .sum()
}

/// The constant `C = −½ ln(N / ∫ e^{−2H})` that gives about `n_quads` quads
/// of size `e^{H + C}` on the face (§3.3 of the paper).
pub fn scaling_constant(topo: &FaceTopology, h: &[f64], n_quads: f64) -> Result<f64, ScalingError> {
    if !(n_quads > 0.0 && n_quads.is_finite()) {
        return Err(ScalingError::InvalidTarget(format!("N = {n_quads}")));
    }
    let i = integral_exp_minus_2h(topo, h);
    if !(i > 0.0 && i.is_finite()) {
        return Err(ScalingError::InvalidTarget(format!("∫e^(-2H) = {i}")));
    }
    Ok(-0.5 * (n_quads / i).ln())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::crossfield::{compute_cross_field, CrossFieldOptions};
    use crate::fixtures::crossfield_meshes as fixtures;

    #[test]
    fn square_scaling_is_uniform() {
        let f = compute_cross_field(
            &fixtures::square_grid(1.0, 16),
            &CrossFieldOptions::default(),
        )
        .unwrap();
        let s = conformal_scaling(&f).unwrap();
        let (lo, hi) =
            s.h.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
        assert!(hi - lo < 1e-9, "H range {lo}..{hi}");
        // unit square, N quads → h = 1/√N
        let c = scaling_constant(&f.topology, &s.h, 100.0).unwrap();
        assert!((s.size(0, c) - 0.1).abs() < 1e-9);
    }

    #[test]
    fn annulus_scaling_grows_linearly_with_radius() {
        let f = compute_cross_field(
            &fixtures::annulus(0.4, 1.0, 24, 128),
            &CrossFieldOptions::default(),
        )
        .unwrap();
        let s = conformal_scaling(&f).unwrap();
        assert_eq!(s.singular_triangles, 0);
        // least-squares slope of H against ln r
        let pts: Vec<(f64, f64)> = f
            .topology
            .positions
            .iter()
            .zip(&s.h)
            .map(|(p, &h)| (p[0].hypot(p[1]).ln(), h))
            .collect();
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let slope = sxy / sxx;
        assert!((slope - 1.0).abs() < 0.05, "slope {slope}");
    }

    #[test]
    fn constant_hits_the_target_quad_count() {
        let f = compute_cross_field(&fixtures::disk(16), &CrossFieldOptions::default()).unwrap();
        let s = conformal_scaling(&f).unwrap();
        assert!(
            s.h.iter().any(|&x| x.abs() > 1e-3),
            "a disk field rotates: H is not constant"
        );
        for n in [10.0, 1234.0, 1e6] {
            let c = scaling_constant(&f.topology, &s.h, n).unwrap();
            let shifted: Vec<f64> = s.h.iter().map(|h| h + c).collect();
            let got = integral_exp_minus_2h(&f.topology, &shifted);
            assert!((got - n).abs() <= 1e-9 * n, "{got} vs {n}");
        }
        assert!(scaling_constant(&f.topology, &s.h, 0.0).is_err());
        assert!(scaling_constant(&f.topology, &s.h, f64::NAN).is_err());
    }
}
