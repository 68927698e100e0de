//! Greedy triangle → quad recombination (paper §5.2, spec §7.3).
//!
//! Every pair of triangles sharing an edge that is not on a CAD curve is a
//! candidate quad. Candidates are ranked by `SICN_min · w`, the quad's worst
//! corner SICN (with the CAD normals) times its alignment `w ∈ [0, 1]` with
//! the cross field, and taken greedily, best first, each triangle at most
//! once, as long as their SICN is above a threshold (0.1 in the paper). A
//! corner between two curve edges is measured as midpoint subdivision will
//! leave it, between the curve's midpoint nodes.
//! Triangles left over stay triangles: the result is quad-dominant (no
//! perfect matching is sought). Optionally ([`recombine`]'s `max_path`), short
//! augmenting paths then pair more triangles: a free triangle, a candidate
//! quad to a matched one, its mate, another candidate, ... ending at another
//! free triangle; flipping the path turns two triangles into one more quad
//! (each triangle left alone becomes an irregular vertex after subdivision).

use crate::core::fast_hash::FastMap;

use geometry::vec3::Vec3;
use geometry::Face;
use mesh::quality::corner_sicn;

use crate::core::patch::LocalNode;
use crate::core::quality::{node_normal, quad_quality};

/// The paper's threshold on the SICN of a recombined quad.
pub const MIN_SICN: f64 = 0.1;

/// Thresholds of [`recombine`] on the SICN of a candidate quad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinSicn {
    /// Its worst corner (the paper's [`MIN_SICN`]).
    pub quad: f64,
    /// Its corners between two curve edges, as subdivision leaves them: a
    /// node on a smooth curve whose only element the quad would be keeps a
    /// nearly flat corner (SICN about 0.17), which no smoothing can open.
    pub curve_corner: f64,
}

/// A quad-dominant mesh of one face on local nodes, counter-clockwise in (u, v).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QuadDominant {
    /// Quads made of two triangles.
    pub quads: Vec<[u32; 4]>,
    /// Triangles left alone.
    pub triangles: Vec<[u32; 3]>,
}

