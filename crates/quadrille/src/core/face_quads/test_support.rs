//! Hand-built planar patches shared by the tests of [`FaceQuads`] and of the
//! operations that edit it (the regular method's swaps, collapses, splits):
//! the plane they live on, a builder from points and quads, a grid, the
//! triangle-split patch, and [`Patch`], which wraps a hand-drawn core of quads
//! in rings of quads so that every core vertex becomes interior with a chosen
//! valence (the "stars" of the operation tests).

use geometry::{primitives, CurveId, FaceId, Model};
use mesh::NodeClass;

use super::{FaceQuads, QVertex};

/// The unit-square model whose face is the plane z = 0 with (u, v) = (x, y)
/// over `[0, side]²`; hand-built patches live on it (the plane extends
/// linearly outside the square).
pub(crate) fn plane(side: f64) -> Model {
    primitives::square(side)
}

/// A planar patch from (u, v) points and counter-clockwise quads: vertices with
/// an open fan are fixed boundary vertices, the others movable.
pub(crate) fn planar(points: &[[f64; 2]], quads: Vec<[u32; 4]>) -> FaceQuads {
    let verts = points
        .iter()
        .enumerate()
        .map(|(i, &uv)| QVertex {
            global: Some(i as u32),
            ..QVertex::interior(
                uv,
                [uv[0], uv[1], 0.0],
                NodeClass::Face(FaceId(0), Some(uv)),
            )
        })
        .collect();
    let mut fq = FaceQuads::new(verts, quads).expect("valid quads");
    for v in 0..fq.verts.len() as u32 {
        if fq.ordered_star(v).is_none() {
            fq.verts[v as usize].fixed = true;
            fq.verts[v as usize].class = NodeClass::Curve(CurveId(0), None);
        }
    }
    fq.classify_fixed();
    fq
}

/// The (n + 1)² integer points of `[0, n]²`, row by row: point `(i, j)` is `j (n + 1) + i`.
fn grid_points(n: u32) -> Vec<[f64; 2]> {
    (0..=n)
        .flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64]))
        .collect()
}

/// An n × n grid of unit quads on `[0, n]²`; vertex `(i, j)` has id `j (n + 1) + i`.
pub(crate) fn grid(n: u32) -> FaceQuads {
    let pts = grid_points(n);
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut quads = Vec::new();
    for j in 0..n {
        for i in 0..n {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    planar(&pts, quads)
}

/// A planar patch made like the regular method's input: an n × n grid of
/// squares, each cut into two triangles, each triangle split into three quads.
pub(crate) fn split_patch(n: u32) -> FaceQuads {
    let mut pts = grid_points(n);
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            // alternate the diagonals for variety
            if (i + j) % 2 == 0 {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            } else {
                tris.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
                tris.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    let quads = split_in_quads(&mut pts, &tris);
    planar(&pts, quads)
}

/// Splits the triangles `tris` on `pts` into three quads each (edge
/// midpoints and centroid, appended to `pts`), as the baseline mesher does.
pub(crate) fn split_in_quads(pts: &mut Vec<[f64; 2]>, tris: &[[u32; 3]]) -> Vec<[u32; 4]> {
    let mut mids = std::collections::BTreeMap::new();
    let mut quads = Vec::new();
    for t in tris {
        let mut m = [0u32; 3];
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            m[k] = *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (pts[a as usize], pts[b as usize]);
                pts.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
                pts.len() as u32 - 1
            });
        }
        let (a, b, c) = (pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]);
        pts.push([(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]);
        let g = pts.len() as u32 - 1;
        quads.push([t[0], m[0], g, m[2]]);
        quads.push([t[1], m[1], g, m[0]]);
        quads.push([t[2], m[2], g, m[1]]);
    }
    quads
}

