//! Geometry of the coarse layout (spec §6.1–§6.3): interior layout vertices
//! by Eq. (1) (with the errata: E_{i+1}, weights frozen per iteration), the
//! straight intermediate network, and the interior edges ("rungs") as
//! distance-weighted iso-lines of each chord's chain-long discrete Coons patch
//! (Fig. 13). Also the arc-length polylines and the bicubically blended Coons
//! evaluation the sampling stage shares.

use geometry::vec3::{add, cross, dist, norm, scale, sub, Vec3};
use mesh::quality::quad_scaled_jacobian;

use super::layout::{EdgeKind, Layout, LayoutError};
use super::PairedCycle;

/// Iterations of Eq. (1) with weights frozen at the previous positions.
const EQ1_ITERATIONS: usize = 12;

/// Samples per rung curve (the dense sampling resamples them by arc length).
const RUNG_SAMPLES: usize = 48;

/// A polyline parametrised by normalised arc length.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Its points in order.
    pub points: Vec<Vec3>,
    /// Cumulative arc length at each point (0 first).
    pub cumulative: Vec<f64>,
}

impl Polyline {
    /// The polyline through `points` (at least one).
    pub fn new(points: Vec<Vec3>) -> Polyline {
        let mut cumulative = Vec::with_capacity(points.len());
        let mut acc = 0.0;
        for k in 0..points.len() {
            if k > 0 {
                acc += dist(points[k - 1], points[k]);
            }
            cumulative.push(acc);
        }
        Polyline { points, cumulative }
    }

