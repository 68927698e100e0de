//! The quantization integer program (paper §III.B–C, spec §4): one integer
//! `q ≥ 0` per arc (arcs that are the single arcs of opposite patch sides
//! share one), consistency (2) on every grid patch, validity (3) and
//! geometric consistency (4) from the traces, and ours: every CAD curve keeps
//! at least `max(1, ⌈turn / 90°⌉)` edges (4 if closed), capped at its input
//! count. Objective (6): `Σ q_a / l_a`. Solved by HiGHS through `good_lp`,
//! started from `q = l` (always feasible); the solver's answer is checked
//! against every row before it is used, else `q = l`.

use super::connectivity::{Connectivity, NodeKind};
use super::tmesh::{PatchShape, TMesh};
use super::traces::{Source, Traces};
use geometry::vec3;
use good_lp::{
    constraint, variable, Expression, ProblemVariables, ResolutionError, Solution, SolutionStatus,
    SolverModel, Variable, WithInitialSolution,
};
use mesh::QuadMesh;
use std::collections::{BTreeMap, HashSet};
use std::time::Instant;

/// Which rule a row comes from (counted in the report).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum RowKind {
    /// (2) opposite sides of a patch of equal length.
    Consistency,
    /// (3) an origin separated from its first in-cone crossing.
    Validity,
    /// (4) an origin outside a trace's cone kept off it.
    Geometric,
    /// Ours: a CAD curve's minimum edge count.
    Curve,
    /// Ours: an arc whose collapse gave a layout that failed its checks,
    /// kept at length ≥ 1.
    Repair,
}

/// One row: `Σ coeff · q_var  (= 0 | ≥ rhs)`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Row {
    /// The rule.
    pub kind: RowKind,
    /// `(variable, coefficient)`, sorted by variable.
    pub coeffs: Vec<(u32, i32)>,
    /// `None`: equality to 0; `Some(r)`: `≥ r`.
    pub at_least: Option<i32>,
}

/// The integer program over merged arc variables.
#[derive(Clone, Debug, Default)]
pub(crate) struct Program {
    /// The variable of each arc.
    pub var_of_arc: Vec<u32>,
    /// The input length `l` of each variable (equal for all its arcs).
    pub input: Vec<u32>,
    /// The objective weight of each variable: `Σ 1 / l_a` over its arcs.
    pub weight: Vec<f64>,
    /// Variables held at their input length (frozen patches, earlier failures).
    pub fixed: Vec<bool>,
    /// The rows, without repeats.
    pub rows: Vec<Row>,
}

/// How the program was solved.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SolveStatus {
    /// HiGHS proved it optimal (within its default gap).
    Optimal,
    /// HiGHS stopped at the time limit; its incumbent passed our check.
    TimeLimit,
    /// `q = l`: time limit 0, or the solver failed (the reason).
    Identity(String),
}

/// The solve's figures.
#[derive(Clone, Debug)]
pub(crate) struct SolveReport {
    /// How it ended.
    pub status: SolveStatus,
    /// Seconds in the solver.
    pub seconds: f64,
}

impl Program {
    /// Number of variables.
    pub fn num_vars(&self) -> usize {
        self.input.len()
    }

    /// Rows of each kind.
    pub fn row_counts(&self) -> BTreeMap<RowKind, usize> {
        let mut m = BTreeMap::new();
        for r in &self.rows {
            *m.entry(r.kind).or_insert(0) += 1;
        }
        m
    }

    /// True when `q` (per variable) meets every row, bound and fixing.
    pub fn satisfied_by(&self, q: &[u32]) -> bool {
        q.len() == self.num_vars()
            && (0..q.len()).all(|v| q[v] <= self.input[v] && (!self.fixed[v] || q[v] == self.input[v]))
            && self.rows.iter().all(|r| {
                let s: i64 = r.coeffs.iter().map(|&(v, c)| c as i64 * q[v as usize] as i64).sum();
                match r.at_least {
                    None => s == 0,
                    Some(k) => s >= k as i64,
                }
            })
    }

    /// The length of every arc under the per-variable answer `q`.
    pub fn arc_lengths(&self, q: &[u32]) -> Vec<u32> {
        self.var_of_arc.iter().map(|&v| q[v as usize]).collect()
    }
}

