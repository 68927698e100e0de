//! Plane geometry in (u, v) for the face triangulation: edge midpoints and
//! centroids of local nodes (poles moved toward the other nodes),
//! circumcentres, orientation and the segment-intersection test.

use crate::core::patch::LocalNode;

/// (u, v) midpoint of the edge between two local nodes (poles moved toward the other end).
pub fn edge_mid_uv(a: &LocalNode, b: &LocalNode) -> [f64; 2] {
    let ua = a.uv_toward(b.uv);
    let ub = b.uv_toward(ua);
    [0.5 * (ua[0] + ub[0]), 0.5 * (ua[1] + ub[1])]
}

/// (u, v) centroid of a triangle of local nodes (poles moved toward the others).
pub fn centroid_uv(nodes: &[LocalNode], t: [u32; 3]) -> [f64; 2] {
    let n = |i: usize| &nodes[t[i] as usize];
    let mut s = [0.0, 0.0];
    for k in 0..3 {
        let o1 = n((k + 1) % 3).uv;
        let o2 = n((k + 2) % 3).uv;
        let uv = n(k).uv_toward([0.5 * (o1[0] + o2[0]), 0.5 * (o1[1] + o2[1])]);
        s[0] += uv[0] / 3.0;
        s[1] += uv[1] / 3.0;
    }
    s
}

pub(super) fn circumcenter(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<[f64; 2]> {
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let d = 2.0 * (bx * cy - by * cx);
    if d.abs() < 1e-300 {
        return None;
    }
    let b2 = bx * bx + by * by;
    let c2 = cx * cx + cy * cy;
    let x = (cy * b2 - by * c2) / d;
    let y = (bx * c2 - cx * b2) / d;
    let r = [a[0] + x, a[1] + y];
    (r[0].is_finite() && r[1].is_finite()).then_some(r)
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// True when segments pq and rs intersect (touching included), sharing no endpoint.
pub(super) fn segments_touch(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    if p == r || p == s || q == r || q == s {
        return false;
    }
    let d1 = orient(p, q, r);
    let d2 = orient(p, q, s);
    let d3 = orient(r, s, p);
    let d4 = orient(r, s, q);
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}
