//! Charts: a patch that no single map flattens well (a disk whose Tutte map
//! is too distorted, a patch with several holes on a curved surface, a
//! patch with handles) is split into *charts*, each a topological disk whose
//! triangle normals stay within a cone, so that a projection onto a plane
//! (or a Tutte map, which is then close to it) parametrizes it with little
//! distortion. The chart borders become curves of the model, like feature
//! curves but only with corners where three charts (or a chart border and a
//! feature curve) meet.
//!
//! Charts grow from a seed triangle, nearest triangle first (distance of
//! centroids to the seed's), taking a neighbour when its normal is within
//! [`CHART_CONE_DEG`] of the seed's and the chart stays a disk: the new
//! triangle shares one edge with the chart and its third vertex is not yet
//! in it, or it shares two edges. Seeds are taken in a fixed order (the
//! patch's triangle order), so the result is deterministic. Tiny charts are
//! then merged into a neighbour when the union stays a disk.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use geometry::{vec3, Vec3};

use crate::topology::Topology;

/// Largest angle (degrees) between a chart triangle's normal and its seed's.
/// Two such normals differ by at most twice this, and every normal is
/// within it of the seed's: below the 72° a plane projection tolerates.
pub const CHART_CONE_DEG: f64 = 50.0;

/// Smallest cone a chart is split with again (a chart that neither projects
/// one-to-one nor has a good Tutte map is split with half its cone, down to
/// this).
pub const MIN_CHART_CONE_DEG: f64 = 10.0;

/// Passes of border smoothing (ears moved to the neighbour chart).
pub const BORDER_PASSES: usize = 8;

/// A chart with fewer triangles than this is merged into a neighbour when
/// the union stays a disk.
pub const MIN_CHART_TRIANGLES: usize = 8;

/// Labels the triangles `tris` (global ids, one patch) with charts;
/// returns the chart of each triangle of `tris` (in its order) and the
/// number of charts. `blocked[e]` edges (feature curves) are never crossed.
/// `cone_deg` bounds the angle between a chart triangle's normal and its
/// seed's ([`CHART_CONE_DEG`] at first).
pub fn split_into_charts(
    points: &[Vec3],
    mesh_tris: &[[u32; 3]],
    topo: &Topology,
    normals: &[Vec3],
    tris: &[u32],
    blocked: &[bool],
    cone_deg: f64,
) -> (Vec<u32>, usize) {
    let n = tris.len();
    let local = LocalIndex::new(mesh_tris.len(), tris);
    let centroid = |t: u32| {
        let [a, b, c] = mesh_tris[t as usize].map(|v| points[v as usize]);
        vec3::scale(vec3::add(vec3::add(a, b), c), 1.0 / 3.0)
    };
    // neighbours across unblocked edges: (local triangle, edge)
    let nbrs = |i: usize| -> Vec<(u32, u32)> {
        let t = tris[i];
        topo.tri_edges[t as usize]
            .iter()
            .filter(|&&e| !blocked[e as usize])
            .filter_map(|&e| {
                let [t0, t1] = topo.edge_tris[e as usize];
                let o = if t0 == t { t1 } else { t0 };
                (o != u32::MAX)
                    .then(|| local.get(&o).map(|&j| (j, e)))
                    .flatten()
            })
            .collect()
    };
    let cos = cone_deg.to_radians().cos();
    let mut chart = vec![u32::MAX; n];
    // vertex → (chart stamp, triangles of that chart using it)
    let mut vert_use: Vec<(u32, u32)> = vec![(u32::MAX, 0); points.len()];
    let mut nchart = 0u32;
    for seed in 0..n {
        if chart[seed] != u32::MAX {
            continue;
        }
        let c = nchart;
        nchart += 1;
        let n0 = normals[tris[seed] as usize];
        let p0 = centroid(tris[seed]);
        let mut heap = BinaryHeap::new();
        heap.push((Reverse(Ordered(0.0)), seed as u32));
        while let Some((_, i)) = heap.pop() {
            let i = i as usize;
            if chart[i] != u32::MAX {
                continue;
            }
            if i != seed && !keeps_disk(mesh_tris, topo, tris, &local, &chart, &vert_use, c, i) {
                continue;
            }
            chart[i] = c;
            for v in mesh_tris[tris[i] as usize] {
                let e = &mut vert_use[v as usize];
                if e.0 != c {
                    *e = (c, 0);
                }
                e.1 += 1;
            }
            for (j, _) in nbrs(i) {
                let j = j as usize;
                if chart[j] == u32::MAX && vec3::dot(normals[tris[j] as usize], n0) >= cos {
                    heap.push((
                        Reverse(Ordered(vec3::dist(centroid(tris[j]), p0))),
                        j as u32,
                    ));
                }
            }
        }
    }
    let seeds_normal: Vec<Vec3> = {
        let mut first = vec![u32::MAX; nchart as usize];
        for (i, &c) in chart.iter().enumerate() {
            if first[c as usize] == u32::MAX {
                first[c as usize] = i as u32;
            }
        }
        first
            .iter()
            .map(|&i| normals[tris[i as usize] as usize])
            .collect()
    };
    smooth_borders(
        mesh_tris,
        topo,
        tris,
        normals,
        &local,
        blocked,
        &seeds_normal,
        cos,
        &mut chart,
    );
    merge_small(
        mesh_tris,
        topo,
        tris,
        &local,
        blocked,
        &mut chart,
        nchart as usize,
    )
}

