//! `quadrille spline`: an open shell (CAD faces or a triangle mesh) to
//! untrimmed, watertight bicubic B-spline patches (paper
//! ricci-flow-iga-reconstruction, issue 31; `docs/spline.md`). This version
//! handles the shells that need no interior cone: disks whose boundary
//! corners' indices sum to 4, and annuli (two loops) with smooth loops, laid
//! out as one patch closing along the loop cut (in STEP: one face whose seam
//! edge is used twice).

use std::time::Instant;

use anyhow::{bail, Context, Result};
use geometry::FaceId;
use mesh::quadmesh::{NodeClass, QuadMesh};
use quadrille::methods::spline::{
    splines_from_checked_shell, Interior, Segments, SplineMethodError, SplineOptions, SplineReport,
    SplineResult,
};
use quadrille::shell::shell_from_model;

use crate::files;
use crate::{InteriorArg, SplineArgs};

/// The output formats.
const OUTPUTS: [&str; 6] = ["step", "stp", "iges", "igs", "json", "vtu"];

/// Divisions of the model's diagonal giving the default triangle size.
const TRIANGLE_DIVISIONS: f64 = 72.0;

/// The options from the arguments.
fn options(args: &SplineArgs) -> Result<SplineOptions> {
    let segments = match args.segments.trim() {
        "auto" => Segments::Auto,
        s => match s.parse::<usize>() {
            Ok(k) if k >= 1 => Segments::Fixed(k),
            _ => bail!("--segments {s}: expected a whole number ≥ 1 or auto"),
        },
    };
    if let Some(t) = args.tolerance {
        if !(t > 0.0 && t.is_finite()) {
            bail!("--tolerance {t} must be a positive number");
        }
    }
    if args.refine == 0 || args.refine > 64 {
        bail!("--refine {} must be between 1 and 64", args.refine);
    }
    Ok(SplineOptions {
        segments,
        tolerance: args.tolerance,
        refine: args.refine,
        interior: match args.interior {
            InteriorArg::Coons => Interior::Coons,
            InteriorArg::Fit => Interior::Fit,
        },
        cones: Default::default(),
    })
}

