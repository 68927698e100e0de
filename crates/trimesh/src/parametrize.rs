//! Parametrization of a disk-shaped patch: a Tutte embedding (Floater) with
//! positive weights and a convex boundary, solved with a sparse Cholesky
//! factorization (`faer`).
//!
//! - Boundary: a rectangle when the boundary loop has exactly four corners
//!   and no interior edge joins two boundary vertices of the same side (each
//!   side by arc length, width and height the mean lengths of opposite
//!   sides: a cylinder side or a box face keeps its proportions); otherwise
//!   a circle of the loop's perimeter, by arc length. Both are convex, and
//!   no triangle has three vertices on one straight side, so by Tutte's
//!   theorem the map is one-to-one: no flipped triangle.
//! - Weights: cotangent weights clamped below at [`MIN_WEIGHT`] (symmetric,
//!   positive: near-conformal on good meshes, still a valid embedding on bad
//!   ones). When rounding leaves a triangle with non-positive area, the map
//!   is recomputed with uniform weights.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use geometry::{vec3, Vec3};

/// Lower bound on the cotangent weights (relative to 1).
pub const MIN_WEIGHT: f64 = 1e-2;

/// The boundary shape a patch was mapped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A circle by arc length.
    Circle,
    /// A rectangle of this width and height (four-cornered loops).
    Rectangle(f64, f64),
    /// Orthogonal projection onto the plane of the mean normal (a patch whose
    /// triangles all face that normal: flat faces, faces with holes).
    Plane,
    /// Free boundary, least-squares conformal ([`lscm`]).
    Free,
}

/// Smallest cosine between a triangle normal and the mean normal for which
/// a patch is parametrized by projection onto the mean plane (about 72°).
pub const PROJECT_MIN_COS: f64 = 0.3;

/// Projection of the patch onto the plane of its area-weighted mean normal,
/// when every triangle's normal is within acos([`PROJECT_MIN_COS`]) of it
/// (then no projected triangle is flipped); `None` otherwise.
pub fn project_plane(xyz: &[Vec3], tris: &[[u32; 3]]) -> Option<DiskMap> {
    let mut n = [0.0; 3];
    let normals: Vec<Vec3> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| xyz[v as usize]);
            let m = vec3::cross(vec3::sub(b, a), vec3::sub(c, a));
            n = vec3::add(n, m);
            m
        })
        .collect();
    let n = vec3::normalize(n)?;
    for m in &normals {
        if vec3::dot(*m, n) < PROJECT_MIN_COS * vec3::norm(*m) {
            return None;
        }
    }
    // an orthonormal basis (e1, e2, n), right-handed so that uv areas are positive
    let helper = if n[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = vec3::normalize(vec3::cross(helper, n))?;
    let e2 = vec3::cross(n, e1);
    let uv: Vec<[f64; 2]> = xyz
        .iter()
        .map(|p| [vec3::dot(*p, e1), vec3::dot(*p, e2)])
        .collect();
    let min_area = tris
        .iter()
        .map(|t| area(uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]))
        .fold(f64::INFINITY, f64::min);
    (min_area > 0.0).then_some(DiskMap {
        uv,
        min_area,
        shape: Shape::Plane,
    })
}

/// The (u, v) of every vertex of a disk and the smallest signed triangle area.
#[derive(Clone, Debug)]
pub struct DiskMap {
    /// (u, v) per vertex.
    pub uv: Vec<[f64; 2]>,
    /// Smallest signed (u, v) area over the triangles (positive: no flip).
    pub min_area: f64,
    /// The boundary shape.
    pub shape: Shape,
}

