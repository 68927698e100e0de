//! The cone file (`--cones FILE`, `--cones-out FILE`): one cone per line,
//! `x y z index`, `#` starting a comment (whole line or after the numbers).
//! Each point is snapped to the nearest shell vertex; a point farther than
//! [`FAR_TRIANGLE_SIZES`] mean edge lengths from every vertex, two lines on
//! one vertex or a malformed line is an error naming the line. Index 0
//! lines are allowed and place nothing (a corner switched off by hand).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use geometry::vec3::dist;

use super::{check_cones, ConeError, ConeSummary};
use crate::ricci::Cone;
use crate::shell::{Shell, ShellTopology};

/// A point farther than this many mean edge lengths from every shell vertex
/// is refused (the issue: "a cone over 2 triangle sizes from any vertex").
pub const FAR_TRIANGLE_SIZES: f64 = 2.0;

fn mean_edge_length(shell: &Shell, topo: &ShellTopology) -> f64 {
    if topo.edges.is_empty() {
        return 0.0;
    }
    topo.edges
        .iter()
        .map(|&[a, b]| shell.edge_length(a, b))
        .sum::<f64>()
        / topo.edges.len() as f64
}

/// Reads the cones of `text` (the contents of `file`, named in errors),
/// snaps them and checks the set ([`check_cones`]). Cones come sorted by vertex.
pub fn parse_cones(
    text: &str,
    file: &str,
    shell: &Shell,
    topo: &ShellTopology,
) -> Result<Vec<Cone>, ConeError> {
    let far = FAR_TRIANGLE_SIZES * mean_edge_length(shell, topo);
    let line_error = |line: usize, message: String| ConeError::Line {
        file: file.into(),
        line,
        message,
    };
    let mut line_of = vec![0usize; shell.vertices.len()];
    let mut cones = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let body = raw.split('#').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let tokens: Vec<&str> = body.split_whitespace().collect();
        if tokens.len() != 4 {
            return Err(line_error(
                line,
                format!(
                    "expected `x y z index`, found {} field(s): {body:?}",
                    tokens.len()
                ),
            ));
        }
        let mut p = [0.0; 3];
        for (c, t) in p.iter_mut().zip(&tokens[..3]) {
            *c = match t.parse::<f64>() {
                Ok(x) if x.is_finite() => x,
                _ => return Err(line_error(line, format!("{t:?} is not a finite number"))),
            };
        }
        let index: i32 = tokens[3].parse().map_err(|_| {
            line_error(line, format!("index {:?} is not a whole number", tokens[3]))
        })?;
        let Some(v) = (0..shell.vertices.len())
            .min_by(|&a, &b| dist(shell.vertices[a], p).total_cmp(&dist(shell.vertices[b], p)))
        else {
            return Err(line_error(line, "the shell has no vertices".into()));
        };
        let d = dist(shell.vertices[v], p);
        if !(d <= far) {
            return Err(line_error(
                line,
                format!(
                    "point {p:?} is {d:.4e} from the nearest shell vertex, more than {FAR_TRIANGLE_SIZES} triangle sizes ({far:.4e})"
                ),
            ));
        }
        if line_of[v] != 0 {
            return Err(line_error(
                line,
                format!(
                    "point {p:?} snaps to vertex {v} at {:?}, like line {}",
                    shell.vertices[v], line_of[v]
                ),
            ));
        }
        line_of[v] = line;
        if index != 0 {
            cones.push(Cone { vertex: v, index });
        }
    }
    cones.sort_by_key(|c| c.vertex);
    check_cones(shell, topo, &cones, file)?;
    Ok(cones)
}

/// The cone file of `cones`: a header with the sums, then `x y z index`
/// per cone (positions printed so they read back exactly), each line
/// commented `interior` or `boundary`.
pub fn format_cones(shell: &Shell, topo: &ShellTopology, cones: &[Cone]) -> String {
    let s = ConeSummary::of(topo, cones);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# quadrille cones: one per line, `x y z index` (+1: valence 3, −1: valence 5, −2: valence 6)"
    );
    let _ = writeln!(
        out,
        "# each point snaps to the nearest shell vertex; Σ I must be 4χ (interior I ≤ 3, boundary I ≤ 1)"
    );
    let _ = writeln!(out, "# {s}");
    for c in cones.iter().filter(|c| c.index != 0) {
        let p = shell.vertices[c.vertex];
        let kind = if topo.on_boundary[c.vertex] {
            "boundary"
        } else {
            "interior"
        };
        let _ = writeln!(out, "{} {} {} {}  # {kind}", p[0], p[1], p[2], c.index);
    }
    out
}

/// Writes `text` to `path` atomically (no partial file on failure).
pub fn write_cones(path: &Path, text: &str) -> Result<(), ConeError> {
    mesh::atomic::write_atomically(path, |w| w.write_all(text.as_bytes())).map_err(
        |e: std::io::Error| ConeError::Io {
            file: path.display().to_string(),
            message: e.to_string(),
        },
    )
}
