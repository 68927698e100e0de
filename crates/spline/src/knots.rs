//! Clamped knot vectors: uniform construction, Greville abscissae, span lookup.

use crate::error::{Result, SplineError};
use serde::{Deserialize, Serialize};

/// A clamped (open) knot vector of a given degree: the first and last
/// `degree + 1` knots are equal, the knots never decrease, and no interior
/// knot repeats more than `degree` times.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
}

impl KnotVector {
    /// The clamped uniform knot vector on [0, 1] with `spans` equal spans:
    /// `degree + spans` control points (spec §9.3).
    pub fn clamped_uniform(degree: usize, spans: usize) -> Result<Self> {
        if degree == 0 || spans == 0 {
            return Err(SplineError::Knots(format!(
                "clamped uniform knots need degree >= 1 and spans >= 1, got degree {degree}, spans {spans}"
            )));
        }
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|i| i as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Ok(Self { degree, knots })
    }

    /// A knot vector from its values, checked: finite, non-decreasing,
    /// clamped at both ends, interior multiplicity at most `degree`, a
    /// non-empty domain.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self> {
        let p = degree;
        if p == 0 || knots.len() < 2 * (p + 1) {
            return Err(SplineError::Knots(format!(
                "degree {p} needs at least {} knots, got {}",
                2 * (p + 1),
                knots.len()
            )));
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return Err(SplineError::Knots(format!("knot {i} is not finite")));
        }
        if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
            return Err(SplineError::Knots(format!(
                "knot {i} ({}) is below knot {} ({})",
                knots[i],
                i - 1,
                knots[i - 1]
            )));
        }
        let m = knots.len();
        if knots[p] != knots[0] || knots[m - 1 - p] != knots[m - 1] {
            return Err(SplineError::Knots(format!(
                "not clamped: the first and last {} knots must be equal (got {:?} … {:?})",
                p + 1,
                &knots[..=p],
                &knots[m - 1 - p..]
            )));
        }
        if !(knots[m - 1] > knots[0]) {
            return Err(SplineError::Knots(format!(
                "empty domain [{}, {}]",
                knots[0],
                knots[m - 1]
            )));
        }
        let kv = Self { degree, knots };
        for &b in &kv.breakpoints()[1..kv.breakpoints().len() - 1] {
            let mult = kv.multiplicity(b);
            if mult > p {
                return Err(SplineError::Knots(format!(
                    "interior knot {b} repeats {mult} times, more than the degree {p}"
                )));
            }
        }
        Ok(kv)
    }

    /// The polynomial degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot values.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// How many control points a spline on these knots has.
    pub fn num_control_points(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The parameter domain `[first knot, last knot]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// The distinct knot values, ascending: the ends of the knot spans.
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for &k in &self.knots {
            if out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }

    /// The number of non-empty knot spans (Bézier elements).
    pub fn num_spans(&self) -> usize {
        self.breakpoints().len() - 1
    }

    /// How many times the value `u` appears in the knot vector.
    pub fn multiplicity(&self, u: f64) -> usize {
        self.knots.iter().filter(|&&k| k == u).count()
    }

    /// The Greville abscissae: the mean of the `degree` knots after the
    /// first of each basis function, the parameters at which the control
    /// points "sit" (linear functions are reproduced through them).
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree;
        (0..self.num_control_points())
            .map(|i| self.knots[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// The span index `k` with `knots[k] <= u < knots[k + 1]` and
    /// `degree <= k < num_control_points()`; `u` outside the domain (or NaN)
    /// is clamped to it, and the domain's end belongs to the last span.
    pub fn find_span(&self, u: f64) -> usize {
        let p = self.degree;
        let n = self.num_control_points();
        let (lo, hi) = self.domain();
        if !(u > lo) {
            // The first non-empty span.
            let mut k = p;
            while k + 1 < n && self.knots[k + 1] <= lo {
                k += 1;
            }
            return k;
        }
        if u >= hi {
            let mut k = n - 1;
            while k > p && self.knots[k] >= hi {
                k -= 1;
            }
            return k;
        }
        let (mut low, mut high) = (p, n);
        while high - low > 1 {
            let mid = (low + high) / 2;
            if u < self.knots[mid] {
                high = mid;
            } else {
                low = mid;
            }
        }
        low
    }

    /// Returns these knots mirrored: `a + b − u` for every knot, reversed,
    /// the knots of the reversed curve. A symmetric knot vector (e.g. a
    /// uniform one) is returned bit for bit, so that an arc used reversed
    /// has exactly the knots of one used forward.
    pub fn reversed(&self) -> Self {
        let (a, b) = self.domain();
        let mut knots: Vec<f64> = self.knots.iter().rev().map(|&k| a + b - k).collect();
        // Keep the ends exact.
        let m = knots.len();
        for k in knots.iter_mut().take(self.degree + 1) {
            *k = a;
        }
        for k in knots.iter_mut().skip(m - self.degree - 1) {
            *k = b;
        }
        let mirrored = Self {
            degree: self.degree,
            knots,
        };
        if self.compatible(&mirrored, 1e-14) {
            return self.clone();
        }
        mirrored
    }

    /// True when both knot vectors have the same degree and knots equal to
    /// within `tol` times the domain length.
    pub fn compatible(&self, other: &Self, tol: f64) -> bool {
        let (a, b) = self.domain();
        self.degree == other.degree
            && self.knots.len() == other.knots.len()
            && self
                .knots
                .iter()
                .zip(&other.knots)
                .all(|(x, y)| (x - y).abs() <= tol * (b - a))
    }

    /// A copy with one more knot `u` (no control-point update; see
    /// `refine::insert_knot`).
    pub(crate) fn with_inserted(&self, span: usize, u: f64) -> Self {
        let mut knots = self.knots.clone();
        knots.insert(span + 1, u);
        Self {
            degree: self.degree,
            knots,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_knots_counts_and_greville() {
        let kv = KnotVector::clamped_uniform(3, 4).unwrap();
        assert_eq!(
            kv.knots(),
            &[0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0]
        );
        assert_eq!(kv.num_control_points(), 7);
        assert_eq!(kv.num_spans(), 4);
        let g = kv.greville();
        let want = [0.0, 1.0 / 12.0, 0.25, 0.5, 0.75, 11.0 / 12.0, 1.0];
        for (a, b) in g.iter().zip(want) {
            assert!((a - b).abs() < 1e-15, "{g:?}");
        }
        // Bézier: 4 control points, Greville 0, 1/3, 2/3, 1.
        let bz = KnotVector::clamped_uniform(3, 1).unwrap();
        assert_eq!(bz.num_control_points(), 4);
        assert!((bz.greville()[1] - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn span_lookup() {
        let kv = KnotVector::clamped_uniform(3, 4).unwrap();
        assert_eq!(kv.find_span(0.0), 3);
        assert_eq!(kv.find_span(0.1), 3);
        assert_eq!(kv.find_span(0.25), 4);
        assert_eq!(kv.find_span(0.6), 5);
        assert_eq!(kv.find_span(1.0), 6);
        assert_eq!(kv.find_span(7.0), 6);
        assert_eq!(kv.find_span(-1.0), 3);
        assert_eq!(kv.find_span(f64::NAN), 3);
    }

    #[test]
    fn bad_knots_are_errors() {
        assert!(KnotVector::clamped_uniform(3, 0).is_err());
        assert!(KnotVector::new(3, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]).is_err());
        assert!(
            KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.4, 1.0, 1.0, 1.0, 1.0]).is_err()
        );
        assert!(KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.1, 1.0, 1.0, 1.0, 1.0]).is_err());
        let msg = KnotVector::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0],
        )
        .unwrap_err()
        .to_string();
        assert!(msg.contains("repeats 4 times"), "{msg}");
        assert!(KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0]).is_ok());
    }

    #[test]
    fn reversal_mirrors() {
        let kv = KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.2, 1.0, 1.0, 1.0, 1.0]).unwrap();
        let r = kv.reversed();
        assert!((r.knots()[4] - 0.8).abs() < 1e-15);
        assert!(r.reversed().compatible(&kv, 1e-15));
        // Symmetric knots come back bit for bit.
        let u = KnotVector::clamped_uniform(3, 3).unwrap();
        assert_eq!(u.reversed(), u);
    }
}
