//! S8 of `quadrille spline` with cones (spec ricci-flow-iga-reconstruction
//! §9.1–9.2): the separatrices of the minimised map φ (S7), traced through
//! the triangles of Ω as iso-lines of u or v, then the patch decomposition
//! they cut the shell into (`graph`).
//!
//! Tracing: from every cone, one ray per axis direction in the half-open
//! sector of each incident triangle (4 − I rays at an interior cone, 1 − I
//! strictly inside the fan at a boundary cone), marched triangle by
//! triangle. A point crossing an edge keeps its edge parameter, so a cut
//! edge needs no translation: the direction turns by the quarter turns
//! between the edge's two child vectors. The line is taken infinitesimally
//! to the left of its direction: a vertex on it counts as right of it,
//! and the signs of the entry edge's ends are carried into the next
//! triangle, so the line never passes through a vertex and the exit edge
//! is always the one edge whose ends differ in sign. A trace ends on the
//! boundary, or at a cone it passes within 10·ε_c (1e-6 × ψ's diagonal)
//! ahead of; it runs through other traces (complete tracing: their
//! crossings are layout nodes, so there are no T-junctions). The existing
//! `layout` module traces exact grids of one chart (cone-free disks and
//! annuli) and shares nothing with this through-triangle march.

use std::f64::consts::FRAC_PI_2;

use thiserror::Error;

use crate::cut::CutMesh;
use crate::ricci::Cone;
use crate::shell::{Shell, ShellTopology, NO_FACE};

mod graph;

pub use graph::{build_patches, LayoutArc, LayoutNode, NodeKind, Patch, PatchLayout};

/// Why the tracing or the patch decomposition failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TraceError {
    /// A cone's fan holds another number of axis directions than its index asks.
    #[error("trace: the cone of index {index} at {position:?} has {found} separatrix directions in φ, {expected} expected (Q2)")]
    Rays {
        /// Its index.
        index: i32,
        /// 3D position.
        position: [f64; 3],
        /// Directions found.
        found: usize,
        /// 4 − I inside, 1 − I on the boundary.
        expected: usize,
    },
    /// A separatrix past the step cap (Q5).
    #[error("trace: the separatrix from the cone at {position:?} leaving along {direction:?} did not end in {steps} triangle steps (Q5)")]
    Unterminated {
        /// Its cone's 3D position.
        position: [f64; 3],
        /// Its first direction in φ.
        direction: [f64; 2],
        /// Steps taken.
        steps: usize,
    },
    /// A face of the layout is not a quad or not closed.
    #[error("trace: {0}")]
    Layout(String),
}

/// One triangle crossing of a separatrix: the segment from `from` to `to`
/// in triangle `face`'s chart, along the axis direction `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSegment {
    /// The triangle of Ω.
    pub face: usize,
    /// Entry point (the cone for the first segment), in `face`'s chart.
    pub from: [f64; 2],
    /// Exit point.
    pub to: [f64; 2],
    /// Unit axis direction of travel in `face`'s chart.
    pub dir: [f64; 2],
}

/// Where a separatrix ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TraceEnd {
    /// At the cone on this shell vertex.
    Cone(usize),
    /// On the boundary edge `side` (corner `side` → `side + 1`) of the last
    /// segment's triangle at edge parameter `t`.
    Boundary {
        /// The side of the last triangle.
        side: usize,
        /// Parameter along it.
        t: f64,
    },
    /// On an earlier trace ([`TraceOptions::stop_at_traces`]): its index,
    /// its segment (in the same triangle) and the parameter along it.
    Trace {
        /// The trace hit.
        trace: usize,
        /// Its segment.
        segment: usize,
        /// Parameter along that segment.
        t: f64,
    },
}

/// How the separatrices are traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraceOptions {
    /// End a separatrix where it meets one traced before it (a T-junction,
    /// the task's "until another trace"); the spec's complete tracing
    /// (false, the default) runs through, so traces only cross.
    pub stop_at_traces: bool,
}

/// One traced separatrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// The shell vertex of its cone.
    pub cone: usize,
    /// Its angle in the cone's fan (radians from the fan's first edge).
    pub fan_angle: f64,
    /// The triangle crossings in order.
    pub segments: Vec<TraceSegment>,
    /// Where it ended.
    pub end: TraceEnd,
    /// Its 3D length.
    pub length: f64,
}

/// Ω with the map φ: triangle charts, neighbours, fans.
pub(crate) struct Charts<'a> {
    pub(crate) shell: &'a Shell,
    pub(crate) topo: &'a ShellTopology,
    pub(crate) cut: &'a CutMesh,
    pub(crate) uv: &'a [[f64; 2]],
}

pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}
/// The angle from `a` to `b` in (−π, π].
pub(crate) fn angle_between(a: [f64; 2], b: [f64; 2]) -> f64 {
    cross(a, b).atan2(dot(a, b))
}

