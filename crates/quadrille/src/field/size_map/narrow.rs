//! The width rule of the size map ([`super::SizeMapOptions::floor_narrow`]):
//! which faces are strips narrower than the floor, and how wide they are.
//!
//! A face is a strip when it is long for its mean width `w = 2 A / P` (area
//! `A`, boundary length `P`; [`NARROW_ELONGATION`]) and its width is even
//! along it ([`NARROW_EVENNESS`]): a fillet or a gear flank between two
//! parallel curves, not a chamfer crescent or a vanishing fillet whose width
//! tapers to nothing. The width along the face is read on its boundary: at
//! each boundary vertex, the distance to the nearest boundary point *across*
//! the face (on another loop, or at least [`ACROSS_DETOUR`] times as far
//! along the loop as in space: the same side is never that far round).

use geometry::vec3;

use crate::field::crossfield::topology::NONE;
use crate::field::crossfield::FaceTopology;

/// A strip narrower than this fraction of the floor is left at the floor by
/// [`super::SizeMapOptions::floor_narrow`]: such faces are slivers or
/// crescents tapering to nothing (the chamfer crescents of a hex nut), whose
/// widths dragged the floor down to a tenth and the nut from 2,856 to
/// 170,728 quads; two quads across them would be thin anyway.
pub const NARROW_MIN_FRACTION: f64 = 0.25;

/// How many times longer than wide a face must be for
/// [`super::SizeMapOptions::floor_narrow`]: length `P / 2 − w` at least this
/// times the width `w` (a compact face narrower than the floor is a small
/// face, which the curves' minimum counts already resolve).
pub const NARROW_ELONGATION: f64 = 3.0;

/// A boundary point is across the face from a boundary vertex when it lies
/// on another loop, or at least this many times farther from the vertex
/// along their loop than in space. Along one side of a strip the two are
/// about equal (a side bent into a half circle: π/2); across a strip of
/// width `w`, `w` apart in space, the way round is at least `w` longer.
pub const ACROSS_DETOUR: f64 = 2.0;

/// The boundary-length quantiles of the local width that
/// [`width_evenness`] compares: the 10 % and the 40 % quantile. Both lie
/// below the half of the boundary that the ends of a short strip can hold
/// (their vertices have no point across, or a far one).
pub const EVENNESS_QUANTILES: (f64, f64) = (0.1, 0.4);

/// A face is a strip of even width for
/// [`super::SizeMapOptions::floor_narrow`] when [`width_evenness`] is at
/// least this. A strip of constant width reads 1; a face whose width tapers
/// linearly to nothing (a lens, a vanishing fillet) reads 0.25 and a
/// parabolic crescent (a hex nut's chamfer crescent) 0.30.
pub const NARROW_EVENNESS: f64 = 0.6;

/// The mean width `2 A / P` of a face's background triangulation (area
/// `A`, boundary length `P`) when the face is at least
/// [`NARROW_ELONGATION`] times as long (`P / 2 − w`) as that, else `None`.
pub(super) fn narrow_width(topo: &FaceTopology) -> Option<f64> {
    let area: f64 = topo.areas.iter().sum();
    let perimeter: f64 = boundary_edges(topo)
        .map(|[a, b]| vec3::dist(topo.positions[a], topo.positions[b]))
        .sum();
    if !(area > 0.0 && perimeter > 0.0) {
        return None;
    }
    let width = 2.0 * area / perimeter;
    let length = 0.5 * perimeter - width;
    (length >= NARROW_ELONGATION * width).then_some(width)
}

/// How even a face's width is: the ratio of the [`EVENNESS_QUANTILES`] of
/// its local width ([`local_widths`]), weighted by boundary length. 1 for a
/// strip of constant width, small for a face tapering to nothing. `None`
/// when the boundary is not a set of simple loops or no vertex has a point
/// across.
pub fn width_evenness(topo: &FaceTopology) -> Option<f64> {
    let widths = local_widths(topo)?;
    let low = weighted_quantile(&widths, EVENNESS_QUANTILES.0)?;
    let mid = weighted_quantile(&widths, EVENNESS_QUANTILES.1)?;
    (mid.is_finite() && mid > 0.0).then(|| low / mid)
}

