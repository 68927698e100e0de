//! The last pass of the default and unstructured methods, after assembly:
//! nodes on CAD curves slide along their curve to raise the SICN of the
//! quads around them, on every face that uses the curve.
//!
//! Each face's own smoothing ([`crate::smoothing::raise_average`]) moves only
//! face-interior nodes: a curve's nodes are laid before the faces are meshed
//! and shared by them. Where a face's interior grid wants the curve's nodes
//! elsewhere (the seam of a sphere laid as a cube, the fillets of a rounded
//! cube) only a pass over the assembled mesh can move them, because a curve
//! node's quads lie on several faces (or, on a seam, on both sides of one).
//!
//! A node moves in its curve parameter `t`, strictly between its two
//! neighbours on the curve, by 1D steps that must raise the sum of its quads'
//! SICN (measured as the statistics measure it: CAD normals at the corners,
//! [`mesh::stats::quad_corner_normals`]) and keep each quad above the floor
//! of [`crate::smoothing::raise_average`] (a quad below 0.5 never gets worse,
//! a better one keeps 95 % of its SICN). Corners, poles (degenerate curves)
//! and nodes whose quads are all about square stay where they are.

use std::collections::HashMap;

use geometry::{Model, Vec3};
use mesh::quadmesh::{NodeClass, QuadMesh};
use mesh::quality::quad_sicn;

use crate::smoothing::kernels::{ascent_floor, ASCENT_GOOD};

/// First step, as a share of the node's parameter interval (between its two
/// curve neighbours).
pub const SLIDE_STEP: f64 = 0.05;
/// A node stops when its step falls below this share of its interval.
pub const SLIDE_MIN_STEP: f64 = 0.0005;
/// A node keeps at least this share of its interval to each curve neighbour.
pub const SLIDE_MARGIN: f64 = 0.1;

/// What [`slide_curve_nodes`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlideReport {
    /// Curve nodes that could move (not corners, poles, or nodes without quads).
    pub nodes: usize,
    /// Steps kept.
    pub moves: usize,
    /// Sweeps made over the nodes.
    pub sweeps: usize,
    /// Average SICN of the quads around those nodes before the pass.
    pub before: f64,
    /// The same after the pass (never lower).
    pub after: f64,
}

/// A curve node that may slide: its node and the parameters of its two
/// curve neighbours (`lo < t < hi`).
struct Slider {
    node: u32,
    lo: f64,
    hi: f64,
}

