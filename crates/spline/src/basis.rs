//! Cox–de Boor basis functions and their derivatives (the triangular
//! recurrence of Piegl & Tiller, *The NURBS Book*, §2.2–2.3).

use crate::knots::KnotVector;

/// The `degree + 1` basis functions not zero on span `span` at `u`:
/// `N[span − degree + j](u)` for `j = 0..=degree`.
pub fn basis_functions(kv: &KnotVector, span: usize, u: f64) -> Vec<f64> {
    basis_derivatives(kv, span, u, 0).swap_remove(0)
}

/// The basis functions on span `span` at `u` and their derivatives up to
/// order `n` (`n` above the degree gives zero rows): `ders[k][j]` is the
/// k-th derivative of `N[span − degree + j]`.
pub fn basis_derivatives(kv: &KnotVector, span: usize, u: f64, n: usize) -> Vec<Vec<f64>> {
    let p = kv.degree();
    let knots = kv.knots();
    // ndu: basis functions (upper triangle) and knot differences (lower).
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = vec![vec![0.0; p + 1]; n + 1];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let nd = n.min(p);
    let mut a = [vec![0.0; p + 1], vec![0.0; p + 1]];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1: usize = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2: usize = if r <= pk + 1 { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
        for v in row.iter_mut() {
            *v *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bezier_basis_is_bernstein() {
        let kv = KnotVector::clamped_uniform(3, 1).unwrap();
        let u = 0.3;
        let d = basis_derivatives(&kv, kv.find_span(u), u, 2);
        let v = 1.0 - u;
        let b = [v * v * v, 3.0 * u * v * v, 3.0 * u * u * v, u * u * u];
        let db = [
            -3.0 * v * v,
            3.0 * v * v - 6.0 * u * v,
            6.0 * u * v - 3.0 * u * u,
            3.0 * u * u,
        ];
        let ddb = [6.0 * v, -12.0 * v + 6.0 * u, 6.0 * v - 12.0 * u, 6.0 * u];
        for j in 0..4 {
            assert!((d[0][j] - b[j]).abs() < 1e-14);
            assert!((d[1][j] - db[j]).abs() < 1e-13);
            assert!((d[2][j] - ddb[j]).abs() < 1e-12);
        }
    }

    #[test]
    fn partition_of_unity_and_derivative_by_differences() {
        let kv = KnotVector::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0],
        )
        .unwrap();
        for i in 0..=50 {
            let u = i as f64 / 50.0;
            let span = kv.find_span(u);
            let n = basis_functions(&kv, span, u);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(n.iter().all(|&x| x >= -1e-15));
        }
        // First derivative against a central difference inside a span.
        let (u, h) = (0.33, 1e-6);
        let span = kv.find_span(u);
        let d = basis_derivatives(&kv, span, u, 1);
        let np = basis_functions(&kv, span, u + h);
        let nm = basis_functions(&kv, span, u - h);
        for j in 0..4 {
            assert!((d[1][j] - (np[j] - nm[j]) / (2.0 * h)).abs() < 1e-6);
        }
    }
}
