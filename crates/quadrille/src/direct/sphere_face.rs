//! A full sphere face (one loop: a seam from pole to pole, a pole, the seam
//! again, the other pole) meshed directly as a cube projected onto the
//! sphere: six N × N grids whose only irregular vertices are the cube's 8
//! corners (valence 3), as a cross field on a sphere asks (8 singularities
//! of index +1/4). The poles sit at the centres of two cube faces (valence
//! 4) and the seam runs along the middle lines of the top, one side and the
//! bottom face, which are great circles on the equal-angle cube map; so N is
//! the seam's coarse count (its 2N mesh edges are N/2 + N + N/2 grid edges)
//! and must be even. The same idea as a pattern (paper §6.1.2) for a face
//! no pattern of the library fits; the unstructured mesher meshes the face
//! when this does not apply or its quads are poor.

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::{FaceId, Model};

use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::queries::full_sphere_seam;
use crate::curves::curve_mesh::CurveMesh;

/// A projected point farther than this share of the radius from the
/// surface means the face is not a sphere.
const OFF_SPHERE: f64 = 1e-3;

/// The cube faces: outward normal, then two in-plane axes `a`, `b` with
/// `a × b` = normal (so grid quads are counter-clockwise seen from outside),
/// in the sphere's frame (x: the seam's meridian at the equator, z: the pole
/// at the loop's `vmax` end).
const FACES: [([f64; 3], [f64; 3], [f64; 3]); 6] = [
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
    ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
    ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
];

/// Unit direction (cube frame) of grid vertex `(i, j)` of face `f`, equal
/// angles along both axes.
fn direction(f: usize, i: u32, j: u32, n: u32) -> Vec3 {
    let (c, a, b) = FACES[f];
    let angle = |k: u32| (k as f64 / n as f64 - 0.5) * std::f64::consts::FRAC_PI_2;
    let (ta, tb) = (angle(i).tan(), angle(j).tan());
    let p = [
        c[0] + ta * a[0] + tb * b[0],
        c[1] + ta * a[1] + tb * b[1],
        c[2] + ta * a[2] + tb * b[2],
    ];
    vec3::normalize(p).unwrap_or(c)
}

/// Meshes face `fid` as a cube on the sphere when it is a full sphere whose
/// seam has an even coarse count; `None` when the face is not such a
/// sphere, `Some(Err)` when it is but the grid could not be laid on it.
pub fn mesh_full_sphere(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
) -> Option<Result<QuadPatch, String>> {
    let (s0, s1) = full_sphere_seam(model, fid)?;
    let seam = model.faces[fid.idx()].loops[0].uses[s0].curve;
    let cm = cms.get(seam.idx())?;
    let n = cm.coarse as u32;
    if n < 2 || n % 2 != 0 {
        return Some(Err(format!(
            "the seam has {n} coarse segments, not an even number"
        )));
    }
    Some(lay_cube(model, fid, cms, (s0, s1), n))
}