/// Builds the program; the arcs in `fixed_arcs` keep their input length,
/// those in `kept_open` a length ≥ 1.
pub(crate) fn build_program(
    mesh: &QuadMesh,
    conn: &Connectivity,
    traces: &Traces,
    tm: &TMesh,
    tan_alpha: f64,
    fixed_arcs: &HashSet<u32>,
    kept_open: &HashSet<u32>,
) -> Program {
    let na = tm.arcs.len();
    // single arcs of opposite sides share a variable
    let mut parent: Vec<u32> = (0..na as u32).collect();
    fn find(p: &mut [u32], mut i: u32) -> u32 {
        while p[i as usize] != i {
            p[i as usize] = p[p[i as usize] as usize];
            i = p[i as usize];
        }
        i
    }
    for p in &tm.patches {
        if let PatchShape::Grid { sides, .. } = &p.shape {
            for s in 0..2 {
                if let ([(a, _)], [(b, _)]) = (sides[s].as_slice(), sides[s + 2].as_slice()) {
                    let (ra, rb) = (find(&mut parent, *a), find(&mut parent, *b));
                    parent[ra.max(rb) as usize] = ra.min(rb);
                }
            }
        }
    }
    let mut var_of_root = vec![u32::MAX; na];
    let mut prog = Program::default();
    for a in 0..na as u32 {
        let r = find(&mut parent, a) as usize;
        if var_of_root[r] == u32::MAX {
            var_of_root[r] = prog.input.len() as u32;
            prog.input.push(tm.arcs[a as usize].len());
            prog.weight.push(0.0);
            prog.fixed.push(false);
        }
        let v = var_of_root[r];
        prog.var_of_arc.push(v);
        prog.weight[v as usize] += 1.0 / tm.arcs[a as usize].len() as f64;
    }
    for p in &tm.patches {
        if matches!(p.shape, PatchShape::Frozen) {
            for &a in &p.boundary_arcs {
                prog.fixed[prog.var_of_arc[a as usize] as usize] = true;
            }
        }
    }
    for &a in fixed_arcs {
        prog.fixed[prog.var_of_arc[a as usize] as usize] = true;
    }
    let mut rows: HashSet<Row> = HashSet::new();
    let mut add = |kind: RowKind, arcs: &[(u32, i32)], at_least: Option<i32>| {
        let mut m: BTreeMap<u32, i32> = BTreeMap::new();
        for &(a, c) in arcs {
            *m.entry(prog.var_of_arc[a as usize]).or_insert(0) += c;
        }
        let coeffs: Vec<(u32, i32)> = m.into_iter().filter(|&(_, c)| c != 0).collect();
        if !coeffs.is_empty() {
            rows.insert(Row { kind, coeffs, at_least });
        }
    };
    for p in &tm.patches {
        if let PatchShape::Grid { sides, .. } = &p.shape {
            for s in 0..2 {
                let mut arcs: Vec<(u32, i32)> = sides[s].iter().map(|&(a, _)| (a, 1)).collect();
                arcs.extend(sides[s + 2].iter().map(|&(a, _)| (a, -1)));
                add(RowKind::Consistency, &arcs, None);
            }
        }
    }
    separation_rows(conn, traces, tm, tan_alpha, &mut add);
    for (arcs, need) in curve_rows(mesh, tm) {
        let arcs: Vec<(u32, i32)> = arcs.iter().map(|&a| (a, 1)).collect();
        add(RowKind::Curve, &arcs, Some(need));
    }
    for &a in kept_open {
        add(RowKind::Repair, &[(a, 1)], Some(1));
    }
    let mut rows: Vec<Row> = rows.into_iter().collect();
    rows.sort_by(|a, b| (a.kind, &a.coeffs, a.at_least).cmp(&(b.kind, &b.coeffs, b.at_least)));
    prog.rows = rows;
    prog
}