    /// Total arc length.
    pub fn length(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// The same curve run backwards.
    pub fn reversed(&self) -> Polyline {
        Polyline::new(self.points.iter().rev().copied().collect())
    }

    /// The point at arc-length fraction `t` in [0, 1] (exact end points).
    pub fn at(&self, t: f64) -> Vec3 {
        let len = self.length();
        let m = self.points.len();
        if t <= 0.0 || len <= 0.0 {
            return self.points[0];
        }
        if t >= 1.0 {
            return self.points[m - 1];
        }
        let s = t * len;
        let k = self.cumulative.partition_point(|&c| c <= s).clamp(1, m - 1);
        let (c0, c1) = (self.cumulative[k - 1], self.cumulative[k]);
        let f = if c1 > c0 { (s - c0) / (c1 - c0) } else { 0.0 };
        add(
            self.points[k - 1],
            scale(sub(self.points[k], self.points[k - 1]), f),
        )
    }

    /// `intervals + 1` points at equal arc-length steps, ends exact.
    pub fn resample(&self, intervals: usize) -> Vec<Vec3> {
        (0..=intervals)
            .map(|k| self.at(k as f64 / intervals as f64))
            .collect()
    }
}

/// Hermite blend F0(t) = 1 − 3t² + 2t³.
fn f0(t: f64) -> f64 {
    1.0 - 3.0 * t * t + 2.0 * t * t * t
}

/// The bicubically blended Coons patch of four sides: `bottom` from P00 to
/// P10 (parameter u), `top` from P01 to P11, `left` from P00 to P01
/// (parameter v), `right` from P10 to P11; all by normalised arc length.
pub fn coons_point(
    bottom: &Polyline,
    right: &Polyline,
    top: &Polyline,
    left: &Polyline,
    u: f64,
    v: f64,
) -> Vec3 {
    let (a0, a1) = (f0(u), 1.0 - f0(u));
    let (b0, b1) = (f0(v), 1.0 - f0(v));
    let p00 = bottom.at(0.0);
    let p10 = bottom.at(1.0);
    let p01 = top.at(0.0);
    let p11 = top.at(1.0);
    let mut p = [0.0; 3];
    let (l, r, b, t) = (left.at(v), right.at(v), bottom.at(u), top.at(u));
    for k in 0..3 {
        p[k] = a0 * l[k] + a1 * r[k] + b0 * b[k] + b1 * t[k]
            - (a0 * b0 * p00[k] + a1 * b0 * p10[k] + a0 * b1 * p01[k] + a1 * b1 * p11[k]);
    }
    p
}

/// Newell normal (vector area, not normalised) of a closed polygon.
pub use super::check::newell;

/// Interior layout vertices by Eq. (1): each is the weighted mean over its
/// quads (G, E_i, C_i, E_{i+1}) of the parallelogram rule E_i + E_{i+1} − C_i,
/// weight 1/a_i with a_i = |E_i − C_i| |C_i − E_{i+1}|. The first solve uses
/// a_i = 1 (Nasri's topological rule); then the weights are frozen at the
/// current positions and the linear system solved again, a fixed number of
/// times. Boundary vertices stay where they are.
pub fn place_interior_vertices(layout: &Layout, diameter: f64) -> Result<Vec<Vec3>, LayoutError> {
    let nb = layout.boundary_vertices;
    let mut pos = layout.positions.clone();
    let m = pos.len() - nb;
    if m == 0 {
        return Ok(pos);
    }
    let floor = 1e-12 * diameter.max(1e-300).powi(2);
    for iteration in 0..=EQ1_ITERATIONS {
        let mut a = vec![0.0; m * m];
        let mut rhs = vec![[0.0; 3]; m];
        for q in &layout.quads {
            for t in 0..4 {
                let g = q.corners[t];
                if g < nb {
                    continue;
                }
                let (ea, c, eb) = (
                    q.corners[(t + 1) % 4],
                    q.corners[(t + 2) % 4],
                    q.corners[(t + 3) % 4],
                );
                let w = if iteration == 0 {
                    1.0
                } else {
                    1.0 / (dist(pos[ea], pos[c]) * dist(pos[c], pos[eb])).max(floor)
                };
                let row = g - nb;
                a[row * m + row] += w;
                for (v, sign) in [(ea, 1.0), (eb, 1.0), (c, -1.0)] {
                    if v >= nb {
                        a[row * m + v - nb] -= sign * w;
                    } else {
                        rhs[row] = add(rhs[row], scale(pos[v], sign * w));
                    }
                }
            }
        }
        let x = solve_dense(a, rhs, m)?;
        for (k, p) in x.into_iter().enumerate() {
            pos[nb + k] = p;
        }
    }
    Ok(pos)
}

/// Gaussian elimination with partial pivoting, three right-hand sides.
fn solve_dense(mut a: Vec<f64>, mut b: Vec<Vec3>, m: usize) -> Result<Vec<Vec3>, LayoutError> {
    let scale_max = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    for col in 0..m {
        let piv = (col..m)
            .max_by(|&r, &s| a[r * m + col].abs().total_cmp(&a[s * m + col].abs()))
            .unwrap_or(col);
        if a[piv * m + col].abs() <= 1e-13 * scale_max {
            return Err(LayoutError::Singular {
                vertices: m,
                row: col,
            });
        }
        if piv != col {
            for k in 0..m {
                a.swap(col * m + k, piv * m + k);
            }
            b.swap(col, piv);
        }
        for r in col + 1..m {
            let f = a[r * m + col] / a[col * m + col];
            if f != 0.0 {
                for k in col..m {
                    a[r * m + k] -= f * a[col * m + k];
                }
                b[r] = sub(b[r], scale(b[col], f));
            }
        }
    }
    let mut x = vec![[0.0; 3]; m];
    for r in (0..m).rev() {
        let mut s = b[r];
        for k in r + 1..m {
            s = sub(s, scale(x[k], a[r * m + k]));
        }
        x[r] = scale(s, 1.0 / a[r * m + r]);
    }
    Ok(x)
}

/// Quality of the straight-edge layout quads: (minimum, mean) scaled
/// Jacobian against the Newell normal of the boundary layout vertices.
pub fn layout_quality(layout: &Layout) -> (f64, f64) {
    let nrm = newell(&layout.positions[..layout.boundary_vertices]);
    let len = norm(nrm);
    let mut min = f64::INFINITY;
    let mut sum = 0.0;
    for q in &layout.quads {
        let p = q.corners.map(|c| layout.positions[c]);
        let n = if len > 0.0 {
            scale(nrm, 1.0 / len)
        } else {
            let d = cross(sub(p[2], p[0]), sub(p[3], p[1]));
            scale(d, 1.0 / norm(d).max(1e-300))
        };
        let sj = quad_scaled_jacobian(&p, &[n; 4]);
        min = min.min(sj);
        sum += sj;
    }
    (min, sum / layout.quads.len().max(1) as f64)
}

/// The points of segment `s` of the cycle, from its start to its end.
pub fn segment_points(cycle: &PairedCycle, s: usize) -> Vec<Vec3> {
    let np = cycle.points.len();
    let a = cycle.starts[s];
    let b = cycle.starts[(s + 1) % cycle.starts.len()];
    let count = (b + np - a) % np;
    let count = if count == 0 { np } else { count };
    (0..=count).map(|t| cycle.points[(a + t) % np]).collect()
}

/// The curve of each layout edge, from `ends[0]` to `ends[1]`: boundary
/// edges are the cycle's segments, interior edges straight (spec §6.2).
pub fn straight_edge_curves(layout: &Layout, cycle: &PairedCycle) -> Vec<Polyline> {
    layout
        .edges
        .iter()
        .map(|e| match e.kind {
            EdgeKind::Boundary(s) => Polyline::new(segment_points(cycle, s)),
            EdgeKind::Interior => Polyline::new(vec![
                layout.positions[e.ends[0]],
                layout.positions[e.ends[1]],
            ]),
        })
        .collect()
}

/// The curve of edge `e` run from vertex `from`.
fn oriented(curves: &[Polyline], layout: &Layout, e: usize, from: usize) -> Polyline {
    if layout.edges[e].ends[0] == from {
        curves[e].clone()
    } else {
        curves[e].reversed()
    }
}

/// The edge joining `a` to `b` that chord `c` does not cross.
fn rail_edge(layout: &Layout, a: usize, b: usize, c: usize) -> Option<usize> {
    layout.edges.iter().position(|e| {
        e.chord != c && ((e.ends[0] == a && e.ends[1] == b) || (e.ends[0] == b && e.ends[1] == a))
    })
}

/// The interior edges as iso-lines (spec §6.3, Fig. 13): per chord, the
/// chain of its quads is one Coons patch bounded by its two segments and its
/// two rails (the straight edges and boundary curves along its sides); each
/// rung of the chord is the curve u(v) = (1 − v) u_L + v u_R, with u_L and
/// u_R the arc-length fractions of the rung's ends along the left and right
/// rails. Boundary edges keep the cycle's curve.
pub fn rung_curves(layout: &Layout, cycle: &PairedCycle) -> Vec<Polyline> {
    let straight = straight_edge_curves(layout, cycle);
    let mut curves = straight.clone();
    for (c, pieces) in layout.pieces.iter().enumerate() {
        let m = pieces.len() - 1;
        if m < 2 {
            continue;
        }
        let mut rails = [Vec::new(), Vec::new()];
        let mut marks = [vec![0.0], vec![0.0]];
        let mut ok = true;
        for (side, rail) in rails.iter_mut().enumerate() {
            let vert = |p: &super::layout::ChordPiece| if side == 0 { p.left } else { p.right };
            rail.push(layout.positions[vert(&pieces[0])]);
            for t in 1..=m {
                let (a, b) = (vert(&pieces[t - 1]), vert(&pieces[t]));
                let Some(e) = rail_edge(layout, a, b, c) else {
                    ok = false;
                    break;
                };
                let seg = oriented(&straight, layout, e, a);
                rail.extend(seg.points.iter().skip(1));
                let last = *marks[side].last().unwrap_or(&0.0);
                marks[side].push(last + seg.length());
            }
        }
        if !ok {
            continue;
        }
        let left_rail = Polyline::new(rails[0].clone());
        let right_rail = Polyline::new(rails[1].clone());
        let (ll, rl) = (
            left_rail.length().max(1e-300),
            right_rail.length().max(1e-300),
        );
        let first = oriented(&straight, layout, pieces[0].edge, pieces[0].left);
        let last = oriented(&straight, layout, pieces[m].edge, pieces[m].left);
        for t in 1..m {
            let (ul, ur) = (marks[0][t] / ll, marks[1][t] / rl);
            let pts: Vec<Vec3> = (0..=RUNG_SAMPLES)
                .map(|k| {
                    let v = k as f64 / RUNG_SAMPLES as f64;
                    let u = (1.0 - v) * ul + v * ur;
                    coons_point(&left_rail, &last, &right_rail, &first, u, v)
                })
                .collect();
            let mut pts = pts;
            pts[0] = layout.positions[pieces[t].left];
            pts[RUNG_SAMPLES] = layout.positions[pieces[t].right];
            let e = pieces[t].edge;
            curves[e] = if layout.edges[e].ends[0] == pieces[t].left {
                Polyline::new(pts)
            } else {
                Polyline::new(pts).reversed()
            };
        }
    }
    curves
}
