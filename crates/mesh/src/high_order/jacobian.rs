//! The geometry of a Lagrange quad: the 1-D Lagrange basis at equidistant
//! nodes, points and det J of an element, Gauss–Legendre points, and the
//! per-element judge [`ElementJacobian`].
//!
//! An element maps the reference square `(ξ, η) ∈ [0, 1]²` to
//! `x(ξ, η) = Σ_ij x_ij l_i(ξ) l_j(η)`, with `l_k` the order-N Lagrange
//! polynomial of the node `k / N`. Its **det J** at a point, relative to a
//! reference normal `n`, is the signed area scale `(x_ξ × x_η) · n / |n|`:
//! the area of a small patch of the element over the area of its preimage in
//! `[0, 1]²`, negative where the element folds over against `n`. A
//! parallelogram with sides `a`, `b` has det J = `|a × b|` everywhere.

use geometry::vec3::{cross, dot, norm, scale};
use geometry::Vec3;

use super::{check_order, HighOrderError, HighOrderQuadMesh};

/// Values and first derivatives of the `order + 1` Lagrange polynomials of
/// the equidistant nodes `k / order` (`k = 0..=order`) at `t`. Polynomial
/// `k` is 1 at node `k` and 0 at the others.
pub fn lagrange_basis(order: usize, t: f64) -> Result<(Vec<f64>, Vec<f64>), HighOrderError> {
    check_order(order)?;
    let node = |k: usize| k as f64 / order as f64;
    let mut values = vec![0.0; order + 1];
    let mut derivatives = vec![0.0; order + 1];
    for k in 0..=order {
        let mut value = 1.0;
        let mut derivative = 0.0;
        for m in (0..=order).filter(|&m| m != k) {
            let d = node(k) - node(m);
            // product rule: (value · f)' = value' · f + value · f'
            derivative = derivative * (t - node(m)) / d + value / d;
            value *= (t - node(m)) / d;
        }
        values[k] = value;
        derivatives[k] = derivative;
    }
    Ok((values, derivatives))
}

/// The `n`-point Gauss–Legendre rule on `[0, 1]`: points in increasing
/// order and their weights (summing to 1), exact for polynomials of degree
/// `2n − 1`. Found by Newton's method on the Legendre polynomial `P_n`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut points = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for k in 0..n {
        // the k-th largest root of P_n on [-1, 1], from a classical first guess
        let mut x = (std::f64::consts::PI * (k as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(n, x);
            let step = p / dp;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        let derivative = legendre(n, x).1;
        // map [-1, 1] to [0, 1]: x falls with k, so the points rise
        points.push((1.0 - x) / 2.0);
        weights.push(1.0 / ((1.0 - x * x) * derivative * derivative));
    }
    (points, weights)
}

/// `P_n(x)` and `P_n'(x)` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    // P_n' = n (x P_n − P_{n−1}) / (x² − 1), away from ±1 (the roots are)
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

/// The judge's verdict on one element: det J (relative to the element's
/// reference normal) over its `(N + 1)²` nodes and its `(N + 1) × (N + 1)`
/// Gauss–Legendre points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementJacobian {
    /// Smallest det J: the element is valid when it is positive.
    pub min_det: f64,
    /// Largest det J.
    pub max_det: f64,
    /// The **Jacobian ratio** `min_det / max |det J|`: 1 for a parallelogram,
    /// in `(0, 1]` for a valid element, `≤ 0` when det J is not positive
    /// somewhere; 0 when det J is 0 everywhere (a degenerate element).
    /// Like the quotient of Gmsh's "minDetJac" and "maxDetJac" qualities
    /// (adaptive extremes, where ours are sampled), it measures how far the
    /// map is from affine; unlike Gmsh's "minSJ" it ignores the corner angles.
    pub ratio: f64,
}

/// Evaluation tables of the Lagrange basis at a set of reference values.
struct Tables {
    values: Vec<Vec<f64>>,
    derivatives: Vec<Vec<f64>>,
}

impl Tables {
    fn new(order: usize, at: &[f64]) -> Result<Tables, HighOrderError> {
        let mut values = Vec::with_capacity(at.len());
        let mut derivatives = Vec::with_capacity(at.len());
        for &t in at {
            let (v, d) = lagrange_basis(order, t)?;
            values.push(v);
            derivatives.push(d);
        }
        Ok(Tables {
            values,
            derivatives,
        })
    }
}