/// Validity (3) and geometric consistency (4) rows, as lists of arcs `≥ 1`.
fn separation_rows(
    conn: &Connectivity,
    traces: &Traces,
    tm: &TMesh,
    tan_alpha: f64,
    add: &mut impl FnMut(RowKind, &[(u32, i32)], Option<i32>),
) {
    let ts = &traces.traces;
    let origin_kind = |t: usize| conn.kind[ts[t].nodes[0] as usize];
    // per trace: (position along it, position along the other, other origin node)
    let mut events: Vec<Vec<(u32, u32, u32)>> = vec![Vec::new(); ts.len()];
    for c in &traces.crossings {
        for k in 0..2 {
            let (i, j) = (c.traces[k] as usize, c.traces[1 - k] as usize);
            events[i].push((c.lengths[k], c.lengths[1 - k], j as u32));
            // (4): j's origin outside the cone of t_i stays off t_i
            if ts[j].source == Source::Origin && c.lengths[1 - k] >= 1 {
                let tan_i = if ts[i].on_curve { 0.0 } else { tan_alpha };
                if c.lengths[1 - k] as f64 > tan_i * c.lengths[k] as f64 + 1e-9 {
                    let arcs = tm.arcs_along(&ts[j].nodes, c.lengths[1 - k] as usize);
                    let arcs: Vec<(u32, i32)> = arcs.iter().map(|&a| (a, 1)).collect();
                    add(RowKind::Geometric, &arcs, Some(1));
                }
            }
        }
    }
    // (3): the first crossing whose origin is in the π/4 cone, else the end
    for (i, t) in ts.iter().enumerate() {
        if t.source != Source::Origin {
            continue;
        }
        let mut best: Option<(u32, NodeKind)> = None;
        for &(pi, pj, j) in &events[i] {
            if ts[j as usize].source == Source::Origin
                && pj <= pi
                && best.is_none_or(|(b, _)| pi < b)
            {
                best = Some((pi, origin_kind(j as usize)));
            }
        }
        let last = t.nodes.len() as u32 - 1;
        if t.end == super::traces::TraceEnd::ReachedOrigin && best.is_none_or(|(b, _)| last < b) {
            best = Some((last, conn.kind[t.nodes[last as usize] as usize]));
        }
        let upto = best.map_or(last, |(p, _)| p);
        if let Some((_, other)) = best {
            if is_three_five_pair(origin_kind(i), other) {
                continue;
            }
        }
        let arcs: Vec<(u32, i32)> =
            tm.arcs_along(&t.nodes, upto as usize).iter().map(|&a| (a, 1)).collect();
        add(RowKind::Validity, &arcs, Some(1));
    }
}

/// True for a face-interior valence-3 / valence-5 pair (they may collapse
/// into a regular node).
fn is_three_five_pair(a: NodeKind, b: NodeKind) -> bool {
    match (a, b) {
        (
            NodeKind::Irregular { valence: va, face_interior: true },
            NodeKind::Irregular { valence: vb, face_interior: true },
        ) => (va == 3 && vb == 5) || (va == 5 && vb == 3),
        _ => false,
    }
}

/// Per CAD curve: its arcs and the edges it keeps at least.
fn curve_rows(mesh: &QuadMesh, tm: &TMesh) -> Vec<(Vec<u32>, i32)> {
    let mut arcs_of: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (a, arc) in tm.arcs.iter().enumerate() {
        if let Some(c) = arc.curve {
            arcs_of.entry(c).or_default().push(a as u32);
        }
    }
    // turning of each curve's polyline, from its nodes with two curve edges
    let mut ends: BTreeMap<u32, BTreeMap<u32, Vec<u32>>> = BTreeMap::new();
    for &([a, b], c) in &mesh.curve_edges {
        let m = ends.entry(c.0).or_default();
        m.entry(a).or_default().push(b);
        m.entry(b).or_default().push(a);
    }
    let mut out = Vec::new();
    for (c, arcs) in arcs_of {
        let Some(m) = ends.get(&c) else { continue };
        let edges: u32 = arcs.iter().map(|&a| tm.arcs[a as usize].len()).sum();
        let closed = m.values().all(|n| n.len() == 2);
        let mut turn = 0.0;
        for (&v, n) in m {
            if n.len() == 2 {
                let p = mesh.nodes[v as usize];
                let d0 = vec3::sub(p, mesh.nodes[n[0] as usize]);
                let d1 = vec3::sub(mesh.nodes[n[1] as usize], p);
                turn += vec3::norm(vec3::cross(d0, d1)).atan2(vec3::dot(d0, d1));
            }
        }
        let mut need = ((turn / std::f64::consts::FRAC_PI_2) - 1e-6).ceil().max(1.0) as u32;
        if closed {
            need = need.max(4);
        }
        out.push((arcs, need.min(edges) as i32));
    }
    out
}