fn lay_cube(
    model: &Model,
    fid: FaceId,
    cms: &[CurveMesh],
    (s0, s1): (usize, usize),
    n: u32,
) -> Result<QuadPatch, String> {
    let face = &model.faces[fid.idx()];
    let uses = &face.loops[0].uses;
    let seam = uses[s0].curve;
    let ce = &model.curves[seam.idx()];
    let cm = &cms[seam.idx()];
    // the sphere's frame from the seam: its two ends are the poles
    let (south, north) = {
        let a = model.corners[ce.start.idx()].point;
        let b = model.corners[ce.end.idx()].point;
        (a, b)
    };
    let center = vec3::scale(vec3::add(south, north), 0.5);
    let radius = 0.5 * vec3::dist(south, north);
    let z = vec3::normalize(vec3::sub(north, center)).ok_or("the poles coincide")?;
    // x: toward the seam's meridian (a seam node, less its z component)
    let mid = vec3::sub(cm.points[cm.points.len() / 2], center);
    let x = vec3::normalize(vec3::sub(mid, vec3::scale(z, vec3::dot(mid, z))))
        .ok_or("the seam runs through the axis")?;
    let y = vec3::cross(z, x);
    let to_world = |d: Vec3| {
        vec3::add(
            center,
            vec3::scale(
                vec3::add(
                    vec3::add(vec3::scale(x, d[0]), vec3::scale(y, d[1])),
                    vec3::scale(z, d[2]),
                ),
                radius,
            ),
        )
    };
    // the two copies of the seam's nodes, by the u side they bound: the use
    // whose pcurve has the smaller u is the side the frame's +y leaves from
    let seam_u = |k: usize| {
        let t = 0.5 * (ce.range.0 + ce.range.1);
        uses[k].pcurve.eval(t)[0]
    };
    let (low, high) = if seam_u(s0) < seam_u(s1) {
        (s0, s1)
    } else {
        (s1, s0)
    };
    let pole_uv = |corner| -> Option<[[f64; 2]; 2]> {
        uses.iter()
            .find(|w| {
                let c = &model.curves[w.curve.idx()];
                c.degenerate && c.start == corner
            })
            .map(|w| face.pole_segment(w, &model.curves[w.curve.idx()]))
    };
    let mut nodes: Vec<LocalNode> = Vec::new();
    let mut pos: Vec<Vec3> = Vec::new();
    // poles: one local node each
    let mut pole_node = [0u32; 2];
    for (k, corner) in [ce.start, ce.end].into_iter().enumerate() {
        let seg = pole_uv(corner).ok_or("a pole has no degenerate curve")?;
        pole_node[k] = nodes.len() as u32;
        nodes.push(LocalNode {
            uv: [0.5 * (seg[0][0] + seg[1][0]), 0.5 * (seg[0][1] + seg[1][1])],
            node: NodeRef::Corner(corner),
            pole: Some(seg),
        });
        pos.push(model.corners[corner.idx()].point);
    }
    // seam nodes 1..2n-1 (from the start pole), one copy per side
    let m = cm.params.len() - 1;
    if m != 2 * n as usize {
        return Err("the seam's mesh does not have 2n edges".into());
    }
    let mut seam_node = [vec![0u32; m + 1], vec![0u32; m + 1]];
    for (side, k) in [low, high].into_iter().enumerate() {
        seam_node[side][0] = pole_node[0];
        seam_node[side][m] = pole_node[1];
        for i in 1..m {
            seam_node[side][i] = nodes.len() as u32;
            nodes.push(LocalNode {
                uv: uses[k].pcurve.eval(cm.params[i]),
                node: NodeRef::Curve(seam, i as u32),
                pole: None,
            });
            pos.push(cm.points[i]);
        }
    }
    // the grid: a vertex is keyed by its direction, rounded, so the cube
    // faces share their edges
    let key = |d: Vec3| {
        let r = |v: f64| (v * 1e9).round() as i64;
        (r(d[0]), r(d[1]), r(d[2]))
    };
    let mut by_dir: HashMap<(i64, i64, i64), u32> = HashMap::new();
    // the seam line in the cube frame: y = 0, x ≥ 0; its latitude index
    // runs 0..=2n from the south pole (z = −1) to the north pole (z = 1)
    let seam_index = |d: Vec3| -> Option<usize> {
        if d[1].abs() > 1e-9 || d[0] < -1e-9 {
            return None;
        }
        let lat = d[2].clamp(-1.0, 1.0).asin();
        let k = (lat / std::f64::consts::PI + 0.5) * 2.0 * n as f64;
        let r = k.round();
        ((k - r).abs() < 1e-6).then_some(r as usize)
    };
    let mut quads: Vec<[u32; 4]> = Vec::new();
    let mut interior = |d: Vec3,
                        nodes: &mut Vec<LocalNode>,
                        pos: &mut Vec<Vec3>,
                        side: usize|
     -> Result<u32, String> {
        if let Some(k) = seam_index(d) {
            return Ok(seam_node[side][k]);
        }
        if let Some(&v) = by_dir.get(&key(d)) {
            return Ok(v);
        }
        let target = to_world(d);
        let (uv, p) = face
            .surface
            .project(target, None)
            .ok_or("a grid point does not project onto the surface")?;
        if vec3::dist(p, target) > OFF_SPHERE * radius {
            return Err("the face is not a sphere".into());
        }
        let v = nodes.len() as u32;
        by_dir.insert(key(d), v);
        nodes.push(LocalNode {
            uv,
            node: NodeRef::Interior,
            pole: None,
        });
        pos.push(p);
        Ok(v)
    };
    for f in 0..6 {
        for i in 0..n {
            for j in 0..n {
                let ds = [
                    direction(f, i, j, n),
                    direction(f, i + 1, j, n),
                    direction(f, i + 1, j + 1, n),
                    direction(f, i, j + 1, n),
                ];
                // the side of the seam this quad lies on
                let cy: f64 = ds.iter().map(|d| d[1]).sum();
                let side = usize::from(cy < 0.0);
                let mut q = [0u32; 4];
                for (k, d) in ds.iter().enumerate() {
                    q[k] = interior(*d, &mut nodes, &mut pos, side)?;
                }
                quads.push(q);
            }
        }
    }
    // the uv of interior nodes next to the seam on the high side: the
    // projection may have put them at the low end of the period
    if let Some(period) = face.surface.periods()[0] {
        let high_u = uses[high].pcurve.eval(0.5 * (ce.range.0 + ce.range.1))[0];
        let low_u = uses[low].pcurve.eval(0.5 * (ce.range.0 + ce.range.1))[0];
        for q in &quads {
            let on_high = q.iter().any(|&v| {
                matches!(nodes[v as usize].node, NodeRef::Curve(..))
                    && (nodes[v as usize].uv[0] - high_u).abs() < 1e-9
            });
            for &v in q {
                let nd = &mut nodes[v as usize];
                if nd.node == NodeRef::Interior
                    && on_high
                    && (nd.uv[0] - low_u).abs() < 0.5 * period
                {
                    // an interior node of a quad on the high side belongs near high_u
                    if (nd.uv[0] + period - high_u).abs() < (nd.uv[0] - high_u).abs() {
                        nd.uv[0] += period;
                    }
                }
            }
        }
    }
    // counter-clockwise about du × dv: the grid is counter-clockwise seen
    // from outside; flip when du × dv points inward or the face is reversed
    let probe = nodes
        .iter()
        .position(|nd| nd.node == NodeRef::Interior)
        .ok_or("no interior node")?;
    let d = face.surface.derivs(nodes[probe].uv);
    let outward = vec3::dot(vec3::cross(d.du, d.dv), vec3::sub(pos[probe], center)) > 0.0;
    if outward == face.reversed {
        for q in &mut quads {
            q.swap(1, 3);
        }
    }
    crate::direct::pattern_face::smooth_and_check(face, nodes, pos, quads, "cube")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::quality::quad_quality;
    use crate::curves::curve_mesh::{discretize_all, plan_curves};

    #[test]
    fn a_full_sphere_is_a_cube_with_eight_valence_3_vertices() {
        let model = geometry::primitives::sphere(1.0);
        let mut laid = 0;
        for h in [0.3, 0.2, 0.15] {
            let cms = discretize_all(&model, &plan_curves(&model, h));
            let seam = model
                .curves
                .iter()
                .position(|c| !c.degenerate)
                .expect("a seam");
            let n = cms[seam].coarse;
            let Some(result) = mesh_full_sphere(&model, FaceId(0), &cms) else {
                panic!("the sphere is not recognized");
            };
            if n % 2 == 1 {
                assert!(result.is_err(), "odd seam count {n}");
                continue;
            }
            let p = result.expect("laid");
            laid += 1;
            assert_eq!(p.quads.len(), 6 * n * n);
            // valences: 8 cube corners of 3, the rest (poles included) 4
            let mut valence: HashMap<NodeRef, usize> = HashMap::new();
            let mut interior = vec![0usize; p.nodes.len()];
            for q in &p.quads {
                for &v in q {
                    match p.nodes[v as usize].node {
                        NodeRef::Interior => interior[v as usize] += 1,
                        other => *valence.entry(other).or_default() += 1,
                    }
                }
            }
            let threes = interior.iter().filter(|&&k| k == 3).count();
            let others = interior
                .iter()
                .filter(|&&k| k != 0 && k != 3 && k != 4)
                .count();
            assert_eq!((threes, others), (8, 0));
            // a pole is one node with 4 quads; a seam node has 4 over its two copies
            assert!(valence.values().all(|&k| k == 4), "{valence:?}");
            let face = &model.faces[0];
            let worst = p
                .quads
                .iter()
                .map(|q| quad_quality(face, &p.nodes, &p.pos, q))
                .fold(f64::INFINITY, f64::min);
            assert!(worst > 0.7, "min SICN {worst}");
        }
        assert!(laid > 0, "no size gave an even seam count");
    }

    #[test]
    fn a_square_is_no_sphere() {
        let model = geometry::primitives::square(1.0);
        let cms = discretize_all(&model, &plan_curves(&model, 0.2));
        assert!(mesh_full_sphere(&model, FaceId(0), &cms).is_none());
    }
}
