//! `quadrille mesh --method coarse`: a coarse block layout and one curved
//! Lagrange quad per block, written as MSH (Gmsh's high-order types) or VTU
//! (VTK Lagrange quads).

use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use mesh::high_order::HighOrderStats;
use mesh::msh::{MshEncoding, MshWriteOptions};
use quadrille::coarse::LayoutOptions;
use quadrille::{CoarseOptions, CoarseReport};
use quadrille::MeshOptions;

use crate::files;
use crate::progress::FaceProgress;
use crate::MeshArgs;

/// Checks the coarse options and output names before any work.
fn check_arguments(args: &MeshArgs) -> Result<String> {
    let o = options(args);
    if !(1..=mesh::high_order::MAX_ORDER).contains(&o.order) {
        bail!("--order {} is out of range: it must be 1 to {}", o.order, mesh::high_order::MAX_ORDER);
    }
    if !(o.layout.alpha_degrees > 0.0 && o.layout.alpha_degrees < 90.0) {
        bail!("--alpha {} is out of range: it must be in (0°, 90°)", o.layout.alpha_degrees);
    }
    let limit = o.layout.ilp_time_limit;
    if !(limit >= 0.0 && limit.is_finite()) {
        bail!("--ilp-time-limit {limit} must be a number of seconds ≥ 0");
    }
    let c = &args.coarse;
    let format = files::check_output(&args.output, &["msh", "vtu", "obj"])?;
    if format == "obj" && o.order > 1 {
        bail!(
            "{}: OBJ holds straight polygons only; write .msh or .vtu for --order {} (or --order 1)",
            args.output.display(),
            o.order
        );
    }
    if let Some(p) = &args.png {
        files::check_output(p, &["png"])?;
    }
    if let Some(p) = &c.layout {
        files::check_output(p, &["msh", "vtu", "obj"])?;
    }
    if let Some(p) = &c.fine {
        files::check_output(p, &["msh", "vtu"])?;
    }
    Ok(format)
}

/// The coarse options from the arguments (defaults where not given).
fn options(args: &MeshArgs) -> CoarseOptions {
    let d = CoarseOptions::default();
    let c = &args.coarse;
    CoarseOptions {
        order: c.order.unwrap_or(d.order),
        layout: LayoutOptions {
            alpha_degrees: c.alpha.unwrap_or(d.layout.alpha_degrees),
            ilp_time_limit: c.ilp_time_limit.unwrap_or(d.layout.ilp_time_limit),
        },
    }
}

/// Reads `--from-mesh`: all quads, every node classified on `model`.
fn read_input_mesh(path: &Path, model: &geometry::Model) -> Result<mesh::QuadMesh> {
    let m = files::read_mesh(path)?;
    quadrille::check_input_mesh(&m, model)
        .with_context(|| format!("{}: not usable as --from-mesh", path.display()))?;
    Ok(m)
}

/// Runs the coarse method.
pub fn run(args: &MeshArgs) -> Result<()> {
    let format = check_arguments(args)?;
    let c = &args.coarse;
    let t0 = Instant::now();
    let model = files::load_model(&args.model)?;
    let input = c.from_mesh.as_deref().map(|p| read_input_mesh(p, &model)).transpose()?;
    let t_load = t0.elapsed().as_secs_f64();
    let bar = FaceProgress::new(args.quiet || input.is_some(), model.faces.len(), "meshing");
    let mesh_opts = MeshOptions {
        size: crate::size_arg(args.size, args.size_factor),
        threads: args.threads,
        progress: bar.callback(),
        quads_per_turn: args.quads_per_turn,
        max_quads: args.max_quads,
        ..MeshOptions::default()
    };
    let opts = options(args);
    let (out, report) = quadrille::mesh_coarse(&model, &mesh_opts, &opts, input)
        .map_err(|e| crate::cmd_mesh::meshing_error(&args.model, e))?;
    bar.finish();
    let t_write = Instant::now();
    let enc = if args.binary { MshEncoding::Binary } else { MshEncoding::Ascii };
    let msh_opts = MshWriteOptions::new(enc).with_parametric(args.parametric);
    let ho = &out.high_order;
    match format.as_str() {
        "msh" => mesh::msh::write_high_order_msh(&args.output, ho, Some(&model), msh_opts)?,
        "vtu" => mesh::vtu::write_high_order_vtu(ho, &args.output)?,
        _ => mesh::obj::write_obj(&ho.to_linear_corners()?, &args.output)?,
    }
    if let Some(p) = &c.layout {
        let layout = ho.to_linear_corners()?;
        write_linear(&layout, p, &model, msh_opts)?;
    }
    if let Some(p) = &c.fine {
        write_linear(&out.fine, p, &model, msh_opts)?;
    }
    if let Some(png) = &args.png {
        let sub = (24 / opts.order).max(2);
        let tess = ho.tessellate(sub)?;
        let overlay = tess.edge_overlay([20, 20, 20]);
        let title = args.model.file_name().map(|n| n.to_string_lossy().into_owned());
        let ropts = mesh::render::RenderOptions {
            title: title.as_deref(),
            show_edges: false,
            show_irregular: false,
            overlay: Some(&overlay),
            ..Default::default()
        };
        mesh::render::render_png(&tess.mesh, &ropts, png)?;
    }
    let t_write = t_write.elapsed().as_secs_f64();
    let stats = HighOrderStats::compute(ho, Some(&model));
    if args.timings {
        eprint!("{}", timings_text(&report, t_load, t_write));
    }
    if c.json {
        println!("{}", serde_json::to_string_pretty(&json_report(&report, &stats, t_load))?);
    }
    if !args.quiet {
        summary(args, &report, &stats, t_load);
    }
    Ok(())
}

