//! The splines of the layout (spec §9.3–9.4): every arc fitted once (cubic,
//! K uniform spans, least squares in ψ's arc length, ends interpolated),
//! patches by the exact Coons patch of their four arcs or with interiors
//! fitted to the shell (ours: boundary rows fixed, the interior control
//! points least squares on the shell's vertices at their ψ parameters, tied
//! lightly to the Coons net; a fit that folds falls back to Coons), and the
//! distance of the shell's vertices to their patch.

use geometry::vec3::{cross, dot, normalize, sub};
use spline::basis::basis_functions;
use spline::{
    fit_curve, jacobian_check, ArcUse, BSplineCurve, BSplinePatch, Multipatch, MultipatchBuilder, SplineError,
};

use super::SplineMethodError;
use crate::cut::CutMesh;
use crate::immersion::Immersion;
use crate::layout::{Layout, PsiLocator};
use crate::shell::Shell;

/// The spans tried by [`Segments::Auto`], smallest first.
pub const SEGMENT_CHOICES: [usize; 10] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32];

/// Uniform spans per arc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Segments {
    /// This many.
    Fixed(usize),
    /// The smallest of [`SEGMENT_CHOICES`] meeting the tolerance (the largest when none does).
    Auto,
}

/// How a patch's interior control points are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interior {
    /// The exact B-spline Coons patch of the four arcs (paper, §9.4).
    Coons,
    /// Least squares on the shell with the arcs fixed (ours).
    Fit,
}

/// Weight of the tie to the Coons net in [`Interior::Fit`], per sample.
const COONS_TIE: f64 = 1e-3;

/// The shell's vertices sorted into the rectangles of the layout, with
/// their parameters (s, t) ∈ [0, 1]² there.
pub(crate) struct ShellSamples {
    /// Per rectangle: (3D point, s, t).
    per_rect: Vec<Vec<([f64; 3], f64, f64)>>,
    /// Mean 3D edge length of the shell.
    edge: f64,
}

impl ShellSamples {
    /// Sorts every child vertex of Ω into the first rectangle holding its ψ position.
    pub(crate) fn new(shell: &Shell, cut: &CutMesh, imm: &Immersion, layout: &Layout) -> Self {
        let boxes: Vec<([f64; 2], [f64; 2])> = layout
            .rects
            .iter()
            .map(|r| (layout.nodes[r.corners[0]], layout.nodes[r.corners[2]]))
            .collect();
        let size = boxes
            .iter()
            .map(|(a, c)| (c[0] - a[0]).max(c[1] - a[1]))
            .fold(0.0, f64::max);
        let eps = 1e-9 * size;
        // An annulus: ψ's x taken modulo the period into the one rectangle.
        let x0 = boxes.first().map_or(0.0, |b| b.0[0]);
        let wrap = |p: [f64; 2]| match layout.period_x {
            Some(c) if c > 0.0 => [x0 + (p[0] - x0).rem_euclid(c), p[1]],
            _ => p,
        };
        let mut per_rect = vec![Vec::new(); boxes.len()];
        for (c, p) in imm.uv.iter().enumerate() {
            let p = &wrap(*p);
            let hit = boxes.iter().position(|(a, b)| {
                p[0] >= a[0] - eps && p[0] <= b[0] + eps && p[1] >= a[1] - eps && p[1] <= b[1] + eps
            });
            if let Some(k) = hit {
                let (a, b) = boxes[k];
                let s = ((p[0] - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
                let t = ((p[1] - a[1]) / (b[1] - a[1])).clamp(0.0, 1.0);
                per_rect[k].push((shell.vertices[cut.parent[c]], s, t));
            }
        }
        let mut total = 0.0;
        let mut count = 0usize;
        for t in &shell.triangles {
            for k in 0..3 {
                total += shell.edge_length(t[k], t[(k + 1) % 3]);
                count += 1;
            }
        }
        ShellSamples {
            per_rect,
            edge: if count > 0 { total / count as f64 } else { 1.0 },
        }
    }
}

/// What the fits share: the shell, its layout and the ψ locator.
pub(crate) struct FitContext<'a> {
    pub(crate) shell: &'a Shell,
    pub(crate) layout: &'a Layout,
    pub(crate) locator: &'a PsiLocator,
    pub(crate) samples: &'a ShellSamples,
}

impl FitContext<'_> {
    /// The shell point under a point of ψ.
    fn on_shell(&self, p: [f64; 2]) -> Result<[f64; 3], SplineMethodError> {
        self.locator
            .to_shell(self.shell, p)
            .map(|(x, _)| x)
            .ok_or_else(|| SplineMethodError::Option(format!("no triangle of ψ near {p:?}")))
    }

