//! Point location in a face's background triangulation and interpolation of
//! its cross field and size map at an arbitrary 3D point (spec §2.7).
//!
//! The background is the welded triangulation a [`CrossField`] lives on
//! ([`FaceTopology`], 3D positions only: seams and poles are welded, so the
//! location is done in 3D, not in (u, v)). A uniform grid of cells holds the
//! triangles whose bounding box overlaps each cell; a query returns the
//! triangle closest to the point, the barycentric coordinates of the closest
//! point on it and the distance. The cross is the Crouzeix–Raviart
//! interpolation ([`CrossField::cross_at`]) there, the size the linear
//! interpolation of the per-vertex sizes.

use geometry::vec3::{self, Vec3};

use crate::field::crossfield::{CrossField, FaceTopology};

/// Cells per triangle in the grid (on average).
const CELLS_PER_TRIANGLE: f64 = 0.5;
/// Upper bound on the cells along one axis.
const MAX_GRID_CELLS_PER_AXIS: usize = 512;

/// What the background says at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Two orthogonal unit branch directions of the cross (the others are
    /// their opposites), tangent to the background triangle.
    pub cross: [Vec3; 2],
    /// Unit normal of the background triangle (`cross[0] × cross[1]`).
    pub normal: Vec3,
    /// Interpolated size (the final quad edge length wanted there).
    pub size: f64,
    /// Distance from the query point to the background triangulation.
    pub distance: f64,
}

/// Per background vertex, how the spacing along each cross branch differs
/// from the size: `log_ratio[v] = [ln r₁, ln r₂]` for the branch along
/// `dir[v]` and the one across it ([`Background::sample_directional`]).
#[derive(Clone, Debug, Default)]
pub struct DirectionalRatios {
    /// A reference branch direction at each vertex.
    pub dir: Vec<Vec3>,
    /// Log of the spacing ratio along `dir` and across it.
    pub log_ratio: Vec<[f64; 2]>,
}

/// Why a background cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BackgroundError {
    /// The size array does not have one finite positive value per welded vertex.
    #[error("size map: {0}")]
    Size(String),
    /// The triangulation has no triangle or a non-finite position.
    #[error("background triangulation: {0}")]
    Triangulation(String),
}