/// Recombines `tris` (counter-clockwise in (u, v), on `nodes` at 3D
/// positions `pos`). `curve_mid(a, b)` is, for an edge on a CAD curve (never
/// removed), the 3D position of its midpoint node on the curve, and `None`
/// for other edges: a quad with two curve edges in a row keeps, after
/// midpoint subdivision, a corner between the two midpoints, flatter than the
/// coarse one on a convex curve, and that corner is what is measured against
/// `min_sicn` (both its thresholds). `alignment` gives the weight of a quad from its
/// four 3D corners (return 1 to rank by quality only). Quads are counter-
/// clockwise in (u, v) like the triangles; their quality is measured with the
/// face's oriented normal (reversed faces are taken into account).
#[allow(clippy::too_many_arguments)]
pub fn recombine(
    face: &Face,
    nodes: &[LocalNode],
    pos: &[Vec3],
    tris: &[[u32; 3]],
    curve_mid: impl Fn(u32, u32) -> Option<Vec3>,
    alignment: impl Fn(&[Vec3; 4]) -> f64,
    min_sicn: MinSicn,
    max_path: usize,
) -> QuadDominant {
    // edge → (triangle, local edge index) of its first use
    let mut first: FastMap<(u32, u32), (u32, usize)> =
        FastMap::with_capacity_and_hasher(3 * tris.len(), Default::default());
    let mut cands: Vec<(f64, u32, u32, [u32; 4])> = Vec::new();
    for (ti, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            match first.get(&key) {
                None => {
                    first.insert(key, (ti as u32, k));
                }
                Some(&(tj, kj)) => {
                    if curve_mid(a, b).is_some() {
                        continue;
                    }
                    let u = tris[tj as usize];
                    // u has the edge b → a at local index kj (same orientation: skip)
                    if u[kj] != b || u[(kj + 1) % 3] != a {
                        continue;
                    }
                    let c = t[(k + 2) % 3];
                    let d = u[(kj + 2) % 3];
                    if c == d {
                        continue;
                    }
                    // t = (a, b, c), u = (b, a, d): the quad a, d, b, c
                    let q = [a, d, b, c];
                    let oriented = if face.reversed {
                        [q[0], q[3], q[2], q[1]]
                    } else {
                        q
                    };
                    let cc = subdivided_curve_corners(face, nodes, pos, &oriented, &curve_mid);
                    let sicn = quad_quality(face, nodes, pos, &oriented).min(cc);
                    if !(sicn > min_sicn.quad && cc > min_sicn.curve_corner) {
                        continue;
                    }
                    let w = alignment(&oriented.map(|i| pos[i as usize]));
                    let w = if w.is_finite() {
                        w.clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    cands.push((sicn * w, tj.min(ti as u32), tj.max(ti as u32), q));
                }
            }
        }
    }
    // best first; ties broken by the triangle pair, so the order is total
    cands.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    // mate[t] = (other triangle, candidate index)
    let mut mate: Vec<Option<(u32, usize)>> = vec![None; tris.len()];
    for (ci, &(_, t1, t2, _)) in cands.iter().enumerate() {
        if mate[t1 as usize].is_some() || mate[t2 as usize].is_some() {
            continue;
        }
        mate[t1 as usize] = Some((t2, ci));
        mate[t2 as usize] = Some((t1, ci));
    }
    if max_path > 0 {
        augment(tris.len(), &cands, &mut mate, max_path);
    }
    let mut out = QuadDominant::default();
    let mut taken: Vec<usize> = mate.iter().flatten().map(|&(_, ci)| ci).collect();
    taken.sort_unstable();
    taken.dedup();
    out.quads = taken.iter().map(|&ci| cands[ci].3).collect();
    out.triangles = tris
        .iter()
        .zip(&mate)
        .filter(|(_, m)| m.is_none())
        .map(|(t, _)| *t)
        .collect();
    out
}

/// Pairs more triangles by augmenting paths of at most `max_path` candidate
/// edges, searched breadth-first from each free triangle in order (candidates
/// of a triangle in rank order), so the result is deterministic.
fn augment(
    ntris: usize,
    cands: &[(f64, u32, u32, [u32; 4])],
    mate: &mut [Option<(u32, usize)>],
    max_path: usize,
) {
    let mut adj: Vec<Vec<(u32, usize)>> = vec![Vec::new(); ntris];
    for (ci, &(_, t1, t2, _)) in cands.iter().enumerate() {
        adj[t1 as usize].push((t2, ci));
        adj[t2 as usize].push((t1, ci));
    }
    // visit stamps and BFS parents: parent[v] = (the matched vertex before v, edge into v)
    let mut stamp = vec![usize::MAX; ntris];
    let mut parent: Vec<(u32, usize)> = vec![(u32::MAX, usize::MAX); ntris];
    for root in 0..ntris {
        if mate[root].is_some() || adj[root].is_empty() {
            continue;
        }
        stamp[root] = root;
        // frontier of "outer" vertices (root, or mates reached through a matched edge)
        let mut frontier = vec![(root as u32, 0usize)];
        let mut found: Option<(u32, u32, usize)> = None;
        'search: while !frontier.is_empty() {
            let mut next = Vec::new();
            for &(u, depth) in &frontier {
                if depth + 1 > max_path {
                    continue;
                }
                for &(v, ci) in &adj[u as usize] {
                    if stamp[v as usize] == root {
                        continue;
                    }
                    match mate[v as usize] {
                        None => {
                            found = Some((u, v, ci));
                            break 'search;
                        }
                        Some((w, _)) => {
                            if stamp[w as usize] == root || depth + 3 > max_path {
                                continue;
                            }
                            stamp[v as usize] = root;
                            stamp[w as usize] = root;
                            parent[v as usize] = (u, ci);
                            next.push((w, depth + 2));
                        }
                    }
                }
            }
            frontier = next;
        }
        let Some((mut u, mut v, mut ci)) = found else {
            continue;
        };
        // flip the path back to the root: v–u becomes matched, u's old mate
        // is re-matched through its parent edge, and so on
        loop {
            let old = mate[u as usize];
            mate[u as usize] = Some((v, ci));
            mate[v as usize] = Some((u, ci));
            match old {
                None => break,
                Some((x, _)) => {
                    // x is matched to u no more; x was reached from parent[x]
                    let (p, pc) = parent[x as usize];
                    v = x;
                    u = p;
                    ci = pc;
                }
            }
        }
    }
}

