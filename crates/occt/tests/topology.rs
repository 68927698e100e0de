//! Entity counts, ids and boundary loops of every bundled CAD model.

mod common;

use common::*;
use geometry::model::signed_area;
use geometry::vec3::dist;
use geometry::FaceId;

#[test]
fn all_26_models_are_found() {
    assert_eq!(cad_files().len(), 26, "data/cad should hold 26 CAD models");
}

#[test]
fn counts_match_occt_map_shapes() {
    for (path, (name, imp)) in cad_files().iter().zip(imports()) {
        let m = &imp.model;
        let (nf, ne, nv) = occt::topology_counts(path).unwrap();
        assert!(nf > 0, "{name}: no face");
        assert_eq!(
            (m.faces.len(), m.curves.len(), m.corners.len()),
            (nf, ne, nv),
            "{name}"
        );
        assert_eq!(imp.curve_tolerance.len(), ne, "{name}");
        assert_eq!(imp.corner_tolerance.len(), nv, "{name}");
        m.validate().unwrap();
    }
}

#[test]
fn literal_counts_of_two_mambo_models() {
    let get = |n: &str| {
        &imports()
            .iter()
            .find(|(name, _)| name.starts_with(n))
            .unwrap()
            .1
            .model
    };
    let m1 = get("i01o_m1");
    assert_eq!(
        (m1.faces.len(), m1.curves.len(), m1.corners.len()),
        (42, 114, 76)
    );
    let s9 = get("i16o_s9");
    assert_eq!(
        (s9.faces.len(), s9.curves.len(), s9.corners.len()),
        (27, 75, 50)
    );
}

/// Curves start and end at their corners; degenerate curves have no geometry.
#[test]
fn curves_join_their_corners() {
    for (name, imp) in imports() {
        let m = &imp.model;
        let diag = m.diagonal();
        for (i, c) in m.curves.iter().enumerate() {
            assert!(c.range.0 < c.range.1, "{name} curve {i}");
            assert_eq!(c.degenerate, c.geom.is_none(), "{name} curve {i}");
            let Some(g) = &c.geom else { continue };
            assert_eq!(g.range(), c.range, "{name} curve {i}");
            for (t, v) in [(c.range.0, c.start), (c.range.1, c.end)] {
                let d = dist(g.eval(t), m.corners[v.idx()].point);
                let tol =
                    2.0 * (imp.corner_tolerance[v.idx()] + imp.curve_tolerance[i]) + 1e-9 * diag;
                assert!(
                    d <= tol,
                    "{name} curve {i}: end {t} is {d} from its corner (tol {tol})"
                );
            }
        }
    }
}

/// Every loop closes in uv, outer loops turn counter-clockwise and holes
/// clockwise, seams appear twice with opposite directions.
#[test]
fn loops_close_and_are_oriented() {
    let mut n_loops = 0;
    let mut n_reversed = 0;
    for (name, imp) in imports() {
        let m = &imp.model;
        for (f, face) in m.faces.iter().enumerate() {
            assert!(!face.loops.is_empty(), "{name} face {f}: no loop");
            assert!(
                face.loops[0].outer,
                "{name} face {f}: first loop is not the outer one"
            );
            assert_eq!(
                face.loops.iter().filter(|l| l.outer).count(),
                1,
                "{name} face {f}"
            );
            n_reversed += face.reversed as usize;
            let b = face.uv_bounds;
            let ext = (b.umax - b.umin).max(b.vmax - b.vmin);
            for (li, l) in face.loops.iter().enumerate() {
                n_loops += 1;
                let k = l.uses.len();
                for j in 0..k {
                    let (a, bu) = (&l.uses[j], &l.uses[(j + 1) % k]);
                    let pa = a.uv_polyline(m.curves[a.curve.idx()].range, 1);
                    let pb = bu.uv_polyline(m.curves[bu.curve.idx()].range, 1);
                    let gap =
                        ((pa[1][0] - pb[0][0]).powi(2) + (pa[1][1] - pb[0][1]).powi(2)).sqrt();
                    assert!(
                        gap <= 1e-4 * ext,
                        "{name} face {f} loop {li}: uses {j}->{} gap {gap} (uv extent {ext})",
                        (j + 1) % k
                    );
                }
                let area = signed_area(&m.loop_uv_polyline(FaceId(f as u32), li, 32));
                if l.outer {
                    assert!(
                        area > 0.0,
                        "{name} face {f} (reversed {}): outer loop area {area}",
                        face.reversed
                    );
                } else {
                    assert!(
                        area < 0.0,
                        "{name} face {f} (reversed {}): hole {li} area {area}",
                        face.reversed
                    );
                }
                for u in &l.uses {
                    if u.seam {
                        let twins: Vec<_> =
                            face.curve_uses().filter(|v| v.curve == u.curve).collect();
                        assert_eq!(
                            twins.len(),
                            2,
                            "{name} face {f}: seam used {} times",
                            twins.len()
                        );
                        assert_ne!(
                            twins[0].forward, twins[1].forward,
                            "{name} face {f}: seam uses in one direction"
                        );
                    }
                }
            }
        }
    }
    assert!(
        n_reversed > 0,
        "expected some reversed faces among the models"
    );
    assert!(n_loops > 500);
}

