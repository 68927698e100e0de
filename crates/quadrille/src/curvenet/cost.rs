//! Segment pairing costs (spec §2, paper §3.1.2): c = w_b·b + w_s·s + w_d·d
//! over the cycle diameter, with per-segment bridge directions t set from
//! influential neighbours and updated from dominant pairs (spec §2.4 and the
//! issue's errata: f vectors leave the shared vertex; a dominant pair's
//! average is an average of axes; the 135°–225° band means inward directions
//! within 45°).

use super::polyline::{
    add, angle, cross, dist, dot, norm, normalized, resample_open, scale,
    sub, symmetric_eigen, P3,
};
use super::PairingOptions;

/// What the costs need of one segment, all lengths divided by D.
#[derive(Clone, Debug)]
pub struct SegmentShape {
    /// `samples` points evenly spaced by arc length, ends included (scaled
    /// by 1/D).
    pub samples: Vec<P3>,
    /// Arc length over D.
    pub length: f64,
    /// Chord f: last point minus first.
    pub chord: P3,
    /// The centroid of the samples.
    pub centre: P3,
    /// n_i: perpendicular to the chord, pointing into the surface (left of
    /// travel): n_CAD × chord with the CAD normal at the segment's middle
    /// sample on a CAD face, else in the best-fit plane of the segment and
    /// its neighbours.
    pub inward: P3,
    /// The CAD normals at the segment's first and last points (a cycle on a
    /// CAD face), else `None`.
    pub end_normals: Option<[P3; 2]>,
}

/// The unit normal of a cycle's CAD surface at the closest point to a
/// point (unscaled coordinates), when the cycle has one.
pub type NormalAt<'a> = &'a dyn Fn(P3) -> Option<P3>;

/// The shapes of a cyclic list of segments (each an open polyline, the last
/// point of one the first of the next), scaled by `1 / diameter`;
/// `cycle_normal` orients the local planes, `normal_at` (a cycle on a CAD
/// face) gives the surface normals that replace them.
pub fn segment_shapes(
    segments: &[Vec<P3>],
    diameter: f64,
    cycle_normal: P3,
    n_samples: usize,
    normal_at: Option<NormalAt<'_>>,
) -> Vec<SegmentShape> {
    let k = segments.len();
    let scaled: Vec<Vec<P3>> =
        segments.iter().map(|s| s.iter().map(|p| scale(*p, 1.0 / diameter)).collect()).collect();
    let samples: Vec<Vec<P3>> = scaled.iter().map(|s| resample_open(s, n_samples)).collect();
    let n_cyc = normalized(cycle_normal).unwrap_or([0.0, 0.0, 1.0]);
    (0..k)
        .map(|i| {
            let line = &scaled[i];
            let chord = sub(*line.last().unwrap_or(&[0.0; 3]), line[0]);
            let centre = scale(samples[i].iter().fold([0.0; 3], |a, p| add(a, *p)), 1.0 / n_samples as f64);
            // Best-fit plane of i and its neighbours.
            let mut pts: Vec<P3> = samples[i].clone();
            if k > 1 {
                pts.extend_from_slice(&samples[(i + k - 1) % k]);
                pts.extend_from_slice(&samples[(i + 1) % k]);
            }
            let local = plane_normal(&pts).filter(|n| dot(*n, n_cyc).abs() > 1e-3).unwrap_or(n_cyc);
            let local = if dot(local, n_cyc) < 0.0 { scale(local, -1.0) } else { local };
            let f_hat = normalized(chord).unwrap_or([1.0, 0.0, 0.0]);
            // On a CAD face: left of travel in the tangent plane at the
            // middle sample (a 180° arc of a half-cylinder bridges along
            // the axis, not across the flat half-disk of its own plane).
            let cad = normal_at.and_then(|at| {
                let mid = scale(samples[i][n_samples / 2], diameter);
                at(mid).and_then(|n| normalized(cross(n, f_hat)))
            });
            let inward = cad
                .or_else(|| normalized(cross(local, f_hat)))
                .or_else(|| normalized(cross(n_cyc, f_hat)))
                .unwrap_or([0.0, 1.0, 0.0]);
            let end_normals = normal_at.and_then(|at| {
                let first = at(segments[i][0])?;
                let last = at(*segments[i].last()?)?;
                Some([first, last])
            });
            SegmentShape {
                samples: samples[i].clone(),
                length: super::polyline::open_length(line),
                chord,
                centre,
                inward,
                end_normals,
            }
        })
        .collect()
}

