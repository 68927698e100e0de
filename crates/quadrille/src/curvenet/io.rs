//! Curve-network files (issue 30, item 1; the formats are described in
//! `docs/curve-networks.md`): JSON in and out, OBJ polylines in.
//!
//! - JSON: `{"curves":[{"points":[[x,y,z],…]}], "cycles":[{"loops":[[[curve,
//!   ±1],…],…]}], "corners":[[x,y,z],…]}`; optional `"cad_curve"` per curve
//!   and `"cad_face"` per cycle (1-based, as in CAD files); unknown keys
//!   ignored. [`to_json`] writes it, and [`parse_json`] reads what it wrote
//!   back to an equal network.
//! - OBJ: `v` vertices and `l` polylines; each closed `l` (its first vertex
//!   is its last) is a one-loop cycle, the curves are the runs between the
//!   vertices where other than 2 cycle edges meet, `p` lists corners. Open
//!   `l` lines and every other record are ignored.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use geometry::vec3::Vec3;
use geometry::{CurveId, FaceId};
use serde::Deserialize;

use super::check::{self, key};
use super::error::CurveNetError;
use super::network::{CurveNetwork, CycleUse, NetworkCurve, NetworkCycle, WELD_FACTOR};

/// Reads a curve network, by extension (case-insensitive): `.json` or `.obj`.
/// CAD files (`.step`, `.stp`, `.iges`, `.igs`, `.brep`) go through
/// `occt::load` and [`crate::curvenet::network_from_model`] instead. Errors
/// name the file.
pub fn read_network(path: &Path) -> Result<CurveNetwork, CurveNetError> {
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let parse: fn(&str, Option<&str>) -> Result<CurveNetwork, CurveNetError> = match ext.as_str() {
        "json" => parse_json,
        "obj" => parse_obj,
        "step" | "stp" | "iges" | "igs" | "brep" | "brp" => {
            return Err(CurveNetError::Format {
                file: Some(name),
                message: "a CAD file: read it with occt::load and network_from_model".into(),
            })
        }
        _ => {
            return Err(CurveNetError::Format {
                file: Some(name),
                message: "unknown curve-network format: use .json or .obj".into(),
            })
        }
    };
    let bytes = std::fs::read(path).map_err(|e| CurveNetError::Io {
        file: name.clone(),
        message: e.to_string(),
    })?;
    let text = String::from_utf8(bytes).map_err(|e| CurveNetError::Io {
        file: name.clone(),
        message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
    })?;
    parse(&text, Some(&name))
}

/// Writes `net` as JSON ([`to_json`]) to `path`.
pub fn write_network(net: &CurveNetwork, path: &Path) -> Result<(), CurveNetError> {
    std::fs::write(path, to_json(net)).map_err(|e| CurveNetError::Io {
        file: path.display().to_string(),
        message: format!("cannot write: {e}"),
    })
}

#[derive(Deserialize)]
#[serde(expecting = "a curve network: {\"curves\": [...], \"cycles\": [...]}")]
struct JsonNetwork {
    curves: Vec<JsonCurve>,
    cycles: Vec<JsonCycle>,
    #[serde(default)]
    corners: Vec<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(expecting = "a curve: {\"points\": [[x, y, z], ...]}")]
struct JsonCurve {
    points: Vec<[f64; 3]>,
    #[serde(default)]
    id: Option<usize>,
    #[serde(default)]
    cad_curve: Option<u32>,
}

#[derive(Deserialize)]
#[serde(expecting = "a cycle: {\"loops\": [[[curve, 1 or -1], ...], ...]}")]
struct JsonCycle {
    loops: Vec<Vec<(usize, i64)>>,
    #[serde(default)]
    id: Option<usize>,
    #[serde(default)]
    cad_face: Option<u32>,
}