/// A planar quad patch under construction (a topological disk): points in
/// (u, v) and counter-clockwise quads. Start from a hand-drawn core (the quads
/// an operation touches), then [`Patch::ring`] it so that the core vertices
/// become interior with the valences the test needs, and [`Patch::build`] it.
/// Vertex ids never change: a ring only appends vertices and quads.
#[derive(Clone, Debug)]
pub(crate) struct Patch {
    /// (u, v) of every vertex.
    pub pts: Vec<[f64; 2]>,
    /// Counter-clockwise quads.
    pub quads: Vec<[u32; 4]>,
}

impl Patch {
    /// A patch from points and counter-clockwise quads.
    pub fn new(pts: &[[f64; 2]], quads: &[[u32; 4]]) -> Self {
        Patch {
            pts: pts.to_vec(),
            quads: quads.to_vec(),
        }
    }

    /// Number of quads holding `v`.
    pub fn fan(&self, v: u32) -> u32 {
        self.quads.iter().filter(|q| q.contains(&v)).count() as u32
    }

    /// The boundary loop, counter-clockwise (the patch on its left), starting
    /// at its smallest vertex id. Panics unless the boundary is one loop.
    pub fn boundary_loop(&self) -> Vec<u32> {
        let directed: std::collections::BTreeSet<(u32, u32)> = self
            .quads
            .iter()
            .flat_map(|q| (0..4).map(move |i| (q[i], q[(i + 1) % 4])))
            .collect();
        let mut next = std::collections::BTreeMap::new();
        for &(a, b) in &directed {
            if !directed.contains(&(b, a)) {
                assert!(
                    next.insert(a, b).is_none(),
                    "vertex {a} is pinched (two boundary edges leave it)"
                );
            }
        }
        let start = *next.keys().next().expect("a patch has a boundary");
        let mut out = vec![start];
        let mut v = next[&start];
        while v != start {
            out.push(v);
            v = next[&v];
            assert!(out.len() <= next.len(), "boundary is not a simple loop");
        }
        assert_eq!(out.len(), next.len(), "the boundary must be a single loop");
        out
    }