    /// Points along arc `a` in ψ, `n` of them, evenly spaced.
    fn arc_points(&self, a: usize, n: usize) -> Vec<[f64; 2]> {
        let [p, q] = self.layout.arcs[a].map(|v| self.layout.nodes[v]);
        (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
            })
            .collect()
    }

    /// Samples to take along arc `a`: two per shell edge length, at least 8 per span.
    fn arc_samples(&self, a: usize, spans: usize) -> usize {
        let [p, q] = self.layout.arcs[a].map(|v| self.layout.nodes[v]);
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        ((2.0 * len / self.samples.edge).ceil() as usize + 1)
            .max(8 * spans + 1)
            .min(20_000)
    }

    /// The unit normal of the shell under the point (s, t) of rectangle `k`.
    pub(crate) fn normal(&self, k: usize, s: f64, t: f64) -> [f64; 3] {
        let r = &self.layout.rects[k];
        let (a, c) = (
            self.layout.nodes[r.corners[0]],
            self.layout.nodes[r.corners[2]],
        );
        let p = [a[0] + s * (c[0] - a[0]), a[1] + t * (c[1] - a[1])];
        self.locator
            .locate(p)
            .and_then(|(f, _)| {
                let tri = self.shell.triangles[f];
                let v = &self.shell.vertices;
                normalize(cross(sub(v[tri[1]], v[tri[0]]), sub(v[tri[2]], v[tri[0]])))
            })
            .unwrap_or([0.0, 0.0, 1.0])
    }

    /// The multipatch with `spans` per arc; returns it and the number of
    /// fitted interiors that fell back to Coons.
    pub(crate) fn build(
        &self,
        spans: usize,
        interior: Interior,
    ) -> Result<(Multipatch, usize), SplineMethodError> {
        let mut b = MultipatchBuilder::new();
        // Builder node of each layout node (glued copies share one) and its point.
        let mut node_index: Vec<usize> = Vec::with_capacity(self.layout.nodes.len());
        let mut node_point: Vec<[f64; 3]> = Vec::new();
        for (i, &p) in self.layout.nodes.iter().enumerate() {
            let glue = self.layout.node_glue.get(i).copied().unwrap_or(i);
            if glue < i {
                node_index.push(node_index[glue]);
            } else {
                let x = self.on_shell(p)?;
                node_point.push(x);
                node_index.push(b.add_node(x));
            }
        }
        let mut arcs = Vec::with_capacity(self.layout.arcs.len());
        for (a, &[s, e]) in self.layout.arcs.iter().enumerate() {
            let uv = self.arc_points(a, self.arc_samples(a, spans));
            let pts = uv
                .iter()
                .map(|&p| self.on_shell(p))
                .collect::<Result<Vec<_>, _>>()?;
            let params: Vec<f64> = (0..pts.len())
                .map(|i| i as f64 / (pts.len() - 1) as f64)
                .collect();
            let curve = fit_curve(&pts, &params, spans)?;
            // The ends on their nodes (a glued copy lies on its node only up to ψ's location error).
            let (s, e) = (node_index[s], node_index[e]);
            let mut control = curve.control_points().to_vec();
            let last = control.len() - 1;
            control[0] = node_point[s];
            control[last] = node_point[e];
            let curve = BSplineCurve::new(curve.knots().clone(), control)?;
            arcs.push(b.add_arc(s, e, &curve)?);
        }
        let mut fallbacks = 0;
        for (k, r) in self.layout.rects.iter().enumerate() {
            let sides = r.sides.map(|(a, rev)| {
                if rev {
                    ArcUse::reverse(arcs[a])
                } else {
                    ArcUse::forward(arcs[a])
                }
            });
            match interior {
                Interior::Coons => {
                    b.add_coons_patch(sides)?;
                }
                Interior::Fit => {
                    b.add_patch_with(sides, |coons| {
                        let fitted = fit_interior(coons, &self.samples.per_rect[k])?;
                        let normal = |_x: [f64; 3], s: f64, t: f64| self.normal(k, s, t);
                        if jacobian_check(&fitted, &normal)?.is_positive() {
                            Ok(fitted)
                        } else {
                            fallbacks += 1;
                            Ok(coons.clone())
                        }
                    })?;
                }
            }
        }
        Ok((b.build()?, fallbacks))
    }

    /// Max and mean distance of the shell's vertices to their patch
    /// (closest point by Gauss–Newton from the vertex's ψ parameters).
    pub(crate) fn distances(&self, mp: &Multipatch) -> Result<(f64, f64), SplineMethodError> {
        let (mut max, mut sum, mut n) = (0.0f64, 0.0, 0usize);
        for (k, samples) in self.samples.per_rect.iter().enumerate() {
            let patch = mp.patch(k)?;
            for &(x, s, t) in samples {
                let d = closest_distance(&patch, x, s, t);
                max = max.max(d);
                sum += d;
                n += 1;
            }
        }
        Ok((max, if n > 0 { sum / n as f64 } else { 0.0 }))
    }

    /// Every arc as a polyline on the shell.
    pub(crate) fn layout_polylines(&self) -> Vec<Vec<[f64; 3]>> {
        (0..self.layout.arcs.len())
            .map(|a| {
                self.arc_points(a, self.arc_samples(a, 1))
                    .into_iter()
                    .filter_map(|p| self.locator.to_shell(self.shell, p).map(|(x, _)| x))
                    .collect()
            })
            .collect()
    }
}

