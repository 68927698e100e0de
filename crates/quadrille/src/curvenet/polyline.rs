//! Closed-polyline helpers for the curve-cycle stages (spec §1–§2): small
//! vector arithmetic on `[f64; 3]`, arc length, resampling, chords, the
//! diameter, turning angles, and the small symmetric eigen-solver the plane
//! and affine fits need.

/// A point or vector in 3D.
pub type P3 = [f64; 3];

pub use geometry::vec3::{add, cross, dist, dot, lerp, norm, normalize as normalized, scale, sub};

/// The unsigned angle between two vectors in `[0, π]` (0 when one is zero).
pub fn angle(a: P3, b: P3) -> f64 {
    norm(cross(a, b)).atan2(dot(a, b))
}


/// The distance from `p` to the straight segment `a`–`b`.
pub use geometry::vec3::segment_distance as point_segment_distance;

/// The edges of `edges` that the closed polyline `points` runs along: from
/// a point equal to `e[0]` straight to the next point equal to `e[1]`, every
/// point between on the segment (within 1e-9 of its length). A straight
/// cut or connector densified by the pairing is still found in the parts
/// made from it.
pub fn edges_along(points: &[P3], edges: &[[P3; 2]]) -> Vec<[P3; 2]> {
    let n = points.len();
    edges
        .iter()
        .filter(|e| {
            let tol = 1e-9 * dist(e[0], e[1]);
            (0..n).filter(|&i| points[i] == e[0]).any(|i| {
                (1..n).position(|t| points[(i + t) % n] == e[1]).is_some_and(|k| {
                    (1..=k).all(|t| point_segment_distance(points[(i + t) % n], e[0], e[1]) <= tol)
                })
            })
        })
        .copied()
        .collect()
}

/// The distance from `p` to an open polyline.
pub fn point_polyline_distance(p: P3, line: &[P3]) -> f64 {
    match line {
        [] => f64::INFINITY,
        [q] => dist(p, *q),
        _ => line
            .windows(2)
            .map(|w| point_segment_distance(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min),
    }
}

/// The arc length of an open polyline.
pub fn open_length(line: &[P3]) -> f64 {
    line.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// The arc length of a closed polyline (last point back to the first).
pub fn closed_length(points: &[P3]) -> f64 {
    let n = points.len();
    (0..n).map(|i| dist(points[i], points[(i + 1) % n])).sum()
}

/// `n ≥ 2` points spaced evenly by arc length along an open polyline, its
/// two ends included. A zero-length line gives `n` copies of its first point.
pub fn resample_open(line: &[P3], n: usize) -> Vec<P3> {
    let total = open_length(line);
    if line.len() < 2 || total <= 0.0 || n < 2 {
        return vec![line.first().copied().unwrap_or([0.0; 3]); n.max(1)];
    }
    let mut out = Vec::with_capacity(n);
    let mut edge = 0;
    let mut walked = 0.0;
    for k in 0..n {
        let target = total * k as f64 / (n - 1) as f64;
        while edge + 2 < line.len() && walked + dist(line[edge], line[edge + 1]) < target {
            walked += dist(line[edge], line[edge + 1]);
            edge += 1;
        }
        let l = dist(line[edge], line[edge + 1]);
        let s = if l > 0.0 { ((target - walked) / l).clamp(0.0, 1.0) } else { 0.0 };
        out.push(lerp(line[edge], line[edge + 1], s));
    }
    out
}

/// The largest distance between two of the points (the cycle diameter D).
pub fn diameter(points: &[P3]) -> f64 {
    let mut d: f64 = 0.0;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            d = d.max(dist(*a, *b));
        }
    }
    d
}

/// The Newell normal of a closed polyline: its length is twice the area of
/// the (projected) loop, its direction the side it runs counter-clockwise
/// about ([`super::check::newell`], doubled).
pub fn newell_normal(points: &[P3]) -> P3 {
    scale(super::check::newell(points), 2.0)
}

/// The turning angle at sample `i` of a closed polyline, measured over `w`
/// samples each way: the angle between `p[i] − p[i−w]` and `p[i+w] − p[i]`.
pub fn turning_angle(points: &[P3], i: usize, w: usize) -> f64 {
    let n = points.len();
    let before = points[(i + n - w % n) % n];
    let after = points[(i + w) % n];
    angle(sub(points[i], before), sub(after, points[i]))
}

/// A closed polyline with extra points on every edge longer than `spacing`
/// (each edge cut evenly). Returns the points and, per input point, its new
/// index.
pub fn densify_closed(points: &[P3], spacing: f64) -> (Vec<P3>, Vec<usize>) {
    let n = points.len();
    let mut out = Vec::with_capacity(n);
    let mut index_of = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        index_of.push(out.len());
        out.push(a);
        let pieces = if spacing > 0.0 { (dist(a, b) / spacing).ceil() as usize } else { 1 };
        for k in 1..pieces.max(1) {
            out.push(lerp(a, b, k as f64 / pieces as f64));
        }
    }
    (out, index_of)
}

