//! S5 of `quadrille spline` (spec ricci-flow-iga-reconstruction §7): the
//! immersion ψ_R of the cut mesh Ω into the plane. Triangles are unfolded
//! breadth-first from a central one across uncut edges with the Ricci
//! lengths (law of cosines); the result is rotated so the boundary edges fit
//! the axes best (α = −¼ arg Σ ℓ e^{4iθ}) and scaled to the 3D area. The
//! two sides of every cut path must then differ by a rotation k·π/2 and a
//! translation (Q4); [`Immersion::transitions`] reports how well they do.

use std::collections::VecDeque;
use std::f64::consts::FRAC_PI_2;

use thiserror::Error;

use crate::cut::CutMesh;
use crate::ricci::RicciMetric;
use crate::shell::{Shell, ShellTopology, NO_FACE};

/// The transition across one cut path: right side = R(k·π/2)·left + t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutTransition {
    /// Index of the path in [`CutMesh::paths`].
    pub path: usize,
    /// k in 0..4: the rotation in quarter turns (counter-clockwise).
    pub quarter_turns: u8,
    /// Largest |edge rotation − k·π/2| over the path's edges (radians).
    pub angle_error: f64,
    /// Largest distance between a right-side child and the transformed
    /// left-side child (3D units, after scaling).
    pub translation_error: f64,
}

/// The planar map ψ_R of Ω.
#[derive(Clone, Debug, PartialEq)]
pub struct Immersion {
    /// Plane position per child vertex of Ω.
    pub uv: Vec<[f64; 2]>,
    /// Rotation applied to align the boundary with the axes (radians).
    pub rotation: f64,
    /// Scale applied to match the 3D area.
    pub scale: f64,
    /// Smallest signed triangle area (positive: every triangle keeps its
    /// orientation, Q1).
    pub min_signed_area: f64,
    /// Smallest signed area over the triangle's 3D area.
    pub min_area_ratio: f64,
    /// Largest deviation of a boundary edge direction from the nearest axis (radians).
    pub boundary_axis_error: f64,
    /// Per boundary loop: the largest deviation of its edge directions, mod
    /// π/2, from its first edge's (radians). Ricci straightens each loop and
    /// turns its corners by multiples of π/2, but the loops of a holed shell
    /// may stay rotated against each other (spec §5.2: the layout energy's
    /// E2 aligns them), so this is the exact check; `boundary_axis_error`
    /// shows the rest.
    pub loop_axis_spread: Vec<f64>,
    /// One transition per cut path.
    pub transitions: Vec<CutTransition>,
}

/// Why Ω could not be laid out.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ImmersionError {
    /// A triangle the unfolding never reaches.
    #[error("immersion: triangle {face} is not reached across uncut edges (Ω is not connected)")]
    Unreached {
        /// The triangle.
        face: usize,
    },
    /// A triangle whose Ricci lengths break the triangle inequality.
    #[error(
        "immersion: triangle {face} has lengths {lengths:?} that break the triangle inequality"
    )]
    Degenerate {
        /// The triangle.
        face: usize,
        /// Its lengths.
        lengths: [f64; 3],
    },
    /// An edge of Ω whose length in ψ is not its Ricci length: the
    /// unfolding reached a child vertex along two routes that disagree.
    #[error(
        "immersion: edge {a}–{b} (shell vertices) of triangle {face} is {planar:.6e} long in the plane but {metric:.6e} in the Ricci metric (relative {relative:.1e}, limit {INCONSISTENCY_LIMIT:.0e})"
    )]
    Inconsistent {
        /// The triangle.
        face: usize,
        /// The edge's shell vertices.
        a: usize,
        /// The edge's other shell vertex.
        b: usize,
        /// Its length in the plane before scaling.
        planar: f64,
        /// Its Ricci length.
        metric: f64,
        /// |planar − metric| / metric.
        relative: f64,
    },
}

