//! Frontal point insertion guided by the scaled cross field (paper §5.1,
//! spec §7.2).
//!
//! The boundary nodes of a face (the coarse, even points of the curve meshes,
//! spec §1.2) seed a first-in first-out queue. A popped node `x` proposes four
//! points, one along each branch `±d1, ±d2` of the cross at `x`, at the 3D
//! distance `factor · s(x)` (`factor` = 2: the triangulation is made at twice
//! the final size and midpoint subdivision halves it). A proposal is mapped
//! to (u, v) through the pseudo-inverse of the surface Jacobian (with one
//! correction so its 3D distance is right) and kept when
//! - no existing node `q` lies in the square exclusion zone aligned with the
//!   cross: `‖Fᵀ(p − q)‖∞ < κ · factor · s(p)` (F = the cross frame and the
//!   normal at `x`), and
//!   Boundary nodes and the midpoints of boundary edges are in that set, so
//!   no point lands on or beside a boundary edge;
//! - it is not a singular point of the surface, and it falls strictly inside the face's constrained triangulation in (u, v)
//!   ([`FaceTriangulation::try_insert`], the Delaunay kernel).
//!
//! With [`insert_frontal_points_directional`] the step and the box have a
//! length of their own along each branch (the plain unstructured method:
//! the spacing of the boundary edges running along that branch, see
//! [`crate::methods::unstructured::boundary_spacing_ratios`]).
//!
//! Kept points go to the end of the queue; insertion stops when the queue is
//! empty. Neighbour queries use a 3D hash grid, so points on both sides of a
//! seam see each other. Everything is sequential per face: the result only
//! depends on the inputs.

use std::collections::VecDeque;

use crate::core::fast_hash::FastMap;

use geometry::vec3::{self, Vec3};
use geometry::Face;

use crate::field::background::{Background, DirectionalRatios};
use crate::triangulate::face_triangulation::FaceTriangulation;

/// Default too-close factor κ (spec §7.2 suggests 0.7). 0.65: on the 26
/// shared models, with every value from 0.62 to 0.68 the default method
/// leaves fewer irregular vertices and better average SICN than with 0.7
/// (at 0.65: irregular share below Gmsh's on 10 models instead of 8,
/// average SICN at least Gmsh's on 13 instead of 12; BENCHMARKS.md, "The
/// frontal exclusion zone"); the fronts meet with fewer holes between them.
pub const KAPPA: f64 = 0.65;

/// Parameters of [`insert_frontal_points_directional`].
#[derive(Clone, Debug)]
pub struct FrontalOptions {
    /// Spacing of the points as a multiple of the size map (2 under the
    /// midpoint-subdivision convention of spec §1.2).
    pub factor: f64,
    /// Too-close factor κ of the L∞ exclusion zone.
    pub kappa: f64,
    /// Most points inserted in one face.
    pub max_points: usize,
}

impl Default for FrontalOptions {
    fn default() -> Self {
        FrontalOptions {
            factor: 2.0,
            kappa: KAPPA,
            max_points: 400_000,
        }
    }
}

/// What [`insert_frontal_points_directional`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrontalStats {
    /// Points inserted into the triangulation.
    pub inserted: usize,
    /// Proposals refused by the exclusion zone.
    pub too_close: usize,
    /// Proposals refused by the triangulation (outside the face, on a
    /// constraint, or too close to a triangulation vertex).
    pub outside: usize,
}

/// Cells per axis above which a query moves to a coarser level.
const MAX_QUERY_CELLS_PER_AXIS: i64 = 6;
/// Ratio of the cell sizes of successive levels.
const LEVEL_RATIO: f64 = 4.0;
/// Levels of the point grid.
const LEVELS: usize = 8;

/// 3D hash grids of points at cell sizes `c, 4c, 16c, …`: a query uses the
/// finest level where its zone spans a few cells, so mixed sizes (tiny
/// boundary edges beside a coarse interior) stay cheap.
struct PointGrid {
    cell: [f64; LEVELS],
    cells: Vec<FastMap<[i64; 3], Vec<u32>>>,
    pts: Vec<Vec3>,
    /// The surface normal at each inserted point; `None` for the boundary
    /// nodes and edge midpoints, which block from either side.
    normals: Vec<Option<Vec3>>,
}

