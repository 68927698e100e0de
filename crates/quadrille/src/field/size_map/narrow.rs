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

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::CurveId;

use super::{BackgroundGraph, FaceBackground};
use crate::core::patch::NodeRef;

use crate::field::crossfield::topology::NONE;
use crate::field::crossfield::FaceTopology;

/// A boundary curve of a strip counts as one of its long sides when its
/// chord is at least this many times the strip's width
/// ([`keep_strips_off_wide_faces`]).
pub const LONG_SIDE_WIDTHS: f64 = 4.0;

/// A long side is straight when no point of it is farther from its chord
/// than this fraction of the chord ([`keep_strips_off_wide_faces`]).
pub const STRAIGHT_SAG: f64 = 0.02;

/// A face whose mean width `2 A / P` is at least this many times the floor
/// is a wide face for [`keep_strips_off_wide_faces`]: the width rule's
/// grading would refine much of it.
pub const WIDE_FACE_FLOORS: f64 = 4.0;

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
    let (width, perimeter) = mean_width(topo)?;
    let length = 0.5 * perimeter - width;
    (length >= NARROW_ELONGATION * width).then_some(width)
}

/// The mean width `2 A / P` of a face's background triangulation and its
/// boundary length `P`; `None` for an empty face.
fn mean_width(topo: &FaceTopology) -> Option<(f64, f64)> {
    let area: f64 = topo.areas.iter().sum();
    let perimeter: f64 = boundary_edges(topo)
        .map(|[a, b]| vec3::dist(topo.positions[a], topo.positions[b]))
        .sum();
    (area > 0.0 && perimeter > 0.0).then(|| (2.0 * area / perimeter, perimeter))
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

/// The width rule's lowered floor per face
/// ([`super::SizeMapOptions::floor_narrow`]): the mean width `w` of a strip
/// ([`narrow_width`]) at least [`NARROW_MIN_FRACTION`] of the floor `lo`,
/// below both `lo` and the face's turn floor `by_turn[i]`, with one boundary
/// loop and an even width ([`NARROW_EVENNESS`]); +∞ for every other face.
pub(super) fn width_floors(faces: &[FaceBackground<'_>], by_turn: &[f64], lo: f64) -> Vec<f64> {
    faces
        .iter()
        .zip(by_turn)
        .map(|(f, &by_turn)| {
            narrow_width(f.topo)
                .filter(|&w| w >= NARROW_MIN_FRACTION * lo && w < lo.min(by_turn))
                .filter(|&w| {
                    let loops = boundary_loop_count(f.topo);
                    let even = width_evenness(f.topo);
                    tracing::debug!(
                        "width rule: face {} width {w:.4} (floor {lo:.4}) loops {loops:?} \
                         evenness {even:?}",
                        f.face.idx() + 1
                    );
                    loops == Some(1) && even.is_some_and(|e| e >= NARROW_EVENNESS)
                })
                .unwrap_or(f64::INFINITY)
        })
        .collect()
}

/// Drops the lowered floor (the turn rule's 90° arc or the width rule's
/// width) from faces whose lowered floor would spill into a wide face along
/// a straight side: a face (lowered floor `floors[i]`, +∞ when neither rule
/// lowers face `i`) sharing a long straight boundary curve
/// ([`LONG_SIDE_WIDTHS`] × `floors[i]`, [`STRAIGHT_SAG`]) with a wide face
/// (mean width at least [`WIDE_FACE_FLOORS`] × the floor `lo`) or with a face
/// so dropped is set back to +∞, repeated until no face changes. Along a
/// straight side, quads stretched along the strip keep their right angles
/// (an edge fillet or the side wall of a thin plate), while the lowered
/// floor would grade the whole wide face from the strip's width up to the
/// floor: a 114 × 49 plate with 0.74-wide edge fillets went from 2,323 to
/// 5,918 quads and from 56 to 241 irregular vertices (width rule), and a
/// pocketed block with 0.49 edge fillets from 4,112 to 9,653 quads and from
/// 8 to 48 (turn rule). Strips along curved sides (gear teeth, fillets of
/// revolution) and strips between strips (a tooth's flank, fillet and tip)
/// keep the rules.
pub fn keep_strips_off_wide_faces(
    graph: &BackgroundGraph,
    faces: &[FaceBackground<'_>],
    lo: f64,
    floors: &mut [f64],
) {
    // each face's curves: points ordered along the curve
    let curves: Vec<HashMap<CurveId, Vec<(u32, Vec3)>>> = faces
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let mut by_curve: HashMap<CurveId, Vec<(u32, Vec3)>> = HashMap::new();
            for (local, r) in f.refs.iter().enumerate() {
                if let NodeRef::Curve(c, k) = *r {
                    let g = graph.face_vertices[i][local] as usize;
                    by_curve.entry(c).or_default().push((k, graph.positions[g]));
                }
            }
            by_curve.values_mut().for_each(|p| p.sort_by_key(|&(k, _)| k));
            by_curve
        })
        .collect();
    let mut faces_of: HashMap<CurveId, Vec<usize>> = HashMap::new();
    for (i, by_curve) in curves.iter().enumerate() {
        for &c in by_curve.keys() {
            faces_of.entry(c).or_default().push(i);
        }
    }
    let mut spills: Vec<bool> = faces
        .iter()
        .map(|f| mean_width(f.topo).is_some_and(|(w, _)| w >= WIDE_FACE_FLOORS * lo))
        .collect();
    loop {
        let mut changed = false;
        for i in 0..faces.len() {
            let w = floors[i];
            if !w.is_finite() {
                continue;
            }
            let on_wide = curves[i].iter().any(|(c, points)| {
                long_and_straight(points, w) && faces_of[c].iter().any(|&j| j != i && spills[j])
            });
            if on_wide {
                tracing::debug!(
                    "narrow-face floor: face {} dropped (a long straight side on a wide face)",
                    faces[i].face.idx() + 1
                );
                floors[i] = f64::INFINITY;
                spills[i] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
}

/// Whether the ordered curve points span a chord of at least
/// [`LONG_SIDE_WIDTHS`] × `width` with no point farther from it than
/// [`STRAIGHT_SAG`] of its length.
fn long_and_straight(points: &[(u32, Vec3)], width: f64) -> bool {
    let (Some(&(_, a)), Some(&(_, b))) = (points.first(), points.last()) else {
        return false;
    };
    let chord = vec3::sub(b, a);
    let len = vec3::norm(chord);
    if len < LONG_SIDE_WIDTHS * width || len <= 0.0 {
        return false;
    }
    let dir = vec3::scale(chord, 1.0 / len);
    points.iter().all(|&(_, p)| {
        let d = vec3::sub(p, a);
        let along = vec3::dot(d, dir);
        let off = vec3::norm(vec3::sub(d, vec3::scale(dir, along)));
        off <= STRAIGHT_SAG * len
    })
}