/// The normal of the best-fit plane of `pts` (smallest principal axis), or
/// `None` when the points are (nearly) collinear and the plane is undefined.
fn plane_normal(pts: &[P3]) -> Option<P3> {
    let c = scale(pts.iter().fold([0.0; 3], |a, p| add(a, *p)), 1.0 / pts.len() as f64);
    let mut m = [[0.0; 3]; 3];
    for p in pts {
        let d = sub(*p, c);
        for r in 0..3 {
            for s in 0..3 {
                m[r][s] += d[r] * d[s];
            }
        }
    }
    let (vals, vecs) = symmetric_eigen(m);
    (vals[1] > 1e-9 * vals[2].max(1e-300)).then_some(vecs[0])
}

/// The initial bridge direction of segment `i` of a cyclic list (spec §2.4):
/// the average of the flow directions of its influential neighbours (taken
/// as vectors leaving the shared vertex, flipped to the inward side), else
/// its inward normal. On a CAD face both directions are taken in the
/// tangent plane at the shared vertex, so a curve that only bends with the
/// surface (an arc of a cylinder) continues straight and does not
/// influence.
pub fn initial_direction(shapes: &[SegmentShape], i: usize, opts: &PairingOptions) -> P3 {
    let k = shapes.len();
    let me = &shapes[i];
    if k < 2 {
        return me.inward;
    }
    let first = me.samples[0];
    let last = *me.samples.last().unwrap_or(&first);
    let mut sum = [0.0; 3];
    let mut any = false;
    // the tangent-plane part of a direction at the first (0) or last (1) point
    let tangent = |v: P3, end: usize| match me.end_normals {
        Some(n) => sub(v, scale(n[end], dot(v, n[end]))),
        None => v,
    };
    for (m, mine, theirs) in [
        ((i + k - 1) % k, tangent(sub(last, first), 0), {
            let p = &shapes[(i + k - 1) % k];
            tangent(sub(p.samples[0], first), 0)
        }),
        ((i + 1) % k, tangent(sub(first, last), 1), {
            let q = &shapes[(i + 1) % k];
            tangent(sub(*q.samples.last().unwrap_or(&last), last), 1)
        }),
    ] {
        let other = &shapes[m];
        if opts.influence_length * other.length > me.length
            && angle(theirs, mine) <= opts.influence_angle.to_radians()
        {
            if let Some(u) = normalized(theirs) {
                let u = if dot(u, me.inward) < 0.0 { scale(u, -1.0) } else { u };
                sum = add(sum, u);
                any = true;
            }
        }
    }
    match normalized(sum) {
        Some(t) if any && dot(t, me.inward) > 0.1 => t,
        _ => me.inward,
    }
}

/// The mean over the samples p of `a` of the smallest angle between `t` and
/// `x − p` for x a sample of `b` (a_{a→b}, spec §2.1).
pub fn mean_bridge_angle(a: &SegmentShape, t: P3, b: &SegmentShape) -> f64 {
    let mut total = 0.0;
    for &p in &a.samples {
        // The best x by cosine (cheap), its angle by atan2 (accurate near 0,
        // where acos would turn rounding into 1e-8 differences and hide ties).
        let mut best: Option<(f64, P3)> = None;
        for &x in &b.samples {
            let v = sub(x, p);
            let l = norm(v);
            if l > 1e-12 && best.is_none_or(|(c, _)| dot(t, v) / l > c) {
                best = Some((dot(t, v) / l, v));
            }
        }
        total += best.map_or(std::f64::consts::PI, |(_, v)| angle(t, v));
    }
    total / a.samples.len() as f64
}

/// The RMS closest-point distance from `a`'s samples mapped by the best
/// affine fit onto `b`'s reversed samples (opposite sides of a quad run in
/// opposite directions), to the polyline of `b` (spec §2.2).
pub fn affine_residual(a: &SegmentShape, b: &SegmentShape) -> f64 {
    let n = a.samples.len();
    let ca = scale(a.samples.iter().fold([0.0; 3], |s, p| add(s, *p)), 1.0 / n as f64);
    let cb = b.centre;
    let mut ptp = [[0.0; 3]; 3];
    let mut ptq = [[0.0; 3]; 3];
    for k in 0..n {
        let p = sub(a.samples[k], ca);
        let q = sub(b.samples[n - 1 - k], cb);
        for r in 0..3 {
            for s in 0..3 {
                ptp[r][s] += p[r] * p[s];
                ptq[r][s] += p[r] * q[s];
            }
        }
    }
    // Pseudo-inverse of PᵀP: planar or straight segments make it singular.
    let (vals, vecs) = symmetric_eigen(ptp);
    let cutoff = 1e-10 * vals[2].max(1e-300);
    let mut pinv = [[0.0; 3]; 3];
    for (val, v) in vals.iter().zip(&vecs) {
        if *val > cutoff {
            for r in 0..3 {
                for s in 0..3 {
                    pinv[r][s] += v[r] * v[s] / val;
                }
            }
        }
    }
    // X = pinv · PᵀQ maps a centred row p to p·X.
    let mut x = [[0.0; 3]; 3];
    for r in 0..3 {
        for s in 0..3 {
            x[r][s] = (0..3).map(|k| pinv[r][k] * ptq[k][s]).sum();
        }
    }
    let line = PolylineSegments::of(&b.samples);
    let mut sq = 0.0;
    for p in &a.samples {
        let d = sub(*p, ca);
        let mapped = add(cb, [0, 1, 2].map(|s| (0..3).map(|r| d[r] * x[r][s]).sum()));
        sq += line.distance(mapped).powi(2);
    }
    (sq / n as f64).sqrt()
}

