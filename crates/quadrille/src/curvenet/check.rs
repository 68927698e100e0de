//! Geometric checks of closed polylines: 3D segment distances found through a
//! grid of buckets (not O(n²)), Newell areas, welding of points.

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};

/// Distance from `p` to segment `[a, b]`, and the parameter of the closest
/// point (0 at `a`, 1 at `b`).
pub(crate) fn point_segment(p: Vec3, a: Vec3, b: Vec3) -> (f64, f64) {
    vec3::segment_closest(p, a, b)
}

/// Closest points of segments `[p1, q1]` and `[p2, q2]` in 3D (Ericson,
/// Real-Time Collision Detection §5.1.9): their distance and the point midway
/// between them.
pub(crate) fn segment_segment(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (f64, Vec3) {
    let d1 = vec3::sub(q1, p1);
    let d2 = vec3::sub(q2, p2);
    let r = vec3::sub(p1, p2);
    let a = vec3::dot(d1, d1);
    let e = vec3::dot(d2, d2);
    let f = vec3::dot(d2, r);
    let (s, t);
    if a <= 0.0 && e <= 0.0 {
        s = 0.0;
        t = 0.0;
    } else if a <= 0.0 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = vec3::dot(d1, r);
        if e <= 0.0 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = vec3::dot(d1, d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let c1 = vec3::add(p1, vec3::scale(d1, s));
    let c2 = vec3::add(p2, vec3::scale(d2, t));
    (vec3::dist(c1, c2), vec3::scale(vec3::add(c1, c2), 0.5))
}

/// Newell vector of a closed polyline (about its centroid): its length is the
/// area of the loop's projection on the best plane, its direction the normal
/// about which the loop runs counter-clockwise.
pub fn newell(points: &[Vec3]) -> Vec3 {
    let c = centroid(points);
    let n = points.len();
    let mut s = [0.0; 3];
    for i in 0..n {
        let a = vec3::sub(points[i], c);
        let b = vec3::sub(points[(i + 1) % n], c);
        s = vec3::add(s, vec3::cross(a, b));
    }
    vec3::scale(s, 0.5)
}

/// Mean of the points (the origin for none).
pub(crate) fn centroid(points: &[Vec3]) -> Vec3 {
    let mut c = [0.0; 3];
    for p in points {
        c = vec3::add(c, *p);
    }
    vec3::scale(c, 1.0 / points.len().max(1) as f64)
}

/// Axis-aligned bounding box; `None` for no point.
pub(crate) fn bbox<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Option<(Vec3, Vec3)> {
    let mut it = points.into_iter();
    let first = *it.next()?;
    let (mut lo, mut hi) = (first, first);
    for p in it {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    Some((lo, hi))
}

/// The bits of a point, for exact hashing of welded points.
pub(crate) fn key(p: Vec3) -> [u64; 3] {
    // +0.0 and −0.0 are the same point
    p.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// Welds points within `tol`: returns for each input point its representative,
/// the first point within `tol` of it (the nearest when several are), or the
/// point itself. Representatives end pairwise at least `tol` apart, so welding
/// again with the same or a smaller tolerance changes nothing.
pub(crate) fn weld(points: &[Vec3], tol: f64) -> Vec<Vec3> {
    let Some((lo, _)) = bbox(points) else {
        return Vec::new();
    };
    let cell = |p: Vec3| -> [i64; 3] { [0, 1, 2].map(|k| ((p[k] - lo[k]) / tol).floor() as i64) };
    let mut grid: HashMap<[i64; 3], Vec<Vec3>> = HashMap::new();
    let mut out = Vec::with_capacity(points.len());
    for &p in points {
        let c = cell(p);
        let mut best: Option<(f64, Vec3)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &r in list {
                        let d = vec3::dist(p, r);
                        if d < tol && best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, r));
                        }
                    }
                }
            }
        }
        match best {
            Some((_, r)) => out.push(r),
            None => {
                grid.entry(c).or_default().push(p);
                out.push(p);
            }
        }
    }
    out
}