/// Position and tangents `(x, x_ξ, x_η)` of an element (nodes in tensor
/// order) from basis values/derivatives in ξ (`a`, `da`) and η (`b`, `db`).
fn frame(nodes: &[Vec3], elem: &[u32], a: &[f64], da: &[f64], b: &[f64], db: &[f64]) -> [Vec3; 3] {
    let m = a.len();
    let mut out = [[0.0; 3]; 3];
    for j in 0..m {
        for i in 0..m {
            let p = nodes[elem[i + m * j] as usize];
            let w = [a[i] * b[j], da[i] * b[j], a[i] * db[j]];
            for (o, wk) in out.iter_mut().zip(w) {
                for c in 0..3 {
                    o[c] += wk * p[c];
                }
            }
        }
    }
    out
}

/// `v / |v|`, or zero when `v` has no length (or is not finite).
fn unit(v: Vec3) -> Vec3 {
    let l = norm(v);
    if l > 0.0 && l.is_finite() {
        scale(v, 1.0 / l)
    } else {
        [0.0; 3]
    }
}

fn check_point(xi: f64, eta: f64) -> Result<(), HighOrderError> {
    let inside = |t: f64| (0.0..=1.0).contains(&t);
    if inside(xi) && inside(eta) {
        Ok(())
    } else {
        Err(HighOrderError::BadReferencePoint(xi, eta))
    }
}

impl HighOrderQuadMesh {
    /// Position, `x_ξ` and `x_η` of element `e` at `(ξ, η)`, after checks.
    fn frame_at(&self, e: usize, xi: f64, eta: f64) -> Result<[Vec3; 3], HighOrderError> {
        let elem = self.checked_element(e)?;
        check_point(xi, eta)?;
        let (a, da) = lagrange_basis(self.order, xi)?;
        let (b, db) = lagrange_basis(self.order, eta)?;
        Ok(frame(&self.nodes, elem, &a, &da, &b, &db))
    }

    /// The point of element `e` at reference coordinates `(ξ, η) ∈ [0, 1]²`.
    pub fn point_at(&self, e: usize, xi: f64, eta: f64) -> Result<Vec3, HighOrderError> {
        Ok(self.frame_at(e, xi, eta)?[0])
    }

    /// The unit normal `x_ξ × x_η` of element `e` at its centre `(½, ½)`;
    /// zero when the element is degenerate there.
    pub fn element_normal(&self, e: usize) -> Result<Vec3, HighOrderError> {
        let [_, dx, dy] = self.frame_at(e, 0.5, 0.5)?;
        Ok(unit(cross(dx, dy)))
    }

    /// det J of element `e` at `(ξ, η) ∈ [0, 1]²` (see the module docs)
    /// relative to `normal`, or with `None` to the element's own normal at
    /// its centre ([`Self::element_normal`]).
    pub fn det_jacobian(
        &self,
        e: usize,
        xi: f64,
        eta: f64,
        normal: Option<Vec3>,
    ) -> Result<f64, HighOrderError> {
        let n = match normal {
            Some(n) => unit(n),
            None => self.element_normal(e)?,
        };
        let [_, dx, dy] = self.frame_at(e, xi, eta)?;
        Ok(dot(cross(dx, dy), n))
    }

    /// Judges element `e` against one reference normal (`None`: its own
    /// normal at its centre): det J at its nodes and Gauss points.
    pub fn element_jacobian(
        &self,
        e: usize,
        normal: Option<Vec3>,
    ) -> Result<ElementJacobian, HighOrderError> {
        let n = match normal {
            Some(n) => unit(n),
            None => self.element_normal(e)?,
        };
        self.element_jacobian_with(e, |_| n)
    }

    /// Judges element `e` with a reference normal per sample point:
    /// `normal_at(x)` gives it at the point `x` of the element (for example
    /// the CAD normal where `x` projects).
    pub fn element_jacobian_with(
        &self,
        e: usize,
        normal_at: impl Fn(Vec3) -> Vec3,
    ) -> Result<ElementJacobian, HighOrderError> {
        self.checked_element(e)?;
        let samples = Samples::new(self.order)?;
        Ok(samples.judge(self, e, &normal_at))
    }

