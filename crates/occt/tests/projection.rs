//! Surface and curve evaluation/projection on every face and curve of every
//! bundled CAD model, serially and from several threads at once.

mod common;

use common::*;
use geometry::vec3::dist;

/// eval → project round trip at ≥ 25 points inside every trimmed face,
/// without hint (global) and with a hint (local).
#[test]
fn surface_projection_round_trips_inside_every_face() {
    let mut n_points = 0;
    for (name, imp) in imports() {
        let m = &imp.model;
        let diag = m.diagonal();
        let tol = 1e-7 * diag;
        for (f, face) in m.faces.iter().enumerate() {
            let pts = interior_points(m, f, 25);
            assert!(
                pts.len() >= 25,
                "{name} face {f}: only {} interior points",
                pts.len()
            );
            let b = face.uv_bounds;
            let (eu, ev) = (b.umax - b.umin, b.vmax - b.vmin);
            let s = &face.surface;
            for uv in pts {
                let p = s.eval(uv);
                assert!(
                    p.iter().all(|x| x.is_finite()),
                    "{name} face {f}: S({uv:?}) = {p:?}"
                );
                let (uv2, q) = s
                    .project(p, None)
                    .unwrap_or_else(|| panic!("{name} face {f}: projection of S({uv:?}) failed"));
                assert!(
                    dist(p, q) <= tol,
                    "{name} face {f}: project(S({uv:?})) = S({uv2:?}) is {} away",
                    dist(p, q)
                );
                assert!(
                    dist(s.eval(uv2), q) <= tol,
                    "{name} face {f}: returned point is not S(uv)"
                );
                // Periodic coordinates come back inside the face's range.
                let slack = 1e-6 * eu.max(ev);
                assert!(
                    uv2[0] >= b.umin - slack
                        && uv2[0] <= b.umax + slack
                        && uv2[1] >= b.vmin - slack
                        && uv2[1] <= b.vmax + slack,
                    "{name} face {f}: uv {uv2:?} outside the face bounds {b:?}"
                );
                let hint = [uv[0] + 0.02 * eu, uv[1] - 0.02 * ev];
                let (_, q) = s.project(p, Some(hint)).unwrap();
                assert!(
                    dist(p, q) <= tol,
                    "{name} face {f}: hinted projection is {} away",
                    dist(p, q)
                );
                n_points += 1;
            }
        }
    }
    assert!(n_points >= 25 * 700);
}

/// A point off the surface projects to a point whose offset is along the normal.
#[test]
fn off_surface_points_project_along_the_normal() {
    for (name, imp) in imports() {
        let m = &imp.model;
        let diag = m.diagonal();
        for (f, face) in m.faces.iter().enumerate() {
            for uv in interior_points(m, f, 5).into_iter().take(5) {
                let s = &face.surface;
                let Some(n) = s.normal(uv) else { continue };
                let p = s.eval(uv);
                let h = 1e-4 * diag;
                let off = [p[0] + h * n[0], p[1] + h * n[1], p[2] + h * n[2]];
                let (_, q) = s.project(off, Some(uv)).unwrap();
                // The foot is at most as far as p (p is a candidate) and, for a
                // small offset on a smooth surface, essentially p itself.
                assert!(
                    dist(off, q) <= h * (1.0 + 1e-6),
                    "{name} face {f}: foot farther than p"
                );
                assert!(
                    dist(q, p) <= 1e-2 * h + 1e-9 * diag,
                    "{name} face {f}: foot {} from p",
                    dist(q, p)
                );
            }
        }
    }
}

/// Curve eval → project round trip, and deriv against finite differences.
#[test]
fn curve_projection_and_derivative() {
    for (name, imp) in imports() {
        let m = &imp.model;
        let diag = m.diagonal();
        for (i, c) in m.curves.iter().enumerate() {
            let Some(g) = &c.geom else { continue };
            let (t0, t1) = c.range;
            for k in 0..=10 {
                let t = t0 + (t1 - t0) * k as f64 / 10.0;
                let p = g.eval(t);
                let (t2, q) = g.project(p, None).unwrap();
                assert!(
                    dist(p, q) <= 1e-7 * diag,
                    "{name} curve {i}: project(C({t})) = C({t2}) is {} away",
                    dist(p, q)
                );
                assert!(
                    (t0..=t1).contains(&t2),
                    "{name} curve {i}: {t2} outside {t0}..{t1}"
                );
                let (_, q) = g.project(p, Some(t + 0.01 * (t1 - t0))).unwrap();
                assert!(
                    dist(p, q) <= 1e-7 * diag,
                    "{name} curve {i}: hinted projection"
                );
                let h = 1e-6 * (t1 - t0);
                let (ta, tb) = ((t - h).max(t0), (t + h).min(t1));
                let fd = geometry::vec3::scale(
                    geometry::vec3::sub(g.eval(tb), g.eval(ta)),
                    1.0 / (tb - ta),
                );
                let d = g.deriv(t);
                let err = dist(fd, d);
                // Truncation error of the difference quotient: ≤ (tb − ta)·|C''|.
                let c2 = dist(g.deriv(tb), g.deriv(ta)) / (tb - ta);
                let tol = 1e-5 * (geometry::vec3::norm(d) + diag / (t1 - t0)) + (tb - ta) * c2;
                assert!(
                    err <= tol,
                    "{name} curve {i}: C'({t}) = {d:?}, difference quotient {fd:?}"
                );
            }
        }
    }
}