impl PointGrid {
    fn new(cell: f64) -> Self {
        let mut c = [cell; LEVELS];
        for k in 1..LEVELS {
            c[k] = c[k - 1] * LEVEL_RATIO;
        }
        PointGrid {
            cell: c,
            cells: vec![FastMap::default(); LEVELS],
            pts: Vec::new(),
            normals: Vec::new(),
        }
    }

    fn key(&self, level: usize, p: Vec3) -> [i64; 3] {
        p.map(|c| (c / self.cell[level]).floor().clamp(-1e15, 1e15) as i64)
    }

    fn add(&mut self, p: Vec3, normal: Option<Vec3>) {
        let id = self.pts.len() as u32;
        for level in 0..LEVELS {
            let k = self.key(level, p);
            self.cells[level].entry(k).or_default().push(id);
        }
        self.pts.push(p);
        self.normals.push(normal);
    }

    /// True when point `q` blocks a proposal at `p` with surface normal
    /// `normal`: it lies within the box `|F·(p − q)|∞ < r` and is not an
    /// inserted point whose surface faces the other way (more than 90° from
    /// `normal`): a point on the far side of a thin shell, such as the
    /// other skin of a wing, is near in 3D but far along the surface.
    fn blocks(&self, q: u32, p: Vec3, normal: Vec3, frame: &[Vec3; 3], r: [f64; 3]) -> bool {
        in_box(p, self.pts[q as usize], frame, r)
            && self.normals[q as usize].is_none_or(|n| vec3::dot(n, normal) >= 0.0)
    }

    /// True when some point blocks a proposal at `p` (see [`Self::blocks`]),
    /// `F` the orthonormal frame `frame`.
    fn any_in_box(&self, p: Vec3, normal: Vec3, frame: &[Vec3; 3], r: [f64; 3]) -> bool {
        // the box lies in the ball of radius |r|
        let reach = vec3::norm(r);
        for level in 0..LEVELS {
            let lo = self.key(level, vec3::sub(p, [reach; 3]));
            let hi = self.key(level, vec3::add(p, [reach; 3]));
            if (0..3).any(|k| hi[k] - lo[k] + 1 > MAX_QUERY_CELLS_PER_AXIS) && level + 1 < LEVELS {
                continue;
            }
            if (0..3).any(|k| hi[k] - lo[k] + 1 > MAX_QUERY_CELLS_PER_AXIS) {
                // larger than every level: scan all points
                return (0..self.pts.len() as u32).any(|q| self.blocks(q, p, normal, frame, r));
            }
            for i in lo[0]..=hi[0] {
                for j in lo[1]..=hi[1] {
                    for k in lo[2]..=hi[2] {
                        if let Some(list) = self.cells[level].get(&[i, j, k]) {
                            if list.iter().any(|&q| self.blocks(q, p, normal, frame, r)) {
                                return true;
                            }
                        }
                    }
                }
            }
            return false;
        }
        false
    }
}

fn in_box(p: Vec3, q: Vec3, frame: &[Vec3; 3], r: [f64; 3]) -> bool {
    let d = vec3::sub(p, q);
    (0..3).all(|k| vec3::dot(d, frame[k]).abs() < r[k])
}

/// The (u, v) step whose image under the surface Jacobian at `uv` is closest
/// to the 3D vector `w` (least squares), or `None` where the Jacobian is singular.
pub fn uv_step(face: &Face, uv: [f64; 2], w: Vec3) -> Option<[f64; 2]> {
    let d = face.surface.first_derivs(uv);
    let (a, b, c) = (
        vec3::dot(d.du, d.du),
        vec3::dot(d.du, d.dv),
        vec3::dot(d.dv, d.dv),
    );
    let det = a * c - b * b;
    if !(det.is_finite() && det > 1e-20 * (a * c).max(1e-300)) {
        return None;
    }
    let (r0, r1) = (vec3::dot(d.du, w), vec3::dot(d.dv, w));
    let s = [(c * r0 - b * r1) / det, (a * r1 - b * r0) / det];
    (s[0].is_finite() && s[1].is_finite()).then_some(s)
}

