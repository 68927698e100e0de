use super::*;
use crate::vec3::dist;

fn cubic(t: f64) -> Point3 {
    [
        1.0 + 2.0 * t - t * t * t,
        t * t - 3.0 * t * t * t,
        0.5 - t + 4.0 * t * t,
    ]
}

#[test]
fn fit_reproduces_cubic_polynomial() {
    let m = 40;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let points: Vec<Point3> = params.iter().map(|&t| cubic(t)).collect();
    for spans in [1, 2, 3, 4, 8] {
        let c = fit_curve(&points, &params, spans).unwrap();
        assert_eq!(c.control_points().len(), spans + 3);
        let mut worst: f64 = 0.0;
        for i in 0..=200 {
            let t = i as f64 / 200.0;
            worst = worst.max(dist(c.eval(t), cubic(t)));
        }
        assert!(worst < 1e-12, "spans {spans}: error {worst:e}");
        assert!(max_fit_error(&c, &points, &params) < 1e-12);
        assert_eq!(c.eval(0.0), points[0]);
        assert_eq!(c.control_points()[0], points[0]);
        assert_eq!(*c.control_points().last().unwrap(), points[m - 1]);
    }
}

#[test]
fn derivative_matches_difference_and_reversal() {
    let params: Vec<f64> = (0..30).map(|i| i as f64 / 29.0).collect();
    let points: Vec<Point3> = params.iter().map(|&t| cubic(t)).collect();
    let c = fit_curve(&points, &params, 3).unwrap();
    let d = c.derivative(0.4);
    let want = [2.0 - 3.0 * 0.16, 0.8 - 9.0 * 0.16, -1.0 + 3.2];
    assert!(dist(d, want) < 1e-11, "{d:?}");
    let r = c.reversed();
    for i in 0..=10 {
        let t = i as f64 / 10.0;
        assert!(dist(r.eval(1.0 - t), c.eval(t)) < 1e-13);
    }
}

/// 400 samples of the unit circle, parameter = angle / 2π.
fn circle_samples() -> (Vec<Point3>, Vec<f64>) {
    let m = 400;
    let tau = std::f64::consts::TAU;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let points = params
        .iter()
        .map(|&t| [(tau * t).cos(), (tau * t).sin(), 0.0])
        .collect();
    (points, params)
}

/// Max distance to the unit circle over a dense sampling of the fitted curve.
fn circle_error(spans: usize) -> f64 {
    let m = 400;
    let tau = std::f64::consts::TAU;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let points: Vec<Point3> = params
        .iter()
        .map(|&t| [(tau * t).cos(), (tau * t).sin(), 0.0])
        .collect();
    let c = fit_curve(&points, &params, spans).unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..=2000 {
        let t = i as f64 / 2000.0;
        worst = worst.max(dist(c.eval(t), [(tau * t).cos(), (tau * t).sin(), 0.0]));
    }
    worst
}

#[test]
fn circle_fit_error_is_bounded_and_falls_with_spans() {
    // Bound: a cubic spline approximation on spans of length h = 1/K of a
    // curve with |x''''| <= (2π)^4 is O(h^4); the constant 5/384 is the one
    // of cubic spline interpolation, here with a factor 4 of slack for least
    // squares with interpolated ends.
    let mut prev = f64::INFINITY;
    eprintln!("K  max error   bound");
    for spans in [4usize, 8, 16, 32] {
        let h = 1.0 / spans as f64;
        let bound = 4.0 * 5.0 / 384.0 * std::f64::consts::TAU.powi(4) * h.powi(4);
        let err = circle_error(spans);
        let (points, params) = circle_samples();
        let fit_err = max_fit_error(
            &fit_curve(&points, &params, spans).unwrap(),
            &points,
            &params,
        );
        assert!(
            fit_err <= 1.05 * err && fit_err > 0.5 * err,
            "K={spans}: sample error {fit_err:e}"
        );
        eprintln!("{spans:2} {err:.3e}  {bound:.3e}");
        assert!(
            err < bound,
            "K={spans}: error {err:e} above bound {bound:e}"
        );
        assert!(
            err < prev / 8.0,
            "K={spans}: error {err:e} did not fall 8x from {prev:e}"
        );
        prev = err;
    }
}

#[test]
fn bad_fits_are_errors() {
    let p = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    // Too few samples for 4 spans: singular.
    let e = fit_curve(&p, &[0.0, 0.5, 1.0], 4).unwrap_err().to_string();
    assert!(e.contains("singular"), "{e}");
    assert!(fit_curve(&p, &[0.0, 1.0], 1).is_err());
    assert!(fit_curve(&p, &[0.0, 0.7, 0.5], 1).is_err());
    assert!(fit_curve(&p, &[0.1, 0.5, 1.0], 1).is_err());
    assert!(fit_curve(&p, &[0.0, f64::NAN, 1.0], 1).is_err());
    assert!(fit_curve(&p, &[0.0, 0.5, 1.0], 0).is_err());
}