/// Least-squares conformal map of the disk `tris` on `xyz` (Lévy et al.
/// 2002): the (u, v) that make every triangle's map as close to a
/// similarity as possible, with two boundary vertices far apart pinned
/// (`boundary`: the disk's boundary loop). The boundary is free, so a curved
/// chart keeps its shape instead of being pressed onto a circle as by
/// [`tutte`]. `None` when the system cannot be solved or a triangle flips
/// (the caller also checks that the boundary stays simple).
pub fn lscm(xyz: &[Vec3], tris: &[[u32; 3]], boundary: &[u32]) -> Option<DiskMap> {
    let n = xyz.len();
    if boundary.len() < 3 || tris.is_empty() {
        return None;
    }
    // pins: the first boundary vertex and the boundary vertex farthest from it
    let a = boundary[0] as usize;
    let b = boundary
        .iter()
        .map(|&v| v as usize)
        .max_by(|&x, &y| vec3::dist(xyz[a], xyz[x]).total_cmp(&vec3::dist(xyz[a], xyz[y])))?;
    let d = vec3::dist(xyz[a], xyz[b]);
    if !(d > 0.0) {
        return None;
    }
    // unknowns: (u, v) of every vertex but the pins, at 2 i and 2 i + 1
    let mut idx = vec![usize::MAX; n];
    let mut m = 0;
    for (v, slot) in idx.iter_mut().enumerate() {
        if v != a && v != b {
            *slot = m;
            m += 1;
        }
    }
    let pinned = |v: usize| {
        if v == a {
            Some([0.0, 0.0])
        } else if v == b {
            Some([d, 0.0])
        } else {
            None
        }
    };
    // normal equations of the two real rows of each triangle
    let mut normal: std::collections::BTreeMap<(usize, usize), f64> =
        std::collections::BTreeMap::new();
    let mut rhs = Mat::<f64>::zeros(2 * m, 1);
    for t in tris {
        let [p0, p1, p2] = t.map(|v| xyz[v as usize]);
        let e = vec3::sub(p1, p0);
        let l = vec3::norm(e);
        let nrm = vec3::cross(e, vec3::sub(p2, p0));
        let area2 = vec3::norm(nrm);
        if !(l > 0.0 && area2 > 0.0) {
            continue;
        }
        let e1 = vec3::scale(e, 1.0 / l);
        let e2 = vec3::cross(vec3::scale(nrm, 1.0 / area2), e1);
        let q = [
            [0.0, 0.0],
            [l, 0.0],
            [
                vec3::dot(vec3::sub(p2, p0), e1),
                vec3::dot(vec3::sub(p2, p0), e2),
            ],
        ];
        let s = 1.0 / area2.sqrt();
        // W_j = x_{j+2} - x_{j+1} (as a complex number), scaled
        let w: Vec<(usize, f64, f64)> = (0..3)
            .map(|j| {
                let (k, l2) = ((j + 2) % 3, (j + 1) % 3);
                (
                    t[j] as usize,
                    s * (q[k][0] - q[l2][0]),
                    s * (q[k][1] - q[l2][1]),
                )
            })
            .collect();
        // real row: Σ wr u − wi v; imaginary row: Σ wi u + wr v
        for row in 0..2 {
            let coef: Vec<(usize, usize, f64)> = w
                .iter()
                .flat_map(|&(v, wr, wi)| {
                    if row == 0 {
                        [(v, 0, wr), (v, 1, -wi)]
                    } else {
                        [(v, 0, wi), (v, 1, wr)]
                    }
                })
                .collect();
            let mut fixed = 0.0;
            for &(v, c, x) in &coef {
                if let Some(p) = pinned(v) {
                    fixed += x * p[c];
                }
            }
            for &(v, c, x) in &coef {
                if idx[v] == usize::MAX {
                    continue;
                }
                let i = 2 * idx[v] + c;
                rhs[(i, 0)] -= x * fixed;
                for &(w2, c2, y) in &coef {
                    if idx[w2] == usize::MAX {
                        continue;
                    }
                    let j = 2 * idx[w2] + c2;
                    if j <= i {
                        *normal.entry((i, j)).or_insert(0.0) += x * y;
                    }
                }
            }
        }
    }
    let trip: Vec<Triplet<usize, usize, f64>> = normal
        .into_iter()
        .map(|((i, j), x)| Triplet::new(i, j, x))
        .collect();
    let mat = SparseColMat::<usize, f64>::try_new_from_triplets(2 * m, 2 * m, &trip).ok()?;
    let llt = mat.sp_cholesky(Side::Lower).ok()?;
    let x = llt.solve(&rhs);
    let mut uv: Vec<[f64; 2]> = (0..n)
        .map(|v| pinned(v).unwrap_or_else(|| [x[(2 * idx[v], 0)], x[(2 * idx[v] + 1, 0)]]))
        .collect();
    if !uv.iter().all(|p| p[0].is_finite() && p[1].is_finite()) {
        return None;
    }
    // a reflection is as conformal as the map: keep the one with the disk's orientation
    let total: f64 = tris
        .iter()
        .map(|t| area(uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]))
        .sum();
    if total < 0.0 {
        for p in &mut uv {
            p[1] = -p[1];
        }
    }
    let min_area = tris
        .iter()
        .map(|t| area(uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]))
        .fold(f64::INFINITY, f64::min);
    (min_area > 0.0).then_some(DiskMap {
        uv,
        min_area,
        shape: Shape::Free,
    })
}

