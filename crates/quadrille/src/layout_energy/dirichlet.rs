//! E1, the symmetric Dirichlet energy of one P1 triangle (spec §8.3, Eq. 14):
//! E_t = A_t ‖J‖_F² (1 + det(J)⁻²) with J the Jacobian from the reference
//! triangle to the plane; its gradient and its Hessian projected to a
//! positive semidefinite matrix (eigenvalues of the 4 × 4 Hessian in J
//! clamped at zero, then pulled back through the linear map x ↦ J).

/// A reference triangle: the inverse of its edge matrix D = [r1 − r0 | r2 − r0]
/// and its area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceTriangle {
    /// D⁻¹, row-major.
    pub dinv: [[f64; 2]; 2],
    /// A_t = ½ det D.
    pub area: f64,
}

impl ReferenceTriangle {
    /// The reference triangle with side lengths `l` (side k from corner k to
    /// k + 1); `None` when they break the triangle inequality.
    pub fn from_lengths(l: [f64; 3]) -> Option<ReferenceTriangle> {
        let x = (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2.0 * l[0]);
        let y2 = l[2] * l[2] - x * x;
        if !(l[0] > 0.0 && y2 > 0.0) {
            return None;
        }
        let y = y2.sqrt();
        let det = l[0] * y;
        Some(ReferenceTriangle {
            dinv: [[y / det, -x / det], [0.0, l[0] / det]],
            area: 0.5 * det,
        })
    }
}

/// Value, gradient and projected Hessian of one triangle's E1 in its six
/// unknowns (u0, v0, u1, v1, u2, v2).
pub struct TriangleTerms {
    /// E_t.
    pub energy: f64,
    /// ∂E_t/∂x.
    pub gradient: [f64; 6],
    /// The PSD projection of ∂²E_t/∂x².
    pub hessian: [[f64; 6]; 6],
}

/// The Jacobian J = X D⁻¹ (row-major: J[i][j], i the plane coordinate).
fn jacobian(x: &[[f64; 2]; 3], r: &ReferenceTriangle) -> [[f64; 2]; 2] {
    let xm = [
        [x[1][0] - x[0][0], x[2][0] - x[0][0]],
        [x[1][1] - x[0][1], x[2][1] - x[0][1]],
    ];
    let mut j = [[0.0; 2]; 2];
    for i in 0..2 {
        for c in 0..2 {
            j[i][c] = xm[i][0] * r.dinv[0][c] + xm[i][1] * r.dinv[1][c];
        }
    }
    j
}

/// E_t at corners `x`; `None` (an infinite energy) when det J ≤ 0.
pub fn energy(x: &[[f64; 2]; 3], r: &ReferenceTriangle) -> Option<f64> {
    let j = jacobian(x, r);
    let d = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if !(d > 0.0) {
        return None;
    }
    let s = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
    Some(r.area * s * (1.0 + 1.0 / (d * d)))
}