/// Slides the nodes of `mesh` that lie on CAD curves along their curves, at
/// most `max_sweeps` Gauss–Seidel sweeps, see the module documentation.
/// Positions and curve parameters of `mesh` change; its topology does not.
/// Sequential, so the result does not depend on the number of threads.
pub fn slide_curve_nodes(model: &Model, mesh: &mut QuadMesh, max_sweeps: usize) -> SlideReport {
    let mut report = SlideReport::default();
    let sliders = sliders(model, mesh);
    if sliders.is_empty() || max_sweeps == 0 {
        return report;
    }
    let mut quads_of: Vec<Vec<u32>> = vec![Vec::new(); mesh.nodes.len()];
    for (qi, q) in mesh.quads.iter().enumerate() {
        for &v in q {
            if let Some(l) = quads_of.get_mut(v as usize) {
                l.push(qi as u32);
            }
        }
    }
    let sliders: Vec<Slider> = sliders
        .into_iter()
        .filter(|s| !quads_of[s.node as usize].is_empty())
        .collect();
    report.nodes = sliders.len();
    // the quads around the sliders, with their corner normals and SICN
    // (indexed by quad; NaN elsewhere)
    let mut around: Vec<u32> = sliders
        .iter()
        .flat_map(|s| quads_of[s.node as usize].iter().copied())
        .collect();
    around.sort_unstable();
    around.dedup();
    let mut normals: Vec<[Vec3; 4]> = vec![[[0.0; 3]; 4]; mesh.quads.len()];
    for (&q, n) in around
        .iter()
        .zip(mesh::stats::quad_corner_normals_of(mesh, model, &around))
    {
        normals[q as usize] = n;
    }
    let points = |mesh: &QuadMesh, q: u32| mesh.quads[q as usize].map(|v| mesh.nodes[v as usize]);
    let mut sicn: Vec<f64> = vec![f64::NAN; mesh.quads.len()];
    for &q in &around {
        sicn[q as usize] = quad_sicn(&points(mesh, q), &normals[q as usize]);
    }
    let initial = sicn.clone();
    let average =
        |sicn: &[f64]| around.iter().map(|&q| sicn[q as usize]).sum::<f64>() / around.len() as f64;
    report.before = average(&sicn);
    let mut step = vec![SLIDE_STEP; sliders.len()];
    let mut new_q: Vec<f64> = Vec::with_capacity(8);
    for _ in 0..max_sweeps {
        report.sweeps += 1;
        let mut active = false;
        for (k, s) in sliders.iter().enumerate() {
            if step[k] < SLIDE_MIN_STEP {
                continue;
            }
            let v = s.node as usize;
            let quads = &quads_of[v];
            if quads.iter().all(|&q| sicn[q as usize] >= ASCENT_GOOD) {
                continue;
            }
            let NodeClass::Curve(c, Some(t0)) = mesh.node_class[v] else {
                continue;
            };
            let curve = &model.curves[c.idx()];
            let Some(geom) = curve.geom.as_ref() else {
                continue;
            };
            active = true;
            let sum_before: f64 = quads.iter().map(|&q| sicn[q as usize]).sum();
            let (old_pos, width) = (mesh.nodes[v], s.hi - s.lo);
            let (t_min, t_max) = (s.lo + SLIDE_MARGIN * width, s.hi - SLIDE_MARGIN * width);
            // the node at parameter t: its quads' SICN (in `new_q`), their
            // sum, whether each stays above its floor, and its corner normals
            let try_at = |mesh: &mut QuadMesh, t: f64, new_q: &mut Vec<f64>| {
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let x = geom.eval(t);
                let mut corner_normals: Vec<(u32, usize, Vec3)> = Vec::with_capacity(quads.len());
                for &q in quads {
                    let f = mesh.quad_face[q as usize];
                    let face = &model.faces[f.idx()];
                    let uv = face.curve_uses().find(|u| u.curve == c)?.pcurve.eval(t);
                    let n = face.regular_normal(uv)?;
                    let at = mesh.quads[q as usize]
                        .iter()
                        .position(|&w| w as usize == v)?;
                    corner_normals.push((q, at, n));
                }
                mesh.nodes[v] = x;
                new_q.clear();
                for &(q, at, n) in &corner_normals {
                    let mut nq = normals[q as usize];
                    nq[at] = n;
                    new_q.push(quad_sicn(&points(mesh, q), &nq));
                }
                mesh.nodes[v] = old_pos;
                let sum: f64 = new_q.iter().sum();
                let floor_ok = quads
                    .iter()
                    .zip(new_q.iter())
                    .all(|(&q, &val)| val >= ascent_floor(initial[q as usize]));
                Some((x, sum, floor_ok, corner_normals))
            };
            let mut kept = false;
            for dir in [1.0, -1.0] {
                let t = t0 + dir * step[k] * width;
                let Some((x, sum, floor_ok, corner_normals)) = try_at(mesh, t, &mut new_q) else {
                    continue;
                };
                if sum > sum_before + 1e-12 && floor_ok {
                    mesh.nodes[v] = x;
                    mesh.node_class[v] = NodeClass::Curve(c, Some(t));
                    for (&(q, at, n), &val) in corner_normals.iter().zip(&new_q) {
                        normals[q as usize][at] = n;
                        sicn[q as usize] = val;
                    }
                    report.moves += 1;
                    kept = true;
                    step[k] *= 1.5;
                    break;
                }
            }
            if !kept {
                step[k] *= 0.25;
            }
        }
        if !active {
            break;
        }
    }
    report.after = average(&sicn);
    report
}

