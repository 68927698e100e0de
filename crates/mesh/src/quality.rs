//! Element quality: SICN and scaled Jacobian of quads sampled at the four
//! corners with a reference normal (Eq. 12 of the quasi-structured paper).
//!
//! For corner i of quad (x0, x1, x2, x3), with `a = x_{i+1} − x_i` and
//! `b = x_{i−1} − x_i` and unit normal `N_i`:
//! - `SJ_i   = (a × b)·N_i / (|a| |b|)`
//! - `SICN_i = 2 (a × b)·N_i / (|a|² + |b|²)`
//!
//! and the quad's value is the minimum over its corners. A square gives 1, a
//! 2:1 rectangle SICN 0.8 and SJ 1, an inverted corner a negative value.

use geometry::vec3::{cross, dot, sub, Vec3};

/// SICN of each corner of the quad `p` with corner normals `n` (unit vectors).
pub fn corner_sicn(p: &[Vec3; 4], n: &[Vec3; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for i in 0..4 {
        let a = sub(p[(i + 1) % 4], p[i]);
        let b = sub(p[(i + 3) % 4], p[i]);
        let den = dot(a, a) + dot(b, b);
        out[i] = if den > 0.0 {
            2.0 * dot(cross(a, b), n[i]) / den
        } else {
            0.0
        };
    }
    out
}

/// Scaled Jacobian of each corner of the quad `p` with corner normals `n`.
pub fn corner_scaled_jacobian(p: &[Vec3; 4], n: &[Vec3; 4]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for i in 0..4 {
        let a = sub(p[(i + 1) % 4], p[i]);
        let b = sub(p[(i + 3) % 4], p[i]);
        let den = (dot(a, a) * dot(b, b)).sqrt();
        out[i] = if den > 0.0 {
            dot(cross(a, b), n[i]) / den
        } else {
            0.0
        };
    }
    out
}

/// Quad SICN: the minimum of [`corner_sicn`].
pub fn quad_sicn(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
    corner_sicn(p, n).into_iter().fold(f64::INFINITY, f64::min)
}

/// Quad scaled Jacobian: the minimum of [`corner_scaled_jacobian`].
pub fn quad_scaled_jacobian(p: &[Vec3; 4], n: &[Vec3; 4]) -> f64 {
    corner_scaled_jacobian(p, n)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    const Z: [Vec3; 4] = [[0.0, 0.0, 1.0]; 4];

    #[test]
    fn hand_computed_values() {
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!((quad_sicn(&square, &Z) - 1.0).abs() < 1e-15);
        let rect = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!((quad_sicn(&rect, &Z) - 0.8).abs() < 1e-15);
        assert!((quad_scaled_jacobian(&rect, &Z) - 1.0).abs() < 1e-15);
        // clockwise seen from +z: inverted
        let cw = [square[0], square[3], square[2], square[1]];
        assert!(quad_sicn(&cw, &Z) < 0.0);
        // a tiny edge: SICN → 0 while SJ stays sin(angle)
        let tiny = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1e-12, 1.0, 0.0],
        ];
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0 + 1e-12, 1e-12, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert!(quad_sicn(&tiny, &Z) > 0.99);
        assert!(quad_sicn(&flat, &Z) < 1e-9);
    }
}