    /// Wraps the patch in one ring of quads. Every vertex `v` of the current
    /// boundary loop becomes interior with exactly `valence(v)` quads (= edges):
    /// it gets `valence(v) − fan(v) − 1` radial edges to the ring's outer loop
    /// (new vertices, the new boundary). Between two consecutive radial edges
    /// lies one ring quad, spanning 0, 1 or 2 edges of the old loop (and 2, 1
    /// or 0 of the outer loop). Panics on a request no single ring can meet:
    /// `valence(v) ≤ fan(v)`, or two consecutive loop vertices both without
    /// radial edge.
    pub fn ring(mut self, valence: impl Fn(u32) -> u32) -> Self {
        let lp = self.boundary_loop();
        let m = lp.len();
        let r: Vec<u32> = lp
            .iter()
            .map(|&v| {
                let (t, f) = (valence(v), self.fan(v));
                assert!(
                    t > f,
                    "vertex {v} has {f} quads already: valence {t} is impossible after a ring"
                );
                t - f - 1
            })
            .collect();
        for j in 0..m {
            assert!(
                r[j] > 0 || r[(j + 1) % m] > 0,
                "loop vertices {} and {} both need 0 radial edges",
                lp[j],
                lp[(j + 1) % m]
            );
        }
        let lpts: Vec<[f64; 2]> = lp.iter().map(|&v| self.pts[v as usize]).collect();
        let p = |j: usize| lpts[j % m];
        let mean_edge = (0..m).map(|j| dist(p(j), p(j + 1))).sum::<f64>() / m as f64;
        let w = 0.6 * mean_edge;
        // radial edges in counter-clockwise order along the loop; at one vertex
        // they fan out evenly over its exterior angle, from the previous loop
        // vertex's side to the next one's
        let mut rad: Vec<(usize, [f64; 2])> = Vec::new();
        for (j, &rj) in r.iter().enumerate() {
            let c = p(j);
            let a_prev = ang(c, p(j + m - 1));
            let a_next = ang(c, p(j + 1));
            let ext = (a_next - a_prev).rem_euclid(std::f64::consts::TAU);
            for t in 1..=rj {
                let a = a_prev + ext * t as f64 / (rj + 1) as f64;
                rad.push((j, [c[0] + w * a.cos(), c[1] + w * a.sin()]));
            }
        }
        let n = rad.len();
        let span = |rad: &[(usize, [f64; 2])], i: usize| -> usize {
            let (a, b) = (rad[i].0, rad[(i + 1) % n].0);
            if a == b {
                0
            } else {
                (b + m - a) % m
            }
        };
        // start after a quad whose outer side is not a single point, so that
        // the last quad closes on the first outer vertex without merging it
        let s = (0..n)
            .find(|&i| span(&rad, (i + n - 1) % n) < 2)
            .expect("some ring quad has an outer edge");
        rad.rotate_left(s);
        let push = |pts: &mut Vec<[f64; 2]>, x: [f64; 2]| {
            pts.push(x);
            pts.len() as u32 - 1
        };
        let mut out = vec![u32::MAX; n];
        let mut shared: Option<(u32, [f64; 2], f64)> = None;
        out[0] = push(&mut self.pts, rad[0].1);
        for i in 0..n {
            let nx = (i + 1) % n;
            let e_in = span(&rad, i);
            assert!(e_in <= 2, "a ring quad would span {e_in} loop edges");
            let mut outer = vec![out[i]];
            match e_in {
                2 => {
                    // both radial edges end at the same outer vertex, placed
                    // nearer the end of the vertex with fewer radial edges (its
                    // quads have the least angle to spare)
                    assert_ne!(nx, 0);
                    out[nx] = out[i];
                    let wt = |k: usize| 1.0 / r[rad[k].0] as f64;
                    let (mut sum, mut wsum) = match shared {
                        Some((v, sum, wsum)) if v == out[i] => (sum, wsum),
                        _ => ([wt(i) * rad[i].1[0], wt(i) * rad[i].1[1]], wt(i)),
                    };
                    sum = [
                        sum[0] + wt(nx) * rad[nx].1[0],
                        sum[1] + wt(nx) * rad[nx].1[1],
                    ];
                    wsum += wt(nx);
                    self.pts[out[i] as usize] = [sum[0] / wsum, sum[1] / wsum];
                    shared = Some((out[i], sum, wsum));
                }
                1 => {
                    if nx != 0 {
                        out[nx] = push(&mut self.pts, rad[nx].1);
                    }
                    outer.push(out[nx]);
                }
                _ => {
                    // two radial edges of one vertex: an outer corner between them
                    let c = p(rad[i].0);
                    let (a, b) = (ang(c, rad[i].1), ang(c, rad[nx].1));
                    let mid = a + 0.5 * (b - a).rem_euclid(std::f64::consts::TAU);
                    let x = push(
                        &mut self.pts,
                        [c[0] + 1.3 * w * mid.cos(), c[1] + 1.3 * w * mid.sin()],
                    );
                    if nx != 0 {
                        out[nx] = push(&mut self.pts, rad[nx].1);
                    }
                    outer.push(x);
                    outer.push(out[nx]);
                }
            }
            // inner chain backwards from the next radial's vertex, then the outer chain
            let (a, b) = (rad[i].0, rad[nx].0);
            let mut q: Vec<u32> = (0..=e_in).map(|t| lp[(a + e_in - t) % m]).collect();
            debug_assert_eq!(q[0], lp[b]);
            q.extend(outer);
            self.quads.push([q[0], q[1], q[2], q[3]]);
        }
        self
    }

