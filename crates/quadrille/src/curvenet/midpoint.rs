//! The midpoint layout of a cycle (paper Fig. 5 top): the fallback when no
//! pairing of its segments lays out (issue 30 item 10).

use geometry::vec3;

use crate::curvenet::PairedCycle;

/// The midpoint layout of a cycle (Fig. 5 top): every segment split at its
/// arc-length middle, and the second half of side k paired with the first
/// half of side k + 2, so the chords make one ring of n quads around a
/// valence-n centre (n ≥ 3 sides).
pub fn midpoint_pairing(paired: &PairedCycle) -> PairedCycle {
    let n = paired.starts.len();
    let np = paired.points.len();
    let mut points: Vec<[f64; 3]> = Vec::with_capacity(np + n);
    let mut starts = Vec::with_capacity(2 * n);
    for s in 0..n {
        let a = paired.starts[s];
        let b = if s + 1 < n { paired.starts[s + 1] } else { paired.starts[0] + np };
        let run: Vec<[f64; 3]> = (a..=b).map(|i| paired.points[i % np]).collect();
        let half = split_at_half_length(&run);
        starts.push(points.len());
        points.extend_from_slice(&run[..half.0]);
        starts.push(points.len());
        points.push(half.1);
        points.extend_from_slice(&run[half.0..run.len() - 1]);
    }
    let m = 2 * n;
    let pairs: Vec<(usize, usize)> = (0..n)
        .map(|k| {
            let (a, b) = (2 * k + 1, (2 * k + 4) % m);
            (a.min(b), a.max(b))
        })
        .collect();
    PairedCycle {
        costs: vec![0.0; pairs.len()],
        pairs,
        unsplittable: vec![false; m],
        diameter: paired.diameter,
        points,
        starts,
    }
}

/// The index of the first point past half the polyline's length, and the
/// point at exactly half the length.
fn split_at_half_length(run: &[[f64; 3]]) -> (usize, [f64; 3]) {
    let len: f64 = run.windows(2).map(|w| vec3::dist(w[0], w[1])).sum();
    let mut acc = 0.0;
    for i in 1..run.len() {
        let l = vec3::dist(run[i - 1], run[i]);
        if acc + l >= 0.5 * len && l > 0.0 {
            let t = ((0.5 * len - acc) / l).clamp(0.0, 1.0);
            let p = vec3::add(run[i - 1], vec3::scale(vec3::sub(run[i], run[i - 1]), t));
            return (i, p);
        }
        acc += l;
    }
    (run.len() - 1, run[run.len() - 1])
}