/// The four axis directions +u, +v, −u, −v.
const AXES: [[f64; 2]; 4] = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];

impl Charts<'_> {
    /// The position of corner `k` of triangle `f` in its chart.
    pub(crate) fn at(&self, f: usize, k: usize) -> [f64; 2] {
        self.uv[self.cut.corners[f][k]]
    }

    /// The corner of `f` on shell vertex `v`.
    pub(crate) fn corner(&self, f: usize, v: usize) -> usize {
        (0..3)
            .position(|k| self.shell.triangles[f][k] == v)
            .unwrap_or(0)
    }

    /// The triangle across side `k` of `f` ([`NO_FACE`] on the boundary).
    pub(crate) fn across(&self, f: usize, k: usize) -> usize {
        let e = self.topo.triangle_edges[f][k];
        let [a, b] = self.topo.edge_faces[e];
        if a == f {
            b
        } else {
            a
        }
    }

    /// The 3D point of `p` in triangle `f`'s chart (barycentric).
    pub(crate) fn point3(&self, f: usize, p: [f64; 2]) -> [f64; 3] {
        let x = [0, 1, 2].map(|k| self.at(f, k));
        let d = cross(sub(x[1], x[0]), sub(x[2], x[0]));
        let l1 = cross(sub(p, x[0]), sub(x[2], x[0])) / d;
        let l2 = cross(sub(x[1], x[0]), sub(p, x[0])) / d;
        let l = [1.0 - l1 - l2, l1, l2];
        let t = self.shell.triangles[f];
        let mut out = [0.0; 3];
        for k in 0..3 {
            for m in 0..3 {
                out[m] += l[k] * self.shell.vertices[t[k]][m];
            }
        }
        out
    }

    /// The interior angle of triangle `f` at corner `k` in φ.
    pub(crate) fn corner_angle(&self, f: usize, k: usize) -> f64 {
        let o = self.at(f, k);
        angle_between(
            sub(self.at(f, (k + 1) % 3), o),
            sub(self.at(f, (k + 2) % 3), o),
        )
    }

    /// The triangles around shell vertex `v` counter-clockwise as
    /// (triangle, corner, angle before it): on the boundary from the
    /// triangle holding the outgoing boundary edge; and the total angle.
    pub(crate) fn fan(&self, v: usize) -> (Vec<(usize, usize, f64)>, f64) {
        let incident: Vec<usize> = (0..self.shell.triangles.len())
            .filter(|&f| self.shell.triangles[f].contains(&v))
            .collect();
        let start = incident
            .iter()
            .copied()
            .find(|&f| self.across(f, self.corner(f, v)) == NO_FACE)
            .or(incident.first().copied());
        let mut out = Vec::new();
        let mut acc = 0.0;
        let mut f = match start {
            Some(f) => f,
            None => return (out, 0.0),
        };
        for _ in 0..=incident.len() {
            let k = self.corner(f, v);
            out.push((f, k, acc));
            acc += self.corner_angle(f, k);
            let g = self.across(f, (k + 2) % 3);
            if g == NO_FACE || Some(g) == start {
                break;
            }
            f = g;
        }
        (out, acc)
    }
}

/// Triangles incident to each vertex would be faster; the fans are only
/// taken at cones, so a scan per cone is enough.
fn rays(ch: &Charts, cone: &Cone) -> Result<Vec<(usize, usize, [f64; 2], f64)>, TraceError> {
    let v = cone.vertex;
    let (fan, total) = ch.fan(v);
    let boundary = ch.topo.on_boundary[v];
    let tol = 1e-4;
    let mut out = Vec::new();
    for &(f, k, acc) in &fan {
        let o = ch.at(f, k);
        let (ea, eb) = (sub(ch.at(f, (k + 1) % 3), o), sub(ch.at(f, (k + 2) % 3), o));
        for d in AXES {
            let ca = cross(ea, d);
            let inside = (ca > 0.0 || (ca == 0.0 && dot(ea, d) > 0.0)) && cross(d, eb) > 0.0;
            if !inside {
                continue;
            }
            let phi = acc + angle_between(ea, d).max(0.0);
            let keep = if boundary {
                phi > tol && phi < total - tol
            } else {
                phi < total - tol
            };
            if keep {
                out.push((f, k, d, phi));
            }
        }
    }
    let expected = if boundary {
        (1 - cone.index).max(0)
    } else {
        4 - cone.index
    } as usize;
    if out.len() != expected {
        return Err(TraceError::Rays {
            index: cone.index,
            position: ch.shell.vertices[v],
            found: out.len(),
            expected,
        });
    }
    Ok(out)
}

