//! An annulus (a face between two smooth closed loops: a washer's flat side,
//! a bearing race's face, a flange face around its bore) as a ring grid of
//! `n` sectors × `m` rows in which every face-interior vertex is regular
//! (ours, a pattern of §6.1.2 for a face with two loops). The unstructured
//! mesher instead puts pairs of valence-3 and valence-5 vertices between
//! the loops wherever their counts differ, and the curve plan gives both
//! loops the same count for this grid (`curves::curve_chords`: one chord
//! for two closed curves, equal totals for a closed curve facing arcs).
//!
//! The rows are spaced geometrically, in the ratio of the loops' lengths,
//! so a circular annulus gets the log-polar grid, whose cells are square:
//! `m = n · w / L̄`, with `w` the mean distance between the matched nodes of
//! the two loops and `L̄ = (L_o − L_i) / ln(L_o / L_i)` the logarithmic mean
//! of the loops' lengths (for circles of radii r < R: `m = n ln(R / r) / 2π`).

use geometry::vec3::{self, Vec3};
use geometry::{FaceId, Model};

use crate::core::patch::QuadPatch;
use crate::curves::curve_chords::{annulus_loops, ring_junction};
use crate::curves::curve_mesh::CurveMesh;
use crate::direct::pattern_face::{loop_ring, ring_step, two_loop_patch, uv_area, Ring};

/// Name of the pattern of [`mesh_ring_face`].
pub const RING_GRID: &str = "ring";

/// Length of a closed polyline.
fn closed_length(pos: &[Vec3]) -> f64 {
    let n = pos.len();
    (0..n)
        .map(|k| vec3::norm(vec3::sub(pos[(k + 1) % n], pos[k])))
        .sum()
}

/// Rows of the ring grid for `n` sectors between loops of lengths `inner`
/// and `outer` whose matched nodes lie `width` apart on average: square
/// cells on average (see the module documentation), at least one row.
pub fn ring_rows(n: usize, inner: f64, outer: f64, width: f64) -> usize {
    let ratio = outer / inner;
    let mean = if (ratio - 1.0).abs() < 1e-9 {
        outer
    } else {
        (outer - inner) / ratio.ln()
    };
    ((n as f64 * width / mean).round() as usize).max(1)
}

/// Fraction of the way from the inner loop to the outer one of row `j` of
/// `m`, for loops whose lengths are in the ratio `ratio` (outer / inner):
/// geometric, so that rows grow with the sectors' width.
pub fn row_fraction(j: usize, m: usize, ratio: f64) -> f64 {
    let s = j as f64 / m as f64;
    if (ratio - 1.0).abs() < 1e-9 {
        s
    } else {
        (ratio.powf(s) - 1.0) / (ratio - 1.0)
    }
}

