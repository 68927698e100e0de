//! `quadrille mesh`: mesh a CAD model and write the result.

use std::time::Instant;

use anyhow::{bail, Result};
use quadrille::MeshOptions;

use crate::files;
use crate::progress::FaceProgress;
use crate::{MeshArgs, Method};

/// The topology stages the arguments ask for, or why the combination is refused.
fn stages(args: &MeshArgs) -> Result<quadrille::Stages> {
    let asked = quadrille::Stages {
        patterns: !args.no_patterns,
        defects: !args.no_defects,
        cavities: !args.no_cavities,
        regular_pass: !args.no_regular_pass,
    };
    let off: Vec<String> = asked
        .switched_off()
        .iter()
        .map(|name| format!("--no-{}", name.replace('_', "-")))
        .collect();
    match args.method {
        Method::QuasiStructured => Ok(asked),
        _ if !off.is_empty() => bail!(
            "{} only applies to --method quasi-structured (the default); --method {} has no such step",
            off.join(", "),
            method_name(args.method)
        ),
        _ => Ok(quadrille::Stages::NONE),
    }
}

/// The library's error naming the model file; the size guard's refusal
/// names the command-line options (`--size`, `--size-factor`, `--max-quads`).
pub(crate) fn meshing_error(model: &std::path::Path, e: quadrille::MeshError) -> anyhow::Error {
    match e {
        quadrille::MeshError::TooManyQuads(t) => anyhow::anyhow!(
            "{}: {}",
            model.display(),
            t.message("--size", "--size-factor", "--max-quads")
        ),
        e => anyhow::anyhow!("{}: {e}", model.display()),
    }
}

/// The command-line name of a method.
fn method_name(m: Method) -> &'static str {
    match m {
        Method::QuasiStructured => "quasi-structured",
        Method::Unstructured => "unstructured",
        Method::Baseline => "baseline",
        Method::Regular => "regular",
        Method::Coarse => "coarse",
    }
}