/// Parses the JSON format; `file` names the file in errors. Syntax errors
/// (and wrong types, missing keys) give the line and column.
pub fn parse_json(text: &str, file: Option<&str>) -> Result<CurveNetwork, CurveNetError> {
    let file_s = file.map(str::to_string);
    let format = |message: String| CurveNetError::Format {
        file: file_s.clone(),
        message,
    };
    if text.trim().is_empty() {
        return Err(CurveNetError::Empty {
            file: file_s.clone(),
            message: "the input is empty".into(),
        });
    }
    let raw: JsonNetwork = serde_json::from_str(text).map_err(|e| {
        let mut message = e.to_string();
        // serde_json appends " at line L column C"; the prefix says it
        if let Some(i) = message.rfind(" at line ") {
            message.truncate(i);
        }
        if e.is_eof() {
            message.push_str(" (the input ends early: truncated?)");
        }
        CurveNetError::Syntax {
            file: file_s.clone(),
            line: e.line(),
            column: e.column(),
            message,
        }
    })?;
    let mut curves = Vec::with_capacity(raw.curves.len());
    for (i, c) in raw.curves.into_iter().enumerate() {
        if c.id.is_some_and(|id| id != i) {
            return Err(format(format!(
                "curve {i} has \"id\": {}; ids must be the curves' positions (0-based)",
                c.id.unwrap_or(0)
            )));
        }
        let cad = match c.cad_curve {
            Some(0) => return Err(format(format!("curve {i}: \"cad_curve\" is 1-based"))),
            Some(n) => Some(CurveId(n - 1)),
            None => None,
        };
        curves.push(NetworkCurve {
            points: c.points,
            cad,
        });
    }
    let mut cycles = Vec::with_capacity(raw.cycles.len());
    for (ci, c) in raw.cycles.into_iter().enumerate() {
        if c.id.is_some_and(|id| id != ci) {
            return Err(format(format!(
                "cycle {ci} has \"id\": {}; ids must be the cycles' positions (0-based)",
                c.id.unwrap_or(0)
            )));
        }
        let cad_face = match c.cad_face {
            Some(0) => return Err(format(format!("cycle {ci}: \"cad_face\" is 1-based"))),
            Some(n) => Some(FaceId(n - 1)),
            None => None,
        };
        let mut loops = Vec::with_capacity(c.loops.len());
        for (li, lp) in c.loops.into_iter().enumerate() {
            let mut uses = Vec::with_capacity(lp.len());
            for (ui, (curve, dir)) in lp.into_iter().enumerate() {
                let forward = match dir {
                    1 => true,
                    -1 => false,
                    d => {
                        return Err(format(format!(
                            "cycle {ci}, loop {li}, use {ui}: direction {d} (1 or -1 expected)"
                        )))
                    }
                };
                uses.push(CycleUse { curve, forward });
            }
            loops.push(uses);
        }
        cycles.push(NetworkCycle { loops, cad_face, surface: None });
    }
    CurveNetwork::new_in(curves, cycles, raw.corners, file_s.clone())
}

/// `x` as JSON (shortest representation that reads back to the same bits).
fn json_num(x: f64) -> String {
    serde_json::to_string(&x).unwrap_or_else(|_| "null".into())
}

fn json_point(out: &mut String, p: Vec3) {
    let _ = write!(
        out,
        "[{},{},{}]",
        json_num(p[0]),
        json_num(p[1]),
        json_num(p[2])
    );
}

/// The network in the JSON format, one curve, cycle or corner list per line.
pub fn to_json(net: &CurveNetwork) -> String {
    let mut out = String::from("{\"curves\":[\n");
    for (i, c) in net.curves().iter().enumerate() {
        out.push_str("{\"points\":[");
        for (k, p) in c.points.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            json_point(&mut out, *p);
        }
        out.push(']');
        if let Some(id) = c.cad {
            let _ = write!(out, ",\"cad_curve\":{}", id.0 as u64 + 1);
        }
        out.push('}');
        out.push_str(if i + 1 < net.curves().len() {
            ",\n"
        } else {
            "\n"
        });
    }
    out.push_str("],\n\"cycles\":[\n");
    for (i, c) in net.cycles().iter().enumerate() {
        out.push_str("{\"loops\":[");
        for (li, lp) in c.loops.iter().enumerate() {
            if li > 0 {
                out.push(',');
            }
            out.push('[');
            for (k, u) in lp.iter().enumerate() {
                if k > 0 {
                    out.push(',');
                }
                let _ = write!(out, "[{},{}]", u.curve, if u.forward { 1 } else { -1 });
            }
            out.push(']');
        }
        out.push(']');
        if let Some(f) = c.cad_face {
            let _ = write!(out, ",\"cad_face\":{}", f.0 as u64 + 1);
        }
        out.push('}');
        out.push_str(if i + 1 < net.cycles().len() {
            ",\n"
        } else {
            "\n"
        });
    }
    out.push_str("],\n\"corners\":[");
    for (k, p) in net.corners().iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        json_point(&mut out, *p);
    }
    out.push_str("]}\n");
    out
}

