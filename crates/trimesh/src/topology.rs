//! Topology of the welded triangles: degenerate triangles dropped, the edge
//! table (each edge with its one or two triangles), non-manifold edges
//! rejected, and a consistent orientation per connected component (outward
//! on closed components).
//!
//! Decisions (documented in the crate docs):
//! - a triangle with a repeated vertex or a zero area (below 1e-14 of the
//!   squared bounding-box diagonal) is dropped with a warning; if every
//!   triangle is degenerate the mesh is rejected;
//! - an edge shared by more than two triangles is an error naming the edge's
//!   end points (non-manifold input is not split into sheets);
//! - orientation is propagated across manifold edges by a breadth-first
//!   search; a component that cannot be oriented (a Möbius strip) is an error;
//!   a closed component with negative signed volume is flipped so that its
//!   normals point outward.

use geometry::{vec3, Vec3};

/// The edge table of a triangle mesh.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Edges as sorted vertex pairs.
    pub edges: Vec<[u32; 2]>,
    /// The one or two triangles of each edge (`u32::MAX` when only one).
    pub edge_tris: Vec<[u32; 2]>,
    /// Edge `k` of each triangle joins its vertices `k` and `k + 1`.
    pub tri_edges: Vec<[u32; 3]>,
}

impl Topology {
    /// True when edge `e` has a single triangle (open boundary).
    pub fn is_boundary(&self, e: usize) -> bool {
        self.edge_tris[e][1] == u32::MAX
    }
}

/// Drops degenerate triangles; returns the kept triangles, how many were
/// dropped and the 1-based number of the first dropped one.
pub fn drop_degenerate(
    points: &[Vec3],
    tris: &[[u32; 3]],
    area_tol: f64,
) -> (Vec<[u32; 3]>, usize, Option<usize>) {
    let mut out = Vec::with_capacity(tris.len());
    let mut first = None;
    for (i, t) in tris.iter().enumerate() {
        let [a, b, c] = t.map(|v| points[v as usize]);
        let area2 = vec3::norm(vec3::cross(vec3::sub(b, a), vec3::sub(c, a)));
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(area2 > area_tol) {
            first.get_or_insert(i + 1);
            continue;
        }
        out.push(*t);
    }
    let dropped = tris.len() - out.len();
    (out, dropped, first)
}

/// Builds the edge table; `Err` names a non-manifold edge (its two vertices).
pub fn build(tris: &[[u32; 3]]) -> Result<Topology, (u32, u32, usize)> {
    let mut half: Vec<(u64, u32)> = Vec::with_capacity(3 * tris.len());
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = ((a.min(b) as u64) << 32) | a.max(b) as u64;
            half.push((key, (t as u32) * 3 + k as u32));
        }
    }
    half.sort_unstable();
    let mut edges = Vec::with_capacity(half.len() / 2 + 1);
    let mut edge_tris = Vec::with_capacity(half.len() / 2 + 1);
    let mut tri_edges = vec![[0u32; 3]; tris.len()];
    let mut i = 0;
    while i < half.len() {
        let key = half[i].0;
        let mut j = i;
        while j < half.len() && half[j].0 == key {
            j += 1;
        }
        if j - i > 2 {
            return Err(((key >> 32) as u32, key as u32, j - i));
        }
        let e = edges.len() as u32;
        edges.push([(key >> 32) as u32, key as u32]);
        let mut et = [u32::MAX; 2];
        for (s, h) in half[i..j].iter().enumerate() {
            et[s] = h.1 / 3;
            tri_edges[(h.1 / 3) as usize][(h.1 % 3) as usize] = e;
        }
        edge_tris.push(et);
        i = j;
    }
    Ok(Topology {
        edges,
        edge_tris,
        tri_edges,
    })
}