/// Signed area of a (u, v) triangle.
pub fn area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Maps the disk (`tris` on `xyz`, boundary loop `boundary` in order with
/// the interior on its left, `corner_at` the positions in `boundary` of the
/// corners) into the plane.
pub fn tutte(
    xyz: &[Vec3],
    tris: &[[u32; 3]],
    boundary: &[u32],
    corner_at: &[usize],
) -> Result<DiskMap, String> {
    let n = xyz.len();
    let nb = boundary.len();
    if nb < 3 {
        return Err(format!("boundary loop of {nb} vertices"));
    }
    let mut on_b = vec![u32::MAX; n];
    for (i, &v) in boundary.iter().enumerate() {
        on_b[v as usize] = i as u32;
    }
    // arc length along the loop
    let mut s = vec![0.0; nb + 1];
    for i in 0..nb {
        s[i + 1] = s[i]
            + vec3::dist(
                xyz[boundary[i] as usize],
                xyz[boundary[(i + 1) % nb] as usize],
            );
    }
    let perim = s[nb];
    if !(perim > 0.0) {
        return Err("boundary loop of zero length".into());
    }
    let mut uv = vec![[0.0; 2]; n];
    let mut shape = Shape::Circle;
    if corner_at.len() == 4 {
        // sides: side k runs from corner_at[k] to corner_at[k+1]
        let mut side_of = vec![[u8::MAX; 2]; n];
        for k in 0..4 {
            let (i0, i1) = (corner_at[k], corner_at[(k + 1) % 4]);
            let mut i = i0;
            loop {
                let v = boundary[i] as usize;
                if side_of[v][0] == u8::MAX {
                    side_of[v][0] = k as u8;
                } else {
                    side_of[v][1] = k as u8;
                }
                if i == i1 {
                    break;
                }
                i = (i + 1) % nb;
            }
        }
        let shares = |a: usize, b: usize| {
            side_of[a]
                .iter()
                .any(|&x| x != u8::MAX && side_of[b].contains(&x))
        };
        let mut chord = false;
        'outer: for t in tris {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if on_b[a] != u32::MAX && on_b[b] != u32::MAX {
                    let (ia, ib) = (on_b[a] as usize, on_b[b] as usize);
                    let adjacent = (ia + 1) % nb == ib || (ib + 1) % nb == ia;
                    if !adjacent && shares(a, b) {
                        chord = true;
                        break 'outer;
                    }
                }
            }
            // three boundary vertices on one side
            if t.iter().all(|&v| on_b[v as usize] != u32::MAX)
                && (0..4u8).any(|k| t.iter().all(|&v| side_of[v as usize].contains(&k)))
            {
                chord = true;
                break;
            }
        }
        if !chord {
            let len = |k: usize| {
                let (i0, i1) = (corner_at[k], corner_at[(k + 1) % 4]);
                if i1 > i0 {
                    s[i1] - s[i0]
                } else {
                    perim - s[i0] + s[i1]
                }
            };
            let (w, h) = (0.5 * (len(0) + len(2)), 0.5 * (len(1) + len(3)));
            if w > 0.0 && h > 0.0 {
                let corners = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
                for k in 0..4 {
                    let (i0, i1) = (corner_at[k], corner_at[(k + 1) % 4]);
                    let l = len(k);
                    let (p, q) = (corners[k], corners[(k + 1) % 4]);
                    let mut i = i0;
                    let mut acc = 0.0;
                    while i != i1 {
                        let f = if l > 0.0 { acc / l } else { 0.0 };
                        uv[boundary[i] as usize] =
                            [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])];
                        acc += s[i + 1] - s[i];
                        i = (i + 1) % nb;
                    }
                }
                shape = Shape::Rectangle(w, h);
            }
        }
    }
    if shape == Shape::Circle {
        let r = perim / std::f64::consts::TAU;
        let off = corner_at.first().copied().unwrap_or(0);
        for i in 0..nb {
            let a = (s[i] - s[off]) / perim * std::f64::consts::TAU;
            uv[boundary[i] as usize] = [r * a.cos(), r * a.sin()];
        }
    }
    // interior unknowns
    let mut idx = vec![u32::MAX; n];
    let mut ni = 0u32;
    for v in 0..n {
        if on_b[v] == u32::MAX {
            idx[v] = ni;
            ni += 1;
        }
    }
    let solve = |cot: bool, uv: &mut Vec<[f64; 2]>| -> Result<(), String> {
        if ni == 0 {
            return Ok(());
        }
        let mut trip: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(7 * ni as usize);
        let mut diag = vec![0.0; ni as usize];
        let mut rhs = Mat::<f64>::zeros(ni as usize, 2);
        for t in tris {
            for k in 0..3 {
                let (a, b, c) = (
                    t[k] as usize,
                    t[(k + 1) % 3] as usize,
                    t[(k + 2) % 3] as usize,
                );
                // half the cotangent of the angle at c, opposite edge ab
                let w = if cot {
                    let (u, v) = (vec3::sub(xyz[a], xyz[c]), vec3::sub(xyz[b], xyz[c]));
                    let sn = vec3::norm(vec3::cross(u, v));
                    (0.5 * vec3::dot(u, v) / sn.max(1e-300)).max(0.5 * MIN_WEIGHT)
                } else {
                    0.5
                };
                for (p, q) in [(a, b), (b, a)] {
                    if idx[p] == u32::MAX {
                        continue;
                    }
                    let i = idx[p] as usize;
                    diag[i] += w;
                    if idx[q] == u32::MAX {
                        rhs[(i, 0)] += w * uv[q][0];
                        rhs[(i, 1)] += w * uv[q][1];
                    } else {
                        trip.push(Triplet::new(i, idx[q] as usize, -w));
                    }
                }
            }
        }
        for (i, d) in diag.iter().enumerate() {
            trip.push(Triplet::new(i, i, *d));
        }
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(ni as usize, ni as usize, &trip)
            .map_err(|e| format!("sparse matrix: {e:?}"))?;
        let llt = m
            .sp_cholesky(Side::Lower)
            .map_err(|e| format!("Cholesky factorization failed: {e:?}"))?;
        let x = llt.solve(&rhs);
        for v in 0..n {
            if idx[v] != u32::MAX {
                uv[v] = [x[(idx[v] as usize, 0)], x[(idx[v] as usize, 1)]];
            }
        }
        Ok(())
    };
    let min_area = |uv: &[[f64; 2]]| {
        tris.iter()
            .map(|t| area(uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]))
            .fold(f64::INFINITY, f64::min)
    };
    solve(true, &mut uv)?;
    let mut m = min_area(&uv);
    if !(m > 0.0) {
        solve(false, &mut uv)?;
        m = min_area(&uv);
    }
    if !(m > 0.0) {
        return Err(format!(
            "the Tutte map has a flipped or flat triangle (min signed area {m:.3e})"
        ));
    }
    Ok(DiskMap {
        uv,
        min_area: m,
        shape,
    })
}