/// Worst SICN, after midpoint subdivision, of the corners of quad `q`
/// (oriented) that lie between two curve edges: the corner's sub-quad meets
/// the curve at the two edges' midpoint nodes (`curve_mid`), not at the far
/// ends. `+∞` when no corner has two curve edges.
fn subdivided_curve_corners(
    face: &Face,
    nodes: &[LocalNode],
    pos: &[Vec3],
    q: &[u32; 4],
    curve_mid: &impl Fn(u32, u32) -> Option<Vec3>,
) -> f64 {
    let mut worst = f64::INFINITY;
    for k in 0..4 {
        let (prev, b, next) = (q[(k + 3) % 4], q[k], q[(k + 1) % 4]);
        let (Some(m_prev), Some(m_next)) = (curve_mid(prev, b), curve_mid(b, next)) else {
            continue;
        };
        let Some(n) = node_normal(face, nodes, q, k) else {
            continue;
        };
        let pb = pos[b as usize];
        // corner 0 of (B, m_next, ·, m_prev) is the sub-quad's corner at B
        let s = corner_sicn(&[pb, m_next, pb, m_prev], &[n; 4])[0];
        worst = worst.min(s);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    impl MinSicn {
        /// The paper's threshold on every corner.
        const PAPER: MinSicn = MinSicn {
            quad: MIN_SICN,
            curve_corner: MIN_SICN,
        };
    }
    use crate::core::patch::NodeRef;
    use geometry::primitives;

    /// Recombination with no curve edge, quality alone (weight 1) and the
    /// paper's threshold.
    fn plain(
        m: &geometry::Model,
        nodes: &[LocalNode],
        pos: &[Vec3],
        tris: &[[u32; 3]],
        max_path: usize,
    ) -> QuadDominant {
        recombine(
            &m.faces[0],
            nodes,
            pos,
            tris,
            |_, _| None,
            |_| 1.0,
            MinSicn::PAPER,
            max_path,
        )
    }

    fn node(u: f64, v: f64) -> LocalNode {
        LocalNode {
            uv: [u, v],
            node: NodeRef::Interior,
            pole: None,
        }
    }

    #[test]
    fn two_right_triangles_make_one_quad() {
        let m = primitives::square(1.0);
        let nodes = vec![
            node(0.0, 0.0),
            node(1.0, 0.0),
            node(1.0, 1.0),
            node(0.0, 1.0),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| [n.uv[0], n.uv[1], 0.0]).collect();
        let tris = [[0, 1, 2], [0, 2, 3]];
        let r = plain(&m, &nodes, &pos, &tris, 0);
        assert_eq!(r.quads.len(), 1);
        assert!(r.triangles.is_empty());
        let q = r.quads[0];
        // the quad is the square, counter-clockwise
        let mut sorted = q;
        sorted.sort();
        assert_eq!(sorted, [0, 1, 2, 3]);
        assert!(quad_quality(&m.faces[0], &nodes, &pos, &q) > 0.99);
        // a CAD curve along the diagonal forbids it
        let r = recombine(
            &m.faces[0],
            &nodes,
            &pos,
            &tris,
            |a, b| ((a.min(b), a.max(b)) == (0, 2)).then_some([0.0; 3]),
            |_| 1.0,
            MinSicn::PAPER,
            3,
        );
        assert!(r.quads.is_empty());
        assert_eq!(r.triangles.len(), 2);
    }

    /// Recombination with curve midpoints `mids`, quality alone (weight 1),
    /// thresholds `min_sicn` and no augmenting path.
    fn with_curves(
        m: &geometry::Model,
        nodes: &[LocalNode],
        pos: &[Vec3],
        tris: &[[u32; 3]],
        mids: impl Fn(u32, u32) -> Option<Vec3>,
        min_sicn: MinSicn,
    ) -> QuadDominant {
        recombine(&m.faces[0], nodes, pos, tris, mids, |_| 1.0, min_sicn, 0)
    }

    /// A (−1, 0), X (0, −1), B (0, h), C (1, 0): B on a circular arc through
    /// A and C bulging `h`, X inside; the triangles (A, X, B), (B, X, C) and
    /// the arc's midpoints on A–B and B–C (`curve_mid`).
    #[allow(clippy::type_complexity)]
    fn arc_corner(
        h: f64,
    ) -> (
        Vec<LocalNode>,
        Vec<Vec3>,
        Vec<[u32; 3]>,
        impl Fn(u32, u32) -> Option<Vec3>,
    ) {
        let nodes = vec![
            node(-1.0, 0.0),
            node(0.0, -1.0),
            node(0.0, h),
            node(1.0, 0.0),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| [n.uv[0], n.uv[1], 0.0]).collect();
        let tris = vec![[0, 1, 2], [2, 1, 3]];
        // the arc: centre (0, c), radius r, through A, B and C
        let c = (h * h - 1.0) / (2.0 * h);
        let r = (1.0 + c * c).sqrt();
        // the arc's midpoint between B (at angle π/2) and the end at x = ±1
        let arc_mid = move |x: f64| {
            let t = 0.5 * ((-c).atan2(x) + 0.5 * std::f64::consts::PI);
            [r * t.cos(), c + r * t.sin(), 0.0]
        };
        let mids = move |a: u32, b: u32| match (a.min(b), a.max(b)) {
            (0, 2) => Some(arc_mid(-1.0)),
            (2, 3) => Some(arc_mid(1.0)),
            _ => None,
        };
        (nodes, pos, tris, mids)
    }

    #[test]
    fn a_corner_flattened_by_subdivision_is_refused() {
        // A, B, C on a circular arc bulging 0.08 at B, X inside: the pair
        // (A, X, B), (B, X, C) makes the quad A X C B, whose corner at B has
        // SICN 0.159; after subdivision that corner lies between the arc's
        // midpoints and its SICN is 0.080, below the threshold
        let m = primitives::square(1.0);
        let (nodes, pos, tris, arc) = arc_corner(0.08);
        let mids = |a: u32, b: u32| arc(a, b);
        // the coarse corner alone passes
        let r0 = plain(&m, &nodes, &pos, &tris, 0);
        assert_eq!(r0.quads.len(), 1);
        let q = r0.quads[0];
        let coarse = quad_quality(&m.faces[0], &nodes, &pos, &q);
        assert!((coarse - 0.159).abs() < 1e-3, "{coarse}");
        // measured at the midpoints, it does not
        let sub = subdivided_curve_corners(&m.faces[0], &nodes, &pos, &q, &mids);
        assert!((sub - 0.0797).abs() < 1e-3, "{sub}");
        let r1 = with_curves(&m, &nodes, &pos, &tris, mids, MinSicn::PAPER);
        assert!(r1.quads.is_empty());
        assert_eq!(r1.triangles.len(), 2);
    }

    #[test]
    fn a_stricter_curve_corner_threshold_refuses_what_the_paper_takes() {
        // the arc of the test above bulging 0.2: after subdivision the
        // corner at B is 168.7° (SICN sin 168.7° = 0.196)
        let m = primitives::square(1.0);
        let (nodes, pos, tris, arc) = arc_corner(0.2);
        let mids = |a: u32, b: u32| arc(a, b);
        let paper = with_curves(&m, &nodes, &pos, &tris, mids, MinSicn::PAPER);
        assert_eq!(paper.quads.len(), 1);
        let q = paper.quads[0];
        let sub = subdivided_curve_corners(&m.faces[0], &nodes, &pos, &q, &mids);
        assert!((sub - 0.196).abs() < 1e-3, "{sub}");
        let strict = MinSicn {
            quad: MIN_SICN,
            curve_corner: 0.3,
        };
        let r = with_curves(&m, &nodes, &pos, &tris, mids, strict);
        assert!(r.quads.is_empty());
        assert_eq!(r.triangles.len(), 2);
        // while the coarse quad itself is well above both thresholds
        assert!(quad_quality(&m.faces[0], &nodes, &pos, &q) > 0.3);
    }

    #[test]
    fn flat_pairs_are_refused_and_the_weight_counts() {
        let m = primitives::square(1.0);
        // a fan of four triangles around the centre of the square
        let nodes = vec![
            node(0.0, 0.0),
            node(1.0, 0.0),
            node(1.0, 1.0),
            node(0.0, 1.0),
            node(0.5, 0.5),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| [n.uv[0], n.uv[1], 0.0]).collect();
        let tris = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        // two pairings are possible (0-1 & 2-3, or 1-2 & 3-0): all four quads
        // have a 180° corner at the centre, SICN 0, refused
        let r = plain(&m, &nodes, &pos, &tris, 3);
        assert!(r.quads.is_empty());
        // a strip of two unit squares cut in four triangles: quality alone
        // takes the two squares, a weight favouring the middle parallelogram
        // (SICN sin 45°) takes it and leaves two triangles
        let nodes = vec![
            node(0.0, 0.0),
            node(1.0, 0.0),
            node(2.0, 0.0),
            node(2.0, 1.0),
            node(1.0, 1.0),
            node(0.0, 1.0),
        ];
        let pos: Vec<Vec3> = nodes.iter().map(|n| [n.uv[0], n.uv[1], 0.0]).collect();
        let tris = [[0, 1, 4], [0, 4, 5], [1, 2, 3], [1, 3, 4]];
        let r = plain(&m, &nodes, &pos, &tris, 0);
        assert_eq!(r.quads.len(), 2);
        assert!(r.triangles.is_empty());
        let middle = |q: &[Vec3; 4]| {
            if q.contains(&[0.0, 0.0, 0.0]) && q.contains(&[2.0, 1.0, 0.0]) {
                1.0
            } else {
                0.5
            }
        };
        let r = recombine(
            &m.faces[0],
            &nodes,
            &pos,
            &tris,
            |_, _| None,
            middle,
            MinSicn::PAPER,
            0,
        );
        assert_eq!(r.quads.len(), 1, "{:?}", r.quads);
        let mut q = r.quads[0];
        q.sort();
        assert_eq!(q, [0, 1, 3, 4]);
        assert_eq!(r.triangles, vec![[0, 4, 5], [1, 2, 3]]);
        // an augmenting path (045 – 014 = 134 – 123) pairs the two leftovers:
        // back to the two squares; a path limit of 1 cannot find it
        let r = recombine(
            &m.faces[0],
            &nodes,
            &pos,
            &tris,
            |_, _| None,
            middle,
            MinSicn::PAPER,
            3,
        );
        assert_eq!(r.quads.len(), 2, "{:?}", r.quads);
        assert!(r.triangles.is_empty());
        let r = recombine(
            &m.faces[0],
            &nodes,
            &pos,
            &tris,
            |_, _| None,
            middle,
            MinSicn::PAPER,
            1,
        );
        assert_eq!(r.quads.len(), 1);
    }
}