/// Border smoothing passes: a triangle of chart A with two edges on chart B
/// (an ear of A poking into B) moves to B when A stays a disk (its third
/// vertex has no other triangle of A) and its normal is within the cone of
/// B's seed. Jagged borders would otherwise make the mesher's chords between
/// border samples leave the chart's projected image.
#[allow(clippy::too_many_arguments)]
fn smooth_borders(
    mesh_tris: &[[u32; 3]],
    topo: &Topology,
    tris: &[u32],
    normals: &[Vec3],
    local: &LocalIndex,
    blocked: &[bool],
    seed_normal: &[Vec3],
    cos: f64,
    chart: &mut [u32],
) {
    // vertex → local triangles using it (compressed rows)
    let nv = mesh_tris
        .iter()
        .flatten()
        .map(|&v| v as usize + 1)
        .max()
        .unwrap_or(0);
    let mut start = vec![0u32; nv + 1];
    for &t in tris {
        for v in mesh_tris[t as usize] {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut items = vec![0u32; start[nv] as usize];
    for (i, &t) in tris.iter().enumerate() {
        for v in mesh_tris[t as usize] {
            items[fill[v as usize] as usize] = i as u32;
            fill[v as usize] += 1;
        }
    }
    let vert_tris = |v: u32| &items[start[v as usize] as usize..start[v as usize + 1] as usize];
    for _ in 0..BORDER_PASSES {
        let mut moved = 0;
        for i in 0..tris.len() {
            let t = tris[i] as usize;
            let a = chart[i];
            // chart across each edge (u32::MAX: blocked or outside)
            let across: Vec<u32> = topo.tri_edges[t]
                .iter()
                .map(|&e| {
                    if blocked[e as usize] {
                        return u32::MAX;
                    }
                    let [t0, t1] = topo.edge_tris[e as usize];
                    let o = if t0 as usize == t { t1 } else { t0 };
                    local.get(&o).map_or(u32::MAX, |&j| chart[j as usize])
                })
                .collect();
            for k in 0..3 {
                // edges k+1 and k+2 on chart b, edge k on a
                let (b, b2) = (across[(k + 1) % 3], across[(k + 2) % 3]);
                if across[k] != a || b != b2 || b == u32::MAX || b == a {
                    continue;
                }
                // vertex shared by edges k+1 and k+2: vertex k+2
                let v = mesh_tris[t][(k + 2) % 3];
                let others_in_a = vert_tris(v)
                    .iter()
                    .filter(|&&j| j as usize != i && chart[j as usize] == a)
                    .count();
                if others_in_a == 0 && vec3::dot(normals[t], seed_normal[b as usize]) >= cos {
                    chart[i] = b;
                    moved += 1;
                    break;
                }
            }
        }
        if moved == 0 {
            break;
        }
    }
}

/// True when adding local triangle `i` to chart `c` keeps it a disk.
fn keeps_disk(
    mesh_tris: &[[u32; 3]],
    topo: &Topology,
    tris: &[u32],
    local: &LocalIndex,
    chart: &[u32],
    vert_use: &[(u32, u32)],
    c: u32,
    i: usize,
) -> bool {
    let t = tris[i] as usize;
    let in_chart = |v: u32| vert_use[v as usize].0 == c && vert_use[v as usize].1 > 0;
    let mut shared = 0;
    let mut shared_edge = [u32::MAX; 2];
    for (k, &e) in topo.tri_edges[t].iter().enumerate() {
        let [t0, t1] = topo.edge_tris[e as usize];
        let o = if t0 as usize == t { t1 } else { t0 };
        if o != u32::MAX && local.get(&o).is_some_and(|&j| chart[j as usize] == c) {
            shared += 1;
            shared_edge = [mesh_tris[t][k], mesh_tris[t][(k + 1) % 3]];
        }
    }
    match shared {
        1 => {
            let third = mesh_tris[t]
                .iter()
                .copied()
                .find(|v| !shared_edge.contains(v))
                .unwrap_or(u32::MAX);
            !in_chart(third)
        }
        2 => true,
        _ => false,
    }
}

/// Merges charts of fewer than [`MIN_CHART_TRIANGLES`] triangles into the
/// neighbour sharing the most edges, when the union stays a disk (checked by
/// its Euler characteristic and boundary loops); renumbers the charts.
fn merge_small(
    mesh_tris: &[[u32; 3]],
    topo: &Topology,
    tris: &[u32],
    local: &LocalIndex,
    blocked: &[bool],
    chart: &mut [u32],
    nchart: usize,
) -> (Vec<u32>, usize) {
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); nchart];
    for (i, &c) in chart.iter().enumerate() {
        members[c as usize].push(i as u32);
    }
    for c in 0..nchart {
        if members[c].is_empty() || members[c].len() >= MIN_CHART_TRIANGLES {
            continue;
        }
        // neighbour charts by shared edges, most first (ties: lowest id)
        let mut counts: std::collections::BTreeMap<u32, usize> = std::collections::BTreeMap::new();
        for &i in &members[c] {
            let t = tris[i as usize];
            for &e in &topo.tri_edges[t as usize] {
                if blocked[e as usize] {
                    continue;
                }
                let [t0, t1] = topo.edge_tris[e as usize];
                let o = if t0 == t { t1 } else { t0 };
                if let Some(&j) = local.get(&o) {
                    let d = chart[j as usize];
                    if d as usize != c {
                        *counts.entry(d).or_default() += 1;
                    }
                }
            }
        }
        let mut order: Vec<(usize, u32)> = counts.into_iter().map(|(d, k)| (k, d)).collect();
        order.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, d) in order {
            let union: Vec<u32> = members[d as usize]
                .iter()
                .chain(&members[c])
                .map(|&i| tris[i as usize])
                .collect();
            if is_disk(mesh_tris, topo, &union) {
                for &i in &members[c] {
                    chart[i as usize] = d;
                }
                let moved = std::mem::take(&mut members[c]);
                members[d as usize].extend(moved);
                break;
            }
        }
    }
    // renumber in order of first triangle
    let mut new_id = vec![u32::MAX; nchart];
    let mut k = 0u32;
    for c in chart.iter_mut() {
        if new_id[*c as usize] == u32::MAX {
            new_id[*c as usize] = k;
            k += 1;
        }
        *c = new_id[*c as usize];
    }
    (chart.to_vec(), k as usize)
}

