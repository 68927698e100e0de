//! Geometry shared by the fine block mesh ([`crate::coarse::fine_mesh`]) and
//! the high-order extraction ([`crate::coarse::high_order_extraction`]):
//! equal-arc-length resampling of a polyline, the curve parameters along a
//! path on a CAD curve, a curve node's (u, v) in a face, points placed on a
//! face from a (u, v) guess, and transfinite interpolation of four sides in
//! (u, v).

use geometry::{vec3, CurveId, Face, Model, Vec3};
use mesh::NodeClass;

use crate::core::patch::{LocalNode, NodeRef};
use crate::smoothing::kernels::map_to_surface;

/// A point of a polyline: on segment `seg` (from point `seg` to `seg + 1`)
/// at the share `lambda` ∈ [0, 1] of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sample {
    /// The segment.
    pub seg: usize,
    /// The share of the segment.
    pub lambda: f64,
}

/// The `parts − 1` points splitting the polyline `points` into `parts`
/// pieces of equal length (by point index when the polyline has no length);
/// nothing for fewer than two points or `parts < 2`.
pub(crate) fn equal_arc_samples(points: &[Vec3], parts: usize) -> Vec<Sample> {
    let m = points.len();
    if m < 2 || parts < 2 {
        return Vec::new();
    }
    let mut cum = vec![0.0f64; m];
    for i in 1..m {
        cum[i] = cum[i - 1] + vec3::dist(points[i - 1], points[i]);
    }
    let total = cum[m - 1];
    if !(total > 0.0 && total.is_finite()) {
        // no length: split by index
        return (1..parts)
            .map(|k| {
                let x = (m - 1) as f64 * k as f64 / parts as f64;
                let seg = (x.floor() as usize).min(m - 2);
                Sample {
                    seg,
                    lambda: (x - seg as f64).clamp(0.0, 1.0),
                }
            })
            .collect();
    }
    let mut seg = 0;
    (1..parts)
        .map(|k| {
            let target = total * k as f64 / parts as f64;
            while seg + 2 < m && cum[seg + 1] <= target {
                seg += 1;
            }
            let len = cum[seg + 1] - cum[seg];
            let lambda = if len > 0.0 {
                ((target - cum[seg]) / len).clamp(0.0, 1.0)
            } else {
                0.0
            };
            Sample { seg, lambda }
        })
        .collect()
}

