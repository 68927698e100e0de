//! A dense Cholesky solve for the small normal equations of curve and patch fitting.

/// Solves `a x = b` for a symmetric positive definite `n × n` matrix `a`
/// (row-major) and each right-hand side in `rhs` (overwritten by its
/// solution). Returns `Err((row, pivot))` when a pivot is not positive
/// relative to the largest diagonal entry: the system is singular.
///
/// Works on the envelope of `a`: row i from its first non-zero column. The
/// factor has no fill-in left of it, so the skipped terms are exact zeros
/// and the result is the dense algorithm's to the bit, at a cost of about
/// n·w² for a band of half-width w (the tensor-product fits: w ≈ 3 rows of
/// control points) instead of n³/3.
pub fn cholesky_solve(
    mut a: Vec<f64>,
    n: usize,
    rhs: &mut [Vec<f64>],
) -> Result<(), (usize, f64)> {
    let max_diag = (0..n).map(|i| a[i * n + i].abs()).fold(0.0, f64::max);
    let tiny = 1e-13 * max_diag.max(f64::MIN_POSITIVE);
    // First non-zero column of each row (the diagonal at the latest).
    let first: Vec<usize> = (0..n)
        .map(|i| (0..i).find(|&k| a[i * n + k] != 0.0).unwrap_or(i))
        .collect();
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in first[j]..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if !(d > tiny) || !d.is_finite() {
            return Err((j, d));
        }
        let l = d.sqrt();
        a[j * n + j] = l;
        for i in j + 1..n {
            if first[i] > j {
                continue;
            }
            let mut s = a[i * n + j];
            for k in first[i].max(first[j])..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / l;
        }
    }
    for b in rhs.iter_mut() {
        for i in 0..n {
            let mut s = b[i];
            for k in first[i]..i {
                s -= a[i * n + k] * b[k];
            }
            b[i] = s / a[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for k in i + 1..n {
                if first[k] <= i {
                    s -= a[k * n + i] * b[k];
                }
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

    #[test]
    fn a_banded_system_gives_the_dense_factor_bit_for_bit() {
        // A 1-D Laplacian plus a coupling 3 apart, ragged envelope: row 5
        // starts at column 2, row 6 at column 5.
        let n = 9;
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 4.0 + i as f64 * 0.1;
            if i > 0 {
                a[i * n + i - 1] = -1.0;
                a[(i - 1) * n + i] = -1.0;
            }
        }
        a[5 * n + 2] = 0.5;
        a[2 * n + 5] = 0.5;
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|k| a[i * n + k] * x[k]).sum())
            .collect();
        let mut rhs = vec![b.clone()];
        cholesky_solve(a.clone(), n, &mut rhs).unwrap();
        for i in 0..n {
            assert!(
                (rhs[0][i] - x[i]).abs() < 1e-14,
                "{i}: {} vs {}",
                rhs[0][i],
                x[i]
            );
        }
        // The dense algorithm (every k, every row) on the same system.
        let mut l = a;
        for j in 0..n {
            let mut d = l[j * n + j];
            for k in 0..j {
                d -= l[j * n + k] * l[j * n + k];
            }
            l[j * n + j] = d.sqrt();
            for i in j + 1..n {
                let mut s = l[i * n + j];
                for k in 0..j {
                    s -= l[i * n + k] * l[j * n + k];
                }
                l[i * n + j] = s / l[j * n + j];
            }
        }
        let mut y = b;
        for i in 0..n {
            for k in 0..i {
                y[i] -= l[i * n + k] * y[k];
            }
            y[i] /= l[i * n + i];
        }
        for i in (0..n).rev() {
            for k in i + 1..n {
                y[i] -= l[k * n + i] * y[k];
            }
            y[i] /= l[i * n + i];
        }
        assert_eq!(rhs[0], y);
    }
}
