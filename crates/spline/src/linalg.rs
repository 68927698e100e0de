//! A dense Cholesky solve for the small normal equations of curve and patch fitting.

/// Solves `a x = b` for a symmetric positive definite `n × n` matrix `a`
/// (row-major) and each right-hand side in `rhs` (overwritten by its
/// solution). Returns `Err((row, pivot))` when a pivot is not positive
/// relative to the largest diagonal entry: the system is singular.
pub fn cholesky_solve(
    mut a: Vec<f64>,
    n: usize,
    rhs: &mut [Vec<f64>],
) -> Result<(), (usize, f64)> {
    let max_diag = (0..n).map(|i| a[i * n + i].abs()).fold(0.0, f64::max);
    let tiny = 1e-13 * max_diag.max(f64::MIN_POSITIVE);
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if !(d > tiny) || !d.is_finite() {
            return Err((j, d));
        }
        let l = d.sqrt();
        a[j * n + j] = l;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / l;
        }
    }
    for b in rhs.iter_mut() {
        for i in 0..n {
            let mut s = b[i];
            for k in 0..i {
                s -= a[i * n + k] * b[k];
            }
            b[i] = s / a[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for k in i + 1..n {
                s -= a[k * n + i] * b[k];
            }
            b[i] = s / a[i * n + i];
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_and_rejects_singular() {
        let a = vec![4.0, 2.0, 2.0, 3.0];
        let mut rhs = vec![vec![2.0, 1.0]];
        cholesky_solve(a, 2, &mut rhs).unwrap();
        assert!((rhs[0][0] - 0.5).abs() < 1e-15 && rhs[0][1].abs() < 1e-15);
        let s = vec![1.0, 1.0, 1.0, 1.0];
        assert_eq!(cholesky_solve(s, 2, &mut []).unwrap_err().0, 1);
    }
}
