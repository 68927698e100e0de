//! Meshing a narrow two-cornered face (a lens: two curve chains between two
//! convex corners, e.g. the run-out strip of a helical thread flank, far
//! narrower than the target size) as one row of quads on its boundary
//! points alone. No pattern of the library has two corners, and the
//! triangulation-based meshers fold there: a strip a thousand times longer
//! than wide leaves no room for interior nodes in (u, v).
//!
//! With `n` segments on each chain (`a_0 … a_n` and `b_0 … b_n`, `a_0 = b_0`
//! and `a_n = b_n` the corners), a middle row `m_1 … m_{n−1}` (the (u, v)
//! midpoints of `a_k b_k`) splits the strip into two rows of near-rectangles
//! `a_k a_{k+1} m_{k+1} m_k` and `m_k m_{k+1} b_{k+1} b_k`, and each tip is one
//! kite `a_0 a_1 m_1 b_1`. `m_1` (and `m_{n−1}`) is moved half a local width
//! away from its tip so that the kite is convex. A row of quads with no
//! middle row (`a_{k+1} a_{k+2} b_{k+1} b_k`) is not used: on a curved strip
//! narrower than the sagitta of a segment its corners pass 180°.
//! The mesh is kept only when every quad is valid by both judges.

use geometry::vec3::{self, Vec3};

use crate::core::patch::{LocalNode, NodeRef, QuadPatch};
use crate::core::quality::quad_quality;
use crate::direct::pattern_face::{needs_reversal, Ring};

/// Name of the strip mesh in reports.
pub const LENS_STRIP: &str = "lens strip";

/// A lens is narrow when its widest cross distance (between the `k`-th
/// points of the two chains) is below this share of its mean segment
/// length: narrower than one target size.
const NARROW_SHARE: f64 = 0.5;

/// Meshes the face of `ring` whose only convex corners are the ring
/// positions `corners` (two of them) as a strip of quads between its two
/// chains; an error (the caller meshes the face another way) when the
/// chains' segment counts differ, the lens is not narrow, or a quad would
/// be inverted by either judge.
pub(crate) fn mesh_lens_strip(
    face: &geometry::Face,
    ring: &Ring,
    corners: [usize; 2],
) -> Result<QuadPatch, String> {
    let nb = ring.nodes.len();
    let (c0, c1) = (corners[0].min(corners[1]), corners[0].max(corners[1]));
    let n = c1 - c0;
    if 2 * n != nb {
        return Err(format!("lens sides {} and {}", n, nb - n));
    }
    if n < 2 {
        return Err("a lens of one segment per side".into());
    }
    // ring positions of a_k (forward from c0) and b_k (backward from c0)
    let a = |k: usize| (c0 + k) % nb;
    let b = |k: usize| (c0 + nb - k) % nb;
    let dist = |i: usize, j: usize| vec3::norm(vec3::sub(ring.pos[i], ring.pos[j]));
    let mean_seg = (0..nb).map(|i| dist(i, (i + 1) % nb)).sum::<f64>() / nb as f64;
    let widest = (1..n).map(|k| dist(a(k), b(k))).fold(0.0, f64::max);
    if !(widest < NARROW_SHARE * mean_seg) {
        return Err(format!(
            "a lens {widest:.3e} wide, segments {mean_seg:.3e} long"
        ));
    }
    let mut nodes = ring.nodes.clone();
    let mut pos: Vec<Vec3> = ring.pos.clone();
    let quads: Vec<[u32; 4]> = if n == 2 {
        vec![[a(0), a(1), a(2), b(1)].map(|i| i as u32)]
    } else {
        let mid = |k: usize| {
            let (p, q) = (ring.nodes[a(k)].uv, ring.nodes[b(k)].uv);
            [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
        };
        // the middle row's (u, v): midpoints, the two next to the tips moved
        // away from them by half the local width (at most 0.3 of a segment)
        let shifted = |k: usize, toward: usize| {
            let (p, q) = (mid(k), mid(toward));
            let along = vec3::norm(vec3::sub(
                vec3::scale(vec3::add(ring.pos[a(k)], ring.pos[b(k)]), 0.5),
                vec3::scale(vec3::add(ring.pos[a(toward)], ring.pos[b(toward)]), 0.5),
            ));
            let t = if along > 0.0 {
                (0.5 * dist(a(k), b(k)) / along).min(0.3)
            } else {
                0.0
            };
            [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
        };
        let first = nodes.len();
        for k in 1..n {
            let mut uv = mid(k);
            if k == 1 {
                uv = shifted(1, 2);
            }
            if k == n - 1 {
                uv = shifted(n - 1, n - 2);
            }
            let p = face.surface.eval(uv);
            if !p.iter().all(|x| x.is_finite()) {
                return Err("a middle node falls outside the surface".into());
            }
            nodes.push(LocalNode {
                uv,
                node: NodeRef::Interior,
                pole: None,
            });
            pos.push(p);
        }
        let m = |k: usize| first + k - 1;
        let mut quads = vec![
            [a(0), a(1), m(1), b(1)],
            [a(n), b(n - 1), m(n - 1), a(n - 1)],
        ];
        for k in 1..n - 1 {
            quads.push([a(k), a(k + 1), m(k + 1), m(k)]);
            quads.push([m(k), m(k + 1), b(k + 1), b(k)]);
        }
        quads.into_iter().map(|q| q.map(|i| i as u32)).collect()
    };
    let mut quads = quads;
    let uv: Vec<[f64; 2]> = nodes.iter().map(|nd| nd.uv).collect();
    if needs_reversal(face, &quads, &uv) {
        for q in &mut quads {
            q.reverse();
        }
    }
    let worst = quads
        .iter()
        .map(|q| quad_quality(face, &nodes, &pos, q))
        .fold(f64::INFINITY, f64::min);
    if !(worst > 0.0) {
        return Err(format!("a lens strip quad of SICN {worst:.3}"));
    }
    Ok(QuadPatch {
        quad_tri: (0..quads.len() as u32).collect(),
        nodes,
        pos,
        quads,
    })
}