/// Whitespace-separated tokens of `line` with their 1-based columns.
fn tokens(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, ch) in line.char_indices() {
        if ch.is_whitespace() {
            if let Some(s) = start.take() {
                out.push((s + 1, &line[s..i]));
            }
        } else if start.is_none() {
            start = Some(i);
        }
    }
    if let Some(s) = start {
        out.push((s + 1, &line[s..]));
    }
    out
}

/// Parses OBJ polylines; `file` names the file in errors.
pub fn parse_obj(text: &str, file: Option<&str>) -> Result<CurveNetwork, CurveNetError> {
    let file_s = file.map(str::to_string);
    let syntax = |line: usize, column: usize, message: String| CurveNetError::Syntax {
        file: file_s.clone(),
        line,
        column,
        message,
    };
    let mut verts: Vec<Vec3> = Vec::new();
    let mut vert_line: Vec<usize> = Vec::new();
    // (line, [(column, raw index, vertex count when read)]) of `l` and `p`
    type Refs = Vec<(usize, i64, usize)>;
    let mut polylines: Vec<(usize, Refs)> = Vec::new();
    let mut points: Vec<(usize, Refs)> = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let ln = ln + 1;
        let line = line.split('#').next().unwrap_or("");
        let toks = tokens(line);
        let Some(&(_, kw)) = toks.first() else {
            continue;
        };
        match kw {
            "v" => {
                if toks.len() < 4 {
                    return Err(syntax(ln, 1, "a vertex needs x y z".into()));
                }
                let mut p = [0.0; 3];
                for k in 0..3 {
                    let (col, t) = toks[k + 1];
                    p[k] = t
                        .parse()
                        .map_err(|_| syntax(ln, col, format!("{t:?} is not a number")))?;
                }
                verts.push(p);
                vert_line.push(ln);
            }
            "l" | "p" => {
                let mut refs = Vec::new();
                for &(col, t) in &toks[1..] {
                    // `l` may carry texture indices: `v/vt`
                    let v = t.split('/').next().unwrap_or("");
                    let i: i64 = v
                        .parse()
                        .map_err(|_| syntax(ln, col, format!("{t:?} is not a vertex index")))?;
                    if i == 0 {
                        return Err(syntax(ln, col, "vertex indices start at 1".into()));
                    }
                    refs.push((col, i, verts.len()));
                }
                if kw == "l" {
                    polylines.push((ln, refs));
                } else {
                    points.push((ln, refs));
                }
            }
            _ => {}
        }
    }
    let resolve =
        |ln: usize, (col, i, seen): (usize, i64, usize)| -> Result<usize, CurveNetError> {
            let idx = if i > 0 { i - 1 } else { seen as i64 + i };
            if idx < 0 || idx as usize >= verts.len() {
                return Err(syntax(
                    ln,
                    col,
                    format!("vertex {i} does not exist ({} vertices)", verts.len()),
                ));
            }
            Ok(idx as usize)
        };
    let mut lines_idx = Vec::with_capacity(polylines.len());
    for (ln, refs) in &polylines {
        let ids = refs
            .iter()
            .map(|&r| resolve(*ln, r))
            .collect::<Result<Vec<_>, _>>()?;
        lines_idx.push((*ln, ids));
    }
    let mut corner_idx = Vec::new();
    for (ln, refs) in &points {
        for &r in refs {
            corner_idx.push(resolve(*ln, r)?);
        }
    }
    if let Some(i) = verts.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(CurveNetError::NotFinite {
            file: file_s.clone(),
            item: format!("vertex {} (line {})", i + 1, vert_line[i]),
            value: verts[i],
        });
    }
    // weld the vertices (at the tolerance of those the cycles and corners
    // use), then number the distinct positions
    let referenced: Vec<Vec3> = lines_idx
        .iter()
        .flat_map(|(_, ids)| ids.iter())
        .chain(&corner_idx)
        .map(|&i| verts[i])
        .collect();
    let used: Vec<Vec3> = verts.clone();
    let tol = match check::bbox(referenced.iter()) {
        Some((lo, hi)) => WELD_FACTOR * geometry::vec3::dist(lo, hi),
        None => 0.0,
    };
    let welded = if tol > 0.0 {
        check::weld(&used, tol)
    } else {
        used
    };
    let mut id_of: HashMap<[u64; 3], u32> = HashMap::new();
    let mut pos: Vec<Vec3> = Vec::new();
    let vid: Vec<u32> = welded
        .iter()
        .map(|p| {
            *id_of.entry(key(*p)).or_insert_with(|| {
                pos.push(*p);
                (pos.len() - 1) as u32
            })
        })
        .collect();
    let mut cycles_v: Vec<Vec<u32>> = Vec::new();
    for (_, ids) in &lines_idx {
        let mut vs: Vec<u32> = ids.iter().map(|&i| vid[i]).collect();
        vs.dedup();
        if vs.len() >= 2 && vs[0] == vs[vs.len() - 1] {
            vs.pop();
            cycles_v.push(vs);
        } else if vs.len() == 1 && ids.len() >= 2 {
            // `l a a`: closed, one point; reported by the cycle's checks
            cycles_v.push(vs);
        }
    }
    if cycles_v.is_empty() {
        return Err(CurveNetError::Empty {
            file: file_s.clone(),
            message: "no closed polyline (an `l` whose first vertex is its last)".into(),
        });
    }
    let (curves_v, cycles) = obj_curves(&cycles_v);
    let curves = curves_v
        .into_iter()
        .map(|vs| NetworkCurve {
            points: vs.iter().map(|&v| pos[v as usize]).collect(),
            cad: None,
        })
        .collect();
    let corners = corner_idx.iter().map(|&i| welded[i]).collect();
    CurveNetwork::new_in(curves, cycles, corners, file_s.clone())
}

