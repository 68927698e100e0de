//! Meshing a narrow two-cornered face (a lens: two curve chains between two
//! convex corners, e.g. the run-out strip of a helical thread flank, far
//! narrower than the target size) as two rows of quads on a middle row of
//! nodes. No pattern of the library has two corners, and the
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

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    /// A crescent ring in the plane z = 0 ((u, v) = (x, y)): chain a on the
    /// circle of radius `r` about (5, 5) over `arc` radians in `n` segments,
    /// chain b back over the same angles at radius r + w sin(π k / n) (`nb`
    /// segments), so the two tips are shared; corners at ring positions 0
    /// and `n`.
    fn crescent(r: f64, w: f64, arc: f64, n: usize, nb: usize) -> Ring {
        let point = |rad: f64, t: f64| [5.0 + rad * t.cos(), 5.0 + rad * t.sin(), 0.0];
        let mut pos = Vec::new();
        for k in 0..=n {
            pos.push(point(r, arc * k as f64 / n as f64));
        }
        for k in (1..nb).rev() {
            let s = k as f64 / nb as f64;
            pos.push(point(r + w * (std::f64::consts::PI * s).sin(), arc * s));
        }
        let nodes = pos
            .iter()
            .map(|p| LocalNode {
                uv: [p[0], p[1]],
                node: NodeRef::Interior,
                pole: None,
            })
            .collect();
        Ring {
            nodes,
            pos,
            corners: vec![(0, 0.0), (n, 0.0)],
        }
    }

    #[test]
    fn a_curved_narrow_lens_gets_two_rows_of_valid_quads() {
        // the rod's run-outs: radius 2.5, 2.5e-4 wide, 8 segments of 0.1 rad
        // (0.25 long, sagitta 0.003: 12 × the width)
        let model = primitives::rectangle(10.0, 10.0);
        let face = &model.faces[0];
        let ring = crescent(2.5, 2.5e-4, 0.8, 8, 8);
        let p = mesh_lens_strip(face, &ring, [0, 8]).expect("a narrow lens");
        // two rows of n − 2 quads and a kite at each tip; n − 1 middle nodes
        assert_eq!(p.quads.len(), 2 * 8 - 2);
        assert_eq!(p.nodes.len(), 16 + 7);
        for q in &p.quads {
            assert!(quad_quality(face, &p.nodes, &p.pos, q) > 0.0, "{q:?}");
            let uv: Vec<[f64; 2]> = q.iter().map(|&i| p.nodes[i as usize].uv).collect();
            // counter-clockwise in the plane, whose normal is +z
            let area: f64 = (0..4)
                .map(|k| uv[k][0] * uv[(k + 1) % 4][1] - uv[(k + 1) % 4][0] * uv[k][1])
                .sum();
            assert!(area > 0.0, "{q:?}");
        }
        // the middle nodes lie between the chains (radius in (r, r + w))
        for (nd, pos) in p.nodes.iter().zip(&p.pos).skip(16) {
            assert_eq!(nd.node, NodeRef::Interior);
            let rad = ((pos[0] - 5.0).powi(2) + (pos[1] - 5.0).powi(2)).sqrt();
            assert!(rad > 2.5 && rad < 2.5 + 2.5e-4, "{rad}");
        }
        // one row on the boundary points alone folds: the quad
        // a_2 a_3 b_2 b_1 has a corner past 180° on the concave chain
        let (a, b) = (|k: usize| k as u32, |k: usize| (16 - k) as u32);
        let mut q = [a(2), a(3), b(2), b(1)];
        q.reverse(); // the ring runs clockwise
        assert!(quad_quality(face, &ring.nodes, &ring.pos, &q) < 0.0);
    }

    #[test]
    fn wide_lenses_and_unequal_chains_are_left_to_other_meshers() {
        let model = primitives::rectangle(10.0, 10.0);
        let face = &model.faces[0];
        // 0.5 wide against segments of 0.25
        let wide = crescent(2.5, 0.5, 0.8, 8, 8);
        assert!(mesh_lens_strip(face, &wide, [0, 8]).is_err());
        // 8 and 10 segments
        let uneven = crescent(2.5, 2.5e-4, 0.8, 8, 10);
        assert!(mesh_lens_strip(face, &uneven, [0, 8]).is_err());
        // n = 2 is one quad A a_1 B b_1; on a crescent its corner at a_1
        // (the concave chain) passes 180°, so it is refused too
        let short = crescent(2.5, 2.5e-4, 0.2, 2, 2);
        let why = mesh_lens_strip(face, &short, [0, 2]).unwrap_err();
        assert!(why.contains("SICN"), "{why}");
    }
}
