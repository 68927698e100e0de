//! The constraint sets of the layout energy, classified once from ψ_R
//! (spec §8.2): Γ_u / Γ_v for the boundary edges and for the feature
//! edges (one vote per run between corners, so a straight run never mixes
//! sets; boundary runs voted in their loop's frame, [`frame_offset`]), and
//! Γ_Hol_k for each cut path (k by the argmin rule). Each
//! constraint becomes linear terms c·φ whose squares E2–E4 sum.

use crate::cut::{CutEdgeSides, CutMesh};
use crate::ricci::Cone;
use crate::shell::{Shell, ShellTopology, NO_FACE};

/// The coordinate an aligned edge keeps constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeldAxis {
    /// Γ_u: u constant (a "vertical" edge).
    U,
    /// Γ_v: v constant.
    V,
}

/// One child edge of Ω in Γ_u or Γ_v (boundary or feature).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlignedEdge {
    /// Its child vertices.
    pub children: [usize; 2],
    /// Their shell vertices.
    pub parents: [usize; 2],
    /// The coordinate held constant.
    pub held: HeldAxis,
    /// Reference (3D) length ℓ_e.
    pub length: f64,
}

/// A cut path in Γ_Hol_k: right side = R(k·π/2)·left + t along it.
#[derive(Clone, Debug, PartialEq)]
pub struct HolonomyPath {
    /// Index of the path in [`CutMesh::paths`].
    pub path: usize,
    /// k in 0..4.
    pub quarter_turns: u8,
    /// Its child edges with their parents' 3D lengths.
    pub edges: Vec<(CutEdgeSides, [usize; 2], f64)>,
}

/// All constraint sets of one shell.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConstraintSets {
    /// Boundary edges (E2).
    pub boundary: Vec<AlignedEdge>,
    /// Feature edges (E3); a feature on a cut constrains both children.
    pub features: Vec<AlignedEdge>,
    /// Cut paths (E4).
    pub holonomy: Vec<HolonomyPath>,
}

impl ConstraintSets {
    /// Edges in Γ_u and in Γ_v (boundary and features together).
    pub fn axis_counts(&self) -> [usize; 2] {
        let all = self.boundary.iter().chain(&self.features);
        let u = all.clone().filter(|e| e.held == HeldAxis::U).count();
        [u, self.boundary.len() + self.features.len() - u]
    }
}

/// The rotation by k quarter turns as (cos, sin).
pub fn quarter_turn(k: u8) -> (f64, f64) {
    match k % 4 {
        0 => (1.0, 0.0),
        1 => (0.0, 1.0),
        2 => (-1.0, 0.0),
        _ => (0.0, -1.0),
    }
}