/// Writes a linear quad mesh by the extension of `path`.
fn write_linear(m: &mesh::QuadMesh, path: &Path, model: &geometry::Model, o: MshWriteOptions) -> Result<()> {
    match files::extension(path).as_str() {
        "msh" => mesh::msh::write_msh(path, m, Some(model), o)?,
        "vtu" => mesh::vtu::write_vtu(m, None, path)?,
        _ => mesh::obj::write_obj(m, path)?,
    }
    Ok(())
}

/// The lines a user reads after a run.
fn summary(args: &MeshArgs, r: &CoarseReport, s: &HighOrderStats, t_load: f64) {
    let l = &r.layout;
    for why in &l.refused {
        eprintln!("layout refused and re-solved with its arcs held: {why}");
    }
    if l.ilp_status != "optimal" {
        eprintln!("integer program: {}", l.ilp_status);
    }
    for line in &r.geometry_notes {
        eprintln!("{line}");
    }
    eprintln!(
        "{}: {} blocks of order {} from {} quads ({} patches in their layout, {} irregular vertices); \
         integer program {} variables, {} in {:.2} s; Jacobian ratio min {:.3}; {} invalid; total {:.2} s (load {:.2} s)",
        args.output.display(),
        l.blocks,
        s.order,
        l.input_quads,
        l.initial_patches,
        l.irregular_nodes,
        l.variables,
        l.ilp_status,
        l.ilp_seconds,
        s.min_jacobian_ratio,
        s.invalid_elements,
        t_load + r.times.total(),
        t_load
    );
}

/// `--json`: the paper's Table 1 columns, the solve, the checks.
fn json_report(r: &CoarseReport, s: &HighOrderStats, t_load: f64) -> serde_json::Value {
    let l = &r.layout;
    let t = &r.times;
    let total = t_load + t.total();
    serde_json::json!({
        "faces": l.input_quads,
        "estimated_quads": r.estimated_quads,
        "p_init": l.initial_patches,
        "irregular": l.irregular_nodes,
        "variables": l.variables,
        "p_final": l.blocks,
        "p_init_over_p_final": l.initial_patches as f64 / l.blocks.max(1) as f64,
        "rows": l.rows,
        "ilp_status": l.ilp_status,
        "ilp_seconds": l.ilp_seconds,
        "rounds": l.rounds,
        "refused": l.refused,
        "round_figures": l.round_figures,
        "first_round_causes": l.first_round_causes,
        "predicted_blocks": l.predicted_blocks,
        "order": s.order,
        "invalid_elements": s.invalid_elements,
        "min_jacobian_ratio": s.min_jacobian_ratio,
        "avg_jacobian_ratio": s.avg_jacobian_ratio,
        "max_node_cad_distance": s.max_node_cad_distance,
        "max_gauss_cad_distance": s.max_gauss_cad_distance,
        "geometry_notes": r.geometry_notes,
        "seconds": {
            "load": t_load,
            "quasi_structured": t.quasi_structured,
            "layout": t.layout,
            "ilp": l.ilp_seconds,
            "fine_mesh": t.fine_mesh,
            "high_order": t.high_order,
            "total": total,
        },
        "shares": {
            "quasi_structured": t.quasi_structured / total,
            "ilp": l.ilp_seconds / total,
            "smoothing_and_high_order": (t.fine_mesh + t.high_order) / total,
        },
    })
}

/// `--timings`: one line per stage, then a `timings:` JSON line.
fn timings_text(r: &CoarseReport, load: f64, write: f64) -> String {
    let t = &r.times;
    let rows = [
        ("load", load),
        ("quasi_structured", t.quasi_structured),
        ("layout", t.layout - r.layout.ilp_seconds),
        ("ilp", r.layout.ilp_seconds),
        ("fine_mesh", t.fine_mesh),
        ("high_order", t.high_order),
        ("write", write),
        ("total", load + t.total()),
    ];
    let mut out = String::from("timings in seconds:\n");
    for (k, v) in rows {
        out.push_str(&format!("  {k:<18} {v:>9.4}\n"));
    }
    let json: Vec<String> = rows.iter().map(|(k, v)| format!("\"{k}\":{v:.4}")).collect();
    out.push_str(&format!("timings:{{{}}}\n", json.join(",")));
    out
}