/// Largest relative difference between an edge's length in ψ and its Ricci
/// length that [`immerse`] accepts. Not 1e-8: the flow stops at a residue
/// of 1e-12–3e-11 per vertex (Newton's step fails below ~1e-12), and that
/// residue, summed along a long strip's unfolding, leaves 1.1e-8 on the
/// flange fillet's face 7 at 0.5 mm (2.0e-5 … 1.9e-1 when the unfolding was
/// wrong, issue 31).
pub const INCONSISTENCY_LIMIT: f64 = 1e-7;

/// Angle at `p` of a triangle with sides `pq`, `pr`, `qr` (law of cosines).
fn angle_at(pq: f64, pr: f64, qr: f64) -> Option<f64> {
    let s = 0.5 * (pq + pr + qr);
    let (a, b, c) = (s - pq, s - pr, s - qr);
    if a <= 0.0 || b <= 0.0 || c <= 0.0 {
        return None;
    }
    Some(2.0 * (a * b).sqrt().atan2((s * c).sqrt()))
}

fn rotate(p: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// `angle` wrapped to (−π, π].
fn wrap(angle: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let mut a = angle % t;
    if a > std::f64::consts::PI {
        a -= t;
    } else if a <= -std::f64::consts::PI {
        a += t;
    }
    a
}

/// The metric's angles at the corners of triangle `f` with side lengths `l`
/// (side k from corner k to k + 1).
fn corner_angles(f: usize, l: [f64; 3]) -> Result<[f64; 3], ImmersionError> {
    let mut corner = [0.0; 3];
    for (k, angle) in corner.iter_mut().enumerate() {
        *angle =
            angle_at(l[k], l[(k + 2) % 3], l[(k + 1) % 3]).ok_or(ImmersionError::Degenerate {
                face: f,
                lengths: l,
            })?;
    }
    Ok(corner)
}

/// The directions of a counter-clockwise triangle's three sides when side
/// `j` points along `first`: each next side turns by π minus the corner
/// angle between them. Wrapped to (−π, π].
fn side_angles(j: usize, first: f64, corner: [f64; 3]) -> [f64; 3] {
    let mut side = [0.0; 3];
    let mut angle = wrap(first);
    for m in 0..3 {
        let s = (j + m) % 3;
        side[s] = angle;
        let next = (s + 1) % 3;
        angle = wrap(angle + std::f64::consts::PI - corner[next]);
    }
    side
}

/// `from` moved by `length` in direction `angle`.
fn step(from: [f64; 2], length: f64, angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [from[0] + length * c, from[1] + length * s]
}

/// Lays Ω out in the plane with the Ricci lengths (spec §7).
pub fn immerse(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    metric: &RicciMetric,
) -> Result<Immersion, ImmersionError> {
    let nf = shell.triangles.len();
    let nc = cut.parent.len();
    // Start at the triangle nearest the vertex centroid.
    let mut centre = [0.0; 3];
    for p in &shell.vertices {
        for k in 0..3 {
            centre[k] += p[k] / shell.vertices.len() as f64;
        }
    }
    let distance = |f: usize| -> f64 {
        let t = shell.triangles[f];
        (0..3)
            .map(|k| {
                let c = (0..3).map(|m| shell.vertices[t[m]][k]).sum::<f64>() / 3.0;
                (c - centre[k]) * (c - centre[k])
            })
            .sum()
    };
    let start = (0..nf)
        .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
        .unwrap_or(0);
    // Side directions are carried from triangle to triangle as angles (the
    // shared side reversed, then the metric's corner angles), never read back
    // from placed positions: rounding and the flow's residue then add up
    // along the unfolding instead of compounding (issue 31: reading each new
    // side's direction from its two placed ends amplified the 1e-11 residue
    // by ~10× per 100 triangles along a 338 × 5 strip, to 20 % at its far end).
    let mut uv = vec![[f64::NAN; 2]; nc];
    let mut placed = vec![false; nc];
    let mut side_angle = vec![[f64::NAN; 3]; nf];
    let c = cut.corners[start];
    let l = metric.triangle_lengths(topo, start);
    let corner = corner_angles(start, l)?;
    side_angle[start] = side_angles(0, 0.0, corner);
    uv[c[0]] = [0.0, 0.0];
    uv[c[1]] = [l[0], 0.0];
    uv[c[2]] = step(uv[c[1]], l[1], side_angle[start][1]);
    for &v in &c {
        placed[v] = true;
    }
    let mut visited = vec![false; nf];
    visited[start] = true;
    let mut queue = VecDeque::from([start]);
    while let Some(f) = queue.pop_front() {
        for k in 0..3 {
            let e = topo.triangle_edges[f][k];
            if cut.is_cut[e] {
                continue;
            }
            let [f0, f1] = topo.edge_faces[e];
            let g = if f0 == f { f1 } else { f0 };
            if g == NO_FACE || visited[g] {
                continue;
            }
            visited[g] = true;
            queue.push_back(g);
            // In g the shared side j runs b → a, opposite to side k of f.
            let a = shell.triangles[f][k];
            let j = (0..3)
                .position(|m| shell.triangles[g][m] == shell.triangles[f][(k + 1) % 3])
                .unwrap_or(0);
            debug_assert_eq!(shell.triangles[g][(j + 1) % 3], a);
            let lg = metric.triangle_lengths(topo, g);
            let corner = corner_angles(g, lg)?;
            side_angle[g] = side_angles(j, side_angle[f][k] + std::f64::consts::PI, corner);
            let gc = cut.corners[g];
            let (q, r) = (gc[(j + 1) % 3], gc[(j + 2) % 3]);
            if !placed[r] {
                uv[r] = step(uv[q], lg[(j + 1) % 3], side_angle[g][(j + 1) % 3]);
                placed[r] = true;
            }
        }
    }
    if let Some(face) = visited.iter().position(|v| !v) {
        return Err(ImmersionError::Unreached { face });
    }
    check_lengths(shell, topo, cut, metric, &uv)?;
    // Axis alignment from the boundary edges of S.
    let boundary_edges: Vec<[usize; 2]> = topo
        .edges
        .iter()
        .enumerate()
        .filter(|&(e, _)| topo.is_boundary_edge(e))
        .map(|(e, &[a, b])| {
            let f = topo.edge_faces[e][0].min(topo.edge_faces[e][1]);
            let child = |v: usize| {
                cut.corners[f][(0..3).position(|k| shell.triangles[f][k] == v).unwrap_or(0)]
            };
            [child(a), child(b)]
        })
        .collect();
    let (mut sx, mut sy) = (0.0, 0.0);
    for &[a, b] in &boundary_edges {
        let d = [uv[b][0] - uv[a][0], uv[b][1] - uv[a][1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let th = d[1].atan2(d[0]);
        sx += len * (4.0 * th).cos();
        sy += len * (4.0 * th).sin();
    }
    let rotation = -0.25 * sy.atan2(sx);
    let area2d: f64 = cut
        .corners
        .iter()
        .map(|c| signed_area(uv[c[0]], uv[c[1]], uv[c[2]]))
        .sum();
    let scale = (shell.area() / area2d).sqrt();
    for p in uv.iter_mut() {
        let r = rotate(*p, rotation);
        *p = [r[0] * scale, r[1] * scale];
    }
    let mut min_signed_area = f64::INFINITY;
    let mut min_area_ratio = f64::INFINITY;
    for (f, c) in cut.corners.iter().enumerate() {
        let a = signed_area(uv[c[0]], uv[c[1]], uv[c[2]]);
        min_signed_area = min_signed_area.min(a);
        let t = shell.triangles[f];
        let s = Shell {
            vertices: vec![
                shell.vertices[t[0]],
                shell.vertices[t[1]],
                shell.vertices[t[2]],
            ],
            triangles: vec![[0, 1, 2]],
        };
        min_area_ratio = min_area_ratio.min(a / s.area());
    }
    let boundary_axis_error = boundary_edges
        .iter()
        .map(|&[a, b]| {
            let th = (uv[b][1] - uv[a][1]).atan2(uv[b][0] - uv[a][0]);
            wrap(th - (th / FRAC_PI_2).round() * FRAC_PI_2).abs()
        })
        .fold(0.0, f64::max);
    let direction = |a: usize, b: usize| -> f64 {
        let f = topo.edge(a, b).map_or(NO_FACE, |e| {
            topo.edge_faces[e][0].min(topo.edge_faces[e][1])
        });
        let child =
            |v: usize| cut.corners[f][(0..3).position(|k| shell.triangles[f][k] == v).unwrap_or(0)];
        let (p, q) = (uv[child(a)], uv[child(b)]);
        (q[1] - p[1]).atan2(q[0] - p[0])
    };
    let loop_axis_spread = topo
        .boundary_loops
        .iter()
        .map(|l| {
            let first = direction(l[0], l[1 % l.len()]);
            (0..l.len())
                .map(|i| {
                    let d = direction(l[i], l[(i + 1) % l.len()]) - first;
                    wrap(d - (d / FRAC_PI_2).round() * FRAC_PI_2).abs()
                })
                .fold(0.0, f64::max)
        })
        .collect();
    let transitions = cut
        .paths
        .iter()
        .enumerate()
        .map(|(i, path)| transition(i, path, &uv))
        .collect();
    Ok(Immersion {
        uv,
        rotation,
        scale,
        min_signed_area,
        min_area_ratio,
        boundary_axis_error,
        loop_axis_spread,
        transitions,
    })
}

/// Every edge of Ω as long in the plane as in the metric (relative
/// [`INCONSISTENCY_LIMIT`]); the first one that is not, as an error.
fn check_lengths(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    metric: &RicciMetric,
    uv: &[[f64; 2]],
) -> Result<(), ImmersionError> {
    for (f, c) in cut.corners.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (uv[c[k]], uv[c[(k + 1) % 3]]);
            let planar = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            let length = metric.lengths[topo.triangle_edges[f][k]];
            let relative = (planar - length).abs() / length;
            // NaN (an unplaced child) fails too.
            if !(relative <= INCONSISTENCY_LIMIT) {
                return Err(ImmersionError::Inconsistent {
                    face: f,
                    a: shell.triangles[f][k],
                    b: shell.triangles[f][(k + 1) % 3],
                    planar,
                    metric: length,
                    relative,
                });
            }
        }
    }
    Ok(())
}

/// The rotation and translation taking a path's left side to its right side.
fn transition(index: usize, path: &crate::cut::CutPath, uv: &[[f64; 2]]) -> CutTransition {
    let edge_angle = |s: &crate::cut::CutEdgeSides| -> f64 {
        let dl = [
            uv[s.left[1]][0] - uv[s.left[0]][0],
            uv[s.left[1]][1] - uv[s.left[0]][1],
        ];
        let dr = [
            uv[s.right[1]][0] - uv[s.right[0]][0],
            uv[s.right[1]][1] - uv[s.right[0]][1],
        ];
        let cross = dl[0] * dr[1] - dl[1] * dr[0];
        let dot = dl[0] * dr[0] + dl[1] * dr[1];
        cross.atan2(dot)
    };
    let first = edge_angle(&path.sides[0]);
    let k = ((first / FRAC_PI_2).round() as i64).rem_euclid(4);
    let rot = k as f64 * FRAC_PI_2;
    let angle_error = path
        .sides
        .iter()
        .map(|s| wrap(edge_angle(s) - rot).abs())
        .fold(0.0, f64::max);
    let s0 = &path.sides[0];
    let moved = rotate(uv[s0.left[0]], rot);
    let t = [uv[s0.right[0]][0] - moved[0], uv[s0.right[0]][1] - moved[1]];
    let mut translation_error: f64 = 0.0;
    for s in &path.sides {
        for m in 0..2 {
            let p = rotate(uv[s.left[m]], rot);
            let q = uv[s.right[m]];
            let d = ((p[0] + t[0] - q[0]).powi(2) + (p[1] + t[1] - q[1]).powi(2)).sqrt();
            translation_error = translation_error.max(d);
        }
    }
    CutTransition {
        path: index,
        quarter_turns: k as u8,
        angle_error,
        translation_error,
    }
}

#[cfg(test)]
mod tests;