/// The number of boundary loops of a face's triangulation; `None` when a
/// boundary vertex does not have exactly two boundary edges. The width rule
/// takes faces of one loop: a strip with two ends (a fillet, a gear flank).
/// A band around an axis (two loops: a chamfer or fillet of revolution)
/// is left at the floor, as its long sides are whole loops of the faces
/// beside it (a screw's shank and head, a bearing's races): a lowered floor
/// there refined those faces around their whole circumference
/// (`shoulder_screw_m6x20` 1,695 → 4,813 quads, average SICN 0.863 → 0.789).
pub fn boundary_loop_count(topo: &FaceTopology) -> Option<usize> {
    boundary_loops(topo).map(|l| l.len())
}

/// The boundary edges of a triangulation (one triangle), as vertex pairs.
fn boundary_edges(topo: &FaceTopology) -> impl Iterator<Item = [usize; 2]> + '_ {
    topo.edges
        .iter()
        .zip(&topo.edge_tris)
        .filter(|(_, t)| t[1] == NONE)
        .map(|(e, _)| [e[0] as usize, e[1] as usize])
}

/// One closed boundary loop: its vertices in order, the arc length at each
/// from the first, and its length.
struct Loop {
    vertices: Vec<usize>,
    arc: Vec<f64>,
    length: f64,
}

/// The boundary loops of a triangulation; `None` when a boundary vertex
/// does not have exactly two boundary edges (not simple loops).
fn boundary_loops(topo: &FaceTopology) -> Option<Vec<Loop>> {
    let n = topo.positions.len();
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
    for [a, b] in boundary_edges(topo) {
        next[a].push(b);
        next[b].push(a);
    }
    if next.iter().any(|x| !x.is_empty() && x.len() != 2) {
        return None;
    }
    let mut seen = vec![false; n];
    let mut loops = Vec::new();
    for start in 0..n {
        if seen[start] || next[start].is_empty() {
            continue;
        }
        let (mut prev, mut v) = (start, start);
        let (mut vertices, mut arc, mut s) = (Vec::new(), Vec::new(), 0.0);
        loop {
            seen[v] = true;
            vertices.push(v);
            arc.push(s);
            let w = if next[v][0] != prev {
                next[v][0]
            } else {
                next[v][1]
            };
            s += vec3::dist(topo.positions[v], topo.positions[w]);
            (prev, v) = (v, w);
            if v == start {
                break;
            }
            if seen[v] {
                return None;
            }
        }
        loops.push(Loop {
            vertices,
            arc,
            length: s,
        });
    }
    Some(loops)
}

/// The local width at every boundary vertex with the boundary length it
/// stands for (half of its two edges): the distance to the nearest point of
/// a boundary edge across the face ([`ACROSS_DETOUR`]), +∞ when there is
/// none (the middle of a strip's end). `None` when the boundary is not a set
/// of simple loops.
pub fn local_widths(topo: &FaceTopology) -> Option<Vec<(f64, f64)>> {
    let loops = boundary_loops(topo)?;
    let p = &topo.positions;
    let mut out = Vec::new();
    for (li, l) in loops.iter().enumerate() {
        let m = l.vertices.len();
        for i in 0..m {
            let v = l.vertices[i];
            let prev = l.vertices[(i + m - 1) % m];
            let next = l.vertices[(i + 1) % m];
            let weight = 0.5 * (vec3::dist(p[prev], p[v]) + vec3::dist(p[v], p[next]));
            let mut width = f64::INFINITY;
            for (lj, k) in loops.iter().enumerate() {
                let km = k.vertices.len();
                for j in 0..km {
                    let (a, b) = (k.vertices[j], k.vertices[(j + 1) % km]);
                    if a == v || b == v {
                        continue;
                    }
                    let (d, t) = vec3::segment_closest(p[v], p[a], p[b]);
                    if d >= width {
                        continue;
                    }
                    let across = if li != lj {
                        true
                    } else {
                        let end = if j + 1 == km { k.length } else { k.arc[j + 1] };
                        let s = k.arc[j] + t * (end - k.arc[j]);
                        let along = (s - l.arc[i]).abs();
                        along.min(l.length - along) >= ACROSS_DETOUR * d
                    };
                    if across {
                        width = d;
                    }
                }
            }
            out.push((width, weight));
        }
    }
    Some(out)
}

/// The value below which the fraction `q` of the total weight lies (values
/// `(value, weight)`); `None` when the total weight is not positive.
pub(super) fn weighted_quantile(values: &[(f64, f64)], q: f64) -> Option<f64> {
    let total: f64 = values.iter().map(|x| x.1).sum();
    if !(total > 0.0) {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut below = 0.0;
    for &(v, w) in &sorted {
        below += w;
        if below >= q * total {
            return Some(v);
        }
    }
    sorted.last().map(|x| x.0)
}