/// Surface derivatives agree with finite differences of eval.
#[test]
fn surface_derivatives_match_finite_differences() {
    use geometry::vec3::{norm, scale, sub};
    for (name, imp) in imports() {
        let m = &imp.model;
        for (f, face) in m.faces.iter().enumerate() {
            let b = face.uv_bounds;
            let (hu, hv) = (1e-6 * (b.umax - b.umin), 1e-6 * (b.vmax - b.vmin));
            for uv in interior_points(m, f, 3).into_iter().take(3) {
                let s = &face.surface;
                let d = s.derivs(uv);
                assert!(
                    dist(d.point, s.eval(uv)) <= 1e-12 * (1.0 + norm(d.point)),
                    "{name} face {f}"
                );
                let fu = scale(
                    sub(s.eval([uv[0] + hu, uv[1]]), s.eval([uv[0] - hu, uv[1]])),
                    0.5 / hu,
                );
                let fv = scale(
                    sub(s.eval([uv[0], uv[1] + hv]), s.eval([uv[0], uv[1] - hv])),
                    0.5 / hv,
                );
                let fuu = scale(
                    sub(
                        s.derivs([uv[0] + hu, uv[1]]).du,
                        s.derivs([uv[0] - hu, uv[1]]).du,
                    ),
                    0.5 / hu,
                );
                let fvv = scale(
                    sub(
                        s.derivs([uv[0], uv[1] + hv]).dv,
                        s.derivs([uv[0], uv[1] - hv]).dv,
                    ),
                    0.5 / hv,
                );
                let fuv = scale(
                    sub(
                        s.derivs([uv[0], uv[1] + hv]).du,
                        s.derivs([uv[0], uv[1] - hv]).du,
                    ),
                    0.5 / hv,
                );
                for (what, a, e) in [
                    ("du", d.du, fu),
                    ("dv", d.dv, fv),
                    ("duu", d.duu, fuu),
                    ("dvv", d.dvv, fvv),
                    ("duv", d.duv, fuv),
                ] {
                    assert!(
                        dist(a, e) <= 1e-4 * (1.0 + norm(a)),
                        "{name} face {f} {what}: {a:?} vs {e:?}"
                    );
                }
            }
        }
    }
}

/// Many threads evaluating and projecting on the same faces at once give
/// bit-identical results to a single thread.
#[test]
fn concurrent_evaluation_matches_serial() {
    let imp = &imports()
        .iter()
        .find(|(n, _)| n.starts_with("i04o_m4"))
        .unwrap()
        .1;
    let m = &imp.model;
    let work = |f: usize| -> Vec<u64> {
        let face = &m.faces[f];
        let mut out = Vec::new();
        for uv in interior_points(m, f, 25) {
            let p = face.surface.eval(uv);
            let (uv2, q) = face
                .surface
                .project([p[0] + 1e-3, p[1], p[2]], None)
                .unwrap();
            let d = face.surface.derivs(uv);
            for x in [p[0], p[1], p[2], uv2[0], uv2[1], q[0], d.duu[0], d.dvv[2]] {
                out.push(x.to_bits());
            }
        }
        out
    };
    let serial: Vec<Vec<u64>> = (0..m.faces.len()).map(work).collect();
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|k| {
                let work = &work;
                s.spawn(move || {
                    // Each thread runs over every face, starting at a different one.
                    let n = m.faces.len();
                    (0..n)
                        .map(|i| ((i + k * n / 4) % n, work((i + k * n / 4) % n)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for h in handles {
            for (f, r) in h.join().unwrap() {
                assert_eq!(r, serial[f], "face {f} differs when evaluated concurrently");
            }
        }
    });
}

/// Normals: unit length, along du × dv, defined at sphere poles.
#[test]
fn normals_are_unit_and_exist_at_poles() {
    let imp = &imports()
        .iter()
        .find(|(n, _)| n.starts_with("s17o_sphere"))
        .unwrap()
        .1;
    let m = &imp.model;
    let mut checked = 0;
    for face in &m.faces {
        let b = face.uv_bounds;
        for uv in [
            [b.umin, b.vmin],
            [b.umax, b.vmax],
            [0.5 * (b.umin + b.umax), b.vmax],
        ] {
            let n = face.surface.normal(uv).expect("limit normal at a pole");
            assert!((geometry::vec3::norm(n) - 1.0).abs() < 1e-12);
            checked += 1;
        }
    }
    assert!(checked >= 3);
}

/// `first_derivs` (OpenCASCADE's D1) gives the point and first derivatives
/// of `derivs` (D2) at points inside every face of every model.
#[test]
fn first_derivatives_agree_with_the_full_evaluation() {
    for (name, imp) in imports() {
        let m = &imp.model;
        for (f, face) in m.faces.iter().enumerate() {
            for uv in interior_points(m, f, 9) {
                let (a, b) = (face.surface.first_derivs(uv), face.surface.derivs(uv));
                for (x, y) in [(a.point, b.point), (a.du, b.du), (a.dv, b.dv)] {
                    let scale = 1.0 + y.iter().map(|c| c.abs()).fold(0.0, f64::max);
                    assert!(
                        dist(x, y) <= 1e-12 * scale,
                        "{name} face {f} at {uv:?}: {x:?} against {y:?}"
                    );
                }
            }
        }
    }
}
