//! The layout graph of the traced separatrices (spec §9.2) and its faces,
//! the patches. Nodes: cones, separatrix ends on the boundary, and the
//! crossings of two segments in one triangle (each in that triangle's
//! chart). Arcs: trace pieces between nodes and boundary pieces between
//! nodes along each loop. Every arc end carries its angle in its node's
//! frame: a crossing's triangle chart, a boundary hit's edge (0 forward
//! along the loop, π backward), a cone's fan (accumulated across wedges
//! and cuts). Faces are walked with the shell on the left, turning to the
//! next arc clockwise at each node; the angle the face keeps there is a
//! corner when it is about π/2, straight when about π.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

use super::{angle_between, cross, sub, Charts, Trace, TraceEnd, TraceError};
use crate::cut::CutMesh;
use crate::ricci::Cone;
use crate::shell::{Shell, ShellTopology};

/// What a layout node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeKind {
    /// A cone (its shell vertex).
    Cone(usize),
    /// A separatrix ending on the boundary.
    BoundaryHit,
    /// Two separatrix pieces crossing.
    Crossing,
}

/// One node of the layout graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutNode {
    /// Its kind.
    pub kind: NodeKind,
    /// Its 3D position.
    pub position: [f64; 3],
    /// On the boundary: its arc ends' angles run from 0 (forward along the
    /// loop) to `total` (backward), not round.
    pub on_boundary: bool,
    /// The angle around it in φ (2π at a crossing, (4 − I)·π/2 at an
    /// interior cone, the fan at a boundary node).
    pub total: f64,
}

/// One arc of the layout graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayoutArc {
    /// Its end nodes.
    pub nodes: [usize; 2],
    /// The direction leaving each end along the arc, as an angle in that
    /// node's frame.
    pub angles: [f64; 2],
    /// A piece of a boundary loop (run forward, shell on its left), else
    /// of the trace with this index.
    pub trace: Option<usize>,
}

/// One face of the layout: a patch.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// Its half-edges in order, shell on the left: (arc, reversed).
    pub sides: Vec<(usize, bool)>,
    /// Turns of about π/2 (its corners).
    pub corners: usize,
    /// Turns neither about π/2 nor about π.
    pub odd_turns: usize,
}

/// The separatrices, the layout graph and its patches.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchLayout {
    /// The traces.
    pub traces: Vec<Trace>,
    /// Nodes.
    pub nodes: Vec<LayoutNode>,
    /// Arcs.
    pub arcs: Vec<LayoutArc>,
    /// Faces.
    pub patches: Vec<Patch>,
    /// V − E + F of the graph (χ of the shell when every face is a disk).
    pub euler: i64,
    /// χ of the shell.
    pub shell_euler: i64,
}

impl PatchLayout {
    /// Patches with exactly four corners and no odd turn.
    pub fn quads(&self) -> usize {
        self.patches
            .iter()
            .filter(|p| p.corners == 4 && p.odd_turns == 0)
            .count()
    }

    /// Crossing nodes.
    pub fn crossings(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| n.kind == NodeKind::Crossing)
            .count()
    }

    /// `Ok` when every patch is a quad and every face a disk (V − E + F = χ).
    pub fn check(&self) -> Result<(), TraceError> {
        if let Some((i, p)) = self
            .patches
            .iter()
            .enumerate()
            .find(|(_, p)| p.corners != 4 || p.odd_turns != 0)
        {
            let a = self.arcs[p.sides[0].0].nodes[0];
            return Err(TraceError::Layout(format!(
                "{} of {} patches are not quads; patch {i} has {} corners and {} odd turns ({} sides, near {:?})",
                self.patches.len() - self.quads(),
                self.patches.len(),
                p.corners,
                p.odd_turns,
                p.sides.len(),
                self.nodes[a].position
            )));
        }
        if self.euler != self.shell_euler {
            return Err(TraceError::Layout(format!(
                "the layout's V − E + F = {} is not the shell's χ = {}: a face is not a disk",
                self.euler, self.shell_euler
            )));
        }
        Ok(())
    }

    /// One line: separatrices, nodes, arcs, patches.
    pub fn describe(&self) -> String {
        format!(
            "S8 traced {} separatrices ({} crossings): {} nodes, {} arcs, {} patches, {} with 4 corners; V − E + F = {} (χ = {})",
            self.traces.len(),
            self.crossings(),
            self.nodes.len(),
            self.arcs.len(),
            self.patches.len(),
            self.quads(),
            self.euler,
            self.shell_euler
        )
    }
}