    /// [`Patch::ring`] aiming at regular vertices: every loop vertex gets
    /// valence 4 (or `overrides`), or one more than it has quads when that is
    /// already 4 or more; where two neighbours on the loop would both need no
    /// radial edge, the second (or the first, if the second is overridden)
    /// gets one more.
    pub fn ring_regular(self, overrides: &[(u32, u32)]) -> Self {
        let lp = self.boundary_loop();
        let m = lp.len();
        let mut t: Vec<u32> = lp
            .iter()
            .map(|&v| {
                overrides
                    .iter()
                    .find(|o| o.0 == v)
                    .map_or((self.fan(v) + 1).max(4), |o| o.1)
            })
            .collect();
        let fixed = |v: u32| overrides.iter().any(|o| o.0 == v);
        for j in 0..m {
            let k = (j + 1) % m;
            if t[j] == self.fan(lp[j]) + 1 && t[k] == self.fan(lp[k]) + 1 {
                let bump = if !fixed(lp[k]) { k } else { j };
                assert!(
                    !fixed(lp[bump]),
                    "overrides of {} and {} both leave no radial edge",
                    lp[j],
                    lp[k]
                );
                t[bump] += 1;
            }
        }
        let map: std::collections::BTreeMap<u32, u32> = lp.into_iter().zip(t).collect();
        self.ring(|v| map[&v])
    }

    /// Evens out the geometry after several rings: the boundary loop goes onto
    /// a circle around the first `pinned` points (spaced like it was along the
    /// loop), then every other vertex with id ≥ `pinned` moves to the mean of
    /// its edge neighbours (Laplacian smoothing). Topology and the first
    /// `pinned` points (the hand-drawn core) are unchanged.
    pub fn relaxed(mut self, pinned: usize) -> Self {
        let lp = self.boundary_loop();
        let m = lp.len();
        let c = self.pts[..pinned].iter().fold([0.0, 0.0], |a, p| {
            [a[0] + p[0] / pinned as f64, a[1] + p[1] / pinned as f64]
        });
        let radius = self.pts.iter().map(|&p| dist(p, c)).fold(0.0, f64::max);
        let len: Vec<f64> = (0..m)
            .map(|j| dist(self.pts[lp[j] as usize], self.pts[lp[(j + 1) % m] as usize]))
            .collect();
        let total: f64 = len.iter().sum();
        let a0 = ang(c, self.pts[lp[0] as usize]);
        let mut s = 0.0;
        for j in 0..m {
            let a = a0 + std::f64::consts::TAU * s / total;
            self.pts[lp[j] as usize] = [c[0] + radius * a.cos(), c[1] + radius * a.sin()];
            s += len[j];
        }
        let mut links = vec![std::collections::BTreeSet::new(); self.pts.len()];
        for q in &self.quads {
            for i in 0..4 {
                links[q[i] as usize].insert(q[(i + 1) % 4]);
                links[q[(i + 1) % 4] as usize].insert(q[i]);
            }
        }
        let free: Vec<usize> = (pinned..self.pts.len())
            .filter(|&v| !lp.contains(&(v as u32)))
            .collect();
        for _ in 0..200 {
            for &v in &free {
                let n = links[v].len() as f64;
                self.pts[v] = links[v].iter().fold([0.0, 0.0], |a, &l| {
                    [
                        a[0] + self.pts[l as usize][0] / n,
                        a[1] + self.pts[l as usize][1] / n,
                    ]
                });
            }
        }
        self
    }

    /// The [`FaceQuads`] of the patch (see [`planar`]): checked, with exactly
    /// the vertices of the outer loop fixed.
    pub fn build(&self) -> FaceQuads {
        let fq = planar(&self.pts, self.quads.clone());
        fq.check().expect("consistent patch");
        let lp = self.boundary_loop();
        for v in 0..fq.verts.len() as u32 {
            assert_eq!(
                fq.verts[v as usize].fixed,
                lp.contains(&v),
                "vertex {v}: fixed iff on the outer loop"
            );
        }
        fq
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn ang(from: [f64; 2], to: [f64; 2]) -> f64 {
    (to[1] - from[1]).atan2(to[0] - from[0])
}
