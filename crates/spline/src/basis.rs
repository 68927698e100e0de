//! Cox–de Boor basis functions and their derivatives (the triangular
//! recurrence of Piegl & Tiller, *The NURBS Book*, §2.2–2.3).

use crate::knots::KnotVector;

/// The `degree + 1` basis functions not zero on span `span` at `u`:
/// `N[span − degree + j](u)` for `j = 0..=degree`.
pub fn basis_functions(kv: &KnotVector, span: usize, u: f64) -> Vec<f64> {
    with_basis_derivatives(kv, span, u, 0, |ders, _| ders.to_vec())
}

/// The basis functions on span `span` at `u` and their derivatives up to
/// order `n` (`n` above the degree gives zero rows): `ders[k][j]` is the
/// k-th derivative of `N[span − degree + j]`.
pub fn basis_derivatives(kv: &KnotVector, span: usize, u: f64, n: usize) -> Vec<Vec<f64>> {
    with_basis_derivatives(kv, span, u, n, |ders, w| {
        ders.chunks(w).map(<[f64]>::to_vec).collect()
    })
}

/// Largest degree and derivative order computed in stack buffers by
/// [`with_basis_derivatives`] (above it, heap buffers).
const STACK_DEGREE: usize = 7;

/// Calls `f(ders, w)` with the values of [`basis_derivatives`] laid out
/// flat, row `k` (the k-th derivatives) at `ders[k * w..(k + 1) * w]` with
/// `w = degree + 1`, without allocating for degrees and orders up to
/// [`STACK_DEGREE`] (the evaluation hot path: closest points, Jacobians).
pub fn with_basis_derivatives<R>(
    kv: &KnotVector,
    span: usize,
    u: f64,
    n: usize,
    f: impl FnOnce(&[f64], usize) -> R,
) -> R {
    const W: usize = STACK_DEGREE + 1;
    let p = kv.degree();
    let w = p + 1;
    if p <= STACK_DEGREE && n <= STACK_DEGREE {
        let mut ndu = [0.0; W * W];
        let (mut left, mut right, mut a) = ([0.0; W], [0.0; W], [0.0; 2 * W]);
        let mut ders = [0.0; W * W];
        let rows = (n + 1) * w;
        let scratch = Scratch {
            ndu: &mut ndu[..w * w],
            left: &mut left[..w],
            right: &mut right[..w],
            a: &mut a[..2 * w],
        };
        derivatives_into(kv, span, u, n, scratch, &mut ders[..rows]);
        f(&ders[..rows], w)
    } else {
        let (mut ndu, mut left, mut right, mut a) = (
            vec![0.0; w * w],
            vec![0.0; w],
            vec![0.0; w],
            vec![0.0; 2 * w],
        );
        let mut ders = vec![0.0; (n + 1) * w];
        let scratch = Scratch {
            ndu: &mut ndu,
            left: &mut left,
            right: &mut right,
            a: &mut a,
        };
        derivatives_into(kv, span, u, n, scratch, &mut ders);
        f(&ders, w)
    }
}

/// Zeroed work space of [`derivatives_into`] for degree p (w = p + 1).
struct Scratch<'a> {
    /// ndu[j][r] at `j * w + r`: basis functions (upper triangle) and knot
    /// differences (lower).
    ndu: &'a mut [f64],
    left: &'a mut [f64],
    right: &'a mut [f64],
    /// The two rows of the derivative coefficients, at `s * w + j`.
    a: &'a mut [f64],
}

/// The triangular recurrence (Piegl & Tiller A2.3) into `ders` (zeroed,
/// `(n + 1) * w`, row k at `k * w`).
fn derivatives_into(kv: &KnotVector, span: usize, u: f64, n: usize, sc: Scratch, ders: &mut [f64]) {
    let p = kv.degree();
    let w = p + 1;
    let knots = kv.knots();
    let Scratch {
        ndu,
        left,
        right,
        a,
    } = sc;
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + j - 1] / ndu[j * w + r];
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for j in 0..=p {
        ders[j] = ndu[j * w + p];
    }
    let nd = n.min(p);
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, w);
        a[0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2] = a[s1] / ndu[(pk + 1) * w + rk];
                d = a[s2] * ndu[rk * w + pk];
            }
            let j1: usize = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2: usize = if r <= pk + 1 { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2 + j] = (a[s1 + j] - a[s1 + j - 1]) / ndu[(pk + 1) * w + idx];
                d += a[s2 + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                a[s2 + k] = -a[s1 + k - 1] / ndu[(pk + 1) * w + r];
                d += a[s2 + k] * ndu[r * w + pk];
            }
            ders[k * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=nd {
        for v in &mut ders[k * w..(k + 1) * w] {
            *v *= factor;
        }
        factor *= (p - k) as f64;
    }
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
    fn degrees_above_the_stack_buffers_give_the_bernstein_basis_too() {
        // Degree 9 > STACK_DEGREE: the heap path. Bézier: B_j = C(9, j) u^j v^(9−j).
        let kv = KnotVector::clamped_uniform(9, 1).unwrap();
        let u = 0.37;
        let v = 1.0 - u;
        let d = basis_derivatives(&kv, kv.find_span(u), u, 1);
        assert_eq!((d.len(), d[0].len()), (2, 10));
        let mut binom = 1.0;
        for j in 0..=9 {
            let b = binom * u.powi(j as i32) * v.powi(9 - j as i32);
            // d/du: C(9, j) (j u^(j−1) v^(9−j) − (9−j) u^j v^(8−j))
            let db = binom
                * (if j > 0 {
                    j as f64 * u.powi(j as i32 - 1) * v.powi(9 - j as i32)
                } else {
                    0.0
                } - if j < 9 {
                    (9 - j) as f64 * u.powi(j as i32) * v.powi(8 - j as i32)
                } else {
                    0.0
                });
            assert!((d[0][j] - b).abs() < 1e-13, "{j}: {} vs {b}", d[0][j]);
            assert!((d[1][j] - db).abs() < 1e-11, "{j}: {} vs {db}", d[1][j]);
            binom = binom * (9 - j) as f64 / (j + 1) as f64;
        }
        // The flat layout of the callback is the rows of basis_derivatives.
        let flat = with_basis_derivatives(&kv, kv.find_span(u), u, 1, |f, w| (f.to_vec(), w));
        assert_eq!(flat.1, 10);
        assert_eq!(flat.0, [d[0].clone(), d[1].clone()].concat());
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