fn length3(shell: &Shell, a: usize, b: usize) -> f64 {
    let (p, q) = (shell.vertices[a], shell.vertices[b]);
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// The child of shell vertex `v` in triangle `f`.
fn child(shell: &Shell, cut: &CutMesh, f: usize, v: usize) -> usize {
    let k = (0..3).position(|k| shell.triangles[f][k] == v).unwrap_or(0);
    cut.corners[f][k]
}

fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Runs of child edges `edges`: chains joined at child vertices whose
/// shell vertex is not a break and that meet exactly two of the edges (a
/// cut ending on the boundary splits a run: its two sides are different
/// children, rotated against each other in ψ_R).
fn runs(edges: &[[usize; 2]], is_break: impl Fn(usize) -> bool) -> Vec<Vec<usize>> {
    let mut at: std::collections::HashMap<usize, Vec<usize>> = Default::default();
    for (i, e) in edges.iter().enumerate() {
        for &v in e {
            at.entry(v).or_default().push(i);
        }
    }
    let mut parent: Vec<usize> = (0..edges.len()).collect();
    for (v, list) in &at {
        if !is_break(*v) && list.len() == 2 {
            let (a, b) = (root(&mut parent, list[0]), root(&mut parent, list[1]));
            parent[a] = b;
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for i in 0..edges.len() {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i);
    }
    groups.into_values().collect()
}

/// The frame offset of a set of child edges: the angle in (−π/4, π/4]
/// their directions keep mod π/2, ¼ arg Σ |d| e^{4iθ} (each edge weighted
/// by its length in ψ). Ricci straightens each boundary loop and turns it
/// by exact quarter turns at corners and cut ends, so every run of one loop
/// keeps one offset; a loop twisted against the axes (the holed shells'
/// inner loops) is voted in its own frame, so its runs agree.
fn frame_offset(uv: &[[f64; 2]], pairs: impl Iterator<Item = [usize; 2]>) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for [a, b] in pairs {
        let (du, dv) = (uv[b][0] - uv[a][0], uv[b][1] - uv[a][1]);
        let l = du.hypot(dv);
        if l > 0.0 {
            let t = 4.0 * dv.atan2(du);
            re += l * t.cos();
            im += l * t.sin();
        }
    }
    if re == 0.0 && im == 0.0 {
        return 0.0;
    }
    0.25 * f64::atan2(im, re)
}

/// Aligned child edges of the shell edges `edges` (both children of an edge
/// on a cut), one vote per run. `group` names the set a shell edge's runs
/// share a frame with (its boundary loop; `None`: the plain axes), see
/// [`frame_offset`].
fn aligned(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    uv: &[[f64; 2]],
    edges: &[usize],
    is_break: &[bool],
    group: impl Fn([usize; 2]) -> Option<usize>,
) -> Vec<AlignedEdge> {
    let mut children: Vec<([usize; 2], [usize; 2])> = Vec::new();
    for &e in edges {
        let [a, b] = topo.edges[e];
        let mut mine: Vec<[usize; 2]> = Vec::new();
        for f in topo.edge_faces[e] {
            if f == NO_FACE {
                continue;
            }
            let pair = [child(shell, cut, f, a), child(shell, cut, f, b)];
            if !mine.contains(&pair) {
                mine.push(pair);
                children.push((pair, [a, b]));
            }
        }
    }
    let pairs: Vec<[usize; 2]> = children.iter().map(|c| c.0).collect();
    let mut offsets: std::collections::BTreeMap<usize, f64> = Default::default();
    for c in &children {
        if let Some(g) = group(c.1) {
            offsets.entry(g).or_insert_with(|| {
                frame_offset(
                    uv,
                    children
                        .iter()
                        .filter(|d| group(d.1) == Some(g))
                        .map(|d| d.0),
                )
            });
        }
    }
    let mut out = Vec::new();
    for run in runs(&pairs, |c| is_break[cut.parent[c]]) {
        let offset = group(children[run[0]].1).map_or(0.0, |g| offsets[&g]);
        let (s, c) = (-offset).sin_cos();
        let (mut du, mut dv) = (0.0, 0.0);
        for &i in &run {
            let [a, b] = children[i].0;
            let (x, y) = (uv[b][0] - uv[a][0], uv[b][1] - uv[a][1]);
            du += (c * x - s * y).abs();
            dv += (s * x + c * y).abs();
        }
        let held = if du <= dv { HeldAxis::U } else { HeldAxis::V };
        for &i in &run {
            let (pair, parents) = children[i];
            out.push(AlignedEdge {
                children: pair,
                parents,
                held,
                length: length3(shell, parents[0], parents[1]),
            });
        }
    }
    out
}

/// Classifies the constraint sets from ψ_R = `uv` (spec §8.2). `features`
/// flags shell edges (per [`ShellTopology::edges`]; empty for none);
/// boundary runs break at boundary cones, feature runs at cones and where
/// features meet or end.
pub fn classify(
    shell: &Shell,
    topo: &ShellTopology,
    cut: &CutMesh,
    cones: &[Cone],
    uv: &[[f64; 2]],
    features: &[bool],
) -> ConstraintSets {
    let mut is_break = vec![false; shell.vertices.len()];
    for c in cones.iter().filter(|c| c.index != 0) {
        if c.vertex < is_break.len() {
            is_break[c.vertex] = true;
        }
    }
    let boundary_edges: Vec<usize> = (0..topo.edges.len())
        .filter(|&e| topo.is_boundary_edge(e))
        .collect();
    let feature_edges: Vec<usize> = (0..topo.edges.len())
        .filter(|&e| features.get(e) == Some(&true) && !topo.is_boundary_edge(e))
        .collect();
    let mut loop_of = vec![usize::MAX; shell.vertices.len()];
    for (i, lp) in topo.boundary_loops.iter().enumerate() {
        for &v in lp {
            loop_of[v] = i;
        }
    }
    let boundary = aligned(
        shell,
        topo,
        cut,
        uv,
        &boundary_edges,
        &is_break,
        |p: [usize; 2]| Some(loop_of[p[0]]),
    );
    let features = aligned(shell, topo, cut, uv, &feature_edges, &is_break, |_| None);
    let holonomy = cut
        .paths
        .iter()
        .enumerate()
        .map(|(i, path)| {
            let d = |p: [usize; 2]| [uv[p[1]][0] - uv[p[0]][0], uv[p[1]][1] - uv[p[0]][1]];
            let misfit = |k: u8| -> f64 {
                let (c, s) = quarter_turn(k);
                path.sides
                    .iter()
                    .map(|sd| {
                        let (l, r) = (d(sd.left), d(sd.right));
                        let rl = [c * l[0] - s * l[1], s * l[0] + c * l[1]];
                        (rl[0] - r[0]).powi(2) + (rl[1] - r[1]).powi(2)
                    })
                    .sum()
            };
            let quarter_turns = (0..4u8)
                .min_by(|&a, &b| misfit(a).total_cmp(&misfit(b)))
                .unwrap_or(0);
            let edges = path
                .sides
                .iter()
                .zip(path.vertices.windows(2))
                .map(|(sd, w)| (*sd, [w[0], w[1]], length3(shell, w[0], w[1])))
                .collect();
            HolonomyPath {
                path: i,
                quarter_turns,
                edges,
            }
        })
        .collect();
    ConstraintSets {
        boundary,
        features,
        holonomy,
    }
}

/// A linear residual c·φ over at most six unknowns (2·child + coordinate),
/// squared and weighted by 1/ℓ in its energy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearTerm {
    /// Unknown indices (repeats allowed).
    pub dofs: [usize; 6],
    /// Their coefficients.
    pub coefs: [f64; 6],
    /// Entries used.
    pub len: usize,
    /// 1 / ℓ_e.
    pub weight: f64,
}

