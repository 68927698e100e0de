//! Dense quads of one paired cycle (spec §6.4): one interval count per chord,
//! every layout edge sampled once by arc length (boundary nodes on the input
//! polyline), each layout quad filled by its bicubically blended discrete
//! Coons surface, the quads welded along shared edges.

use geometry::vec3::Vec3;

use super::geometry::{coons_point, rung_curves, segment_points, Polyline};
use super::layout::{embed, EdgeKind, Layout, LayoutError};
use super::PairedCycle;

/// The dense quad mesh of one cycle and the layout it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct CycleQuads {
    /// Node positions.
    pub nodes: Vec<Vec3>,
    /// Quads, counter-clockwise with the surface on the left of the cycle's
    /// direction (normal by the right-hand rule).
    pub quads: Vec<[usize; 4]>,
    /// Per node: on the input polyline.
    pub boundary: Vec<bool>,
    /// The coarse layout (vertex `k` is node `k`).
    pub layout: Layout,
    /// Number of layout quads (patches).
    pub patches: usize,
    /// Valence of each interior layout vertex.
    pub interior_vertex_valences: Vec<usize>,
    /// Interval count of each chord (each edge it crosses gets this many).
    pub intervals: Vec<usize>,
}

/// The quads of one paired cycle at target edge length `h`: layout (§5),
/// geometry (§6.1–6.3), sampling (§6.4). A disconnected chord graph is an
/// error naming the cut (see [`super::cut::find_cut`]).
pub fn quadrangulate(cycle: &PairedCycle, h: f64) -> Result<CycleQuads, LayoutError> {
    quadrangulate_with_minimums(cycle, h, &[])
}

/// [`quadrangulate`] with a smallest interval count per segment:
/// `minimums[s]` (0 or absent: none) raises the count of the chord ending at
/// segment `s`. The caller uses it to sample a cut shared by two parts
/// (Fig. 10) alike on both sides.
pub fn quadrangulate_with_minimums(
    cycle: &PairedCycle,
    h: f64,
    minimums: &[usize],
) -> Result<CycleQuads, LayoutError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(LayoutError::BadSize { h });
    }
    let layout = embed(cycle)?;
    Ok(sample_layout(cycle, layout, h, minimums))
}

/// Per chord: n = max(⌈len_i / h⌉, ⌈len_j / h⌉, 1) over its two segments,
/// raised to `minimums[i]` and `minimums[j]` where given.
pub fn chord_intervals(cycle: &PairedCycle, layout: &Layout, h: f64, minimums: &[usize]) -> Vec<usize> {
    let least = |s: usize| minimums.get(s).copied().unwrap_or(0);
    layout
        .chords
        .iter()
        .map(|&(i, j)| {
            let li = Polyline::new(segment_points(cycle, i)).length();
            let lj = Polyline::new(segment_points(cycle, j)).length();
            let n = (li / h).ceil().max((lj / h).ceil()).max(1.0) as usize;
            n.max(least(i)).max(least(j))
        })
        .collect()
}

/// Samples a layout (interior vertices placed) into welded dense quads.
pub fn sample_layout(cycle: &PairedCycle, layout: Layout, h: f64, minimums: &[usize]) -> CycleQuads {
    let intervals = chord_intervals(cycle, &layout, h, minimums);
    sample_layout_with_intervals(cycle, layout, intervals)
}

/// Samples a layout with given interval counts, one per `layout.chords`
/// entry (the network stage's, spec §7.4).
pub fn sample_layout_with_intervals(cycle: &PairedCycle, layout: Layout, intervals: Vec<usize>) -> CycleQuads {
    let curves = rung_curves(&layout, cycle);
    let mut nodes: Vec<Vec3> = layout.positions.clone();
    let mut boundary: Vec<bool> = (0..nodes.len())
        .map(|v| v < layout.boundary_vertices)
        .collect();
    // The node ids along each edge, from ends[0] to ends[1].
    let mut edge_nodes: Vec<Vec<usize>> = Vec::with_capacity(layout.edges.len());
    for (e, edge) in layout.edges.iter().enumerate() {
        let k = intervals[edge.chord];
        let pts = curves[e].resample(k);
        let mut ids = vec![edge.ends[0]];
        for p in &pts[1..k] {
            ids.push(nodes.len());
            nodes.push(*p);
            boundary.push(matches!(edge.kind, EdgeKind::Boundary(_)));
        }
        ids.push(edge.ends[1]);
        edge_nodes.push(ids);
    }
    let mut quads = Vec::new();
    for q in &layout.quads {
        let side = |t: usize| -> (Vec<usize>, Polyline) {
            let (e, fwd) = q.sides[t];
            if fwd {
                (edge_nodes[e].clone(), curves[e].clone())
            } else {
                (
                    edge_nodes[e].iter().rev().copied().collect(),
                    curves[e].reversed(),
                )
            }
        };
        let (b_ids, b) = side(0);
        let (r_ids, r) = side(1);
        let (t_ids_rev, t_rev) = side(2);
        let (l_ids_rev, l_rev) = side(3);
        let t_ids: Vec<usize> = t_ids_rev.into_iter().rev().collect();
        let l_ids: Vec<usize> = l_ids_rev.into_iter().rev().collect();
        let (t, l) = (t_rev.reversed(), l_rev.reversed());
        let mu = b_ids.len() - 1;
        let mv = r_ids.len() - 1;
        let mut grid = vec![vec![0usize; mv + 1]; mu + 1];
        for a in 0..=mu {
            for bb in 0..=mv {
                grid[a][bb] = if a == 0 {
                    l_ids[bb]
                } else if a == mu {
                    r_ids[bb]
                } else if bb == 0 {
                    b_ids[a]
                } else if bb == mv {
                    t_ids[a]
                } else {
                    // Equal arc-length samples on opposite sides: the discrete
                    // parameters are the sample fractions.
                    let (u, v) = (a as f64 / mu as f64, bb as f64 / mv as f64);
                    nodes.push(coons_point(&b, &r, &t, &l, u, v));
                    boundary.push(false);
                    nodes.len() - 1
                };
            }
        }
        for a in 0..mu {
            for bb in 0..mv {
                quads.push([
                    grid[a][bb],
                    grid[a + 1][bb],
                    grid[a + 1][bb + 1],
                    grid[a][bb + 1],
                ]);
            }
        }
    }
    let patches = layout.quads.len();
    let interior_vertex_valences = layout.interior_valences();
    CycleQuads {
        nodes,
        quads,
        boundary,
        layout,
        patches,
        interior_vertex_valences,
        intervals,
    }
}