/// The curves of OBJ cycles (closed vertex lists, last ≠ first): the runs
/// between vertices where other than 2 distinct cycle edges meet; a loop
/// without such a vertex is one closed curve from its least vertex. Returns
/// the curves (vertex lists) and the cycles as curve uses.
fn obj_curves(cycles_v: &[Vec<u32>]) -> (Vec<Vec<u32>>, Vec<NetworkCycle>) {
    let mut edges: std::collections::HashSet<(u32, u32)> = Default::default();
    for vs in cycles_v {
        let m = vs.len();
        for k in 0..m {
            let (a, b) = (vs[k], vs[(k + 1) % m]);
            if a != b {
                edges.insert((a.min(b), a.max(b)));
            }
        }
    }
    let mut degree: HashMap<u32, usize> = HashMap::new();
    for &(a, b) in &edges {
        *degree.entry(a).or_default() += 1;
        *degree.entry(b).or_default() += 1;
    }
    let junction = |v: u32| degree.get(&v).copied().unwrap_or(0) != 2;
    let mut curves: Vec<Vec<u32>> = Vec::new();
    let mut edge_curve: HashMap<(u32, u32), (usize, bool)> = HashMap::new();
    let mut cycles = Vec::with_capacity(cycles_v.len());
    for vs in cycles_v {
        let m = vs.len();
        if m < 2 {
            curves.push(vs.clone());
            cycles.push(NetworkCycle {
                loops: vec![vec![CycleUse {
                    curve: curves.len() - 1,
                    forward: true,
                }]],
                cad_face: None,
                surface: None,
            });
            continue;
        }
        let start = (0..m)
            .find(|&k| junction(vs[k]))
            .unwrap_or_else(|| (0..m).min_by_key(|&k| vs[k]).expect("a vertex"));
        let ws: Vec<u32> = (0..=m).map(|k| vs[(start + k) % m]).collect();
        let mut uses = Vec::new();
        let mut k = 0;
        while k < m {
            let e = (ws[k], ws[k + 1]);
            if let Some(&(c, fwd)) = edge_curve.get(&e) {
                let len = curves[c].len() - 1;
                let matches = k + len <= m && {
                    let run: Vec<u32> = ws[k..=k + len].to_vec();
                    let mut cv = curves[c].clone();
                    if !fwd {
                        cv.reverse();
                    }
                    run == cv
                };
                if matches {
                    uses.push(CycleUse {
                        curve: c,
                        forward: fwd,
                    });
                    k += len;
                    continue;
                }
            }
            // a new curve: from ws[k] to the next junction (or around)
            let mut j = k + 1;
            while j < m && !junction(ws[j]) {
                j += 1;
            }
            let run = ws[k..=j].to_vec();
            let c = curves.len();
            for w in run.windows(2) {
                edge_curve.entry((w[0], w[1])).or_insert((c, true));
                edge_curve.entry((w[1], w[0])).or_insert((c, false));
            }
            curves.push(run);
            uses.push(CycleUse {
                curve: c,
                forward: true,
            });
            k = j;
        }
        cycles.push(NetworkCycle {
            loops: vec![uses],
            cad_face: None,
            surface: None,
        });
    }
    (curves, cycles)
}

#[cfg(test)]
mod tests;