/// True when the (u, v) images of the boundary loops (each a cycle of
/// vertex indices into `uv`) are simple and do not cross each other. A
/// projection without flipped triangles is one-to-one exactly when this
/// holds; a patch that bends back over itself (a U-shaped band) projects
/// without flips yet overlaps, and its boundary then crosses itself.
pub fn loops_are_simple(uv: &[[f64; 2]], loops: &[Vec<u32>]) -> bool {
    // segments (a, b) with their loop position, swept in order of min u
    let mut segs: Vec<([f64; 2], [f64; 2], [u32; 2])> = Vec::new();
    for lp in loops {
        let n = lp.len();
        for i in 0..n {
            let (a, b) = (lp[i], lp[(i + 1) % n]);
            segs.push((uv[a as usize], uv[b as usize], [a, b]));
        }
    }
    segs.sort_by(|x, y| x.0[0].min(x.1[0]).total_cmp(&y.0[0].min(y.1[0])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    for i in 0..segs.len() {
        let (a, b, ab) = segs[i];
        let amax = a[0].max(b[0]);
        for &(c, d, cd) in &segs[i + 1..] {
            if c[0].min(d[0]) > amax {
                break;
            }
            if ab.iter().any(|v| cd.contains(v)) {
                continue; // segments sharing an end (neighbours, loops meeting at a corner)
            }
            let (d1, d2) = (cross(a, b, c), cross(a, b, d));
            let (d3, d4) = (cross(c, d, a), cross(c, d, b));
            if d1 * d2 <= 0.0
                && d3 * d4 <= 0.0
                && (d1 != 0.0 || d2 != 0.0 || d3 != 0.0 || d4 != 0.0)
            {
                return false;
            }
            if d1 == 0.0 && d2 == 0.0 {
                // collinear: overlapping extents (along the line's main axis) cross
                let k = usize::from((b[1] - a[1]).abs() > (b[0] - a[0]).abs());
                let (lo1, hi1) = (a[k].min(b[k]), a[k].max(b[k]));
                let (lo2, hi2) = (c[k].min(d[k]), c[k].max(d[k]));
                if lo1 <= hi2 && lo2 <= hi1 {
                    return false;
                }
            }
        }
    }
    true
}

/// How unevenly a map scales lengths: the ratio of the 95th to the 5th
/// percentile (by 3D area) of the per-triangle length scale
/// sqrt(3D area / uv area). 1 for an isometry, up to a few for a cylinder
/// or sphere cap on its rectangle or circle; a disk with many holes cut
/// open and pressed onto a circle reaches hundreds: the mesher's uv
/// triangulation then cannot follow the 3D size and its quads fold.
pub fn scale_spread(xyz: &[Vec3], tris: &[[u32; 3]], uv: &[[f64; 2]]) -> f64 {
    let mut s: Vec<(f64, f64)> = tris
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|v| xyz[v as usize]);
            let a3 = 0.5 * vec3::norm(vec3::cross(vec3::sub(b, a), vec3::sub(c, a)));
            let a2 = area(uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]);
            (a3 > 0.0 && a2 > 0.0).then(|| ((a3 / a2).sqrt(), a3))
        })
        .collect();
    if s.is_empty() {
        return f64::INFINITY;
    }
    s.sort_by(|x, y| x.0.total_cmp(&y.0));
    let total: f64 = s.iter().map(|x| x.1).sum();
    let at = |q: f64| {
        let mut acc = 0.0;
        for x in &s {
            acc += x.1;
            if acc >= q * total {
                return x.0;
            }
        }
        s[s.len() - 1].0
    };
    at(0.95) / at(0.05)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangulated square grid (k × k cells), its boundary counter-clockwise.
    fn grid(k: usize) -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<u32>) {
        let id = |i: usize, j: usize| (j * (k + 1) + i) as u32;
        let mut p = Vec::new();
        for j in 0..=k {
            for i in 0..=k {
                p.push([i as f64, j as f64, ((i * j) as f64 * 0.3).sin()]);
            }
        }
        let mut t = Vec::new();
        for j in 0..k {
            for i in 0..k {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mut b = Vec::new();
        for i in 0..k {
            b.push(id(i, 0));
        }
        for j in 0..k {
            b.push(id(k, j));
        }
        for i in (1..=k).rev() {
            b.push(id(i, k));
        }
        for j in (1..=k).rev() {
            b.push(id(0, j));
        }
        (p, t, b)
    }

    #[test]
    fn lscm_unrolls_a_developable_strip_without_distortion() {
        // a half cylinder of radius 1 (k × k cells), rolled from a 3 × π/1 strip
        let k = 12;
        let (flat, t, b) = grid(k);
        let rolled: Vec<Vec3> = flat
            .iter()
            .map(|p| {
                let a = p[0] / k as f64 * std::f64::consts::PI;
                [a.cos(), a.sin(), 3.0 * p[1] / k as f64]
            })
            .collect();
        let m = lscm(&rolled, &t, &b).expect("a developable disk maps");
        assert!(m.min_area > 0.0);
        let spread = scale_spread(&rolled, &t, &m.uv);
        assert!(spread < 1.02, "LSCM spread {spread}");
        // the circle boundary of the Tutte map spreads lengths on the same strip
        let tutte = tutte(&rolled, &t, &b, &[]).unwrap();
        assert!(scale_spread(&rolled, &t, &tutte.uv) > 1.2);
        // lengths are kept up to one scale: the strip's two long sides stay parallel and equal
        let len = |uv: &[[f64; 2]], a: u32, c: u32| {
            let (p, q) = (uv[a as usize], uv[c as usize]);
            (p[0] - q[0]).hypot(p[1] - q[1])
        };
        let id = |i: usize, j: usize| (j * (k + 1) + i) as u32;
        let r = len(&m.uv, id(0, 0), id(0, k)) / len(&m.uv, id(k, 0), id(k, k));
        assert!((r - 1.0).abs() < 1e-3, "{r}");
    }

    #[test]
    fn crossing_loops_are_found() {
        let uv = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [0.5, 0.5],
            [1.5, 0.5],
            [1.0, 1.5],
            [1.0, -1.0],
        ];
        // a square with a triangle hole inside: simple
        assert!(loops_are_simple(&uv, &[vec![0, 1, 2, 3], vec![4, 6, 5]]));
        // a hole poking out through the bottom side
        assert!(!loops_are_simple(&uv, &[vec![0, 1, 2, 3], vec![4, 6, 7]]));
        // a bow tie
        assert!(!loops_are_simple(&uv, &[vec![0, 2, 1, 3]]));
        // collinear sides apart on one line are no crossing: a U shape
        let u = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 2.0],
            [2.0, 2.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        assert!(loops_are_simple(&u, &[(0..8).collect()]));
        // and a U whose arms overlap along a line crosses
        let v = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [0.5, 1.0],
            [0.5, 2.0],
            [2.0, 2.0],
            [2.0, 1.0],
            [0.0, 1.0],
        ];
        assert!(!loops_are_simple(&v, &[(0..8).collect()]));
    }

    #[test]
    fn square_maps_to_rectangle_and_circle_without_flips() {
        let (p, t, b) = grid(12);
        let m = tutte(&p, &t, &b, &[0, 12, 24, 36]).unwrap();
        assert!(matches!(m.shape, Shape::Rectangle(..)));
        assert!(m.min_area > 0.0);
        let c = tutte(&p, &t, &b, &[0]).unwrap();
        assert_eq!(c.shape, Shape::Circle);
        assert!(c.min_area > 0.0);
        // a boundary point lies on the circle
        let r = (c.uv[b[5] as usize][0].powi(2) + c.uv[b[5] as usize][1].powi(2)).sqrt();
        let perim: f64 = (0..b.len())
            .map(|i| vec3::dist(p[b[i] as usize], p[b[(i + 1) % b.len()] as usize]))
            .sum();
        assert!((r - perim / std::f64::consts::TAU).abs() < 1e-9);
    }
}