pub fn run(args: &MeshArgs) -> Result<()> {
    // Everything that can be checked before meshing is checked first.
    let stages = stages(args)?;
    if args.method == Method::Coarse {
        return crate::cmd_coarse::run(args);
    }
    let coarse_only = args.coarse.given();
    if !coarse_only.is_empty() {
        bail!(
            "{} only applies to --method coarse; --method {} has no such option",
            coarse_only.join(", "),
            method_name(args.method)
        );
    }
    let format = files::check_output(&args.output, &["msh", "vtu", "obj"])?;
    if let Some(png) = &args.png {
        files::check_output(png, &["png"])?;
    }
    let size = crate::size_arg(args.size, args.size_factor);
    let t0 = Instant::now();
    let model = files::load_model(&args.model)?;
    let t_load = t0.elapsed().as_secs_f64();

    let bar = FaceProgress::new(args.quiet, model.faces.len(), "meshing");
    let regularize_bar =
        FaceProgress::new(args.quiet, model.faces.len(), "regularizing").hidden_until_first();
    let opts = MeshOptions {
        size,
        threads: args.threads,
        progress: bar.callback(),
        regularize_progress: regularize_bar.callback_after(&bar),
        quads_per_turn: args.quads_per_turn,
        max_quads: args.max_quads,
        ..MeshOptions::default()
    };
    let t1 = Instant::now();
    let method = match args.method {
        Method::QuasiStructured => quadrille::MeshMethod::QuasiStructured(stages),
        Method::Unstructured => quadrille::MeshMethod::Unstructured,
        Method::Baseline => quadrille::MeshMethod::Baseline,
        Method::Regular => quadrille::MeshMethod::regular(args.threads),
        Method::Coarse => unreachable!("the coarse method returned above"),
    };
    let (m, report) = quadrille::mesh_model_with(&model, &opts, method)
        .map_err(|e| meshing_error(&args.model, e))?;
    bar.finish();
    regularize_bar.finish();
    if !args.quiet {
        if !report.slivers.is_empty() {
            let list: Vec<String> = report
                .slivers
                .iter()
                .map(|(c, len)| format!("{} ({len:.1e})", c.0 + 1))
                .collect();
            eprintln!(
                "{} curves shorter than {:.0e} of the model's diagonal meshed as points (their end corners share one node): {}",
                list.len(),
                quadrille::SLIVER_LENGTH,
                list.join(", ")
            );
        }
        for (f, reason) in &report.fallback {
            eprintln!(
                "face {}: {} meshing failed ({reason}); meshed with the baseline",
                f.0 + 1,
                method_name(args.method)
            );
        }
        if args.method == Method::QuasiStructured {
            eprintln!("{}", topology_summary(&report, model.faces.len(), stages));
        }
        if let Some(rep) = &report.regularize {
            let (before, after) = rep.irregular();
            let reverted = rep.faces.iter().filter(|f| f.reverted).count();
            eprintln!(
                "regularized {} faces: face-local irregular vertices {before} -> {after}{}",
                rep.faces.len(),
                if reverted > 0 {
                    format!(", {reverted} kept as split (regularizing them inverted quads)")
                } else {
                    String::new()
                }
            );
            for (f, why) in &rep.skipped {
                eprintln!("face {}: not regularized ({why})", f.0 + 1);
            }
        }
    }
    let t_improve = report.times.regularize.as_secs_f64();
    let t_mesh = t1.elapsed().as_secs_f64() - t_improve;

    let t3 = Instant::now();
    // the quality summary and the VTU's cell data (a whole-mesh pass with the
    // CAD normals: not computed when nothing shows it)
    let sicn = if format == "vtu" || !args.quiet {
        mesh::stats::quad_sicn_values(&m, Some(&model))
    } else {
        Default::default()
    };
    match format.as_str() {
        "msh" => {
            let enc = if args.binary {
                mesh::msh::MshEncoding::Binary
            } else {
                mesh::msh::MshEncoding::Ascii
            };
            let opts = mesh::msh::MshWriteOptions::new(enc).with_parametric(args.parametric);
            mesh::msh::write_msh(&args.output, &m, Some(&model), opts)?
        }
        "vtu" => mesh::vtu::write_vtu(&m, Some(&sicn), &args.output)?,
        "obj" => mesh::obj::write_obj(&m, &args.output)?,
        other => bail!(
            "{}: unknown output extension '.{other}'",
            args.output.display()
        ),
    }
    if let Some(png) = &args.png {
        let title = args
            .model
            .file_name()
            .map(|n| n.to_string_lossy().into_owned());
        let ropts = mesh::render::RenderOptions {
            title: title.as_deref(),
            ..Default::default()
        };
        mesh::render::render_png(&m, &ropts, png)?;
    }
    let t_write = t3.elapsed().as_secs_f64();
    if args.timings {
        let threads = args
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        eprint!(
            "{}",
            timings_text(
                &report.times,
                threads,
                [t_load, t_mesh, t_improve, t_write],
                (report.estimated_quads, m.quads.len())
            )
        );
    }
    if !args.quiet {
        let inverted = sicn.iter().filter(|&&s| s < 0.0).count();
        let min = sicn.iter().cloned().fold(f64::INFINITY, f64::min);
        let avg = sicn.iter().sum::<f64>() / sicn.len().max(1) as f64;
        eprintln!(
            "{}: {} quads, {} nodes in {:.2} s (load {:.2} s); SICN min {:.3} avg {:.3}; {} inverted",
            args.output.display(),
            m.quads.len(),
            m.nodes.len(),
            t_load + t_mesh + t_improve,
            t_load,
            min,
            avg,
            inverted
        );
    }
    Ok(())
}

/// The summary line of the topology steps: faces by pattern, defects, cavities
/// (a step switched off says so).
fn topology_summary(
    report: &quadrille::MeshReport,
    faces: usize,
    stages: quadrille::Stages,
) -> String {
    let patterns = if stages.patterns {
        format!(
            "{} of {faces} faces meshed by a pattern",
            report.patterns.len()
        )
    } else {
        "patterns off".to_string()
    };
    let d = &report.defects;
    let defects = if stages.defects {
        format!(
            "defects: {} of {} very irregular vertices and {} of {} corners off their ideal valence replaced by disk quadrangulations",
            d.replaced, d.found, d.boundary_replaced, d.boundary_found
        )
    } else {
        "defects off".to_string()
    };
    let c = &report.cavities;
    let cavities = if stages.cavities {
        format!(
            "cavities: {} remeshed (steps 1-4: {}), {} undone; irregular vertices {} -> {}, {} kept as singularities{}",
            c.replaced.iter().sum::<usize>(),
            c.replaced.map(|n| n.to_string()).join("/"),
            c.rejected,
            c.irregular_before,
            c.irregular_after,
            c.singular,
            if c.capped { " (work cap reached)" } else { "" }
        )
    } else {
        "cavities off".to_string()
    };
    let (tried, kept, removed) = report.regular_pass;
    let regular = if stages.regular_pass {
        format!(
            "regular pass: kept on {kept} of {tried} faces, {removed} irregular vertices removed"
        )
    } else {
        "regular pass off".to_string()
    };
    format!("{patterns}; {defects}; {cavities}; {regular}")
}

