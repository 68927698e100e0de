//! B-spline curves in space and their least-squares fit with the end points
//! interpolated (spec §9.3).

use crate::basis::{basis_functions, with_basis_derivatives};
use crate::error::{Result, SplineError};
use crate::knots::KnotVector;
use crate::linalg::cholesky_solve;
use crate::vec3::{axpy, Point3, Vec3};

/// A non-rational B-spline curve: knots and one control point per basis function.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve {
    knots: KnotVector,
    control: Vec<Point3>,
}

impl BSplineCurve {
    /// A curve from knots and control points; their counts must match.
    pub fn new(knots: KnotVector, control: Vec<Point3>) -> Result<Self> {
        if control.len() != knots.num_control_points() {
            return Err(SplineError::Shape(format!(
                "curve: {} knots of degree {} need {} control points, got {}",
                knots.knots().len(),
                knots.degree(),
                knots.num_control_points(),
                control.len()
            )));
        }
        Ok(Self { knots, control })
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The control points, in parameter order.
    pub fn control_points(&self) -> &[Point3] {
        &self.control
    }

    /// The point at parameter `u` (clamped to the domain).
    pub fn eval(&self, u: f64) -> Point3 {
        self.eval_with_derivative(u).0
    }

    /// The first derivative dC/du at `u`.
    pub fn derivative(&self, u: f64) -> Vec3 {
        self.eval_with_derivative(u).1
    }

    /// The point and first derivative at `u`.
    pub fn eval_with_derivative(&self, u: f64) -> (Point3, Vec3) {
        let p = self.knots.degree();
        let span = self.knots.find_span(u);
        with_basis_derivatives(&self.knots, span, u, 1, |d, w| {
            let (mut c, mut dc) = ([0.0; 3], [0.0; 3]);
            for (j, (&n0, &n1)) in d[..w].iter().zip(&d[w..]).enumerate() {
                let cp = self.control[span - p + j];
                c = axpy(c, n0, cp);
                dc = axpy(dc, n1, cp);
            }
            (c, dc)
        })
    }

    /// The same curve traversed the other way (mirrored knots, reversed control points).
    pub fn reversed(&self) -> Self {
        Self {
            knots: self.knots.reversed(),
            control: self.control.iter().rev().copied().collect(),
        }
    }
}

/// The largest distance between `points` and the curve at their `params`:
/// the fit error to report (spec §14.5) and to compare with a tolerance.
pub fn max_fit_error(curve: &BSplineCurve, points: &[Point3], params: &[f64]) -> f64 {
    points
        .iter()
        .zip(params)
        .map(|(x, &t)| crate::vec3::dist(curve.eval(t), *x))
        .fold(0.0, f64::max)
}

/// Fits a cubic B-spline with `spans` uniform spans on [0, 1] to `points`
/// sampled at `params` by least squares, with the first and last control
/// points equal to the first and last points (so curves meeting at a node
/// share it exactly). `params` must rise from exactly 0 to exactly 1.
/// Errors when the counts differ, a parameter is out of order, or the normal
/// equations are singular (too few samples in some span).
pub fn fit_curve(points: &[Point3], params: &[f64], spans: usize) -> Result<BSplineCurve> {
    let m = points.len();
    if m != params.len() {
        return Err(SplineError::Fit(format!(
            "{m} points but {} parameters",
            params.len()
        )));
    }
    if m < 2 {
        return Err(SplineError::Fit(format!("need at least 2 points, got {m}")));
    }
    if params[0] != 0.0 || params[m - 1] != 1.0 {
        return Err(SplineError::Fit(format!(
            "parameters must run from 0 to 1, got {} … {}",
            params[0],
            params[m - 1]
        )));
    }
    if let Some(i) = (1..m).find(|&i| !(params[i] >= params[i - 1])) {
        return Err(SplineError::Fit(format!(
            "parameter {i} ({}) is below parameter {} ({})",
            params[i],
            i - 1,
            params[i - 1]
        )));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(SplineError::Fit(format!("point {i} is not finite")));
    }
    let knots = KnotVector::clamped_uniform(3, spans)?;
    let n = knots.num_control_points();
    let first = points[0];
    let last = points[m - 1];
    // Unknowns: control points 1..n-1 (n - 2 of them).
    let u = n - 2;
    let mut ata = vec![0.0; u * u];
    let mut atb = vec![vec![0.0; u]; 3];
    for (x, &t) in points.iter().zip(params) {
        let span = knots.find_span(t);
        let basis = basis_functions(&knots, span, t);
        let mut r = *x;
        for (j, &nj) in basis.iter().enumerate() {
            let i = span - 3 + j;
            if i == 0 {
                r = axpy(r, -nj, first);
            } else if i == n - 1 {
                r = axpy(r, -nj, last);
            }
        }
        for (ja, &na) in basis.iter().enumerate() {
            let ia = span - 3 + ja;
            if ia == 0 || ia == n - 1 {
                continue;
            }
            for c in 0..3 {
                atb[c][ia - 1] += na * r[c];
            }
            for (jb, &nb) in basis.iter().enumerate() {
                let ib = span - 3 + jb;
                if ib == 0 || ib == n - 1 {
                    continue;
                }
                ata[(ia - 1) * u + (ib - 1)] += na * nb;
            }
        }
    }
    cholesky_solve(ata, u, &mut atb).map_err(|(row, pivot)| {
        SplineError::Fit(format!(
            "singular normal equations at control point {} of {n} ({m} samples for {spans} spans, pivot {pivot:.3e}): too few samples in some span",
            row + 1
        ))
    })?;
    let mut control = Vec::with_capacity(n);
    control.push(first);
    control.extend((0..u).map(|i| [atb[0][i], atb[1][i], atb[2][i]]));
    control.push(last);
    BSplineCurve::new(knots, control)
}

#[cfg(test)]
mod tests;