impl LinearTerm {
    fn new(pairs: &[(usize, f64)], weight: f64) -> LinearTerm {
        let mut t = LinearTerm {
            dofs: [0; 6],
            coefs: [0.0; 6],
            len: 0,
            weight,
        };
        for &(d, c) in pairs.iter().filter(|p| p.1 != 0.0) {
            t.dofs[t.len] = d;
            t.coefs[t.len] = c;
            t.len += 1;
        }
        t
    }

    /// c·φ.
    pub fn value(&self, phi: &[f64]) -> f64 {
        (0..self.len)
            .map(|k| self.coefs[k] * phi[self.dofs[k]])
            .sum()
    }
}

/// The linear terms of aligned edges: Δu (Γ_u) or Δv (Γ_v).
pub fn aligned_terms(edges: &[AlignedEdge]) -> Vec<LinearTerm> {
    edges
        .iter()
        .map(|e| {
            let axis = match e.held {
                HeldAxis::U => 0,
                HeldAxis::V => 1,
            };
            let [a, b] = e.children;
            LinearTerm::new(&[(2 * b + axis, 1.0), (2 * a + axis, -1.0)], 1.0 / e.length)
        })
        .collect()
}

/// The linear terms of the cut paths: both components of
/// R_k·d_left − d_right per cut edge.
pub fn holonomy_terms(paths: &[HolonomyPath]) -> Vec<LinearTerm> {
    let mut out = Vec::new();
    for p in paths {
        let (c, s) = quarter_turn(p.quarter_turns);
        for (sd, _, length) in &p.edges {
            let [l0, l1] = sd.left;
            let [r0, r1] = sd.right;
            // Row 0: c·Δu_l − s·Δv_l − Δu_r; row 1: s·Δu_l + c·Δv_l − Δv_r.
            for (cu, cv, axis) in [(c, -s, 0), (s, c, 1)] {
                out.push(LinearTerm::new(
                    &[
                        (2 * l1, cu),
                        (2 * l0, -cu),
                        (2 * l1 + 1, cv),
                        (2 * l0 + 1, -cv),
                        (2 * r1 + axis, -1.0),
                        (2 * r0 + axis, 1.0),
                    ],
                    1.0 / length,
                ));
            }
        }
    }
    out
}