/// Runs frontal insertion on `ft` (which holds only its boundary nodes, or
/// more), guided by the cross field and size map of `bg`. Every node already
/// in `ft` is a seed and blocks proposals near it. Where `ratios` is given,
/// with a spacing of its own along each cross branch ([`Background::sample_directional`]): the
/// steps along `±d₁` and `±d₂` and the exclusion box's half-widths follow
/// them.
pub fn insert_frontal_points_directional(
    ft: &mut FaceTriangulation<'_>,
    face: &Face,
    bg: &Background<'_>,
    opts: &FrontalOptions,
    ratios: Option<&DirectionalRatios>,
) -> FrontalStats {
    let sample = |p: Vec3| -> Option<(crate::field::background::Sample, [f64; 2])> {
        match ratios {
            Some(r) => bg.sample_directional(p, r),
            None => bg.sample(p).map(|s| (s, [s.size; 2])),
        }
    };
    let mut stats = FrontalStats::default();
    // grid cell: the smallest exclusion radius seen on the boundary
    let mut min_r = f64::INFINITY;
    for p in &ft.pos {
        if let Some((_, sp)) = sample(*p) {
            min_r = min_r.min(opts.kappa * opts.factor * sp[0].min(sp[1]));
        }
    }
    if !(min_r.is_finite() && min_r > 0.0) {
        return stats;
    }
    let mut grid = PointGrid::new(min_r);
    let mut queue: VecDeque<u32> = VecDeque::new();
    for (i, p) in ft.pos.iter().enumerate() {
        grid.add(*p, None);
        queue.push_back(i as u32);
    }
    // the midpoints of boundary edges block too: no point lands on (or right
    // beside) a boundary edge between two boundary nodes
    let mut mids: Vec<(&(u32, u32), Vec3)> =
        ft.boundary_mid.iter().map(|(k, m)| (k, m.pos)).collect();
    mids.sort_by_key(|m| *m.0);
    for (_, p) in mids {
        grid.add(p, None);
    }
    while let Some(i) = queue.pop_front() {
        if stats.inserted >= opts.max_points {
            break;
        }
        let node = ft.nodes[i as usize];
        if node.pole.is_some() {
            continue;
        }
        let x = ft.pos[i as usize];
        let Some((sx, spacing)) = sample(x) else {
            continue;
        };
        let frame = [sx.cross[0], sx.cross[1], sx.normal];
        let dirs = [
            (sx.cross[0], spacing[0]),
            (sx.cross[1], spacing[1]),
            (vec3::scale(sx.cross[0], -1.0), spacing[0]),
            (vec3::scale(sx.cross[1], -1.0), spacing[1]),
        ];
        for (d, s_along) in dirs {
            let len = opts.factor * s_along;
            let Some(step) = uv_step(face, node.uv, vec3::scale(d, len)) else {
                continue;
            };
            let mut uv = [node.uv[0] + step[0], node.uv[1] + step[1]];
            let mut p = face.surface.eval(uv);
            // one correction of the step length so that |p − x| = len
            let got = vec3::dist(p, x);
            if got > 0.0 && got.is_finite() {
                let r = len / got;
                if (0.5..=2.0).contains(&r) && (r - 1.0).abs() > 1e-3 {
                    uv = [node.uv[0] + r * step[0], node.uv[1] + r * step[1]];
                    p = face.surface.eval(uv);
                }
            }
            // never on a singular point of the surface (an apex, a pole)
            let normal = match face.surface.normal(uv) {
                Some(n) if p.iter().all(|c| c.is_finite()) && !face.is_singular(uv) => n,
                _ => continue,
            };
            let sp = sample(p).map_or(spacing, |s| s.1);
            let r = [
                opts.kappa * opts.factor * sp[0],
                opts.kappa * opts.factor * sp[1],
                opts.kappa * opts.factor * sp[0].max(sp[1]),
            ];
            if grid.any_in_box(p, normal, &frame, r) {
                stats.too_close += 1;
                continue;
            }
            if !ft.try_insert(uv, 0.1 * r[0].min(r[1])) {
                stats.outside += 1;
                continue;
            }
            grid.add(p, Some(normal));
            stats.inserted += 1;
            queue.push_back((ft.nodes.len() - 1) as u32);
        }
    }
    stats
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{primitives, FaceId};

    #[test]
    fn square_gives_a_near_grid() {
        // unit square, final size 0.05: coarse spacing 0.1, a 10 × 10 grid of cells
        let h = 0.05;
        let model = primitives::square(1.0);
        let (fields, cms) = crate::fixtures::grids::fields_and_curves(&model, h);
        let ff = fields.faces[0].outcome.as_ref().unwrap();
        let size = ff.size.as_ref().unwrap();
        let bg = Background::new(&ff.field, size).unwrap();
        let mut ft = FaceTriangulation::new(&model, FaceId(0), &cms, 2.0 * h).unwrap();
        let nb = ft.nodes.len();
        assert_eq!(nb, 40);
        let st = insert_frontal_points_directional(
            &mut ft,
            &model.faces[0],
            &bg,
            &FrontalOptions::default(),
            None,
        );
        // a 10 × 10 grid has 9 × 9 = 81 interior points
        assert!((70..=95).contains(&st.inserted), "{st:?}");
        // interior points sit near grid positions: valence 4 in the
        // triangulation's quad sense is hard to read, so check the spacing
        // instead: nearest neighbour of every interior point ≈ 0.1
        for i in nb..ft.nodes.len() {
            let p = ft.pos[i];
            let d = (0..ft.nodes.len())
                .filter(|&j| j != i)
                .map(|j| vec3::dist(p, ft.pos[j]))
                .fold(f64::INFINITY, f64::min);
            assert!(d > 0.06 && d < 0.13, "node {i} at {p:?}: nearest {d}");
        }
        // all inside the square
        assert!(ft.pos[nb..]
            .iter()
            .all(|p| p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.0));
    }

    #[test]
    fn uv_step_inverts_the_jacobian() {
        let model = primitives::cylinder(2.0, 1.0);
        let face = &model.faces[0];
        let uv = [0.3, 0.5];
        let d = face.surface.first_derivs(uv);
        let w = vec3::add(vec3::scale(d.du, 0.01), vec3::scale(d.dv, -0.02));
        let s = uv_step(face, uv, w).unwrap();
        assert!(
            (s[0] - 0.01).abs() < 1e-12 && (s[1] + 0.02).abs() < 1e-12,
            "{s:?}"
        );
    }

    #[test]
    fn a_point_on_the_far_skin_of_a_thin_shell_does_not_block() {
        // two skins 0.01 apart facing away from each other (a wing near its
        // trailing edge); the exclusion box is 0.2 wide
        let mut grid = PointGrid::new(0.05);
        let up = [0.0, 0.0, 1.0];
        let down = [0.0, 0.0, -1.0];
        let frame = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], up];
        grid.add([0.0, 0.0, -0.01], Some(down));
        let p = [0.02, 0.0, 0.0];
        assert!(!grid.any_in_box(p, up, &frame, [0.2; 3]));
        // the same point on this skin blocks
        grid.add([0.0, 0.05, -0.001], Some(up));
        assert!(grid.any_in_box(p, up, &frame, [0.2; 3]));
        // a boundary node (no normal) blocks either skin
        let mut boundary = PointGrid::new(0.05);
        boundary.add([0.0, 0.0, -0.01], None);
        assert!(boundary.any_in_box(p, up, &frame, [0.2; 3]));
        assert!(boundary.any_in_box(p, down, &frame, [0.2; 3]));
        // and nothing blocks from outside the box
        assert!(!boundary.any_in_box([0.5, 0.0, 0.0], up, &frame, [0.2; 3]));
    }
}
