//! A plate with one hole meshed directly as a grid with a rectangular hole
//! (a pattern of §6.1.2 for a face with two loops): the outer loop has four
//! convex corners and opposite sides of equal counts `nx`, `ny`; the inner
//! loop is smooth (no corner off 180°) with `2 (mx + my)` edges. The
//! `nx × ny` grid without its middle `mx × my` cells is mapped onto the
//! face: the grid's perimeter on the outer loop, the hole's perimeter on
//! the inner loop, the rest by a harmonic map in (u, v). Every
//! face-interior vertex is regular; the four nodes of the inner loop at
//! the hole's corners take three quads each (the index a round hole in a
//! square needs). The unstructured mesher instead leaves valence-3 vertices
//! inside the face, and no cavity removes them, because a cavity never
//! wraps around a hole (s11o_cube_cyl's top: 2 of them).

use geometry::{FaceId, Model};

use crate::core::patch::{LocalNode, QuadPatch};
use crate::core::valence::ideal_corner_valence;
use crate::curves::curve_mesh::CurveMesh;
use crate::direct::pattern_face::{harmonic_uv, loop_ring, ring_step, two_loop_patch, uv_area};

/// Name of the pattern of [`mesh_holed_face`].
pub const HOLED_GRID: &str = "holed grid";

/// The hole's widths `(mx, my)` in grid cells: `mx + my = half`, split in
/// the proportion of the outer sides, each at least 1 and leaving at least
/// one cell on each side of the hole. `None` when that is impossible.
pub fn hole_widths(nx: usize, ny: usize, half: usize) -> Option<(usize, usize)> {
    if nx < 3 || ny < 3 || half < 2 || half > nx + ny - 4 {
        return None;
    }
    let want = (half as f64 * nx as f64 / (nx + ny) as f64).round() as usize;
    // mx in [max(1, half − (ny − 2)), min(nx − 2, half − 1)]
    let lo = 1.max(half.saturating_sub(ny - 2));
    let hi = (nx - 2).min(half - 1);
    (lo <= hi).then(|| {
        let mx = want.clamp(lo, hi);
        (mx, half - mx)
    })
}

/// The grid of [`mesh_holed_face`] in grid coordinates: vertex ids of the
/// `(nx + 1) × (ny + 1)` lattice without the hole's inside, the quads
/// (counter-clockwise in grid coordinates), the outer perimeter from
/// `(0, 0)` counter-clockwise, and the hole's perimeter from its corner
/// `(ax, ay)` counter-clockwise.
pub struct HoledGrid {
    /// Grid coordinates of each vertex.
    pub coords: Vec<[usize; 2]>,
    /// Quads as vertex ids.
    pub quads: Vec<[u32; 4]>,
    /// Outer perimeter, `2 (nx + ny)` vertex ids.
    pub outer: Vec<u32>,
    /// Hole perimeter, `2 (mx + my)` vertex ids.
    pub inner: Vec<u32>,
}

/// Builds the [`HoledGrid`] with the hole's lower-left cell corner at `(ax, ay)`.
pub fn holed_grid(nx: usize, ny: usize, ax: usize, ay: usize, mx: usize, my: usize) -> HoledGrid {
    let inside = |i: usize, j: usize| i > ax && i < ax + mx && j > ay && j < ay + my;
    let mut id = vec![u32::MAX; (nx + 1) * (ny + 1)];
    let mut coords = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            if !inside(i, j) {
                id[j * (nx + 1) + i] = coords.len() as u32;
                coords.push([i, j]);
            }
        }
    }
    let at = |i: usize, j: usize| id[j * (nx + 1) + i];
    let mut quads = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let in_hole = i >= ax && i < ax + mx && j >= ay && j < ay + my;
            if !in_hole {
                quads.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    let perimeter = |x0: usize, y0: usize, w: usize, h: usize| -> Vec<u32> {
        let mut out = Vec::with_capacity(2 * (w + h));
        out.extend((0..w).map(|k| at(x0 + k, y0)));
        out.extend((0..h).map(|k| at(x0 + w, y0 + k)));
        out.extend((0..w).map(|k| at(x0 + w - k, y0 + h)));
        out.extend((0..h).map(|k| at(x0, y0 + h - k)));
        out
    };
    HoledGrid {
        outer: perimeter(0, 0, nx, ny),
        inner: perimeter(ax, ay, mx, my),
        coords,
        quads,
    }
}