    /// Judges every element: with `normals`, one reference normal per
    /// element; without, each element's own normal at its centre.
    pub fn jacobian_judge(
        &self,
        normals: Option<&[Vec3]>,
    ) -> Result<Vec<ElementJacobian>, HighOrderError> {
        self.validate()?;
        if let Some(n) = normals {
            if n.len() != self.num_elements() {
                return Err(HighOrderError::Length {
                    what: "reference normals",
                    got: n.len(),
                    want: self.num_elements(),
                });
            }
        }
        let samples = Samples::new(self.order)?;
        let centre = Tables::new(self.order, &[0.5])?;
        let c = (&centre.values[0], &centre.derivatives[0]);
        Ok((0..self.num_elements())
            .map(|e| {
                let n = match normals {
                    Some(n) => unit(n[e]),
                    None => {
                        let [_, dx, dy] = frame(&self.nodes, self.element(e), c.0, c.1, c.0, c.1);
                        unit(cross(dx, dy))
                    }
                };
                samples.judge(self, e, &|_| n)
            })
            .collect())
    }

    /// The Jacobian ratio of every element (its own normal as reference):
    /// what the VTU writer stores as `jacobian_ratio`.
    pub fn jacobian_ratios(&self) -> Result<Vec<f64>, HighOrderError> {
        Ok(self.jacobian_judge(None)?.iter().map(|j| j.ratio).collect())
    }
}

/// The judge's sample sets: the nodes `i / N` and the N + 1 Gauss points, each
/// taken as a tensor grid.
struct Samples {
    sets: [Tables; 2],
}

impl Samples {
    fn new(order: usize) -> Result<Samples, HighOrderError> {
        let nodes: Vec<f64> = (0..=order).map(|k| k as f64 / order as f64).collect();
        let gauss = gauss_legendre(order + 1).0;
        Ok(Samples {
            sets: [Tables::new(order, &nodes)?, Tables::new(order, &gauss)?],
        })
    }