/// `a + s (b − a)` in the plane.
pub(crate) fn lerp2(a: [f64; 2], b: [f64; 2], s: f64) -> [f64; 2] {
    [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
}

/// The (u, v) of sample `s` of a path whose nodes are seen as `local` in a
/// face: the interpolation of its segment's ends (a pole taken at the point
/// of its segment nearest to the other end).
pub(crate) fn sample_hint(local: &[LocalNode], s: Sample) -> [f64; 2] {
    let (a, b) = (&local[s.seg], &local[s.seg + 1]);
    lerp2(a.uv_toward(b.uv), b.uv_toward(a.uv), s.lambda)
}

/// The parameter on curve `c` of every node of `path` (nodes with classes
/// `class` at positions `pos`): a curve node's own parameter (projected when
/// it has none), a corner's end of the curve (the end nearest its
/// neighbour's parameter on a closed curve). An error names a node that is
/// neither on `c` nor one of its end corners.
pub(crate) fn path_params(
    model: &Model,
    class: &[NodeClass],
    pos: &[Vec3],
    path: &[u32],
    c: CurveId,
) -> Result<Vec<f64>, String> {
    let curve = model
        .curves
        .get(c.idx())
        .ok_or_else(|| format!("curve {} is not in the model", c.0 + 1))?;
    // each node's own parameter, or the corner it is
    let mut t: Vec<Result<f64, geometry::CornerId>> = Vec::with_capacity(path.len());
    for &n in path {
        let value = match class.get(n as usize) {
            Some(NodeClass::Curve(d, Some(x))) if *d == c => Ok(*x),
            Some(NodeClass::Curve(d, None)) if *d == c => {
                let g = curve
                    .geom
                    .as_ref()
                    .ok_or("a degenerate curve has no nodes")?;
                Ok(g.project(pos[n as usize], None)
                    .ok_or_else(|| format!("node {n} does not project onto curve {}", c.0 + 1))?
                    .0)
            }
            Some(NodeClass::Corner(k)) if curve.start == *k || curve.end == *k => Err(*k),
            _ => return Err(format!("node {n} is not on curve {}", c.0 + 1)),
        };
        t.push(value);
    }
    let (r0, r1) = curve.range;
    let mut out = Vec::with_capacity(path.len());
    for (i, x) in t.iter().enumerate() {
        out.push(match *x {
            Ok(x) => x,
            Err(k) if curve.start != curve.end => {
                if curve.start == k {
                    r0
                } else {
                    r1
                }
            }
            Err(_) => {
                // a closed curve: the end next to the neighbour's parameter
                let near = [i.checked_sub(1), Some(i + 1)]
                    .into_iter()
                    .flatten()
                    .find_map(|j| t.get(j).and_then(|v| v.ok()))
                    .unwrap_or(r0);
                if (near - r0).abs() <= (r1 - near).abs() {
                    r0
                } else {
                    r1
                }
            }
        });
    }
    Ok(out)
}

/// The (u, v) in `face` of the point of curve `c` at parameter `t`: the
/// pcurve point (of the face's uses of `c`: two on a seam) nearest to
/// `hint`; `hint` when the face does not use `c`.
pub(crate) fn curve_uv(face: &Face, c: CurveId, t: f64, hint: [f64; 2]) -> [f64; 2] {
    let d2 = |p: [f64; 2]| (p[0] - hint[0]).powi(2) + (p[1] - hint[1]).powi(2);
    face.curve_uses()
        .filter(|u| u.curve == c)
        .map(|u| u.pcurve.eval(t))
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .min_by(|a, b| d2(*a).total_cmp(&d2(*b)))
        .unwrap_or(hint)
}

/// The point of `face` nearest to `target` found from the (u, v) guess
/// `hint` (Gauss–Newton steps, [`map_to_surface`]); S(`hint`) where that
/// fails (a singular point). `None` when neither is finite.
pub(crate) fn onto_face(
    face: &Face,
    hint: [f64; 2],
    target: Vec3,
    tol: f64,
) -> Option<([f64; 2], Vec3)> {
    if let Some((uv, p, _)) = map_to_surface(face, hint, target, tol) {
        if uv.iter().chain(p.iter()).all(|x| x.is_finite()) {
            return Some((uv, p));
        }
    }
    let p = face.surface.eval(hint);
    p.iter().all(|x| x.is_finite()).then_some((hint, p))
}

/// The (u, v) of the nodes of one side of a block, in order: each node's
/// own (u, v), a pole's taken toward its neighbour along the side.
pub(crate) fn side_uvs(nodes: &[LocalNode]) -> Vec<[f64; 2]> {
    let m = nodes.len();
    (0..m)
        .map(|i| {
            let other = if i + 1 < m {
                nodes[i + 1].uv
            } else if i > 0 {
                nodes[i - 1].uv
            } else {
                nodes[i].uv
            };
            nodes[i].uv_toward(other)
        })
        .collect()
}

/// The four sides of a block in (u, v), each from its lower-index corner:
/// `bottom` and `top` by `i ∈ 0..=n1`, `left` and `right` by `j ∈ 0..=n2`
/// (so the block runs bottom → right → top backwards → left backwards).
pub(crate) struct UvSides {
    /// Side from corner (0, 0) to (n1, 0).
    pub bottom: Vec<[f64; 2]>,
    /// Side from corner (n1, 0) to (n1, n2).
    pub right: Vec<[f64; 2]>,
    /// Side from corner (0, n2) to (n1, n2).
    pub top: Vec<[f64; 2]>,
    /// Side from corner (0, 0) to (0, n2).
    pub left: Vec<[f64; 2]>,
}

impl UvSides {
    /// Transfinite (Coons) interpolation at node `(i, j)`, by node index;
    /// each corner term is the mean of its two sides' views of it (they
    /// differ at a pole). `None` when the sides' lengths disagree.
    pub(crate) fn at(&self, i: usize, j: usize) -> Option<[f64; 2]> {
        let n1 = self.bottom.len().checked_sub(1)?;
        let n2 = self.left.len().checked_sub(1)?;
        if n1 == 0 || n2 == 0 || self.top.len() != n1 + 1 || self.right.len() != n2 + 1 {
            return None;
        }
        let (i, j) = (i.min(n1), j.min(n2));
        let (s, t) = (i as f64 / n1 as f64, j as f64 / n2 as f64);
        let mid = |a: [f64; 2], b: [f64; 2]| lerp2(a, b, 0.5);
        let c00 = mid(self.bottom[0], self.left[0]);
        let c10 = mid(self.bottom[n1], self.right[0]);
        let c11 = mid(self.top[n1], self.right[n2]);
        let c01 = mid(self.top[0], self.left[n2]);
        let (b, r, tp, l) = (self.bottom[i], self.right[j], self.top[i], self.left[j]);
        let mut p = [0.0; 2];
        for k in 0..2 {
            p[k] = (1.0 - t) * b[k] + t * tp[k] + (1.0 - s) * l[k] + s * r[k]
                - ((1.0 - s) * (1.0 - t) * c00[k]
                    + s * (1.0 - t) * c10[k]
                    + s * t * c11[k]
                    + (1.0 - s) * t * c01[k]);
        }
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    #[test]
    fn equal_arc_samples_split_a_bent_polyline_evenly() {
        // an L of lengths 1 and 3: quarters at 1, 2, 3 along it
        let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 3.0, 0.0]];
        let s = equal_arc_samples(&pts, 4);
        assert_eq!(s.len(), 3);
        assert_eq!(
            s[0],
            Sample {
                seg: 1,
                lambda: 0.0
            }
        );
        assert_eq!((s[1].seg, s[2].seg), (1, 1));
        assert!((s[1].lambda - 1.0 / 3.0).abs() < 1e-12);
        assert!((s[2].lambda - 2.0 / 3.0).abs() < 1e-12);
        assert!(equal_arc_samples(&pts, 1).is_empty());
        // no length: by index
        let z = [[0.0; 3]; 3];
        let s = equal_arc_samples(&z, 2);
        assert_eq!(
            s,
            vec![Sample {
                seg: 1,
                lambda: 0.0
            }]
        );
    }

    #[test]
    fn tfi_reproduces_a_bilinear_map() {
        let f = |i: usize, j: usize| {
            let (s, t) = (i as f64 / 3.0, j as f64 / 2.0);
            [1.0 + 2.0 * s + 0.5 * t + 0.3 * s * t, -1.0 + s + 3.0 * t]
        };
        let sides = UvSides {
            bottom: (0..=3).map(|i| f(i, 0)).collect(),
            top: (0..=3).map(|i| f(i, 2)).collect(),
            left: (0..=2).map(|j| f(0, j)).collect(),
            right: (0..=2).map(|j| f(3, j)).collect(),
        };
        for j in 0..=2 {
            for i in 0..=3 {
                let p = sides.at(i, j).unwrap();
                let q = f(i, j);
                assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
            }
        }
        let bad = UvSides {
            top: vec![[0.0; 2]; 2],
            ..sides
        };
        assert!(bad.at(1, 1).is_none());
    }

    #[test]
    fn corners_of_a_closed_curve_take_the_end_next_to_their_neighbour() {
        let m = primitives::cylinder(1.0, 2.0);
        // circle 0 from corner 0 (t = 0 = 2π), nodes at t = 6 and t = 0.5
        let class = vec![
            NodeClass::Corner(geometry::CornerId(0)),
            NodeClass::Curve(CurveId(0), Some(6.0)),
            NodeClass::Curve(CurveId(0), Some(0.5)),
        ];
        let pos = vec![[1.0, 0.0, 0.0]; 3];
        let tau = std::f64::consts::TAU;
        assert_eq!(
            path_params(&m, &class, &pos, &[1, 0], CurveId(0)).unwrap(),
            vec![6.0, tau]
        );
        assert_eq!(
            path_params(&m, &class, &pos, &[0, 2], CurveId(0)).unwrap(),
            vec![0.0, 0.5]
        );
        // a node off the curve
        assert!(path_params(&m, &class, &pos, &[0, 2], CurveId(1)).is_err());
    }
}

/// The local node of a resampled side node `g` of class `class` in `face`:
/// on a CAD curve at its parameter's (u, v) (near `hint`), inside the face
/// at its own (u, v), else at `hint` — shared by the fine mesh and the
/// high-order extraction.
pub(crate) fn resampled_node(face: &Face, class: NodeClass, g: u32, hint: [f64; 2]) -> LocalNode {
    let (uv, node) = match class {
        NodeClass::Curve(c, Some(t)) => (curve_uv(face, c, t, hint), NodeRef::Curve(c, g + 1)),
        NodeClass::Face(_, Some(uv)) => (uv, NodeRef::Interior),
        _ => (hint, NodeRef::Interior),
    };
    LocalNode { uv, node, pole: None }
}