/// The indices of a closed polyline from `from` to `to` inclusive, walking
/// forward (wrapping past the end); `from == to` walks the whole loop.
pub fn cyclic_range(n: usize, from: usize, to: usize) -> Vec<usize> {
    let steps = if to > from { to - from } else { to + n - from };
    (0..=steps).map(|k| (from + k) % n).collect()
}

/// The points of the sub-polyline from `from` to `to` (see [`cyclic_range`]).
pub fn sub_polyline(points: &[P3], from: usize, to: usize) -> Vec<P3> {
    cyclic_range(points.len(), from, to).into_iter().map(|i| points[i]).collect()
}

/// The interior index of the sub-polyline `from..to` whose arc length from
/// `from` is closest to `fraction` of the whole; `None` when the piece has no
/// interior point (the split point of a segment, spec §4).
pub fn split_index(points: &[P3], from: usize, to: usize, fraction: f64) -> Option<usize> {
    let idx = cyclic_range(points.len(), from, to);
    if idx.len() < 3 {
        return None;
    }
    let mut arc = vec![0.0; idx.len()];
    for k in 1..idx.len() {
        arc[k] = arc[k - 1] + dist(points[idx[k - 1]], points[idx[k]]);
    }
    let target = fraction.clamp(0.0, 1.0) * arc[idx.len() - 1];
    (1..idx.len() - 1)
        .min_by(|&a, &b| (arc[a] - target).abs().total_cmp(&(arc[b] - target).abs()))
        .map(|k| idx[k])
}

/// Eigen-decomposition of a small symmetric matrix by cyclic Jacobi sweeps:
/// the eigenvalues ascending and the matching unit eigenvectors (columns given
/// as rows of the second result). Used for best-fit planes (3×3) and the
/// affine fit's pseudo-inverse.
pub fn symmetric_eigen<const N: usize>(m: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
    let mut a = m;
    let mut v = [[0.0; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _sweep in 0..60 {
        let off: f64 = (0..N).flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j))).map(|(i, j)| a[i][j] * a[i][j]).sum();
        let diag: f64 = (0..N).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag.max(1e-300) {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (rp, rq) = (a[p], a[q]);
                a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
                a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let mut order: Vec<usize> = (0..N).collect();
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let mut vals = [0.0; N];
    let mut vecs = [[0.0; N]; N];
    for (k, &i) in order.iter().enumerate() {
        vals[k] = a[i][i];
        for r in 0..N {
            vecs[k][r] = v[r][i];
        }
    }
    (vals, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resample_and_lengths_of_a_square() {
        let sq = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        assert!((closed_length(&sq) - 4.0).abs() < 1e-12);
        assert!((diameter(&sq) - 2f64.sqrt()).abs() < 1e-12);
        let r = resample_open(&sq, 4);
        assert!(dist(r[1], [1.0, 0.0, 0.0]) < 1e-12 && dist(r[2], [1.0, 1.0, 0.0]) < 1e-12);
        assert!((newell_normal(&sq)[2] - 2.0).abs() < 1e-12);
        assert!((turning_angle(&sq, 1, 1) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let (d, idx) = densify_closed(&sq, 0.25);
        assert_eq!((d.len(), idx), (16, vec![0, 4, 8, 12]));
        assert_eq!(split_index(&d, 12, 4, 0.5), Some(0));
    }

    #[test]
    fn jacobi_finds_the_eigenpairs() {
        let (vals, vecs) = symmetric_eigen([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        assert!((vals[0] - 1.0).abs() < 1e-12 && (vals[1] - 3.0).abs() < 1e-12 && (vals[2] - 5.0).abs() < 1e-12);
        assert!((vecs[0][0] + vecs[0][1]).abs() < 1e-12 && vecs[0][2].abs() < 1e-12);
    }

    /// A connector densified into a run of points is still found; an
    /// edge between two points whose run bends, or runs the other way, is not.
    #[test]
    fn a_densified_connector_is_found_along_the_polyline() {
        // a square whose right side (the connector, (2,0) → (2,2)) is densified
        let points = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 0.5, 0.0], [2.0, 1.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
        let connector = [[2.0, 0.0, 0.0], [2.0, 2.0, 0.0]];
        let backwards = [[2.0, 2.0, 0.0], [2.0, 0.0, 0.0]];
        let bent = [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let single = [[0.0, 2.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(edges_along(&points, &[connector, backwards, bent, single]), vec![connector, single]);
        // a point off the straight edge inside the run
        let mut off = points.clone();
        off[2] = [2.1, 0.5, 0.0];
        assert!(edges_along(&off, &[connector]).is_empty());
    }
}