/// Runs `quadrille spline`.
pub fn run(args: &SplineArgs) -> Result<()> {
    let mut opts = options(args)?;
    let format = files::check_output(&args.output, &OUTPUTS)?;
    if let Some(p) = &args.png {
        files::check_output(p, &["png"])?;
    }
    if let Some(s) = args.triangle_size {
        if !(s > 0.0 && s.is_finite()) {
            bail!("--triangle-size {s} must be a positive number");
        }
    }
    let name = args.input.display().to_string();
    let t0 = Instant::now();
    let model = files::load_model(&args.input)?;
    let faces: Vec<usize> = match &args.faces {
        Some(f) => {
            if let Some(&bad) = f.iter().find(|&&k| k == 0 || k > model.faces.len()) {
                bail!(
                    "{name}: --faces {bad} is out of range: the model has faces 1 to {}",
                    model.faces.len()
                );
            }
            f.iter().map(|&k| k - 1).collect()
        }
        None => Vec::new(),
    };
    let size = args
        .triangle_size
        .unwrap_or(model.diagonal() / TRIANGLE_DIVISIONS);
    let shell =
        shell_from_model(&model, &faces, size).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
    let t_load = t0.elapsed().as_secs_f64();
    // One topology check: the cone choice and the spline stage share it.
    let t_check = Instant::now();
    let topo = shell
        .check()
        .map_err(SplineMethodError::from)
        .with_context(|| name.clone())?;
    let t_check = t_check.elapsed().as_secs_f64();
    let t_cones = Instant::now();
    opts.cones = crate::cmd_spline_cones::choose_cones(args, &shell, &topo, &name)?;
    let t_cones = t_cones.elapsed().as_secs_f64();
    let result = match splines_from_checked_shell(&shell, &topo, &opts) {
        Ok(r) => r,
        Err(e) => {
            if let SplineMethodError::NeedsLayoutEnergy {
                times: t, energy, ..
            } = &e
            {
                if args.timings {
                    eprintln!(
                        "time: load+triangulate {t_load:.3} s, check {t_check:.3} s, cones {t_cones:.3} s, refine {:.3} s, ricci {:.3} s, cut {:.3} s, immersion {:.3} s, layout energy {:.3} s, trace {:.3} s (stopped: no splines on a traced layout)",
                        t.refine, t.ricci, t.cut, t.immersion, t.energy, t.trace
                    );
                }
                if args.json {
                    // The stages that ran, before the refusal (stdout).
                    println!(
                        "{}",
                        serde_json::to_string_pretty(&serde_json::json!({
                            "triangles": shell.triangles.len(),
                            "stopped": "splines on a traced layout (S9 across cut charts) not built",
                            "layout_energy": {
                                "converged": energy.converged,
                                "residual": energy.residual,
                                "tolerance": energy.tolerance,
                                "min_det_j": energy.min_det,
                                "iterations": energy.iterations,
                                "stages": energy.stages,
                            },
                            "trace": {
                                "separatrices": energy.separatrices,
                                "patches": energy.patches,
                                "quads": energy.quads,
                            },
                            "seconds": {
                                "load": t_load,
                                "check": t_check,
                                "cones": t_cones,
                                "refine": t.refine,
                                "ricci": t.ricci,
                                "cut": t.cut,
                                "immersion": t.immersion,
                                "layout_energy": t.energy,
                                "trace": t.trace,
                            }
                        }))?
                    );
                }
            }
            return Err(anyhow::Error::new(e).context(name.clone()));
        }
    };
    let t1 = Instant::now();
    let mp = &result.multipatch;
    let mut step_note = String::new();
    match format.as_str() {
        "step" | "stp" => {
            let data: Vec<occt::BSplineSurfaceData> = (0..mp.patches().len())
                .map(|k| {
                    let p = mp.patch(k)?;
                    Ok(occt::BSplineSurfaceData {
                        degree_s: p.knots_s().degree(),
                        degree_t: p.knots_t().degree(),
                        knots_s: p.knots_s().knots().to_vec(),
                        knots_t: p.knots_t().knots().to_vec(),
                        control: p.control_points().to_vec(),
                    })
                })
                .collect::<Result<_, spline::SplineError>>()?;
            let w = occt::write_bspline_step(&data, &args.output)?;
            step_note = format!(
                "STEP: {} faces, {} shell(s), {} shared and {} free edges after sewing\n",
                w.faces, w.shells, w.shared_edges, w.free_edges
            );
        }
        "iges" | "igs" => spline::iges::write_iges(&args.output, mp)?,
        "json" => spline::json::write_json(&args.output, mp)?,
        _ => spline::vtu::write_vtu(&args.output, mp)?,
    }
    if let Some(png) = &args.png {
        render(&result, &name, png)?;
    }
    let t_write = t1.elapsed().as_secs_f64();
    let r = &result.report;
    if !r.tolerance_met {
        eprintln!(
            "warning: {name}: max distance {:.3e} is above the tolerance {:.3e} at {} spans",
            r.max_distance, r.tolerance, r.segments
        );
    }
    if args.json {
        println!(
            "{}",
            report_json(
                r,
                shell.triangles.len(),
                [t_load, t_check, t_cones, t_write]
            )
        );
    } else if !args.quiet {
        print!("{}{step_note}", summary_text(r));
    }
    if args.timings {
        eprintln!(
            "time: load+triangulate {t_load:.3} s, check {t_check:.3} s, cones {t_cones:.3} s, shell {:.3} s, ricci {:.3} s, cut {:.3} s, immersion {:.3} s, layout {:.3} s, splines {:.3} s (stages {:.3} s), write {t_write:.3} s",
            r.times.shell, r.times.ricci, r.times.cut, r.times.immersion, r.times.layout, r.times.splines,
            r.times.total()
        );
    }
    Ok(())
}

/// The text summary.
fn summary_text(r: &SplineReport) -> String {
    format!(
        "shell: {} triangles, {} boundary loop(s), {} boundary corners ({} reflex); Ricci {} iterations, max |K̄−K| {:.1e}\n\
         layout: {} separatrices, {} patches, {} arcs{}\n\
         splines: {} span(s) per arc, refine {}, {} control points; distance max {:.3e} ({:.2e} D), mean {:.3e}; \
         min scaled Jacobian {:.3}; {} shared sides, gap {:e}\n",
        r.triangles,
        r.boundary_loops,
        r.corners,
        r.reflex_corners,
        r.ricci_iterations,
        r.ricci_error,
        r.separatrices,
        r.patches,
        r.arcs,
        r.seam_rotation
            .map(|a| format!(", closing along the loop cut (seam rotation {a:.1e} rad)"))
            .unwrap_or_default(),
        r.segments,
        r.refine,
        r.control_points,
        r.max_distance,
        r.max_distance / r.diagonal,
        r.mean_distance,
        r.min_scaled_jacobian,
        r.shared_sides,
        r.max_gap
    )
}