/// The distance from `x` to the patch, from a few clamped Gauss–Newton
/// steps on |S(s, t) − x|² started at (s, t).
fn closest_distance(patch: &BSplinePatch, x: [f64; 3], mut s: f64, mut t: f64) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..8 {
        let (p, ps, pt) = patch.derivatives(s, t);
        let r = sub(p, x);
        best = best.min(dot(r, r).sqrt());
        let (a, b, c) = (dot(ps, ps), dot(ps, pt), dot(pt, pt));
        let (g0, g1) = (dot(ps, r), dot(pt, r));
        let det = a * c - b * b;
        if !(det.abs() > 1e-300) {
            break;
        }
        let ds = -(c * g0 - b * g1) / det;
        let dt = -(a * g1 - b * g0) / det;
        s = (s + ds).clamp(0.0, 1.0);
        t = (t + dt).clamp(0.0, 1.0);
        if ds.abs() + dt.abs() < 1e-12 {
            break;
        }
    }
    let p = patch.eval(s, t);
    best.min(dot(sub(p, x), sub(p, x)).sqrt())
}

/// The interior control points of `coons` fitted to `samples` (3D point,
/// s, t) by least squares, the boundary rows kept, tied to the Coons net by
/// [`COONS_TIE`] per sample (so rows no sample reaches stay Coons).
fn fit_interior(
    coons: &BSplinePatch,
    samples: &[([f64; 3], f64, f64)],
) -> Result<BSplinePatch, SplineError> {
    let (ns, nt) = (coons.n_s(), coons.n_t());
    if ns < 3 || nt < 3 {
        return Ok(coons.clone());
    }
    let (ks, kt) = (coons.knots_s(), coons.knots_t());
    let (ps, pt) = (ks.degree(), kt.degree());
    let unknown = |i: usize, j: usize| -> Option<usize> {
        (i > 0 && j > 0 && i + 1 < ns && j + 1 < nt).then(|| (j - 1) * (ns - 2) + (i - 1))
    };
    let m = (ns - 2) * (nt - 2);
    let mut a = vec![0.0; m * m];
    let mut rhs = vec![[0.0; 3]; m];
    let tie = COONS_TIE * (samples.len().max(1) as f64) / m as f64;
    for j in 1..nt - 1 {
        for i in 1..ns - 1 {
            if let Some(u) = unknown(i, j) {
                a[u * m + u] += tie;
                let c = coons.control_point(i, j);
                for d in 0..3 {
                    rhs[u][d] += tie * c[d];
                }
            }
        }
    }
    let mut row: Vec<(usize, usize, f64)> = Vec::with_capacity((ps + 1) * (pt + 1));
    for &(x, s, t) in samples {
        let (ss, st) = (ks.find_span(s), kt.find_span(t));
        let (bs, bt) = (basis_functions(ks, ss, s), basis_functions(kt, st, t));
        row.clear();
        let mut target = x;
        for (jj, &wt) in bt.iter().enumerate() {
            for (ii, &ws) in bs.iter().enumerate() {
                let (i, j) = (ss - ps + ii, st - pt + jj);
                let w = ws * wt;
                match unknown(i, j) {
                    Some(u) => row.push((u, 0, w)),
                    None => {
                        let c = coons.control_point(i, j);
                        for d in 0..3 {
                            target[d] -= w * c[d];
                        }
                    }
                }
            }
        }
        for &(u, _, wu) in &row {
            for &(v, _, wv) in &row {
                a[u * m + v] += wu * wv;
            }
            for d in 0..3 {
                rhs[u][d] += wu * target[d];
            }
        }
    }
    // the three coordinates as three right-hand sides of one factorization
    let mut columns: Vec<Vec<f64>> = (0..3).map(|d| rhs.iter().map(|r| r[d]).collect()).collect();
    spline::linalg::cholesky_solve(a, m, &mut columns).map_err(|_| {
        SplineError::Fit("interior fit: the normal equations are singular".into())
    })?;
    let solution: Vec<[f64; 3]> = (0..m).map(|u| [columns[0][u], columns[1][u], columns[2][u]]).collect();
    let mut control = coons.control_points().to_vec();
    for j in 1..nt - 1 {
        for i in 1..ns - 1 {
            if let Some(u) = unknown(i, j) {
                control[j * ns + i] = solution[u];
            }
        }
    }
    BSplinePatch::new(ks.clone(), kt.clone(), control)
}

