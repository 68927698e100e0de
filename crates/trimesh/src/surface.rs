//! The geometry of the discrete model: the [`Surface`] of a patch (its
//! triangles with their (u, v) map), the [`Curve`] of a feature or seam curve
//! (a polyline by arc length) and the [`Curve2d`] of its pcurves (the same
//! polyline's (u, v) images, on the same parameter breakpoints).
//!
//! Evaluation is piecewise linear: `S(u, v)` is the point of the 3D triangle
//! whose (u, v) image contains (u, v), with the same barycentric
//! coordinates; `∂S/∂u`, `∂S/∂v` are that triangle's (constant), second
//! derivatives are zero. Outside the (u, v) image (the meshers sample the
//! bounding box) the nearest triangle's closest point is used, so `S` stays
//! on the input surface. The normal is the barycentric blend of area-weighted
//! vertex normals of the patch (smooth inside a patch, oriented as `du × dv`).
//! Point location (2D) and projection (3D) use uniform grids of triangle
//! lists, built on first use.

use std::sync::{Arc, OnceLock};

use geometry::model::Bounds2;
use geometry::vec3::{self, Vec3};
use geometry::{Curve, Curve2d, Surface, SurfaceDerivs};

/// A uniform grid of triangle lists over a box (2D or 3D: unused axes have one cell).
#[derive(Debug)]
struct Grid {
    lo: [f64; 3],
    h: [f64; 3],
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    /// Grid over the boxes `boxes` (lo, hi), about `target` cells.
    fn new(boxes: &[([f64; 3], [f64; 3])], dim: usize, target: usize) -> Grid {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (a, b) in boxes {
            for k in 0..dim {
                lo[k] = lo[k].min(a[k]);
                hi[k] = hi[k].max(b[k]);
            }
        }
        for k in dim..3 {
            lo[k] = 0.0;
            hi[k] = 0.0;
        }
        let ext: Vec<f64> = (0..3).map(|k| (hi[k] - lo[k]).max(0.0)).collect();
        let maxe = ext.iter().cloned().fold(0.0, f64::max).max(1e-300);
        // cell size: the largest extent split so that the cell count is near target
        let target = target.clamp(1, 1 << 21) as f64;
        let mut h = maxe / target.powf(1.0 / dim as f64);
        let mut dims = [1usize; 3];
        for _ in 0..30 {
            for k in 0..3 {
                dims[k] = if k < dim {
                    ((ext[k] / h).ceil() as usize).clamp(1, 2048)
                } else {
                    1
                };
            }
            if (dims[0] * dims[1] * dims[2]) as f64 <= 2.0 * target {
                break;
            }
            h *= 1.25;
        }
        let hs = [0, 1, 2].map(|k| {
            if dims[k] > 1 || ext[k] > 0.0 {
                (ext[k] / dims[k] as f64).max(1e-300)
            } else {
                1.0
            }
        });
        let mut g = Grid {
            lo,
            h: hs,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        let ncell = dims[0] * dims[1] * dims[2];
        let mut count = vec![0u32; ncell + 1];
        let range = |g: &Grid, a: [f64; 3], b: [f64; 3]| -> [[usize; 2]; 3] {
            [0, 1, 2].map(|k| [g.cell(k, a[k]), g.cell(k, b[k])])
        };
        for (a, b) in boxes {
            let r = range(&g, *a, *b);
            for i in r[0][0]..=r[0][1] {
                for j in r[1][0]..=r[1][1] {
                    for l in r[2][0]..=r[2][1] {
                        count[g.index([i, j, l]) + 1] += 1;
                    }
                }
            }
        }
        for c in 0..ncell {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[ncell] as usize];
        for (t, (a, b)) in boxes.iter().enumerate() {
            let r = range(&g, *a, *b);
            for i in r[0][0]..=r[0][1] {
                for j in r[1][0]..=r[1][1] {
                    for l in r[2][0]..=r[2][1] {
                        let c = g.index([i, j, l]);
                        items[fill[c] as usize] = t as u32;
                        fill[c] += 1;
                    }
                }
            }
        }
        g.start = count;
        g.items = items;
        g
    }

    fn cell(&self, k: usize, x: f64) -> usize {
        let c = ((x - self.lo[k]) / self.h[k]).floor();
        if c.is_nan() || c < 0.0 {
            0
        } else {
            (c as usize).min(self.dims[k] - 1)
        }
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    fn list(&self, c: [usize; 3]) -> &[u32] {
        let i = self.index(c);
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Visits the cells at Chebyshev distance `r` from `c` (a shell), calling
    /// `f` with each cell's list; false when the shell is entirely outside.
    fn shell(&self, c: [usize; 3], r: usize, f: &mut dyn FnMut(&[u32])) -> bool {
        let r = r as i64;
        let mut any = false;
        let lo = |k: usize| (c[k] as i64 - r).max(0);
        let hi = |k: usize| (c[k] as i64 + r).min(self.dims[k] as i64 - 1);
        for l in lo(2)..=hi(2) {
            for j in lo(1)..=hi(1) {
                for i in lo(0)..=hi(0) {
                    let d = (i - c[0] as i64)
                        .abs()
                        .max((j - c[1] as i64).abs())
                        .max((l - c[2] as i64).abs());
                    if d != r {
                        continue;
                    }
                    any = true;
                    f(self.list([i as usize, j as usize, l as usize]));
                }
            }
        }
        any
    }

    /// Smallest cell size over the used axes.
    fn hmin(&self, dim: usize) -> f64 {
        (0..dim).map(|k| self.h[k]).fold(f64::INFINITY, f64::min)
    }

    /// Nearest item to `p` by `dist` (a distance to item): ring search.
    fn nearest(
        &self,
        p: [f64; 3],
        dim: usize,
        dist: &mut dyn FnMut(u32) -> f64,
    ) -> Option<(u32, f64)> {
        let c = [0, 1, 2].map(|k| self.cell(k, p[k]));
        let mut best: Option<(u32, f64)> = None;
        let hmin = self.hmin(dim);
        let maxr = self.dims.iter().cloned().max().unwrap_or(1);
        for r in 0..=maxr {
            let mut f = |list: &[u32]| {
                for &t in list {
                    let d = dist(t);
                    if best.is_none_or(|b| d < b.1) {
                        best = Some((t, d));
                    }
                }
            };
            if !self.shell(c, r, &mut f) {
                break;
            }
            if let Some((_, d)) = best {
                if d <= r as f64 * hmin {
                    break;
                }
            }
        }
        best
    }
}

/// Barycentric coordinates of `p` in the (u, v) triangle `a b c`.
fn bary2(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 3] {
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / d;
    let l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / d;
    [1.0 - l1 - l2, l1, l2]
}

/// Closest point of segment `a b` to `p` in 2D: (parameter, squared distance).
fn seg2(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    let s = if dd > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + s * d[0] - p[0], a[1] + s * d[1] - p[1]];
    (s, q[0] * q[0] + q[1] * q[1])
}

/// Closest point to `p` on the 3D triangle `a b c`, as barycentric coordinates.
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> [f64; 3] {
    let ab = vec3::sub(b, a);
    let ac = vec3::sub(c, a);
    let ap = vec3::sub(p, a);
    let d1 = vec3::dot(ab, ap);
    let d2 = vec3::dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = vec3::sub(p, b);
    let d3 = vec3::dot(ab, bp);
    let d4 = vec3::dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = vec3::sub(p, c);
    let d5 = vec3::dot(ab, cp);
    let d6 = vec3::dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    [1.0 - v - w, v, w]
}

/// The surface of one patch: its triangles in 3D and their (u, v) images.
#[derive(Debug)]
pub struct TriSurface {
    xyz: Vec<Vec3>,
    uv: Vec<[f64; 2]>,
    tris: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    bounds: Bounds2,
    /// Twice the median edge length: [`Surface::resolution`]. Below a few
    /// input triangles, a uv triangle's chord and normal deviations measure
    /// the facets' creases, not curvature that more points would follow.
    resolution: f64,
    grid2: OnceLock<Grid>,
    grid3: OnceLock<Grid>,
}

impl TriSurface {
    /// A surface from vertices (3D and (u, v)) and triangles counter-clockwise in (u, v).
    pub fn new(xyz: Vec<Vec3>, uv: Vec<[f64; 2]>, tris: Vec<[u32; 3]>) -> Self {
        let mut normals = vec![[0.0; 3]; xyz.len()];
        for t in &tris {
            let [a, b, c] = t.map(|v| xyz[v as usize]);
            let n = vec3::cross(vec3::sub(b, a), vec3::sub(c, a));
            for &v in t {
                normals[v as usize] = vec3::add(normals[v as usize], n);
            }
        }
        let mut bounds = Bounds2 {
            umin: f64::INFINITY,
            umax: f64::NEG_INFINITY,
            vmin: f64::INFINITY,
            vmax: f64::NEG_INFINITY,
        };
        for p in &uv {
            bounds.umin = bounds.umin.min(p[0]);
            bounds.umax = bounds.umax.max(p[0]);
            bounds.vmin = bounds.vmin.min(p[1]);
            bounds.vmax = bounds.vmax.max(p[1]);
        }
        let mut lengths: Vec<f64> = tris
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
            .map(|(a, b)| vec3::dist(xyz[a as usize], xyz[b as usize]))
            .collect();
        let resolution = if lengths.is_empty() {
            0.0
        } else {
            let mid = lengths.len() / 2;
            2.0 * *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        TriSurface {
            xyz,
            uv,
            tris,
            normals,
            bounds,
            resolution,
            grid2: OnceLock::new(),
            grid3: OnceLock::new(),
        }
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.tris.len()
    }

    /// Smallest signed (u, v) area of a triangle (positive: no flipped triangle).
    pub fn min_uv_area(&self) -> f64 {
        self.tris
            .iter()
            .map(|t| {
                crate::parametrize::area(
                    self.uv[t[0] as usize],
                    self.uv[t[1] as usize],
                    self.uv[t[2] as usize],
                )
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn grid2(&self) -> &Grid {
        self.grid2.get_or_init(|| {
            let boxes: Vec<_> = self
                .tris
                .iter()
                .map(|t| {
                    let p = t.map(|v| self.uv[v as usize]);
                    (
                        [
                            p[0][0].min(p[1][0]).min(p[2][0]),
                            p[0][1].min(p[1][1]).min(p[2][1]),
                            0.0,
                        ],
                        [
                            p[0][0].max(p[1][0]).max(p[2][0]),
                            p[0][1].max(p[1][1]).max(p[2][1]),
                            0.0,
                        ],
                    )
                })
                .collect();
            Grid::new(&boxes, 2, self.tris.len())
        })
    }

    fn grid3(&self) -> &Grid {
        self.grid3.get_or_init(|| {
            let boxes: Vec<_> = self
                .tris
                .iter()
                .map(|t| {
                    let p = t.map(|v| self.xyz[v as usize]);
                    (
                        [0, 1, 2].map(|k| p[0][k].min(p[1][k]).min(p[2][k])),
                        [0, 1, 2].map(|k| p[0][k].max(p[1][k]).max(p[2][k])),
                    )
                })
                .collect();
            Grid::new(&boxes, 3, 2 * self.tris.len())
        })
    }

    /// The triangle holding `uv` (or the nearest one) and the barycentric
    /// coordinates of `uv` there (clamped onto it when outside).
    fn locate(&self, uv: [f64; 2]) -> (usize, [f64; 3]) {
        let g = self.grid2();
        let c = [g.cell(0, uv[0]), g.cell(1, uv[1]), 0];
        let tol = -1e-12;
        for &t in g.list(c) {
            let [a, b, cc] = self.tris[t as usize].map(|v| self.uv[v as usize]);
            let l = bary2(uv, a, b, cc);
            if l.iter().all(|&x| x >= tol) {
                return (t as usize, l);
            }
        }
        // outside (or on a cell wall): the nearest triangle
        let mut dist = |t: u32| -> f64 {
            let [a, b, cc] = self.tris[t as usize].map(|v| self.uv[v as usize]);
            let l = bary2(uv, a, b, cc);
            if l.iter().all(|&x| x >= tol) {
                return 0.0;
            }
            seg2(uv, a, b)
                .1
                .min(seg2(uv, b, cc).1)
                .min(seg2(uv, cc, a).1)
                .sqrt()
        };
        let (t, _) = g
            .nearest([uv[0], uv[1], 0.0], 2, &mut dist)
            .unwrap_or((0, 0.0));
        let [a, b, cc] = self.tris[t as usize].map(|v| self.uv[v as usize]);
        let l = bary2(uv, a, b, cc);
        if l.iter().all(|&x| x >= tol) {
            return (t as usize, l);
        }
        // clamp onto the nearest edge
        let cand = [
            (0, 1, seg2(uv, a, b)),
            (1, 2, seg2(uv, b, cc)),
            (2, 0, seg2(uv, cc, a)),
        ];
        let (i, j, (s, _)) =
            cand.iter()
                .cloned()
                .fold(cand[0], |m, x| if x.2 .1 < m.2 .1 { x } else { m });
        let mut l = [0.0; 3];
        l[i] = 1.0 - s;
        l[j] = s;
        (t as usize, l)
    }

    fn tri_derivs(&self, t: usize) -> (Vec3, Vec3) {
        let [a, b, c] = self.tris[t];
        let (p, q, r) = (
            self.uv[a as usize],
            self.uv[b as usize],
            self.uv[c as usize],
        );
        let (x0, x1, x2) = (
            self.xyz[a as usize],
            self.xyz[b as usize],
            self.xyz[c as usize],
        );
        let (e1, e2) = (vec3::sub(x1, x0), vec3::sub(x2, x0));
        let (du1, dv1, du2, dv2) = (q[0] - p[0], q[1] - p[1], r[0] - p[0], r[1] - p[1]);
        let det = du1 * dv2 - du2 * dv1;
        let inv = 1.0 / det;
        // [e1 e2] = [Su Sv] [[du1 du2] [dv1 dv2]]
        let su = vec3::scale(vec3::sub(vec3::scale(e1, dv2), vec3::scale(e2, dv1)), inv);
        let sv = vec3::scale(vec3::sub(vec3::scale(e2, du1), vec3::scale(e1, du2)), inv);
        (su, sv)
    }

    fn blend(&self, t: usize, l: [f64; 3]) -> Vec3 {
        let [a, b, c] = self.tris[t];
        let mut p = vec3::scale(self.xyz[a as usize], l[0]);
        p = vec3::add(p, vec3::scale(self.xyz[b as usize], l[1]));
        vec3::add(p, vec3::scale(self.xyz[c as usize], l[2]))
    }
}

impl Surface for TriSurface {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        let (t, l) = self.locate(uv);
        self.blend(t, l)
    }

    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let (t, l) = self.locate(uv);
        let (du, dv) = self.tri_derivs(t);
        SurfaceDerivs {
            point: self.blend(t, l),
            du,
            dv,
            duu: [0.0; 3],
            duv: [0.0; 3],
            dvv: [0.0; 3],
        }
    }

    fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let (t, l) = self.locate(uv);
        let [a, b, c] = self.tris[t];
        let mut n = vec3::scale(self.normals[a as usize], l[0].max(0.0));
        n = vec3::add(n, vec3::scale(self.normals[b as usize], l[1].max(0.0)));
        n = vec3::add(n, vec3::scale(self.normals[c as usize], l[2].max(0.0)));
        vec3::normalize(n).or_else(|| {
            let (du, dv) = self.tri_derivs(t);
            vec3::normalize(vec3::cross(du, dv))
        })
    }

    fn uv_bounds(&self) -> Bounds2 {
        self.bounds
    }

    fn periods(&self) -> [Option<f64>; 2] {
        [None, None]
    }

    fn resolution(&self) -> f64 {
        self.resolution
    }

    fn project(&self, p: Vec3, _hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        if !p.iter().all(|x| x.is_finite()) || self.tris.is_empty() {
            return None;
        }
        let g = self.grid3();
        let mut dist = |t: u32| {
            let [a, b, c] = self.tris[t as usize].map(|v| self.xyz[v as usize]);
            let l = closest_on_triangle(p, a, b, c);
            vec3::dist(p, self.blend(t as usize, l))
        };
        let (t, _) = g.nearest(p, 3, &mut dist)?;
        let [a, b, c] = self.tris[t as usize];
        let l = closest_on_triangle(
            p,
            self.xyz[a as usize],
            self.xyz[b as usize],
            self.xyz[c as usize],
        );
        let uv = [0, 1].map(|k| {
            l[0] * self.uv[a as usize][k]
                + l[1] * self.uv[b as usize][k]
                + l[2] * self.uv[c as usize][k]
        });
        Some((uv, self.blend(t as usize, l)))
    }
}

/// Index of the segment of breakpoints `t` holding `x` (clamped).
fn segment(t: &[f64], x: f64) -> usize {
    let n = t.len() - 1;
    match t.binary_search_by(|a| a.partial_cmp(&x).unwrap_or(std::cmp::Ordering::Less)) {
        Ok(i) => i.min(n - 1),
        Err(i) => i.saturating_sub(1).min(n - 1),
    }
}

/// A 3D polyline parametrized by arc length on `[0, length]`.
#[derive(Debug)]
pub struct PolyCurve {
    /// Breakpoints (cumulative arc length), shared with the pcurves.
    pub t: Arc<Vec<f64>>,
    /// The points.
    pub pts: Vec<Vec3>,
}

impl PolyCurve {
    /// The polyline through `pts` (at least 2 points, positive length).
    pub fn new(pts: Vec<Vec3>) -> Self {
        let mut t = vec![0.0; pts.len()];
        for i in 1..pts.len() {
            t[i] = t[i - 1] + vec3::dist(pts[i - 1], pts[i]);
        }
        PolyCurve {
            t: Arc::new(t),
            pts,
        }
    }
    /// Total length.
    pub fn length(&self) -> f64 {
        *self.t.last().unwrap_or(&0.0)
    }
}

impl Curve for PolyCurve {
    fn eval(&self, x: f64) -> Vec3 {
        let i = segment(&self.t, x);
        let d = self.t[i + 1] - self.t[i];
        let s = if d > 0.0 { (x - self.t[i]) / d } else { 0.0 };
        vec3::lerp(self.pts[i], self.pts[i + 1], s)
    }
    fn deriv(&self, x: f64) -> Vec3 {
        let i = segment(&self.t, x);
        let d = self.t[i + 1] - self.t[i];
        if d > 0.0 {
            vec3::scale(vec3::sub(self.pts[i + 1], self.pts[i]), 1.0 / d)
        } else {
            [0.0; 3]
        }
    }
    fn range(&self) -> (f64, f64) {
        (0.0, self.length())
    }
    fn breakpoints(&self) -> Option<Vec<f64>> {
        Some(self.t.to_vec())
    }
    fn project(&self, p: Vec3, _hint: Option<f64>) -> Option<(f64, Vec3)> {
        let mut best: Option<(f64, f64, Vec3)> = None;
        for i in 0..self.pts.len() - 1 {
            let (a, b) = (self.pts[i], self.pts[i + 1]);
            let d = vec3::sub(b, a);
            let dd = vec3::dot(d, d);
            let s = if dd > 0.0 {
                (vec3::dot(vec3::sub(p, a), d) / dd).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = vec3::lerp(a, b, s);
            let dist = vec3::dist(p, q);
            if best.is_none_or(|b| dist < b.0) {
                best = Some((dist, self.t[i] + s * (self.t[i + 1] - self.t[i]), q));
            }
        }
        best.map(|(_, t, q)| (t, q))
    }
}

/// A (u, v) polyline on the breakpoints of its 3D curve.
#[derive(Debug)]
pub struct PolyCurve2d {
    /// Breakpoints (the 3D curve's).
    pub t: Arc<Vec<f64>>,
    /// (u, v) at each breakpoint.
    pub uv: Vec<[f64; 2]>,
}

impl Curve2d for PolyCurve2d {
    fn eval(&self, x: f64) -> [f64; 2] {
        let i = segment(&self.t, x);
        let d = self.t[i + 1] - self.t[i];
        let s = if d > 0.0 {
            ((x - self.t[i]) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        [0, 1].map(|k| self.uv[i][k] + s * (self.uv[i + 1][k] - self.uv[i][k]))
    }
    fn deriv(&self, x: f64) -> [f64; 2] {
        let i = segment(&self.t, x);
        let d = self.t[i + 1] - self.t[i];
        if d > 0.0 {
            [0, 1].map(|k| (self.uv[i + 1][k] - self.uv[i][k]) / d)
        } else {
            [0.0; 2]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(
            closest_on_triangle([-1.0, -1.0, 3.0], a, b, c),
            [1.0, 0.0, 0.0]
        );
        let l = closest_on_triangle([0.25, 0.25, 2.0], a, b, c);
        assert!((l[1] - 0.25).abs() < 1e-12 && (l[2] - 0.25).abs() < 1e-12);
        let l = closest_on_triangle([0.5, -1.0, 0.0], a, b, c);
        assert!((l[1] - 0.5).abs() < 1e-12 && l[2] == 0.0);
    }

    #[test]
    fn surface_evaluates_projects_and_clamps() {
        // a unit square in the plane z = x, two triangles
        let xyz = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 0.0],
        ];
        let uv = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let s = TriSurface::new(xyz, uv, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(vec3::dist(s.eval([0.25, 0.75]), [0.25, 0.75, 0.25]) < 1e-12);
        let d = s.derivs([0.7, 0.2]);
        assert!(
            vec3::dist(d.du, [1.0, 0.0, 1.0]) < 1e-12 && vec3::dist(d.dv, [0.0, 1.0, 0.0]) < 1e-12
        );
        let (uv, q) = s.project([0.5, 0.5, 3.0], None).unwrap();
        assert!(vec3::dist(s.eval(uv), q) < 1e-12);
        assert!((q[0] - q[2]).abs() < 1e-12);
        // outside the (u, v) square: clamped onto it
        let p = s.eval([2.0, 0.5]);
        assert!(vec3::dist(p, [1.0, 0.5, 1.0]) < 1e-12);
        assert!(s.min_uv_area() > 0.0);
        let n = s.normal([0.5, 0.5]).unwrap();
        assert!((vec3::dot(n, [-1.0, 0.0, 1.0]) / 2f64.sqrt() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn polyline_curves_share_breakpoints() {
        let c = PolyCurve::new(vec![[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 4.0, 0.0]]);
        assert_eq!(c.range(), (0.0, 7.0));
        assert_eq!(c.eval(5.0), [3.0, 2.0, 0.0]);
        let (t, q) = c.project([4.0, 1.0, 0.0], None).unwrap();
        assert!((t - 4.0).abs() < 1e-12 && q == [3.0, 1.0, 0.0]);
        let pc = PolyCurve2d {
            t: c.t.clone(),
            uv: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        };
        assert_eq!(pc.eval(5.0), [1.0, 0.5]);
    }
}