/// The curve nodes of `mesh` that may slide, each with the parameters of its
/// neighbours along the curve (from the mesh's curve edges; a corner
/// neighbour at the curve's end nearer the node's side).
fn sliders(model: &Model, mesh: &QuadMesh) -> Vec<Slider> {
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &([a, b], _) in &mesh.curve_edges {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut out = Vec::new();
    for (v, class) in mesh.node_class.iter().enumerate() {
        let NodeClass::Curve(c, Some(t)) = *class else {
            continue;
        };
        let Some(curve) = model.curves.get(c.idx()) else {
            continue;
        };
        if curve.degenerate || curve.geom.is_none() {
            continue;
        }
        let Some(nb) = next.get(&(v as u32)) else {
            continue;
        };
        // the neighbours' parameters (both ends for a corner)
        let mut params: Vec<f64> = Vec::with_capacity(4);
        for &w in nb {
            match mesh.node_class.get(w as usize) {
                Some(NodeClass::Curve(d, Some(s))) if *d == c => params.push(*s),
                Some(NodeClass::Corner(_)) => params.extend([curve.range.0, curve.range.1]),
                _ => {}
            }
        }
        let lo = params
            .iter()
            .copied()
            .filter(|&s| s < t)
            .fold(f64::NEG_INFINITY, f64::max);
        let hi = params
            .iter()
            .copied()
            .filter(|&s| s > t)
            .fold(f64::INFINITY, f64::min);
        if nb.len() == 2 && lo.is_finite() && hi.is_finite() {
            out.push(Slider {
                node: v as u32,
                lo,
                hi,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{mesh_model_with, MeshMethod, MeshOptions, Size};
    use geometry::primitives;

    /// The quads' SICN with the statistics' normals.
    fn sicn(model: &Model, mesh: &QuadMesh) -> Vec<f64> {
        mesh::stats::quad_sicn_values(mesh, Some(model))
    }

    #[test]
    fn a_curve_node_pushed_aside_slides_back_and_stays_on_its_curve() {
        let model = primitives::square(1.0);
        let opts = MeshOptions {
            size: Size::Absolute(0.25),
            threads: Some(1),
            ..Default::default()
        };
        let (mut mesh, _) = mesh_model_with(&model, &opts, MeshMethod::Baseline).unwrap();
        let sliders = sliders(&model, &mesh);
        assert!(!sliders.is_empty());
        // push one curve node a third of the way toward a neighbour
        let s = &sliders[sliders.len() / 2];
        let v = s.node as usize;
        let NodeClass::Curve(c, Some(t0)) = mesh.node_class[v] else {
            panic!("not a curve node");
        };
        let t1 = t0 + (s.lo - t0) / 3.0;
        let geom = model.curves[c.idx()].geom.clone().unwrap();
        mesh.nodes[v] = geom.eval(t1);
        mesh.node_class[v] = NodeClass::Curve(c, Some(t1));
        let before = sicn(&model, &mesh);
        let corners: Vec<Vec3> = mesh
            .corner_nodes
            .iter()
            .map(|&(n, _)| mesh.nodes[n as usize])
            .collect();
        let interior: Vec<Vec3> = (0..mesh.nodes.len())
            .filter(|&n| mesh.is_face_interior(n))
            .map(|n| mesh.nodes[n])
            .collect();
        let report = slide_curve_nodes(&model, &mut mesh, 20);
        let after = sicn(&model, &mesh);
        let avg = |q: &[f64]| q.iter().sum::<f64>() / q.len() as f64;
        assert!(
            report.moves > 0 && report.after > report.before,
            "{report:?}"
        );
        assert!(avg(&after) > avg(&before));
        // no quad fell below its floor
        for (b, a) in before.iter().zip(&after) {
            assert!(*a >= ascent_floor(*b) - 1e-12, "{b} → {a}");
        }
        // the pushed node went back toward where it was, between its neighbours
        let NodeClass::Curve(c2, Some(t2)) = mesh.node_class[v] else {
            panic!("reclassified");
        };
        assert_eq!(c2, c);
        assert!((t2 - t0).abs() < (t1 - t0).abs(), "{t0} {t1} {t2}");
        // every curve node sits on its curve at its parameter; corners and
        // face-interior nodes did not move
        for (n, class) in mesh.node_class.iter().enumerate() {
            if let NodeClass::Curve(c, Some(t)) = class {
                let on = model.curves[c.idx()].geom.as_ref().unwrap().eval(*t);
                assert!(geometry::vec3::dist(on, mesh.nodes[n]) < 1e-12);
            }
        }
        let corners_after: Vec<Vec3> = mesh
            .corner_nodes
            .iter()
            .map(|&(n, _)| mesh.nodes[n as usize])
            .collect();
        assert_eq!(corners, corners_after);
        let interior_after: Vec<Vec3> = (0..mesh.nodes.len())
            .filter(|&n| mesh.is_face_interior(n))
            .map(|n| mesh.nodes[n])
            .collect();
        assert_eq!(interior, interior_after);
    }
}