/// An open polyline's segments with their vectors and squared lengths
/// computed once, for many point distances (issue 30: the affine residuals
/// are most of the pairing time).
struct PolylineSegments<'a> {
    points: &'a [P3],
    /// Per segment: `b − a` and its squared length.
    segments: Vec<(P3, f64)>,
}

impl<'a> PolylineSegments<'a> {
    fn of(points: &'a [P3]) -> Self {
        let segments = points
            .windows(2)
            .map(|w| {
                let ab = sub(w[1], w[0]);
                (ab, dot(ab, ab))
            })
            .collect();
        PolylineSegments { points, segments }
    }

    /// Bit-identical to `point_polyline_distance(p, points)`: the same
    /// closest point per segment, the smallest squared distance and one
    /// square root (the root is monotonic, so the root of the least is the
    /// least root).
    fn distance(&self, p: P3) -> f64 {
        match self.points {
            [] => f64::INFINITY,
            [q] => dist(p, *q),
            _ => {
                let mut least = f64::INFINITY;
                for (&a, &(ab, l2)) in self.points.iter().zip(&self.segments) {
                    let t = if l2 > 0.0 { (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
                    let v = sub(p, add(a, scale(ab, t)));
                    least = least.min(dot(v, v));
                }
                least.sqrt()
            }
        }
    }
}

/// The three terms and the total of one pair's cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairCost {
    /// Bridge curvature b (radians, or over π when `b_in_radians` is off).
    pub bridge: f64,
    /// Similarity s.
    pub similarity: f64,
    /// Distance d between the centres, over D.
    pub distance: f64,
    /// c = w_b b + w_s s + w_d d.
    pub total: f64,
}

/// The cost of pairing segments `a` and `b` with bridge directions `ta`, `tb`.
pub fn pair_cost(a: &SegmentShape, ta: P3, b: &SegmentShape, tb: P3, opts: &PairingOptions) -> PairCost {
    let angles = [mean_bridge_angle(a, ta, b), mean_bridge_angle(b, tb, a)];
    let residuals = [affine_residual(a, b), affine_residual(b, a)];
    pair_cost_of_parts(a, b, angles, residuals, opts)
}

/// [`pair_cost`] from its expensive parts computed beforehand (the refiner
/// caches them, issue 30): `angles` = [`mean_bridge_angle`] a→b and b→a,
/// `residuals` = [`affine_residual`] (a, b) and (b, a). Bit-identical to
/// [`pair_cost`] for the same parts.
pub fn pair_cost_of_parts(
    a: &SegmentShape,
    b: &SegmentShape,
    angles: [f64; 2],
    residuals: [f64; 2],
    opts: &PairingOptions,
) -> PairCost {
    let mut bridge = angles[0].max(angles[1]);
    if !opts.b_in_radians {
        bridge /= std::f64::consts::PI;
    }
    let l = 0.5 * (residuals[0] + residuals[1]);
    let sigma = opts.shape_sigma;
    let similarity = 0.5 * (a.length - b.length).abs() + 0.5 * (1.0 - (-(l * l) / (sigma * sigma)).exp());
    let distance = dist(a.centre, b.centre);
    let total = opts.w_bridge * bridge + opts.w_similarity * similarity + opts.w_distance * distance;
    PairCost { bridge, similarity, distance, total }
}

/// The symmetric cost matrix of a list of segments (diagonal 0).
pub fn cost_matrix(shapes: &[SegmentShape], t: &[P3], opts: &PairingOptions) -> Vec<Vec<f64>> {
    let k = shapes.len();
    let mut c = vec![vec![0.0; k]; k];
    for i in 0..k {
        for j in i + 1..k {
            let v = pair_cost(&shapes[i], t[i], &shapes[j], t[j], opts).total;
            c[i][j] = v;
            c[j][i] = v;
        }
    }
    c
}

/// The per-iteration update of bridge directions from dominant pairs (spec
/// §2.4, paper Fig. 9d): a dominant pair's directions become their average
/// axis; a segment not dominantly matched with a dominant neighbour aligns
/// with it (within 45°) or turns orthogonal to it in its own plane.
pub fn dominant_update(shapes: &[SegmentShape], t: &mut [P3], mate: &[Option<usize>], c: &[Vec<f64>], dom: f64) {
    let k = shapes.len();
    let dominant: Vec<bool> = (0..k).map(|i| mate[i].is_some_and(|j| c[i][j] < dom)).collect();
    for i in 0..k {
        if let Some(j) = mate[i].filter(|&j| j > i && dominant[i]) {
            if let Some(axis) = normalized(sub(t[i], t[j])) {
                t[i] = axis;
                t[j] = scale(axis, -1.0);
            }
        }
    }
    let frozen = t.to_vec();
    for i in (0..k).filter(|&i| !dominant[i]) {
        let neighbours = [(i + k - 1) % k, (i + 1) % k];
        let m = neighbours
            .into_iter()
            .filter(|&m| m != i && dominant[m])
            .min_by(|&a, &b| {
                let ca = mate[a].map_or(f64::INFINITY, |j| c[a][j]);
                let cb = mate[b].map_or(f64::INFINITY, |j| c[b][j]);
                ca.total_cmp(&cb).then(a.cmp(&b))
            });
        let Some(m) = m else { continue };
        let tm = frozen[m];
        if angle(t[i], tm) <= std::f64::consts::FRAC_PI_4 {
            t[i] = tm;
            continue;
        }
        let Some(e1) = normalized(shapes[i].chord) else { continue };
        let e2 = shapes[i].inward;
        let (a1, a2) = (dot(tm, e1), dot(tm, e2));
        if a1.abs() < 0.1 * (a1 * a1 + a2 * a2).sqrt() {
            continue;
        }
        // In-plane orthogonal of (a1, a2) with a positive inward part.
        let v = add(scale(e1, -a2), scale(e2, a1));
        let v = if a1 < 0.0 { scale(v, -1.0) } else { v };
        if let Some(v) = normalized(v) {
            t[i] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The four sides of the rectangle [0,2]×[0,1] (CCW about +z), each
    /// sampled at 11 points.
    fn rectangle_sides() -> Vec<Vec<P3>> {
        let c = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        (0..4).map(|s| (0..=10).map(|k| super::super::polyline::lerp(c[s], c[(s + 1) % 4], k as f64 / 10.0)).collect()).collect()
    }

    fn close(a: P3, b: P3) -> bool {
        dist(a, b) < 1e-9
    }

    #[test]
    fn rectangle_bridge_directions_point_across() {
        let o = PairingOptions::default();
        let d = 5f64.sqrt();
        let shapes = segment_shapes(&rectangle_sides(), d, [0.0, 0.0, 1.0], o.samples, None);
        let t: Vec<P3> = (0..4).map(|i| initial_direction(&shapes, i, &o)).collect();
        let want = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]];
        for i in 0..4 {
            assert!(close(t[i], want[i]) && close(shapes[i].inward, want[i]), "{i}: {:?} {:?}", t[i], shapes[i].inward);
        }
        // Opposite sides: straight bridges (b = 0), same shape, so c = 0.1·(0.5|Δl| + d).
        let c = pair_cost(&shapes[0], t[0], &shapes[2], t[2], &o);
        assert!(c.bridge.abs() < 1e-12, "{c:?}");
        assert!((c.distance - 1.0 / d).abs() < 1e-12);
        assert!(c.similarity.abs() < 1e-9, "{c:?}");
        assert!((c.total - 0.1 / d).abs() < 1e-9);
        // A side with its neighbour bends the bridge by about 45° or more.
        assert!(pair_cost(&shapes[0], t[0], &shapes[1], t[1], &o).bridge > 0.7);
    }

    #[test]
    fn an_affine_image_has_no_shape_difference() {
        let o = PairingOptions::default();
        let arc: Vec<P3> = (0..=40).map(|k| {
            let a = std::f64::consts::PI * k as f64 / 40.0;
            [a.cos(), a.sin(), 0.0]
        }).collect();
        // Reversed, sheared and scaled: opposite sides run opposite ways.
        let image: Vec<P3> = arc.iter().rev().map(|p| [2.0 * p[0] + 0.5 * p[1] + 3.0, 0.5 * p[1] - 4.0, 0.2 * p[0]]).collect();
        let bent: Vec<P3> = (0..=40).map(|k| {
            let a = 3.0 * std::f64::consts::PI * k as f64 / 40.0;
            [k as f64 / 20.0, a.sin(), 0.0]
        }).collect();
        // Rotated by 90° about z, scaled by 2, moved: arc length maps evenly.
        let similar: Vec<P3> = arc.iter().rev().map(|p| [-2.0 * p[1] + 1.0, 2.0 * p[0], 5.0]).collect();
        let shapes = segment_shapes(&[arc, image, bent, similar], 10.0, [0.0, 0.0, 1.0], o.samples, None);
        let (sheared, bent, similar) =
            (affine_residual(&shapes[0], &shapes[1]), affine_residual(&shapes[0], &shapes[2]), affine_residual(&shapes[0], &shapes[3]));
        // Samples correspond by arc length, which a shear does not keep even,
        // so the sheared image is close but not exact.
        assert!(similar < 1e-9, "{similar}");
        assert!(sheared < 0.01 && bent > 2.0 * sheared, "{sheared} {bent}");
    }

    #[test]
    fn polyline_segments_distance_is_bit_identical_to_the_plain_one() {
        use super::super::polyline::point_polyline_distance;
        // A helix-like polyline with a repeated point (a zero-length segment).
        let mut line: Vec<P3> = (0..12).map(|k| {
            let a = 0.7 * k as f64;
            [a.cos(), a.sin(), 0.13 * k as f64]
        }).collect();
        line.insert(5, line[5]);
        let fast = PolylineSegments::of(&line);
        let mut checked = 0;
        for i in 0..40 {
            let s = i as f64 * 0.37;
            let p = [1.3 * s.sin(), 0.9 * (1.7 * s).cos(), 0.05 * i as f64 - 0.3];
            assert_eq!(fast.distance(p).to_bits(), point_polyline_distance(p, &line).to_bits(), "at {p:?}");
            checked += 1;
        }
        assert_eq!(checked, 40);
        // One point, and none.
        let one = [[1.0, 2.0, 2.0]];
        assert_eq!(PolylineSegments::of(&one).distance([0.0; 3]), 3.0);
        assert_eq!(PolylineSegments::of(&[]).distance([0.0; 3]), f64::INFINITY);
    }

    #[test]
    fn pair_cost_of_parts_equals_pair_cost() {
        let sides = rectangle_sides();
        let shapes = segment_shapes(&sides, 2.0, [0.0, 0.0, 1.0], 9, None);
        let o = PairingOptions::default();
        let t: Vec<P3> = (0..4).map(|i| initial_direction(&shapes, i, &o)).collect();
        for (i, j) in [(0, 2), (0, 1), (1, 3)] {
            let (a, b) = (&shapes[i], &shapes[j]);
            let angles = [mean_bridge_angle(a, t[i], b), mean_bridge_angle(b, t[j], a)];
            let residuals = [affine_residual(a, b), affine_residual(b, a)];
            assert_eq!(pair_cost_of_parts(a, b, angles, residuals, &o), pair_cost(a, t[i], b, t[j], &o));
        }
    }

    #[test]
    fn dominant_pairs_share_an_axis_and_neighbours_follow() {
        let o = PairingOptions::default();
        let shapes = segment_shapes(&rectangle_sides(), 5f64.sqrt(), [0.0, 0.0, 1.0], o.samples, None);
        let s = 0.1f64.sin();
        let mut t = vec![[s, 0.1f64.cos(), 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.6, 0.8, 0.0]];
        let mate = vec![Some(2), None, Some(0), None];
        let mut c = vec![vec![1.0; 4]; 4];
        c[0][2] = 0.05;
        c[2][0] = 0.05;
        dominant_update(&shapes, &mut t, &mate, &c, o.dom);
        assert!(close(t[2], scale(t[0], -1.0)), "the pair's t opposite");
        assert!(t[0][1] > 0.99 && t[0][0] > 0.0, "average axis of up and a slightly tilted up");
        // Segment 1 (right side, t = −x) is 90° from t_0: turned orthogonal to it,
        // inward: about −x. Segment 3 (t = (0.6, 0.8)) is 37° from t_0: aligned with it.
        assert!(t[1][0] < -0.99, "{:?}", t[1]);
        assert!(close(t[3], t[0]), "{:?}", t[3]);
    }
}