/// Each pcurve, mapped through its surface, lies on its 3D curve.
#[test]
fn pcurves_map_onto_their_curves() {
    for (name, imp) in imports() {
        let m = &imp.model;
        let diag = m.diagonal();
        let mut worst: f64 = 0.0;
        for (f, face) in m.faces.iter().enumerate() {
            for u in face.curve_uses() {
                let c = &m.curves[u.curve.idx()];
                // OCCT's edge tolerance, plus 1e-6 of the model size: some
                // STEP files understate their tolerances (i02o_m2: 43× at 1.5e-7·diag).
                let tol = 3.0 * imp.curve_tolerance[u.curve.idx()] + 1e-6 * diag;
                for i in 0..=16 {
                    let t = c.range.0 + (c.range.1 - c.range.0) * i as f64 / 16.0;
                    let d = dist(face.surface.eval(u.pcurve.eval(t)), c.eval(m, t));
                    worst = worst.max(d / diag);
                    assert!(
                        d <= tol,
                        "{name} face {f} curve {}: S(c({t})) is {d} from C (tol {tol})",
                        u.curve.idx()
                    );
                }
            }
        }
        eprintln!("{name}: worst pcurve distance / diagonal = {worst:.2e}");
    }
}

/// Where two different faces share a curve, their loops run along it in
/// opposite 3D directions once the face orientation is applied (a use runs
/// counter-clockwise around du × dv; `reversed` flips that): so the shells
/// are consistently oriented and `forward`/`reversed` agree with OCCT.
#[test]
fn shared_curves_are_traversed_oppositely() {
    let mut checked = 0;
    for (name, imp) in imports() {
        let m = &imp.model;
        let mut uses: Vec<Vec<(usize, i32)>> = vec![Vec::new(); m.curves.len()];
        for (f, face) in m.faces.iter().enumerate() {
            for u in face.curve_uses() {
                let dir = if u.forward { 1 } else { -1 } * if face.reversed { -1 } else { 1 };
                uses[u.curve.idx()].push((f, dir));
            }
        }
        for (c, list) in uses.iter().enumerate() {
            if list.len() == 2 && list[0].0 != list[1].0 && !m.curves[c].degenerate {
                assert_eq!(
                    list[0].1, -list[1].1,
                    "{name} curve {c}: faces {} and {} run along it the same way",
                    list[0].0, list[1].0
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

/// On convex solids the oriented face normal points away from any interior
/// point (here the bounding-box centre): checks `reversed` against geometry.
#[test]
fn oriented_normals_point_outwards_on_convex_solids() {
    use geometry::vec3::{dot, sub};
    for stem in [
        "s17o_sphere",
        "s15o_cylinder",
        "s12o_cube_rounded_1",
        "s13o_cube_rounded_2",
    ] {
        let imp = &imports()
            .iter()
            .find(|(n, _)| n.starts_with(stem))
            .unwrap()
            .1;
        let m = &imp.model;
        let (lo, hi) = m.bounding_box();
        let centre = [
            0.5 * (lo[0] + hi[0]),
            0.5 * (lo[1] + hi[1]),
            0.5 * (lo[2] + hi[2]),
        ];
        for (f, face) in m.faces.iter().enumerate() {
            for uv in interior_points(m, f, 9) {
                let n = face.normal(uv).unwrap();
                let s = dot(n, sub(face.surface.eval(uv), centre));
                assert!(
                    s > 0.0,
                    "{stem} face {f} (reversed {}): normal points inwards at {uv:?}",
                    face.reversed
                );
            }
        }
    }
}