/// A background triangulation with its cross field and size map, ready for
/// point queries.
pub struct Background<'a> {
    field: &'a CrossField,
    size: &'a [f64],
    lo: Vec3,
    cell: f64,
    dims: [usize; 3],
    /// Start of each cell's list in `items` (prefix sums, `cells + 1` entries).
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> Background<'a> {
    /// Indexes the triangles of `field.topology`; `size` holds one size per
    /// welded vertex (finite and positive).
    pub fn new(field: &'a CrossField, size: &'a [f64]) -> Result<Self, BackgroundError> {
        let topo: &FaceTopology = &field.topology;
        if size.len() != topo.positions.len() {
            return Err(BackgroundError::Size(format!(
                "{} values for {} vertices",
                size.len(),
                topo.positions.len()
            )));
        }
        if let Some(i) = size.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(BackgroundError::Size(format!(
                "value {} at vertex {i} is not a positive number",
                size[i]
            )));
        }
        if topo.triangles.is_empty() {
            return Err(BackgroundError::Triangulation("no triangles".into()));
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &topo.positions {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(BackgroundError::Triangulation(
                    "non-finite vertex position".into(),
                ));
            }
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let ext = vec3::sub(hi, lo);
        let diag = vec3::norm(ext).max(1e-300);
        // cell edge: a cube of the bounding box volume shared by the wanted
        // cell count, but at least a small fraction of the diagonal (flat faces)
        let ncells = (topo.triangles.len() as f64 * CELLS_PER_TRIANGLE).max(1.0);
        let mean_edge = {
            let mut s = 0.0;
            for t in &topo.triangles {
                s += vec3::dist(topo.positions[t[0] as usize], topo.positions[t[1] as usize]);
            }
            s / topo.triangles.len() as f64
        };
        let vol_cell =
            (ext[0].max(1e-9 * diag) * ext[1].max(1e-9 * diag) * ext[2].max(1e-9 * diag) / ncells)
                .cbrt();
        let mut cell = vol_cell
            .max(mean_edge)
            .max(diag / MAX_GRID_CELLS_PER_AXIS as f64);
        if !(cell.is_finite() && cell > 0.0) {
            cell = diag;
        }
        let dims =
            [0, 1, 2].map(|k| ((ext[k] / cell).floor() as usize + 1).min(MAX_GRID_CELLS_PER_AXIS));
        let mut bg = Background {
            field,
            size,
            lo,
            cell,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        let total = dims[0] * dims[1] * dims[2];
        let mut count = vec![0u32; total + 1];
        let ranges: Vec<[[usize; 3]; 2]> = topo
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|v| topo.positions[v as usize]);
                let mut a = [usize::MAX; 3];
                let mut b = [0usize; 3];
                for q in &p {
                    let c = bg.cell_of(*q);
                    for k in 0..3 {
                        a[k] = a[k].min(c[k]);
                        b[k] = b[k].max(c[k]);
                    }
                }
                [a, b]
            })
            .collect();
        for r in &ranges {
            for i in r[0][0]..=r[1][0] {
                for j in r[0][1]..=r[1][1] {
                    for k in r[0][2]..=r[1][2] {
                        count[bg.index([i, j, k]) + 1] += 1;
                    }
                }
            }
        }
        for c in 0..total {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[total] as usize];
        for (t, r) in ranges.iter().enumerate() {
            for i in r[0][0]..=r[1][0] {
                for j in r[0][1]..=r[1][1] {
                    for k in r[0][2]..=r[1][2] {
                        let c = bg.index([i, j, k]);
                        items[fill[c] as usize] = t as u32;
                        fill[c] += 1;
                    }
                }
            }
        }
        bg.start = count;
        bg.items = items;
        Ok(bg)
    }

    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        [0, 1, 2].map(|k| {
            let x = ((p[k] - self.lo[k]) / self.cell).floor();
            if x.is_finite() && x > 0.0 {
                (x as usize).min(self.dims[k] - 1)
            } else {
                0
            }
        })
    }

    /// A lower bound on the distance from `p` (in cell `c`) to any triangle
    /// registered only in cells outside the box of Chebyshev radius `r`
    /// around `c`: the distance to the nearest side of the box that has
    /// cells beyond it (sides at the grid's ends have none: infinity).
    fn unseen_distance(&self, p: Vec3, c: [usize; 3], r: usize) -> f64 {
        let mut bound = f64::INFINITY;
        for k in 0..3 {
            if c[k] > r {
                let side = self.lo[k] + (c[k] - r) as f64 * self.cell;
                bound = bound.min(p[k] - side);
            }
            if c[k] + r + 1 < self.dims[k] {
                let side = self.lo[k] + (c[k] + r + 1) as f64 * self.cell;
                bound = bound.min(side - p[k]);
            }
        }
        bound
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[0] * self.dims[1] + c[1]) * self.dims[2] + c[2]
    }

    /// The triangle closest to `p`: `(triangle, barycentric coordinates of
    /// the closest point, distance)`. `None` only for a non-finite `p`.
    pub fn locate(&self, p: Vec3) -> Option<(usize, [f64; 3], f64)> {
        if p.iter().any(|c| !c.is_finite()) {
            return None;
        }
        let topo = &self.field.topology;
        let c = self.cell_of(p);
        let max_r = self.dims[0].max(self.dims[1]).max(self.dims[2]);
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        let mut r = 0usize;
        loop {
            // the shell of cells at Chebyshev distance r from c
            let range = |k: usize| (c[k].saturating_sub(r), (c[k] + r).min(self.dims[k] - 1));
            let (i0, i1) = range(0);
            let (j0, j1) = range(1);
            let (k0, k1) = range(2);
            for i in i0..=i1 {
                for j in j0..=j1 {
                    for k in k0..=k1 {
                        let on_shell =
                            i.abs_diff(c[0]) == r || j.abs_diff(c[1]) == r || k.abs_diff(c[2]) == r;
                        if !on_shell {
                            continue;
                        }
                        let cell = self.index([i, j, k]);
                        for &t in
                            &self.items[self.start[cell] as usize..self.start[cell + 1] as usize]
                        {
                            let tri = topo.triangles[t as usize];
                            let q = tri.map(|v| topo.positions[v as usize]);
                            let (bary, x) = closest_on_triangle(p, q);
                            let d = vec3::dist(p, x);
                            if best.is_none_or(|b| d < b.2 || (d == b.2 && (t as usize) < b.0)) {
                                best = Some((t as usize, bary, d));
                            }
                        }
                    }
                }
            }
            // a triangle not seen yet lies beyond the searched box on some
            // axis, so at least `unseen` away: once the best is closer, it is
            // the closest (ties included, as they are all seen)
            if let Some(b) = best {
                if b.2 < self.unseen_distance(p, c, r) || r >= max_r {
                    return best;
                }
            } else if r >= max_r {
                return None;
            }
            r += 1;
        }
    }

    /// The cross, normal and size at (the point of the background closest to) `p`.
    pub fn sample(&self, p: Vec3) -> Option<Sample> {
        let (t, bary, distance) = self.locate(p)?;
        Some(self.sample_in(t, bary, distance))
    }

    /// The sample at barycentric coordinates `bary` of triangle `t`, found
    /// at `distance` from the query point.
    fn sample_in(&self, t: usize, bary: [f64; 3], distance: f64) -> Sample {
        let topo = &self.field.topology;
        let tri = topo.triangles[t];
        let size = (0..3)
            .map(|k| bary[k] * self.size[tri[k] as usize])
            .sum::<f64>();
        let cross = self
            .field
            .cross_at(t, bary)
            .or_else(|| self.field.triangle_cross(t))
            .unwrap_or_else(|| {
                // at a singularity the interpolant vanishes: any tangent frame will do
                let x = topo.edge_dir[topo.tri_edges[t][0] as usize];
                [x, vec3::cross(topo.normals[t], x)]
            });
        Sample {
            cross,
            normal: vec3::cross(cross[0], cross[1]),
            size,
            distance,
        }
    }

    /// [`Self::sample`], and the sizes along its two cross branches: the
    /// size times the ratios `ratios` holds per background vertex (each
    /// vertex's pair matched to the branches by its reference direction).
    pub fn sample_directional(
        &self,
        p: Vec3,
        ratios: &DirectionalRatios,
    ) -> Option<(Sample, [f64; 2])> {
        let (t, bary, distance) = self.locate(p)?;
        let s = self.sample_in(t, bary, distance);
        let tri = self.field.topology.triangles[t];
        let mut log = [0.0; 2];
        for k in 0..3 {
            let v = tri[k] as usize;
            let (Some(d), Some(r)) = (ratios.dir.get(v), ratios.log_ratio.get(v)) else {
                return Some((s, [s.size; 2]));
            };
            let along_first = vec3::dot(*d, s.cross[0]).abs() >= vec3::dot(*d, s.cross[1]).abs();
            let (a, b) = if along_first {
                (r[0], r[1])
            } else {
                (r[1], r[0])
            };
            log[0] += bary[k] * a;
            log[1] += bary[k] * b;
        }
        Some((s, [s.size * log[0].exp(), s.size * log[1].exp()]))
    }

    /// Alignment of a polygon with the cross field (spec §7.3): at the
    /// centroid of `pts`, the mean over its edges of `(1 + cos 4Δ) / 2`, Δ the
    /// angle between the edge (in the tangent plane) and the cross. In
    /// [0, 1]; 1 for edges along the cross branches. `None` when the centroid
    /// cannot be located.
    pub fn alignment(&self, pts: &[Vec3]) -> Option<f64> {
        let n = pts.len();
        if n < 2 {
            return None;
        }
        let mut c = [0.0; 3];
        for p in pts {
            c = vec3::add(c, *p);
        }
        let s = self.sample(vec3::scale(c, 1.0 / n as f64))?;
        let mut sum = 0.0;
        for k in 0..n {
            let e = vec3::sub(pts[(k + 1) % n], pts[k]);
            let (x, y) = (vec3::dot(e, s.cross[0]), vec3::dot(e, s.cross[1]));
            let a = if x == 0.0 && y == 0.0 {
                0.0
            } else {
                (1.0 + (4.0 * y.atan2(x)).cos()) / 2.0
            };
            sum += a;
        }
        Some(sum / n as f64)
    }
}