/// True when triangle `t` traverses edge `[a, b]` from a to b.
fn runs(t: &[u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
}

/// Orients every component consistently (breadth-first); closed components
/// outward. Returns the number of flipped triangles, or `Err(triangle)` for a
/// non-orientable component (0-based triangle where the conflict shows).
pub fn orient(points: &[Vec3], tris: &mut [[u32; 3]], topo: &Topology) -> Result<usize, usize> {
    let n = tris.len();
    let mut comp = vec![u32::MAX; n];
    let mut flipped = vec![false; n];
    let mut ncomp = 0u32;
    let mut queue = Vec::new();
    for seed in 0..n {
        if comp[seed] != u32::MAX {
            continue;
        }
        comp[seed] = ncomp;
        queue.clear();
        queue.push(seed);
        let mut closed = true;
        let mut members = Vec::new();
        while let Some(t) = queue.pop() {
            members.push(t);
            for k in 0..3 {
                let e = topo.tri_edges[t][k] as usize;
                let [t0, t1] = topo.edge_tris[e];
                if t1 == u32::MAX {
                    closed = false;
                    continue;
                }
                let o = if t0 as usize == t { t1 } else { t0 } as usize;
                // t may have been flipped already: take the edge's direction in t now
                let [p, q] = topo.edges[e];
                let (a, b) = if runs(&tris[t], p, q) { (p, q) } else { (q, p) };
                let consistent = runs(&tris[o], b, a);
                if comp[o] == u32::MAX {
                    comp[o] = ncomp;
                    if !consistent {
                        tris[o].swap(1, 2);
                        flipped[o] = !flipped[o];
                    }
                    queue.push(o);
                } else if !consistent {
                    return Err(o);
                }
            }
        }
        if closed {
            let mut vol = 0.0;
            for &t in &members {
                let [a, b, c] = tris[t].map(|v| points[v as usize]);
                vol += vec3::dot(a, vec3::cross(b, c));
            }
            if vol < 0.0 {
                for &t in &members {
                    tris[t].swap(1, 2);
                    flipped[t] = !flipped[t];
                }
            }
        }
        ncomp += 1;
    }
    // the edge table stays valid: edges are unordered pairs and a swap of
    // vertices 1 and 2 permutes the triangle's edges, fixed by the caller
    Ok(flipped.iter().filter(|&&f| f).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tet() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        (p, vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    }

    #[test]
    fn orientation_is_repaired_and_outward() {
        let (p, mut t) = tet();
        t[1].swap(1, 2);
        t[2].swap(0, 1);
        let topo = build(&t).unwrap();
        let flipped = orient(&p, &mut t, &topo).unwrap();
        assert!(flipped >= 1);
        let vol: f64 = t
            .iter()
            .map(|tr| {
                let [a, b, c] = tr.map(|v| p[v as usize]);
                vec3::dot(a, vec3::cross(b, c))
            })
            .sum();
        assert!(vol > 0.0);
        let topo = build(&t).unwrap();
        assert_eq!(orient(&p, &mut t, &topo).unwrap(), 0);
    }

    #[test]
    fn non_manifold_edge_is_reported() {
        let t = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
        assert_eq!(build(&t).unwrap_err(), (0, 1, 3));
    }

    #[test]
    fn mobius_strip_is_not_orientable() {
        // a strip of 6 quads closed with a half twist
        let n = 6;
        let mut p = Vec::new();
        for i in 0..n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            p.push([a.cos(), a.sin(), -0.3]);
            p.push([a.cos(), a.sin(), 0.3]);
        }
        let mut t = Vec::new();
        for i in 0..n {
            let (a, b) = (2 * i as u32, 2 * i as u32 + 1);
            let (c, d) = if i + 1 < n {
                (2 * (i + 1) as u32, 2 * (i + 1) as u32 + 1)
            } else {
                (1, 0)
            };
            t.push([a, c, d]);
            t.push([a, d, b]);
        }
        let topo = build(&t).unwrap();
        assert!(orient(&p, &mut t, &topo).is_err());
    }
}