/// Solves `prog` with HiGHS (one thread, `time_limit` seconds) for objective
/// (6); `q = l` when the limit is 0 or the answer fails
/// [`Program::satisfied_by`].
pub(crate) fn solve(prog: &Program, time_limit: f64) -> (Vec<u32>, SolveReport) {
    solve_weighted(prog, &prog.weight, &prog.input, time_limit)
}

/// [`solve`] with other objective weights (per variable) and MIP start
/// `start` (which must be feasible).
pub(crate) fn solve_weighted(
    prog: &Program,
    weight: &[f64],
    start: &[u32],
    time_limit: f64,
) -> (Vec<u32>, SolveReport) {
    let identity = prog.input.clone();
    let fallback = |why: String, seconds: f64| {
        tracing::warn!("coarse: the integer program falls back to the input lengths: {why}");
        (
            identity.clone(),
            SolveReport { status: SolveStatus::Identity(why), seconds },
        )
    };
    if !(time_limit > 0.0) {
        return fallback("time limit 0".into(), 0.0);
    }
    let started = Instant::now();
    let mut vars = ProblemVariables::new();
    let xs: Vec<Variable> = (0..prog.num_vars())
        .map(|v| {
            // ours: no arc longer than its input length, so that every
            // layout vertex has an input node of its own (centres are nodes)
            let def = variable().integer().min(0).max(prog.input[v]);
            vars.add(if prog.fixed[v] { def.min(prog.input[v]) } else { def })
        })
        .collect();
    let objective: Expression = xs.iter().zip(weight).map(|(&x, &w)| w * x).sum();
    let mut model = vars
        .minimise(objective)
        .using(good_lp::highs)
        .with_initial_solution(xs.iter().zip(start).map(|(&x, &l)| (x, l as f64)));
    model.set_verbose(false);
    let mut model = model
        .set_threads(1)
        .set_time_limit(time_limit)
        .set_option("output_flag", false)
        .set_option("mip_rel_gap", 1e-9);
    for r in &prog.rows {
        let lhs: Expression = r.coeffs.iter().map(|&(v, c)| c as f64 * xs[v as usize]).sum();
        match r.at_least {
            None => model.add_constraint(constraint!(lhs == 0.0)),
            Some(k) => model.add_constraint(constraint!(lhs >= k as f64)),
        };
    }
    let solved = model.solve();
    let seconds = started.elapsed().as_secs_f64();
    let solution = match solved {
        Ok(s) => s,
        Err(ResolutionError::Infeasible) => {
            return fallback("HiGHS says infeasible (a bug: q = l is feasible)".into(), seconds)
        }
        Err(e) => return fallback(format!("HiGHS: {e}"), seconds),
    };
    let q: Vec<u32> = xs.iter().map(|&x| solution.value(x).round().max(0.0) as u32).collect();
    if !prog.satisfied_by(&q) {
        return fallback("the solver's answer breaks a constraint".into(), seconds);
    }
    let status = match solution.status() {
        SolutionStatus::Optimal | SolutionStatus::GapLimit => SolveStatus::Optimal,
        _ => SolveStatus::TimeLimit,
    };
    (q, SolveReport { status, seconds })
}

/// Objective weights that linearize the block count (5) about arc lengths
/// `q` (per arc): each variable's paper weight `Σ 1 / l_a`, plus for each
/// patch side an arc lies on, half the patch's other dimension — the slope of
/// `Q1 · Q2` along the arc (ours: the paper's linear objective leaves arcs
/// with `q ≥ 2` that multiply blocks, its §V; this steps toward (5)).
pub(crate) fn area_weights(prog: &Program, tm: &TMesh, q: &[u32]) -> Vec<f64> {
    let mut w = prog.weight.clone();
    for p in &tm.patches {
        if let PatchShape::Grid { sides, .. } = &p.shape {
            let dim = |s: usize| sides[s].iter().map(|&(a, _)| q[a as usize]).sum::<u32>() as f64;
            for (s, side) in sides.iter().enumerate() {
                let across = dim((s + 1) % 4);
                for &(a, _) in side {
                    w[prog.var_of_arc[a as usize] as usize] += 0.5 * across;
                }
            }
        }
    }
    w
}