/// True when the triangles (global ids) form a topological disk: Euler
/// characteristic 1, one boundary loop, no pinched vertex.
pub fn is_disk(mesh_tris: &[[u32; 3]], topo: &Topology, tris: &[u32]) -> bool {
    let set: std::collections::HashSet<u32> = tris.iter().copied().collect();
    let mut verts = std::collections::HashSet::new();
    let mut edges = std::collections::HashSet::new();
    // boundary edges: vertex → outgoing boundary edge count
    let mut out_deg: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
    let mut nb = 0usize;
    for &t in tris {
        for (k, &e) in topo.tri_edges[t as usize].iter().enumerate() {
            edges.insert(e);
            let [t0, t1] = topo.edge_tris[e as usize];
            let o = if t0 == t { t1 } else { t0 };
            if o == u32::MAX || !set.contains(&o) {
                nb += 1;
                *out_deg.entry(mesh_tris[t as usize][k]).or_default() += 1;
            }
        }
        verts.extend(mesh_tris[t as usize]);
    }
    if out_deg.values().any(|&d| d > 1) || nb == 0 {
        return false;
    }
    // one loop: the boundary vertices count equals the boundary edges, and
    // Euler characteristic 1 (with no pinch, loops = 2 - χ - 2g; χ = 1 gives
    // one loop and genus 0)
    let euler = verts.len() as i64 - edges.len() as i64 + tris.len() as i64;
    euler == 1
}