    fn judge(
        &self,
        mesh: &HighOrderQuadMesh,
        e: usize,
        normal_at: &dyn Fn(Vec3) -> Vec3,
    ) -> ElementJacobian {
        let elem = mesh.element(e);
        let (mut lo, mut hi, mut big) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for t in &self.sets {
            for (b, db) in t.values.iter().zip(&t.derivatives) {
                for (a, da) in t.values.iter().zip(&t.derivatives) {
                    let [x, dx, dy] = frame(&mesh.nodes, elem, a, da, b, db);
                    let det = dot(cross(dx, dy), unit(normal_at(x)));
                    lo = lo.min(det);
                    hi = hi.max(det);
                    big = big.max(det.abs());
                }
            }
        }
        ElementJacobian {
            min_det: lo,
            max_det: hi,
            ratio: if big > 0.0 { lo / big } else { 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::high_order_patch;

    #[test]
    fn lagrange_basis_interpolates_and_differentiates() {
        for n in 1..=10 {
            for k in 0..=n {
                let (v, _) = lagrange_basis(n, k as f64 / n as f64).unwrap();
                for (m, x) in v.iter().enumerate() {
                    let want = if m == k { 1.0 } else { 0.0 };
                    assert!((x - want).abs() < 1e-9, "order {n}: l_{m}({k}/{n}) = {x}");
                }
            }
            // reproduces t^n and its derivative anywhere in [0, 1]
            let t = 0.37;
            let (v, d) = lagrange_basis(n, t).unwrap();
            let f = |s: f64| s.powi(n as i32);
            let value: f64 = (0..=n).map(|k| v[k] * f(k as f64 / n as f64)).sum();
            let slope: f64 = (0..=n).map(|k| d[k] * f(k as f64 / n as f64)).sum();
            assert!((value - f(t)).abs() < 1e-9, "order {n}");
            let want = n as f64 * t.powi(n as i32 - 1);
            assert!((slope - want).abs() < 1e-7, "order {n}: {slope} vs {want}");
            // partition of unity
            assert!((v.iter().sum::<f64>() - 1.0).abs() < 1e-9);
            assert!(d.iter().sum::<f64>().abs() < 1e-7);
        }
        assert_eq!(lagrange_basis(0, 0.5), Err(HighOrderError::BadOrder(0)));
        assert_eq!(lagrange_basis(11, 0.5), Err(HighOrderError::BadOrder(11)));
    }

    #[test]
    fn gauss_legendre_integrates_exactly_to_degree_2n_minus_1() {
        for n in 1..=11 {
            let (p, w) = gauss_legendre(n);
            assert_eq!(p.len(), n);
            assert!(p.windows(2).all(|s| s[0] < s[1]), "{p:?}");
            assert!(p.iter().all(|&t| t > 0.0 && t < 1.0));
            for deg in 0..2 * n {
                let q: f64 = p.iter().zip(&w).map(|(t, w)| w * t.powi(deg as i32)).sum();
                let exact = 1.0 / (deg as f64 + 1.0);
                assert!(
                    (q - exact).abs() < 1e-13,
                    "n {n}, degree {deg}: {q} vs {exact}"
                );
            }
            // degree 2n has the rule's known error (n!)⁴ / ((2n + 1) ((2n)!)²) on [0, 1]
            if n <= 8 {
                let q: f64 = p
                    .iter()
                    .zip(&w)
                    .map(|(t, w)| w * t.powi(2 * n as i32))
                    .sum();
                let fact = |k: usize| (1..=k).map(|i| i as f64).product::<f64>();
                let err = fact(n).powi(4) / ((2 * n + 1) as f64 * fact(2 * n).powi(2));
                let got = 1.0 / (2.0 * n as f64 + 1.0) - q;
                assert!(
                    (got - err).abs() < 1e-3 * err,
                    "n {n}: error {got} vs {err}"
                );
            }
        }
        // two points: ½ ± 1/(2√3), weights ½
        let (p, w) = gauss_legendre(2);
        assert!((p[0] - (0.5 - 0.5 / 3f64.sqrt())).abs() < 1e-15);
        assert!((w[1] - 0.5).abs() < 1e-15);
        assert_eq!(gauss_legendre(0), (vec![], vec![]));
    }

    #[test]
    fn a_parallelogram_has_constant_det_j_at_every_order() {
        // x = o + ξ a + η b with a = (2, 0.5, 0), b = (0.3, 1.5, 1):
        // det J = |a × b| = |(0.5, −2, 2.85)|
        let (a, b) = ([2.0, 0.5, 0.0], [0.3, 1.5, 1.0]);
        let area = (0.25f64 + 4.0 + 2.85 * 2.85).sqrt();
        for order in 1..=10 {
            // a 2 × 1 patch of unit elements in (u, v), mapped affinely
            let m = high_order_patch(order, 2, 1, |u, v| {
                [
                    1.0 + u * a[0] + v * b[0],
                    u * a[1] + v * b[1] - 3.0,
                    u * a[2] + v * b[2],
                ]
            });
            for e in 0..2 {
                for (xi, eta) in [(0.0, 0.0), (0.3, 0.9), (1.0, 0.5), (0.5, 0.5)] {
                    let d = m.det_jacobian(e, xi, eta, None).unwrap();
                    assert!(
                        (d - area).abs() < 1e-9 * area,
                        "order {order}: {d} vs {area}"
                    );
                }
                let j = m.element_jacobian(e, None).unwrap();
                assert!((j.min_det - area).abs() < 1e-9 && (j.max_det - area).abs() < 1e-9);
                assert!((j.ratio - 1.0).abs() < 1e-9, "{j:?}");
                // against the opposite normal the element is inverted
                let n = cross(a, b);
                let flipped = m.element_jacobian(e, Some(scale(n, -3.0))).unwrap();
                assert!((flipped.max_det + area).abs() < 1e-9, "{flipped:?}");
                assert!((flipped.ratio + 1.0).abs() < 1e-9);
            }
            let judged = m.jacobian_judge(None).unwrap();
            assert_eq!(judged.len(), 2);
            assert!(m
                .jacobian_ratios()
                .unwrap()
                .iter()
                .all(|r| (r - 1.0).abs() < 1e-9));
        }
    }

    #[test]
    fn a_curved_element_matches_its_map() {
        // x(u, v) = (u, v, u²) on one element: x_u × x_v = (−2u, 0, 1), and the
        // normal at the centre is (−1, 0, 1)/√2, so det J = (2u + 1)/√2
        for order in 2..=6 {
            let m = high_order_patch(order, 1, 1, |u, v| [u, v, u * u]);
            for (xi, eta) in [(0.0, 0.0), (0.25, 0.7), (1.0, 1.0), (0.9, 0.1)] {
                let d = m.det_jacobian(0, xi, eta, None).unwrap();
                let want = (2.0 * xi + 1.0) / 2f64.sqrt();
                assert!(
                    (d - want).abs() < 1e-9,
                    "order {order} at ({xi}, {eta}): {d} vs {want}"
                );
                let p = m.point_at(0, xi, eta).unwrap();
                assert!((p[2] - xi * xi).abs() < 1e-12 && (p[1] - eta).abs() < 1e-12);
            }
            let j = m.element_jacobian(0, None).unwrap();
            // extremes at the nodes ξ = 0 and ξ = 1
            assert!((j.min_det - 1.0 / 2f64.sqrt()).abs() < 1e-9, "{j:?}");
            assert!((j.max_det - 3.0 / 2f64.sqrt()).abs() < 1e-9, "{j:?}");
            assert!((j.ratio - 1.0 / 3.0).abs() < 1e-9);
            // against the exact normal of the surface at each point, det J is |x_u × x_v|
            let exact = m
                .element_jacobian_with(0, |p| [-2.0 * p[0], 0.0, 1.0])
                .unwrap();
            assert!(
                (exact.min_det - 1.0).abs() < 1e-9 && (exact.max_det - 5f64.sqrt()).abs() < 1e-9
            );
        }
        // a planar map with a varying Jacobian: x = (u + 0.3 u² v, v + 0.2 u v², 0)
        // det J = (1 + 0.6uv)(1 + 0.4uv) − 0.06 u² v²
        let m = high_order_patch(3, 1, 1, |u, v| {
            [u + 0.3 * u * u * v, v + 0.2 * u * v * v, 0.0]
        });
        for (xi, eta) in [(0.5, 0.5), (1.0, 1.0), (0.2, 0.8)] {
            let uv = xi * eta;
            let want = (1.0 + 0.6 * uv) * (1.0 + 0.4 * uv) - 0.06 * uv * uv;
            let d = m.det_jacobian(0, xi, eta, Some([0.0, 0.0, 5.0])).unwrap();
            assert!((d - want).abs() < 1e-12, "{d} vs {want}");
        }
    }

    #[test]
    fn folded_and_degenerate_elements_and_bad_requests() {
        // a bow tie: the top edge crosses over, det J changes sign
        let mut m = high_order_patch(2, 1, 1, |u, v| [u, v, 0.0]);
        m.nodes.swap(6, 8);
        let j = m.element_jacobian(0, Some([0.0, 0.0, 1.0])).unwrap();
        assert!(j.min_det < 0.0 && j.max_det > 0.0 && j.ratio < 0.0, "{j:?}");
        // every node at one point
        let mut flat = m.clone();
        flat.nodes = vec![[1.0, 2.0, 3.0]; flat.nodes.len()];
        let j = flat.jacobian_judge(None).unwrap()[0];
        assert_eq!((j.min_det, j.max_det, j.ratio), (0.0, 0.0, 0.0));
        assert_eq!(
            m.det_jacobian(1, 0.5, 0.5, None),
            Err(HighOrderError::NoSuchElement { index: 1, count: 1 })
        );
        assert_eq!(
            m.point_at(0, 1.5, 0.0),
            Err(HighOrderError::BadReferencePoint(1.5, 0.0))
        );
        assert!(m.point_at(0, f64::NAN, 0.0).is_err());
        assert!(matches!(
            m.jacobian_judge(Some(&[])),
            Err(HighOrderError::Length {
                what: "reference normals",
                ..
            })
        ));
        m.order = 12;
        assert_eq!(m.jacobian_ratios(), Err(HighOrderError::BadOrder(12)));
    }
}