/// The `--timings` report: one line per stage (seconds), then the same as one
/// `timings:` JSON line (`total` = load + meshing + improvement, writing excluded).
/// `cli` holds the times measured by the command: load, meshing, regularization, writing;
/// `quads` the size guard's estimate and the quads made (a line of their own,
/// and `estimated_quads`, `quads` in the JSON line).
fn timings_text(
    t: &quadrille::StageTimes,
    threads: usize,
    cli: [f64; 4],
    quads: (u64, usize),
) -> String {
    let [load, mesh, regularize, write] = cli;
    let s = |d: std::time::Duration| d.as_secs_f64();
    let rows: [(&str, &str, f64); 18] = [
        ("load", "load", load),
        (
            "estimate",
            "quad count estimate (size guard)",
            s(t.estimate),
        ),
        ("fields", "cross fields and size map", s(t.fields)),
        ("curves", "curve planning and discretization", s(t.curves)),
        ("faces", "faces (wall time)", s(t.faces)),
        ("patterns", "  patterns", s(t.patterns)),
        (
            "frontal",
            "  frontal+recombination+subdivision",
            s(t.frontal),
        ),
        ("smoothing", "  smoothing", s(t.smoothing)),
        ("defects", "  defects", s(t.defects)),
        ("cavities", "  cavities", s(t.cavities)),
        ("regular_pass", "  regular pass", s(t.regular_pass)),
        ("fallback", "  fallback (baseline)", s(t.fallback)),
        ("assembly", "assembly", s(t.assembly)),
        ("curve_slide", "curve nodes slid", s(t.curve_slide)),
        ("mesh", "meshing (wall time)", mesh),
        ("regularize", "regularize", regularize),
        ("write", "writing", write),
        (
            "total",
            "total (load + meshing + regularize)",
            load + mesh + regularize,
        ),
    ];
    let mut out = format!(
        "timings in seconds ({threads} thread{}; the indented per-face stages are sums over faces, which run in parallel):\n",
        if threads == 1 { "" } else { "s" }
    );
    for (_, label, v) in &rows {
        out.push_str(&format!("  {label:<37} {v:>9.4}\n"));
    }
    let (estimated, made) = quads;
    out.push_str(&format!(
        "quads: {made} made, {estimated} estimated before meshing (estimate / made = {:.2})\n",
        estimated as f64 / made.max(1) as f64
    ));
    let mut json: Vec<String> = rows
        .iter()
        .map(|(key, _, v)| format!("\"{key}\":{v:.4}"))
        .collect();
    json.push(format!("\"estimated_quads\":{estimated},\"quads\":{made}"));
    out.push_str(&format!("timings:{{{}}}\n", json.join(",")));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timings_list_every_stage_and_parse_as_json() {
        let t = quadrille::StageTimes {
            frontal: std::time::Duration::from_millis(250),
            ..Default::default()
        };
        let text = timings_text(&t, 2, [0.5, 1.0, 0.0, 0.25], (1234, 1000));
        for stage in [
            "load",
            "quad count estimate",
            "cross fields",
            "curve planning",
            "patterns",
            "frontal+recombination+subdivision",
            "smoothing",
            "defects",
            "cavities",
            "regular pass",
            "fallback",
            "assembly",
            "writing",
            "total",
        ] {
            assert!(text.contains(stage), "{stage} missing: {text}");
        }
        assert!(
            text.contains("2 threads") && text.contains("sums over faces"),
            "{text}"
        );
        let json = text
            .lines()
            .find_map(|l| l.strip_prefix("timings:"))
            .expect("a timings: line");
        assert!(json.contains("\"frontal\":0.2500"), "{json}");
        // load + meshing + regularize, writing excluded
        assert!(json.contains("\"total\":1.5000"), "{json}");
        // the size guard's estimate beside the count made
        assert!(
            json.contains("\"estimated_quads\":1234,\"quads\":1000"),
            "{json}"
        );
        assert!(
            text.contains("1000 made, 1234 estimated") && text.contains("= 1.23"),
            "{text}"
        );
    }
}