/// A trace's node events: (segment, parameter, node, angle forward, angle back).
type Event = (usize, f64, usize, f64, f64);

fn axis_angle(d: [f64; 2]) -> f64 {
    d[1].atan2(d[0]).rem_euclid(TAU)
}

/// Builds the layout graph of `traces` (from [`super::trace_separatrices`]
/// on the same inputs) and walks its faces.
pub fn build_patches(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    cones: &[Cone],
    uv: &[[f64; 2]],
    traces: Vec<Trace>,
) -> Result<PatchLayout, TraceError> {
    let ch = Charts {
        shell,
        topo,
        cut,
        uv,
    };
    let mut nodes: Vec<LayoutNode> = Vec::new();
    // Cone nodes with their fans.
    let mut cone_node = std::collections::BTreeMap::new();
    for c in cones.iter().filter(|c| c.index != 0) {
        let (fan, total) = ch.fan(c.vertex);
        cone_node.insert(c.vertex, (nodes.len(), fan));
        nodes.push(LayoutNode {
            kind: NodeKind::Cone(c.vertex),
            position: shell.vertices[c.vertex],
            on_boundary: topo.on_boundary[c.vertex],
            total,
        });
    }
    let fan_angle = |v: usize, f: usize, d: [f64; 2]| -> f64 {
        let (_, fan) = &cone_node[&v];
        let Some(&(_, k, acc)) = fan.iter().find(|e| e.0 == f) else {
            return 0.0;
        };
        let o = ch.at(f, k);
        let ea = sub(ch.at(f, (k + 1) % 3), o);
        acc + angle_between(ea, d).clamp(0.0, ch.corner_angle(f, k))
    };
    // Crossings: segment pairs per triangle.
    let mut events: Vec<Vec<Event>> = vec![Vec::new(); traces.len()];
    let mut by_face: Vec<Vec<(usize, usize)>> = vec![Vec::new(); shell.triangles.len()];
    for (ti, t) in traces.iter().enumerate() {
        for (si, s) in t.segments.iter().enumerate() {
            by_face[s.face].push((ti, si));
        }
    }
    // A trace's own end nodes are not crossings.
    let near_cone = |ti: usize, si: usize, r: f64| {
        let t = &traces[ti];
        (si == 0 && r < 1e-7)
            || (si + 1 == t.segments.len()
                && matches!(t.end, TraceEnd::Cone(_) | TraceEnd::Trace { .. })
                && r > 1.0 - 1e-7)
    };
    for (f, list) in by_face.iter().enumerate() {
        for (i, &(ta, sa)) in list.iter().enumerate() {
            for &(tb, sb) in &list[i + 1..] {
                let (a, b) = (traces[ta].segments[sa], traces[tb].segments[sb]);
                let (r, s) = (sub(a.to, a.from), sub(b.to, b.from));
                let den = cross(r, s);
                let scale = (r[0].hypot(r[1]) * s[0].hypot(s[1])).max(f64::MIN_POSITIVE);
                if den.abs() <= 1e-9 * scale {
                    continue;
                }
                let qp = sub(b.from, a.from);
                let (x, y) = (cross(qp, s) / den, cross(qp, r) / den);
                if !(0.0..1.0).contains(&x) || !(0.0..1.0).contains(&y) {
                    continue;
                }
                if near_cone(ta, sa, x) || near_cone(tb, sb, y) {
                    continue;
                }
                let p = [a.from[0] + x * r[0], a.from[1] + x * r[1]];
                let n = nodes.len();
                nodes.push(LayoutNode {
                    kind: NodeKind::Crossing,
                    position: ch.point3(f, p),
                    on_boundary: false,
                    total: TAU,
                });
                let neg = |d: [f64; 2]| [-d[0], -d[1]];
                events[ta].push((sa, x, n, axis_angle(a.dir), axis_angle(neg(a.dir))));
                events[tb].push((sb, y, n, axis_angle(b.dir), axis_angle(neg(b.dir))));
            }
        }
    }
    // Boundary positions per loop: (index in loop, parameter, node, back angle).
    let mut loop_pos = vec![(usize::MAX, 0); shell.vertices.len()];
    for (l, lp) in topo.boundary_loops.iter().enumerate() {
        for (i, &v) in lp.iter().enumerate() {
            loop_pos[v] = (l, i);
        }
    }
    let mut on_loop: Vec<Vec<(usize, f64, usize, f64)>> =
        vec![Vec::new(); topo.boundary_loops.len()];
    for (&v, (n, _)) in &cone_node {
        if topo.on_boundary[v] {
            let (l, i) = loop_pos[v];
            on_loop[l].push((i, 0.0, *n, nodes[*n].total));
        }
    }
    // T-junctions: a trace ended on an earlier one.
    let mut t_end = std::collections::BTreeMap::new();
    for (ti, t) in traces.iter().enumerate() {
        if let (
            TraceEnd::Trace {
                trace,
                segment,
                t: y,
            },
            Some(last),
        ) = (t.end, t.segments.last())
        {
            let hit = traces[trace].segments[segment];
            let n = nodes.len();
            nodes.push(LayoutNode {
                kind: NodeKind::Crossing,
                position: ch.point3(last.face, last.to),
                on_boundary: false,
                total: TAU,
            });
            let neg = |d: [f64; 2]| [-d[0], -d[1]];
            events[trace].push((segment, y, n, axis_angle(hit.dir), axis_angle(neg(hit.dir))));
            t_end.insert(ti, (n, axis_angle(neg(last.dir))));
        }
    }
    // Trace arcs.
    let mut arcs: Vec<LayoutArc> = Vec::new();
    for (ti, t) in traces.iter().enumerate() {
        let Some(last) = t.segments.last() else {
            continue;
        };
        let back = [-last.dir[0], -last.dir[1]];
        let (end_node, end_angle) = match t.end {
            TraceEnd::Cone(v) => (cone_node[&v].0, fan_angle(v, last.face, back)),
            TraceEnd::Trace { .. } => t_end[&ti],
            TraceEnd::Boundary { side, t: par } => {
                let f = last.face;
                let (a, b) = (ch.at(f, side), ch.at(f, (side + 1) % 3));
                let angle = angle_between(sub(b, a), back).clamp(0.0, PI);
                let n = nodes.len();
                let q = [a[0] + par * (b[0] - a[0]), a[1] + par * (b[1] - a[1])];
                nodes.push(LayoutNode {
                    kind: NodeKind::BoundaryHit,
                    position: ch.point3(f, q),
                    on_boundary: true,
                    total: PI,
                });
                let (l, i) = loop_pos[shell.triangles[f][side]];
                if l == usize::MAX {
                    return Err(TraceError::Layout(format!(
                        "a separatrix from {:?} left through an edge of no boundary loop",
                        shell.vertices[t.cone]
                    )));
                }
                on_loop[l].push((i, par, n, PI));
                (n, angle)
            }
        };
        let mut ev = std::mem::take(&mut events[ti]);
        ev.sort_by(|a, b| {
            (a.0, a.1)
                .partial_cmp(&(b.0, b.1))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let (mut from, mut from_angle) = (cone_node[&t.cone].0, t.fan_angle);
        for &(_, _, n, fwd, bwd) in &ev {
            arcs.push(LayoutArc {
                nodes: [from, n],
                angles: [from_angle, bwd],
                trace: Some(ti),
            });
            (from, from_angle) = (n, fwd);
        }
        arcs.push(LayoutArc {
            nodes: [from, end_node],
            angles: [from_angle, end_angle],
            trace: Some(ti),
        });
    }
    // Boundary arcs along each loop.
    for (l, list) in on_loop.iter_mut().enumerate() {
        if list.is_empty() {
            return Err(TraceError::Layout(format!(
                "boundary loop {l} ({} vertices, through {:?}) has no layout node: no cone on it and no separatrix reaches it",
                topo.boundary_loops[l].len(),
                shell.vertices[topo.boundary_loops[l][0]]
            )));
        }
        list.sort_by(|a, b| {
            (a.0, a.1)
                .partial_cmp(&(b.0, b.1))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for k in 0..list.len() {
            let (a, b) = (list[k], list[(k + 1) % list.len()]);
            arcs.push(LayoutArc {
                nodes: [a.2, b.2],
                angles: [0.0, b.3],
                trace: None,
            });
        }
    }
    let patches = walk_faces(&nodes, &arcs)?;
    let euler = nodes.len() as i64 - arcs.len() as i64 + patches.len() as i64;
    Ok(PatchLayout {
        traces,
        nodes,
        arcs,
        patches,
        euler,
        shell_euler: topo.euler,
    })
}

/// The faces with the shell on the left: half-edge `2·arc` runs from
/// `nodes[0]` to `nodes[1]`, `2·arc + 1` back; a boundary arc's back
/// half-edge bounds the outside and starts no face.
fn walk_faces(nodes: &[LayoutNode], arcs: &[LayoutArc]) -> Result<Vec<Patch>, TraceError> {
    let mut out_at: Vec<Vec<(f64, usize)>> = vec![Vec::new(); nodes.len()];
    for (a, arc) in arcs.iter().enumerate() {
        out_at[arc.nodes[0]].push((arc.angles[0], 2 * a));
        out_at[arc.nodes[1]].push((arc.angles[1], 2 * a + 1));
    }
    let mut slot = vec![(0, 0); 2 * arcs.len()];
    for (n, list) in out_at.iter_mut().enumerate() {
        list.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        for (i, &(_, h)) in list.iter().enumerate() {
            slot[h] = (n, i);
        }
    }
    let dest = |h: usize| arcs[h / 2].nodes[1 - h % 2];
    let outer = |h: usize| arcs[h / 2].trace.is_none() && h % 2 == 1;
    // The next half-edge after `h` and the angle the face keeps at its node.
    let next = |h: usize| -> Result<(usize, f64), TraceError> {
        let twin = h ^ 1;
        let (n, i) = slot[twin];
        let list = &out_at[n];
        let node = nodes[n];
        let theta = list[i].0;
        let (j, wrap) = if i == 0 {
            (list.len() - 1, true)
        } else {
            (i - 1, false)
        };
        if wrap && node.on_boundary {
            return Err(TraceError::Layout(format!(
                "a face leaves the shell at the boundary node {:?}",
                node.position
            )));
        }
        let mut angle = theta - list[j].0;
        if wrap {
            angle += node.total;
        }
        Ok((list[j].1, angle))
    };
    let mut seen = vec![false; 2 * arcs.len()];
    let mut patches = Vec::new();
    for h0 in 0..2 * arcs.len() {
        if seen[h0] || outer(h0) {
            continue;
        }
        let (mut h, mut sides, mut corners, mut odd) = (h0, Vec::new(), 0, 0);
        loop {
            if seen[h] || sides.len() > 2 * arcs.len() {
                return Err(TraceError::Layout(format!(
                    "a face walk does not close (at the node {:?})",
                    nodes[dest(h)].position
                )));
            }
            seen[h] = true;
            sides.push((h / 2, h % 2 == 1));
            let (g, angle) = next(h)?;
            if (angle - FRAC_PI_2).abs() < FRAC_PI_4 {
                corners += 1;
            } else if (angle - PI).abs() >= FRAC_PI_4 {
                odd += 1;
            }
            h = g;
            if h == h0 {
                break;
            }
        }
        patches.push(Patch {
            sides,
            corners,
            odd_turns: odd,
        });
    }
    Ok(patches)
}