/// Segments bucketed in a uniform grid: each segment is cut into pieces no
/// longer than a cell, and each piece's box, grown by `tol`, is entered in the
/// cells it overlaps. Two segments closer than `tol`, or a point closer than
/// `tol` to a segment, then share a cell.
pub(crate) struct SegmentGrid {
    lo: Vec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl SegmentGrid {
    /// The grid of `segments` for distances below `tol`.
    pub(crate) fn new(segments: &[[Vec3; 2]], tol: f64) -> SegmentGrid {
        let lens: Vec<f64> = segments.iter().map(|s| vec3::dist(s[0], s[1])).collect();
        let total: f64 = lens.iter().sum();
        let mut sorted = lens.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        // a few very long segments among short ones are cut into at most
        // 8 pieces per segment on average
        let cell = median
            .max(total / (8.0 * segments.len().max(1) as f64))
            .max(4.0 * tol)
            .max(f64::MIN_POSITIVE);
        let lo = bbox(segments.iter().flatten())
            .map(|(lo, _)| lo)
            .unwrap_or([0.0; 3]);
        let mut grid = SegmentGrid {
            lo,
            cell,
            cells: HashMap::new(),
        };
        for (i, s) in segments.iter().enumerate() {
            let pieces = (lens[i] / cell).ceil().clamp(1.0, 1e6) as usize;
            for j in 0..pieces {
                let a = vec3::lerp(s[0], s[1], j as f64 / pieces as f64);
                let b = vec3::lerp(s[0], s[1], (j + 1) as f64 / pieces as f64);
                let c0 = grid.cell_of([0, 1, 2].map(|k| a[k].min(b[k]) - tol));
                let c1 = grid.cell_of([0, 1, 2].map(|k| a[k].max(b[k]) + tol));
                for x in c0[0]..=c1[0] {
                    for y in c0[1]..=c1[1] {
                        for z in c0[2]..=c1[2] {
                            let list = grid.cells.entry([x, y, z]).or_default();
                            if list.last() != Some(&(i as u32)) {
                                list.push(i as u32);
                            }
                        }
                    }
                }
            }
        }
        grid
    }

    fn cell_of(&self, p: Vec3) -> [i64; 3] {
        [0, 1, 2].map(|k| ((p[k] - self.lo[k]) / self.cell).floor() as i64)
    }

    /// The segments that may lie within `tol` of `p`.
    pub(crate) fn near(&self, p: Vec3) -> &[u32] {
        self.cells
            .get(&self.cell_of(p))
            .map(|v| v.as_slice())
            .unwrap_or(&[])
    }

    /// Every pair `(i, j)`, `i < j`, of segments sharing a cell (a pair may
    /// come more than once).
    pub(crate) fn pairs(&self, mut f: impl FnMut(usize, usize)) {
        for list in self.cells.values() {
            for (k, &i) in list.iter().enumerate() {
                for &j in &list[k + 1..] {
                    let (i, j) = (i.min(j) as usize, i.max(j) as usize);
                    if i != j {
                        f(i, j);
                    }
                }
            }
        }
    }
}

/// Where closed loops come closer than `tol` to themselves or each other: two
/// segments that are not neighbours within `tol` (3D distance), or two
/// neighbours folding back onto each other (the far end of one within `tol`
/// of the other). Returns the first such pair in loop and segment order:
/// `(loop a, loop b, distance, point)`.
pub(crate) fn self_contact(loops: &[&[Vec3]], tol: f64) -> Option<(usize, usize, f64, Vec3)> {
    let mut segs = Vec::new();
    let mut owner = Vec::new(); // (loop, index in loop)
    for (l, pts) in loops.iter().enumerate() {
        let n = pts.len();
        for i in 0..n {
            segs.push([pts[i], pts[(i + 1) % n]]);
            owner.push((l, i));
        }
    }
    let grid = SegmentGrid::new(&segs, tol);
    let mut best: Option<(usize, usize, f64, Vec3)> = None;
    grid.pairs(|i, j| {
        if best.is_some_and(|(bi, bj, _, _)| (i, j) >= (bi, bj)) {
            return;
        }
        let ((li, ii), (lj, jj)) = (owner[i], owner[j]);
        let n = loops[li].len();
        let neighbours = li == lj && ((ii + 1) % n == jj || (jj + 1) % n == ii);
        let contact = if neighbours {
            // the shared point and the far ends: folding back puts a far end
            // on the other segment
            let (a, b) = (segs[i], segs[j]);
            let (d1, _) = point_segment(a[0], b[0], b[1]);
            let (d2, _) = point_segment(a[1], b[0], b[1]);
            let (d3, _) = point_segment(b[0], a[0], a[1]);
            let (d4, _) = point_segment(b[1], a[0], a[1]);
            // the shared end is at distance 0 from the other segment; each far
            // end must stay farther than tol
            let far = if (ii + 1) % n == jj {
                // a[1] == b[0]: far ends a[0], b[1]
                d1.min(d4)
            } else {
                // b[1] == a[0]: far ends a[1], b[0]
                d2.min(d3)
            };
            (far < tol).then(|| {
                let (_, p) = segment_segment(a[0], a[1], b[0], b[1]);
                (far, p)
            })
        } else {
            let (d, p) = segment_segment(segs[i][0], segs[i][1], segs[j][0], segs[j][1]);
            (d < tol).then_some((d, p))
        };
        if let Some((d, p)) = contact {
            best = Some((i, j, d, p));
        }
    });
    best.map(|(i, j, d, p)| (owner[i].0, owner[j].0, d, p))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances() {
        let (d, p) = segment_segment([0.0; 3], [1.0, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, 1.0, 1.0]);
        assert!((d - 1.0).abs() < 1e-15);
        assert!(vec3::dist(p, [0.5, 0.0, 0.5]) < 1e-15);
        // parallel, overlapping
        let (d, _) = segment_segment([0.0; 3], [1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [2.0, 0.5, 0.0]);
        assert!((d - 0.5).abs() < 1e-15);
        // beyond the ends
        let (d, _) = segment_segment([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]);
        assert!((d - 1.0).abs() < 1e-15);
        let (d, t) = point_segment([0.5, 2.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0]);
        assert!((d - 2.0).abs() < 1e-15 && (t - 0.5).abs() < 1e-15);
    }

    #[test]
    fn welding_is_idempotent() {
        let pts = vec![
            [0.0; 3],
            [0.5e-9, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.9e-9, 0.0],
        ];
        let w = weld(&pts, 1e-9);
        assert_eq!(
            w,
            vec![[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
        );
        assert_eq!(weld(&w, 1e-9), w);
    }

    #[test]
    fn newell_area_of_a_unit_square() {
        let sq = [
            [0.0, 0.0, 2.0],
            [1.0, 0.0, 2.0],
            [1.0, 1.0, 2.0],
            [0.0, 1.0, 2.0],
        ];
        assert_eq!(newell(&sq), [0.0, 0.0, 1.0]);
    }
}