/// det J at corners `x`.
pub fn det_j(x: &[[f64; 2]; 3], r: &ReferenceTriangle) -> f64 {
    let j = jacobian(x, r);
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

/// E_t with its gradient and projected Hessian; `None` when det J ≤ 0.
pub fn terms(x: &[[f64; 2]; 3], r: &ReferenceTriangle) -> Option<TriangleTerms> {
    let j = jacobian(x, r);
    let d = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if !(d > 0.0) {
        return None;
    }
    let g = [j[0][0], j[0][1], j[1][0], j[1][1]];
    // ∂det/∂J in the same order (the cofactor).
    let c = [j[1][1], -j[1][0], -j[0][1], j[0][0]];
    let s: f64 = g.iter().map(|v| v * v).sum();
    let (d2, d3) = (1.0 / (d * d), 1.0 / (d * d * d));
    let d4 = d2 * d2;
    let a = r.area;
    let mut grad_j = [0.0; 4];
    for k in 0..4 {
        grad_j[k] = a * (2.0 * g[k] * (1.0 + d2) - 2.0 * s * d3 * c[k]);
    }
    // ∂c/∂J: the anti-diagonal (1, −1, −1, 1).
    let hd = |p: usize, q: usize| -> f64 {
        match (p, q) {
            (0, 3) | (3, 0) => 1.0,
            (1, 2) | (2, 1) => -1.0,
            _ => 0.0,
        }
    };
    let mut h = [[0.0; 4]; 4];
    for p in 0..4 {
        for q in 0..4 {
            let id = if p == q { 2.0 * (1.0 + d2) } else { 0.0 };
            h[p][q] = a
                * (id - 4.0 * d3 * (g[p] * c[q] + c[p] * g[q]) + 6.0 * s * d4 * c[p] * c[q]
                    - 2.0 * s * d3 * hd(p, q));
        }
    }
    let h = project_twist(h, &j, a);
    // ∂J/∂x: J[i][c] depends on corner p's coordinate i through w[c][p].
    let w = [0, 1].map(|c| [-r.dinv[0][c] - r.dinv[1][c], r.dinv[0][c], r.dinv[1][c]]);
    let mut gradient = [0.0; 6];
    for p in 0..3 {
        for i in 0..2 {
            gradient[2 * p + i] = w[0][p] * grad_j[2 * i] + w[1][p] * grad_j[2 * i + 1];
        }
    }
    // H·B (4 × 6), then Bᵀ·(H·B).
    let mut hb = [[0.0; 6]; 4];
    for (row, hrow) in hb.iter_mut().zip(&h) {
        for q in 0..3 {
            for k in 0..2 {
                row[2 * q + k] = hrow[2 * k] * w[0][q] + hrow[2 * k + 1] * w[1][q];
            }
        }
    }
    let mut hessian = [[0.0; 6]; 6];
    for p in 0..3 {
        for i in 0..2 {
            let out = &mut hessian[2 * p + i];
            for m in 0..6 {
                out[m] = w[0][p] * hb[2 * i][m] + w[1][p] * hb[2 * i + 1][m];
            }
        }
    }
    Some(TriangleTerms {
        energy: a * s * (1.0 + d2),
        gradient,
        hessian,
    })
}

/// The PSD projection of E_t's Hessian `h` in J (area `a` included) in
/// closed form. E1 per unit area is σ1² + σ2² + σ1⁻² + σ2⁻² in the singular
/// values of J (separable), so of the four eigenvalues of its Hessian in J
/// (the analytic eigensystem of isotropic energies, Smith, de Goes & Kim
/// 2019) the two scaling ones 2 + 6σᵢ⁻⁴ and the flip one
/// 2 + 2(σ1² + σ1σ2 + σ2²)/(σ1σ2)³ are positive; only the twist one,
/// 2 − 2(σ1² − σ1σ2 + σ2²)/(σ1σ2)³, along T = R·Q/√2 (Q the polar rotation
/// of J, R the quarter turn) can be negative, and is then removed.
pub fn project_twist(h: [[f64; 4]; 4], j: &[[f64; 2]; 2], a: f64) -> [[f64; 4]; 4] {
    let d = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    // σ1σ2 = det J, σ1² + σ2² = ‖J‖²: σ1² − σ1σ2 + σ2² = ‖J‖² − det J.
    let s = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
    let twist = 2.0 - 2.0 * (s - d) / (d * d * d);
    if twist >= 0.0 {
        return h;
    }
    // Q = [[α, −β], [β, α]]; R·Q = [[−β, −α], [α, −β]] (row-major order).
    let (p, q) = (j[0][0] + j[1][1], j[1][0] - j[0][1]);
    let norm = (p * p + q * q).sqrt() * std::f64::consts::SQRT_2;
    let t = [-q / norm, -p / norm, p / norm, -q / norm];
    let mut out = h;
    for r in 0..4 {
        for c in 0..4 {
            out[r][c] -= a * twist * t[r] * t[c];
        }
    }
    out
}

/// True when the symmetric 4 × 4 matrix `h` has a Cholesky factorization
/// with pivots above 1e-12 × its largest diagonal entry (so it is positive
/// definite and its projection is itself).
fn cholesky_succeeds(h: &[[f64; 4]; 4]) -> bool {
    let floor = 1e-12 * (0..4).fold(0.0f64, |m, k| m.max(h[k][k].abs()));
    let mut l = [[0.0f64; 4]; 4];
    for j in 0..4 {
        let mut d = h[j][j];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        if !(d > floor) {
            return false;
        }
        let d = d.sqrt();
        l[j][j] = d;
        for i in j + 1..4 {
            let mut v = h[i][j];
            for k in 0..j {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / d;
        }
    }
    true
}

/// The symmetric 4 × 4 matrix `h` with its negative eigenvalues set to zero
/// (cyclic Jacobi rotations; `h` itself when it is positive definite).
pub fn project_psd(h: [[f64; 4]; 4]) -> [[f64; 4]; 4] {
    if cholesky_succeeds(&h) {
        return h;
    }
    let mut a = h;
    let mut v = [[0.0; 4]; 4];
    for (k, row) in v.iter_mut().enumerate() {
        row[k] = 1.0;
    }
    for _sweep in 0..30 {
        let off: f64 = (0..4)
            .flat_map(|p| (0..4).map(move |q| (p, q)))
            .filter(|(p, q)| p != q)
            .map(|(p, q)| a[p][q] * a[p][q])
            .sum();
        let diag: f64 = (0..4).map(|p| a[p][p] * a[p][p]).sum();
        if off <= 1e-30 * diag.max(1e-300) {
            break;
        }
        for p in 0..3 {
            for q in p + 1..4 {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let cs = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * cs;
                for k in 0..4 {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = cs * akp - sn * akq;
                    a[k][q] = sn * akp + cs * akq;
                }
                for k in 0..4 {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = cs * apk - sn * aqk;
                    a[q][k] = sn * apk + cs * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = cs * vp - sn * vq;
                    row[q] = sn * vp + cs * vq;
                }
            }
        }
    }
    let lambda: Vec<f64> = (0..4).map(|k| a[k][k].max(0.0)).collect();
    let mut out = [[0.0; 4]; 4];
    for p in 0..4 {
        for q in 0..4 {
            out[p][q] = (0..4).map(|k| v[p][k] * lambda[k] * v[q][k]).sum();
        }
    }
    out
}

/// The largest τ > 0 with det(X + τ·dX) > 0 kept on (0, τ) for a triangle
/// with edge vectors e1, e2 moving by f1, f2 (spec §8.4): the smallest
/// positive root of aτ² + bτ + c, ∞ when there is none.
pub fn flip_free_step(e1: [f64; 2], e2: [f64; 2], f1: [f64; 2], f2: [f64; 2]) -> f64 {
    let cross = |p: [f64; 2], q: [f64; 2]| p[0] * q[1] - p[1] * q[0];
    let a = cross(f1, f2);
    let b = cross(e1, f2) + cross(f1, e2);
    let c = cross(e1, e2);
    let scale = b.abs().max(c.abs()).max(f64::MIN_POSITIVE);
    let mut best = f64::INFINITY;
    if a.abs() <= 1e-14 * scale {
        if b < 0.0 {
            best = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            // Stable roots.
            let qr = -0.5 * (b + b.signum() * disc.sqrt());
            for root in [qr / a, if qr != 0.0 { c / qr } else { f64::INFINITY }] {
                if root > 0.0 && root < best {
                    best = root;
                }
            }
        }
    }
    best
}
