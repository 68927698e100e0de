//! The final exact snap of the layout energy (spec §8.4, [F]): the map
//! φ* of a penalty stage projected onto the constraints' null space,
//! φ = φ* − Cᵀ(CCᵀ)⁻¹Cφ* (the nearest map in the plain norm with every
//! E2–E4 row exactly zero). CCᵀ is solved by conjugate gradients without
//! forming it (rows of 2 to 6 unknowns; dependent rows are harmless: Cφ* is
//! in its range). The caller keeps it only when every det J stays positive.

use super::constraints::LinearTerm;

/// C·x over the rows `terms`.
fn apply(terms: &[&LinearTerm], x: &[f64], out: &mut [f64]) {
    for (o, t) in out.iter_mut().zip(terms) {
        *o = t.value(x);
    }
}

/// Cᵀ·y added into `out` (zeroed first).
fn apply_transposed(terms: &[&LinearTerm], y: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for (t, &w) in terms.iter().zip(y) {
        for k in 0..t.len {
            out[t.dofs[k]] += t.coefs[k] * w;
        }
    }
}

/// `phi` projected onto {C·φ = 0} for the rows `terms`; also the largest
/// move of one unknown. `None` when CG does not reach a relative residual
/// of 1e-13 in `max_iterations`.
pub fn snap(terms: &[&LinearTerm], phi: &[f64], max_iterations: usize) -> Option<(Vec<f64>, f64)> {
    let (m, n) = (terms.len(), phi.len());
    let mut b = vec![0.0; m];
    apply(terms, phi, &mut b);
    let bnorm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    if bnorm == 0.0 {
        return Some((phi.to_vec(), 0.0));
    }
    let (mut y, mut r, mut p) = (vec![0.0; m], b.clone(), b);
    let (mut ap, mut tmp) = (vec![0.0; m], vec![0.0; n]);
    let mut rr: f64 = r.iter().map(|v| v * v).sum();
    let mut converged = false;
    for _ in 0..max_iterations {
        if rr.sqrt() <= 1e-13 * bnorm {
            converged = true;
            break;
        }
        apply_transposed(terms, &p, &mut tmp);
        apply(terms, &tmp, &mut ap);
        let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
        if !(pap > 0.0) {
            break;
        }
        let alpha = rr / pap;
        for k in 0..m {
            y[k] += alpha * p[k];
            r[k] -= alpha * ap[k];
        }
        let next: f64 = r.iter().map(|v| v * v).sum();
        let beta = next / rr;
        rr = next;
        for k in 0..m {
            p[k] = r[k] + beta * p[k];
        }
    }
    if !converged && rr.sqrt() > 1e-13 * bnorm {
        return None;
    }
    apply_transposed(terms, &y, &mut tmp);
    let shift = tmp.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    Some((phi.iter().zip(&tmp).map(|(a, d)| a - d).collect(), shift))
}