/// The first point where the segment `a` (in triangle `f`) meets a segment of
/// `earlier` (traces, with their segments per triangle) or one of `own`
/// before its last: (parameter along `a`, trace, segment, parameter).
fn first_hit(
    a: &TraceSegment,
    earlier: &[Trace],
    by_face: &[Vec<(usize, usize)>],
    own: &[TraceSegment],
    own_index: usize,
    skip_start: bool,
) -> Option<(f64, usize, usize, f64)> {
    let r = sub(a.to, a.from);
    let mut best: Option<(f64, usize, usize, f64)> = None;
    let mut test = |b: &TraceSegment, ti: usize, si: usize| {
        let s = sub(b.to, b.from);
        let den = cross(r, s);
        let scale = (r[0].hypot(r[1]) * s[0].hypot(s[1])).max(f64::MIN_POSITIVE);
        if den.abs() <= 1e-9 * scale {
            return;
        }
        let qp = sub(b.from, a.from);
        let (x, y) = (cross(qp, s) / den, cross(qp, r) / den);
        let lo = if skip_start { 1e-7 } else { 0.0 };
        if x > lo && x <= 1.0 && (0.0..1.0).contains(&y) && best.is_none_or(|h| x < h.0) {
            best = Some((x, ti, si, y));
        }
    };
    for &(ti, si) in &by_face[a.face] {
        test(&earlier[ti].segments[si], ti, si);
    }
    if own.len() > 1 {
        for (si, b) in own[..own.len() - 1].iter().enumerate() {
            if b.face == a.face {
                test(b, own_index, si);
            }
        }
    }
    best
}

/// Earlier traces a new one may stop on, indexed per triangle.
struct Stops<'a> {
    traces: &'a [Trace],
    by_face: &'a [Vec<(usize, usize)>],
}

/// Marches one ray from the cone at corner `k` of triangle `f` along `d`.
fn march(
    ch: &Charts,
    is_cone: &[bool],
    eps: f64,
    (f0, k0, d0, phi): (usize, usize, [f64; 2], f64),
    max_steps: usize,
    stops: Option<Stops>,
) -> Result<Trace, TraceError> {
    let cone = ch.shell.triangles[f0][k0];
    let mut segments = Vec::new();
    let (mut f, mut d) = (f0, d0);
    let mut p = ch.at(f0, k0);
    // Corners whose side of the line is known (carried across the entry edge).
    let mut known: [Option<bool>; 3] = [None; 3];
    known[(k0 + 1) % 3] = Some(false);
    known[(k0 + 2) % 3] = Some(true);
    let mut entry: Option<usize> = None;
    for _ in 0..max_steps {
        let n = [-d[1], d[0]];
        let x = [0, 1, 2].map(|k| ch.at(f, k));
        let s = x.map(|w| dot(n, sub(w, p)));
        // A cone ahead within ε of the line ends the trace (not the start).
        for m in 0..3 {
            let v = ch.shell.triangles[f][m];
            if !is_cone[v] || (f == f0 && m == k0 && segments.is_empty()) {
                continue;
            }
            if s[m].abs() < eps && dot(d, sub(x[m], p)) > 0.0 {
                segments.push(TraceSegment {
                    face: f,
                    from: p,
                    to: x[m],
                    dir: d,
                });
                return Ok(finish(ch, cone, phi, segments, TraceEnd::Cone(v)));
            }
        }
        let left: [bool; 3] = [0, 1, 2].map(|m| known[m].unwrap_or(s[m] > 0.0));
        // From the cone: the side opposite it (its two other sides touch it).
        let first = segments.is_empty() && f == f0;
        let Some(j) = (0..3).find(|&j| {
            if first {
                j == (k0 + 1) % 3
            } else {
                Some(j) != entry && left[j] != left[(j + 1) % 3]
            }
        }) else {
            return Err(TraceError::Layout(format!(
                "a separatrix from {:?} found no exit from triangle {f}",
                ch.shell.vertices[cone]
            )));
        };
        let (sa, sb) = (s[j].abs(), s[(j + 1) % 3].abs());
        let t = if sa + sb > 0.0 { sa / (sa + sb) } else { 0.5 };
        let q = lerp(x[j], x[(j + 1) % 3], t);
        segments.push(TraceSegment {
            face: f,
            from: p,
            to: q,
            dir: d,
        });
        if let Some(st) = &stops {
            let own = st.traces.len();
            let last = segments[segments.len() - 1];
            if let Some((x, trace, segment, t)) =
                first_hit(&last, st.traces, st.by_face, &segments, own, first)
            {
                let n = segments.len();
                segments[n - 1].to = lerp(last.from, last.to, x);
                let end = TraceEnd::Trace { trace, segment, t };
                return Ok(finish(ch, cone, phi, segments, end));
            }
        }
        let g = ch.across(f, j);
        if g == NO_FACE {
            return Ok(finish(
                ch,
                cone,
                phi,
                segments,
                TraceEnd::Boundary { side: j, t },
            ));
        }
        let (a, b) = (ch.shell.triangles[f][j], ch.shell.triangles[f][(j + 1) % 3]);
        let (ka, kb) = (ch.corner(g, a), ch.corner(g, b));
        let e = ch.topo.triangle_edges[f][j];
        if ch.cut.is_cut[e] {
            let turn = angle_between(sub(x[(j + 1) % 3], x[j]), sub(ch.at(g, kb), ch.at(g, ka)));
            let k = ((turn / FRAC_PI_2).round() as i64).rem_euclid(4);
            for _ in 0..k {
                d = [-d[1], d[0]];
            }
        }
        known = [None; 3];
        known[ka] = Some(left[j]);
        known[kb] = Some(left[(j + 1) % 3]);
        p = lerp(ch.at(g, ka), ch.at(g, kb), t);
        entry = Some(if (ka + 1) % 3 == kb { ka } else { kb });
        f = g;
    }
    Err(TraceError::Unterminated {
        position: ch.shell.vertices[cone],
        direction: d0,
        steps: max_steps,
    })
}