/// The `--json` report; `cli_times`: load+triangulate, topology check,
/// cone choice and writing (seconds), measured here around the library's
/// stages.
fn report_json(r: &SplineReport, triangles: usize, cli_times: [f64; 4]) -> String {
    let [load, check, cones, write] = cli_times;
    serde_json::to_string_pretty(&serde_json::json!({
        "triangles": triangles,
        "vertices": r.vertices,
        "corners": r.corners,
        "reflex_corners": r.reflex_corners,
        "boundary_loops": r.boundary_loops,
        "seam_rotation": r.seam_rotation,
        "ricci_iterations": r.ricci_iterations,
        "ricci_error": r.ricci_error,
        "boundary_deviation": r.boundary_deviation,
        "min_area_ratio": r.min_area_ratio,
        "separatrices": r.separatrices,
        "patches": r.patches,
        "arcs": r.arcs,
        "segments": r.segments,
        "refine": r.refine,
        "control_points": r.control_points,
        "diagonal": r.diagonal,
        "tolerance": r.tolerance,
        "max_distance": r.max_distance,
        "mean_distance": r.mean_distance,
        "tolerance_met": r.tolerance_met,
        "shared_sides": r.shared_sides,
        "max_gap": r.max_gap,
        "min_scaled_jacobian": r.min_scaled_jacobian,
        "coons_fallbacks": r.coons_fallbacks,
        "seconds": {
            "load": load,
            "check": check,
            "cones": cones,
            "shell": r.times.shell,
            "ricci": r.times.ricci,
            "cut": r.times.cut,
            "immersion": r.times.immersion,
            "layout": r.times.layout,
            "splines": r.times.splines,
            "stages": r.times.total(),
            "write": write,
        },
    }))
    .unwrap_or_default()
}

/// A picture: each patch tessellated into quads, the patch boundaries in
/// green, the control net in red and the layout traced on the shell in blue.
fn render(result: &SplineResult, name: &str, png: &std::path::Path) -> Result<()> {
    let mp = &result.multipatch;
    let mut m = QuadMesh::default();
    let mut overlay = mesh::render::Overlay {
        line_width: 2.5,
        ..Default::default()
    };
    let n = 24usize;
    for k in 0..mp.patches().len() {
        let p = mp.patch(k)?;
        let base = m.nodes.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                m.nodes
                    .push(p.eval(i as f64 / n as f64, j as f64 / n as f64));
                m.node_class.push(NodeClass::Unclassified);
            }
        }
        let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                m.quads
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                m.quad_face.push(FaceId(k as u32));
            }
        }
        for i in 0..n {
            for (a, b) in [
                (id(i, 0), id(i + 1, 0)),
                (id(i, n), id(i + 1, n)),
                (id(0, i), id(0, i + 1)),
                (id(n, i), id(n, i + 1)),
            ] {
                overlay.segments.push(mesh::render::OverlaySegment {
                    a: m.nodes[a as usize],
                    b: m.nodes[b as usize],
                    color: [20, 150, 60],
                    normal: None,
                });
            }
        }
    }
    // The control net: each patch's rows and columns of control points.
    for g in mp.patches() {
        let (ns, nt) = (g.n_s(), g.n_t());
        let at = |i: usize, j: usize| mp.points()[g.indices[j * ns + i]];
        for j in 0..nt {
            for i in 0..ns {
                for (di, dj) in [(1, 0), (0, 1)] {
                    if i + di < ns && j + dj < nt {
                        overlay.segments.push(mesh::render::OverlaySegment {
                            a: at(i, j),
                            b: at(i + di, j + dj),
                            color: [200, 60, 40],
                            normal: None,
                        });
                    }
                }
            }
        }
    }
    for line in &result.layout_polylines {
        for w in line.windows(2) {
            overlay.segments.push(mesh::render::OverlaySegment {
                a: w[0],
                b: w[1],
                color: [40, 70, 200],
                normal: None,
            });
        }
    }
    let title = format!(
        "{} - {} patches, {} span(s)",
        std::path::Path::new(name)
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        mp.patches().len(),
        result.report.segments
    );
    let ropts = mesh::render::RenderOptions {
        title: Some(&title),
        overlay: Some(&overlay),
        show_irregular: false,
        show_info: false,
        ..Default::default()
    };
    mesh::render::render_png(&m, &ropts, png)?;
    Ok(())
}