/// Meshes a face with two loops as a [`HoledGrid`] (see the module
/// documentation); an error says why the face does not fit. The result is
/// kept only when every quad reaches [`crate::direct::pattern_face::MIN_PATTERN_SICN`].
pub fn mesh_holed_face(model: &Model, fid: FaceId, cms: &[CurveMesh]) -> Result<QuadPatch, String> {
    let face = &model.faces[fid.idx()];
    if face.loops.len() != 2 {
        return Err(format!("{} boundary loops", face.loops.len()));
    }
    if face.surface.periods().iter().any(Option::is_some) {
        return Err("a periodic surface".into());
    }
    let rings = [
        loop_ring(model, fid, cms, 0)?,
        loop_ring(model, fid, cms, 1)?,
    ];
    if rings
        .iter()
        .flat_map(|r| &r.nodes)
        .any(|n| n.pole.is_some())
    {
        return Err("a pole on a loop".into());
    }
    // the outer loop encloses the larger (u, v) area
    let areas = [uv_area(&rings[0]), uv_area(&rings[1])];
    let (o, h) = if areas[0].abs() >= areas[1].abs() {
        (0, 1)
    } else {
        (1, 0)
    };
    let (outer, hole) = (&rings[o], &rings[h]);
    let mut corners = Vec::new();
    for &(at, angle) in &outer.corners {
        match ideal_corner_valence(angle) {
            1 => corners.push(at),
            2 => {}
            _ => {
                return Err(format!(
                    "a concave outer corner ({:.0}°)",
                    angle.to_degrees()
                ))
            }
        }
    }
    if corners.len() != 4 {
        return Err(format!("{} convex outer corners", corners.len()));
    }
    if hole
        .corners
        .iter()
        .any(|&(_, angle)| ideal_corner_valence(angle) != 2)
    {
        return Err("a corner on the hole".into());
    }
    let nb = outer.nodes.len();
    let side = |k: usize| (corners[(k + 1) % 4] + nb - corners[k]) % nb;
    let (nx, ny) = (side(0), side(1));
    if side(2) != nx || side(3) != ny {
        return Err(format!(
            "outer sides {:?} are not two equal pairs",
            [side(0), side(1), side(2), side(3)]
        ));
    }
    let nh = hole.nodes.len();
    if nh % 2 != 0 {
        return Err(format!("a hole of {nh} edges"));
    }
    let (mx, my) = hole_widths(nx, ny, nh / 2)
        .ok_or_else(|| format!("a hole of {nh} edges in {nx} × {ny}"))?;
    let (ax, ay) = ((nx - mx) / 2, (ny - my) / 2);
    let grid = holed_grid(nx, ny, ax, ay, mx, my);
    // the outer perimeter from corner 0 in the ring's order; the hole's in
    // the same sense of rotation, from the node that puts the hole's corners
    // nearest the outer corners (each hole corner faces its outer corner)
    let outer_at = |k: usize| (corners[0] + k) % nb;
    let same_sense = (areas[o] > 0.0) == (areas[h] > 0.0);
    let hole_at = |r: usize, k: usize| ring_step(r, k, nh, same_sense);
    let hole_corner_offsets = [0, mx, mx + my, 2 * mx + my];
    let outer_corner_offsets = [0, nx, nx + ny, 2 * nx + ny];
    let dist2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let rotation = (0..nh)
        .min_by(|&r1, &r2| {
            let cost = |r: usize| -> f64 {
                (0..4)
                    .map(|c| {
                        dist2(
                            hole.nodes[hole_at(r, hole_corner_offsets[c])].uv,
                            outer.nodes[outer_at(outer_corner_offsets[c])].uv,
                        )
                    })
                    .sum()
            };
            cost(r1).total_cmp(&cost(r2))
        })
        .unwrap_or(0);
    // local nodes: the outer ring, the hole's ring, then the grid's inside
    let nv = grid.coords.len();
    let mut local = vec![u32::MAX; nv];
    let mut fixed = vec![false; nv];
    for (k, &v) in grid.outer.iter().enumerate() {
        local[v as usize] = outer_at(k) as u32;
        fixed[v as usize] = true;
    }
    for (k, &v) in grid.inner.iter().enumerate() {
        local[v as usize] = (nb + hole_at(rotation, k)) as u32;
        fixed[v as usize] = true;
    }
    let ring_node = |l: u32| -> &LocalNode {
        let l = l as usize;
        if l < nb {
            &outer.nodes[l]
        } else {
            &hole.nodes[l - nb]
        }
    };
    // interior (u, v): harmonic, from the outer ring's centroid
    let centroid = crate::direct::pattern_face::uv_centroid(&outer.nodes);
    let mut uv: Vec<[f64; 2]> = (0..nv)
        .map(|v| {
            if fixed[v] {
                ring_node(local[v]).uv
            } else {
                centroid
            }
        })
        .collect();
    harmonic_uv(&grid.quads, &mut uv, &fixed);
    two_loop_patch(face, outer, hole, &uv, &fixed, &mut local, &grid.quads, HOLED_GRID, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hole_widths_split_the_hole_like_the_sides_and_leave_a_cell_around_it() {
        // s11o_cube_cyl's top: 12 × 12 edges around a hole of 28
        assert_eq!(hole_widths(12, 12, 14), Some((7, 7)));
        // a long plate: the hole stretches along its long side
        assert_eq!(hole_widths(20, 10, 12), Some((8, 4)));
        // a hole too large to leave a cell on each side, or too small
        assert_eq!(hole_widths(6, 6, 9), None);
        assert_eq!(hole_widths(6, 6, 1), None);
        assert_eq!(hole_widths(6, 6, 8), Some((4, 4)));
    }

    #[test]
    fn a_holed_grid_has_a_regular_inside_and_the_hole_corners_on_three_quads() {
        let (nx, ny, ax, ay, mx, my) = (6, 5, 2, 1, 2, 3);
        let g = holed_grid(nx, ny, ax, ay, mx, my);
        assert_eq!(g.quads.len(), nx * ny - mx * my);
        assert_eq!(g.coords.len(), (nx + 1) * (ny + 1) - (mx - 1) * (my - 1));
        assert_eq!(g.outer.len(), 2 * (nx + ny));
        assert_eq!(g.inner.len(), 2 * (mx + my));
        let mut quads_at = vec![0usize; g.coords.len()];
        for q in &g.quads {
            for &v in q {
                quads_at[v as usize] += 1;
            }
        }
        let on_outer = |v: usize| g.outer.contains(&(v as u32));
        let on_inner = |v: usize| g.inner.contains(&(v as u32));
        for (v, &k) in quads_at.iter().enumerate() {
            let [i, j] = g.coords[v];
            let grid_corner = (i == 0 || i == nx) && (j == 0 || j == ny);
            let hole_corner = (i == ax || i == ax + mx) && (j == ay || j == ay + my);
            let want = if grid_corner {
                1
            } else if hole_corner {
                3
            } else if on_outer(v) || on_inner(v) {
                2
            } else {
                4
            };
            assert_eq!(k, want, "vertex {v} at {:?}", g.coords[v]);
        }
        // the perimeters run counter-clockwise: the outer one starts along
        // the bottom, the hole's along its bottom from its lower-left corner
        assert_eq!(g.coords[g.outer[1] as usize], [1, 0]);
        assert_eq!(g.coords[g.inner[0] as usize], [ax, ay]);
        assert_eq!(g.coords[g.inner[1] as usize], [ax + 1, ay]);
        assert_eq!(g.coords[g.inner[mx] as usize], [ax + mx, ay]);
        // every edge of the hole's perimeter is on exactly one quad
        let edge_quads = |a: u32, b: u32| {
            g.quads
                .iter()
                .filter(|q| {
                    (0..4).any(|k| {
                        (q[k], q[(k + 1) % 4]) == (a, b) || (q[k], q[(k + 1) % 4]) == (b, a)
                    })
                })
                .count()
        };
        let n = g.inner.len();
        for k in 0..n {
            assert_eq!(edge_quads(g.inner[k], g.inner[(k + 1) % n]), 1);
        }
    }
}