fn finish(ch: &Charts, cone: usize, phi: f64, segments: Vec<TraceSegment>, end: TraceEnd) -> Trace {
    let length = segments
        .iter()
        .map(|s| {
            let (a, b) = (ch.point3(s.face, s.from), ch.point3(s.face, s.to));
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .sum();
    Trace {
        cone,
        fan_angle: phi,
        segments,
        end,
        length,
    }
}

/// The 3D midpoint (by length) of a trace.
fn midpoint(ch: &Charts, t: &Trace) -> [f64; 3] {
    let mut run = 0.0;
    for s in &t.segments {
        let (a, b) = (ch.point3(s.face, s.from), ch.point3(s.face, s.to));
        let l = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        if run + l >= 0.5 * t.length && l > 0.0 {
            let w = (0.5 * t.length - run) / l;
            return [0, 1, 2].map(|m| a[m] + w * (b[m] - a[m]));
        }
        run += l;
    }
    t.segments
        .last()
        .map_or([0.0; 3], |s| ch.point3(s.face, s.to))
}

/// Traces every separatrix of `cones` (index ≠ 0) in the map `uv` of Ω =
/// `cut` of `shell`; a separatrix joining two cones is kept once (the one
/// traced first).
pub fn trace_separatrices(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    cones: &[Cone],
    uv: &[[f64; 2]],
    opts: &TraceOptions,
) -> Result<Vec<Trace>, TraceError> {
    let ch = Charts {
        shell,
        topo,
        cut,
        uv,
    };
    let mut is_cone = vec![false; shell.vertices.len()];
    for c in cones.iter().filter(|c| c.index != 0) {
        is_cone[c.vertex] = true;
    }
    let eps = 1e-6 * diagonal(uv);
    let max_steps = 20 * shell.triangles.len() + 1000;
    let mut traces: Vec<Trace> = Vec::new();
    let mut mids: Vec<[f64; 3]> = Vec::new();
    let mut by_face: Vec<Vec<(usize, usize)>> = vec![Vec::new(); shell.triangles.len()];
    for c in cones.iter().filter(|c| c.index != 0) {
        for ray in rays(&ch, c)? {
            let stops = opts.stop_at_traces.then_some(Stops {
                traces: &traces,
                by_face: &by_face,
            });
            let t = march(&ch, &is_cone, eps, ray, max_steps, stops)?;
            let mid = midpoint(&ch, &t);
            let duplicate = traces.iter().zip(&mids).any(|(o, m)| {
                o.end == TraceEnd::Cone(t.cone)
                    && t.end == TraceEnd::Cone(o.cone)
                    && (o.length - t.length).abs() <= 1e-3 * o.length.max(t.length)
                    && geometry::vec3::dist(*m, mid) <= 1e-3 * o.length.max(t.length)
            });
            if !duplicate {
                for (si, s) in t.segments.iter().enumerate() {
                    by_face[s.face].push((traces.len(), si));
                }
                traces.push(t);
                mids.push(mid);
            }
        }
    }
    Ok(traces)
}

/// S8 in one call: [`trace_separatrices`], then [`build_patches`] (the
/// caller checks the patches with [`PatchLayout::check`]).
pub fn trace_patches(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    cones: &[Cone],
    uv: &[[f64; 2]],
    opts: &TraceOptions,
) -> Result<PatchLayout, TraceError> {
    let traces = trace_separatrices(shell, topo, cut, cones, uv, opts)?;
    build_patches(shell, topo, cut, cones, uv, traces)
}

/// The diagonal of the bounding box of `uv`.
pub(crate) fn diagonal(uv: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in uv {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2))
        .sqrt()
        .max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests;