/// Meshes an annulus ([`annulus_loops`]) as a ring grid; an error says why the
/// face does not fit (loops of different counts, a corner, a pole, a quad
/// below [`crate::direct::pattern_face::MIN_PATTERN_SICN`] after smoothing).
pub fn mesh_ring_face(model: &Model, fid: FaceId, cms: &[CurveMesh]) -> Result<QuadPatch, String> {
    let face = &model.faces[fid.idx()];
    if annulus_loops(model, face).is_none() {
        return Err("not two smooth loops on a non-periodic surface".into());
    }
    let rings = [
        loop_ring(model, fid, cms, 0)?,
        loop_ring(model, fid, cms, 1)?,
    ];
    for r in &rings {
        if r.nodes.iter().any(|n| n.pole.is_some()) {
            return Err("a pole on a loop".into());
        }
        if let Some(&(_, a)) = r.corners.iter().find(|c| !ring_junction(c.1)) {
            return Err(format!("a corner of {:.0}° on a loop", a.to_degrees()));
        }
    }
    let n = rings[0].nodes.len();
    if rings[1].nodes.len() != n || n < 6 {
        return Err(format!(
            "loops of {} and {} edges",
            rings[0].nodes.len(),
            rings[1].nodes.len()
        ));
    }
    // the outer loop encloses the larger (u, v) area
    let areas = [uv_area(&rings[0]), uv_area(&rings[1])];
    let (o, h) = if areas[0].abs() >= areas[1].abs() {
        (0, 1)
    } else {
        (1, 0)
    };
    let (outer, hole): (&Ring, &Ring) = (&rings[o], &rings[h]);
    // the hole's node facing outer node k, in the outer loop's sense of
    // rotation, with the offset that puts matched nodes nearest each other
    let same_sense = (areas[o] > 0.0) == (areas[h] > 0.0);
    let hole_at = |r: usize, k: usize| ring_step(r, k, n, same_sense);
    let dist2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let cost = |r: usize| -> f64 {
        (0..n)
            .map(|k| dist2(outer.nodes[k].uv, hole.nodes[hole_at(r, k)].uv))
            .sum()
    };
    let rotation = (0..n)
        .map(|r| (r, cost(r)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(0, |(r, _)| r);
    let (l_out, l_in) = (closed_length(&outer.pos), closed_length(&hole.pos));
    let width = (0..n)
        .map(|k| vec3::norm(vec3::sub(outer.pos[k], hole.pos[hole_at(rotation, k)])))
        .sum::<f64>()
        / n as f64;
    if !(l_out > 0.0 && l_in > 0.0 && width > 0.0) {
        return Err("a loop or the ring of zero size".into());
    }
    let m = ring_rows(n, l_in, l_out, width);
    let ratio = l_out / l_in;
    // grid vertex (row j, sector k): row 0 on the hole, row m on the outer
    // loop; local ids: the outer ring, the hole's ring, then the inside
    let vid = |j: usize, k: usize| j * n + k % n;
    let nv = (m + 1) * n;
    let mut local = vec![u32::MAX; nv];
    let mut fixed = vec![false; nv];
    let mut uv = vec![[0.0; 2]; nv];
    for k in 0..n {
        let (a, b) = (hole.nodes[hole_at(rotation, k)].uv, outer.nodes[k].uv);
        for j in 0..=m {
            let t = row_fraction(j, m, ratio);
            uv[vid(j, k)] = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        }
        local[vid(m, k)] = k as u32;
        fixed[vid(m, k)] = true;
        local[vid(0, k)] = (n + hole_at(rotation, k)) as u32;
        fixed[vid(0, k)] = true;
    }
    let grid: Vec<[u32; 4]> = (0..m)
        .flat_map(|j| {
            (0..n).map(move |k| {
                [vid(j, k), vid(j, k + 1), vid(j + 1, k + 1), vid(j + 1, k)].map(|v| v as u32)
            })
        })
        .collect();
    two_loop_patch(face, outer, hole, &uv, &fixed, &mut local, &grid, RING_GRID, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles_get_the_log_polar_row_count() {
        // radii 1 and 2, 64 sectors: m = 64 ln 2 / 2π = 7.06
        let tau = std::f64::consts::TAU;
        assert_eq!(ring_rows(64, tau, 2.0 * tau, 1.0), 7);
        // equal lengths (a straight band closed on itself): width / cell
        assert_eq!(ring_rows(40, 10.0, 10.0, 1.0), 4);
        // a ring far thinner than a cell still gets a row
        assert_eq!(ring_rows(8, 10.0, 10.1, 0.01), 1);
    }

    #[test]
    fn rows_grow_geometrically_from_the_hole() {
        // ratio 2, 4 rows: radii 1, 2^(1/4), 2^(1/2), ... → fractions r − 1
        for j in 0..=4 {
            let want = 2f64.powf(j as f64 / 4.0) - 1.0;
            assert!((row_fraction(j, 4, 2.0) - want).abs() < 1e-12, "row {j}");
        }
        assert_eq!(row_fraction(3, 6, 1.0), 0.5);
        // each row's width over its inner radius is the same: square cells
        let r = |j: usize| 1.0 + row_fraction(j, 8, 3.0) * 2.0;
        let growth: Vec<f64> = (0..8).map(|j| (r(j + 1) - r(j)) / r(j)).collect();
        assert!(growth.iter().all(|g| (g - growth[0]).abs() < 1e-12));
    }
}