/// Closest point to `p` on triangle `q`: its barycentric coordinates and position.
pub fn closest_on_triangle(p: Vec3, q: [Vec3; 3]) -> ([f64; 3], Vec3) {
    let (a, b, c) = (q[0], q[1], q[2]);
    let ab = vec3::sub(b, a);
    let ac = vec3::sub(c, a);
    let ap = vec3::sub(p, a);
    let d1 = vec3::dot(ab, ap);
    let d2 = vec3::dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return ([1.0, 0.0, 0.0], a);
    }
    let bp = vec3::sub(p, b);
    let d3 = vec3::dot(ab, bp);
    let d4 = vec3::dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return ([0.0, 1.0, 0.0], b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return ([1.0 - v, v, 0.0], vec3::add(a, vec3::scale(ab, v)));
    }
    let cp = vec3::sub(p, c);
    let d5 = vec3::dot(ab, cp);
    let d6 = vec3::dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return ([0.0, 0.0, 1.0], c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return ([1.0 - w, 0.0, w], vec3::add(a, vec3::scale(ac, w)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (
            [0.0, 1.0 - w, w],
            vec3::add(b, vec3::scale(vec3::sub(c, b), w)),
        );
    }
    let denom = va + vb + vc;
    if !(denom.abs() > 0.0) {
        return ([1.0, 0.0, 0.0], a);
    }
    let v = vb / denom;
    let w = vc / denom;
    (
        [1.0 - v - w, v, w],
        vec3::add(a, vec3::add(vec3::scale(ab, v), vec3::scale(ac, w))),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::options::Size;
    use crate::field::field_report::{model_fields, FieldOptions};

    #[test]
    fn closest_point_regions() {
        let q = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let (b, x) = closest_on_triangle([0.25, 0.25, 3.0], q);
        assert!(
            (b[0] - 0.5).abs() < 1e-12 && (b[1] - 0.25).abs() < 1e-12 && x == [0.25, 0.25, 0.0]
        );
        assert_eq!(closest_on_triangle([-1.0, -1.0, 0.0], q).0, [1.0, 0.0, 0.0]);
        assert_eq!(closest_on_triangle([2.0, -0.5, 0.0], q).0, [0.0, 1.0, 0.0]);
        let (b, _) = closest_on_triangle([1.0, 1.0, 0.0], q);
        assert!((b[1] - 0.5).abs() < 1e-12 && (b[2] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn square_background_gives_the_sides_and_the_size() {
        let model = geometry::primitives::square(2.0);
        let fields = model_fields(
            &model,
            &FieldOptions {
                size: Size::Absolute(0.5),
                ..Default::default()
            },
        )
        .unwrap();
        let ff = fields.faces[0].outcome.as_ref().unwrap();
        let size = ff.size.as_ref().unwrap();
        let bg = Background::new(&ff.field, size).unwrap();
        for p in [
            [0.3, 0.4, 0.0],
            [1.9, 1.2, 0.0],
            [1.0, 1.0, 0.2],
            [-0.5, 3.0, 0.0],
        ] {
            let s = bg.sample(p).unwrap();
            assert!((s.size - 0.5).abs() < 0.03, "size {}", s.size);
            let c = s.cross[0][0].abs().max(s.cross[0][1].abs());
            assert!(c > 0.99, "cross {:?}", s.cross);
            assert!((s.normal[2].abs() - 1.0).abs() < 1e-9);
        }
        // distance to the plane of the square, and to its corner from outside
        assert!((bg.sample([1.0, 1.0, 0.2]).unwrap().distance - 0.2).abs() < 1e-12);
        assert!((bg.sample([-0.5, 3.0, 0.0]).unwrap().distance - 0.5f64.hypot(1.0)).abs() < 1e-12);
        // an axis-aligned square is perfectly aligned, a 45°-turned one not at all
        let sq = [
            [0.5, 0.5, 0.0],
            [1.0, 0.5, 0.0],
            [1.0, 1.0, 0.0],
            [0.5, 1.0, 0.0],
        ];
        assert!(bg.alignment(&sq).unwrap() > 0.99);
        let diamond = [
            [1.0, 0.5, 0.0],
            [1.5, 1.0, 0.0],
            [1.0, 1.5, 0.0],
            [0.5, 1.0, 0.0],
        ];
        assert!(bg.alignment(&diamond).unwrap() < 0.01);
        // bad size arrays are refused
        assert!(Background::new(&ff.field, &size[1..]).is_err());
        let mut neg = size.clone();
        neg[0] = -1.0;
        assert!(Background::new(&ff.field, &neg).is_err());
    }
}