/// Position of each global triangle in the patch's list (`u32::MAX` outside).
struct LocalIndex(Vec<u32>);

impl LocalIndex {
    fn new(ntris: usize, tris: &[u32]) -> Self {
        let mut v = vec![u32::MAX; ntris];
        for (i, &t) in tris.iter().enumerate() {
            v[t as usize] = i as u32;
        }
        LocalIndex(v)
    }
    fn get(&self, t: &u32) -> Option<&u32> {
        self.0.get(*t as usize).filter(|&&i| i != u32::MAX)
    }
}

/// An `f64` ordered for the heap by `total_cmp` (no NaN reaches it:
/// distances); equality and both orders agree.
#[derive(Clone, Copy)]
struct Ordered(f64);
impl PartialEq for Ordered {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed cylinder side (k around, m high) as triangles, without caps.
    fn tube(k: usize, m: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..=m {
            for i in 0..k {
                let a = i as f64 / k as f64 * std::f64::consts::TAU;
                p.push([a.cos(), a.sin(), j as f64 * 0.3]);
            }
        }
        let id = |i: usize, j: usize| (j * k + i % k) as u32;
        let mut t = Vec::new();
        for j in 0..m {
            for i in 0..k {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (p, t)
    }

    #[test]
    fn a_tube_splits_into_disk_charts_within_the_cone() {
        let (p, t) = tube(24, 6);
        let topo = crate::topology::build(&t).unwrap();
        let normals = crate::features::tri_normals(&p, &t);
        let all: Vec<u32> = (0..t.len() as u32).collect();
        let blocked = vec![false; topo.edges.len()];
        let (label, n) = split_into_charts(&p, &t, &topo, &normals, &all, &blocked, CHART_CONE_DEG);
        // 360° of normals in cones of ±50°: at least 4 charts
        assert!(n >= 4, "{n} charts");
        assert!(n <= 8, "{n} charts");
        for c in 0..n as u32 {
            let members: Vec<u32> = all
                .iter()
                .copied()
                .filter(|&i| label[i as usize] == c)
                .collect();
            assert!(is_disk(&t, &topo, &members), "chart {c} is not a disk");
            // every pair of normals within twice the cone
            let lim = (2.0 * CHART_CONE_DEG).to_radians().cos() - 1e-9;
            for &a in &members {
                for &b in &members {
                    assert!(vec3::dot(normals[a as usize], normals[b as usize]) >= lim);
                }
            }
        }
        // the whole tube is no disk (an annulus), one row of it is not either
        assert!(!is_disk(&t, &topo, &all));
    }
}
