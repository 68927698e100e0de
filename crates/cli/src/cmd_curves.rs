//! `quadrille curves`: an all-quad mesh of the closed cycles of a 3D curve
//! network (JSON, OBJ lines, or the face boundaries of a CAD model), with no
//! surface given (paper curve-network-quadrangulation; `docs/curve-networks.md`).

use std::time::Instant;

use anyhow::{bail, Context, Result};
use quadrille::curvenet::{
    network_from_model, network_from_wires, read_network, write_network, CurveNetwork,
    WireCurveUse,
};
use quadrille::methods::curvenet::{mesh_curve_network, CurvesOptions, CurvesReport};

use crate::files;
use crate::CurvesArgs;

/// CAD extensions read through OpenCASCADE, whose faces' loops become cycles.
const CAD_EXTENSIONS: [&str; 6] = ["step", "stp", "iges", "igs", "brep", "brp"];

/// Reads the network: a curve file, or the face boundaries of a CAD model
/// (`--faces`, 1-based; faces that cannot be cycles are listed on stderr).
fn load_network(args: &CurvesArgs) -> Result<CurveNetwork> {
    let ext = files::extension(&args.network);
    if CAD_EXTENSIONS.contains(&ext.as_str()) {
        let model = match files::load_model(&args.network) {
            Ok(model) => model,
            // a wireframe: its closed wires are the cycles
            Err(e) if matches!(e.downcast_ref(), Some(occt::ImportError::NoFace { .. })) => {
                return load_wire_network(args, e)
            }
            Err(e) => return Err(e),
        };
        let faces: Option<Vec<usize>> = args
            .faces
            .as_ref()
            .map(|f| f.iter().map(|&k| k.saturating_sub(1)).collect());
        if let Some(f) = &args.faces {
            if let Some(&bad) = f.iter().find(|&&k| k == 0 || k > model.faces.len()) {
                bail!(
                    "{}: --faces {bad} is out of range: the model has faces 1 to {}",
                    args.network.display(),
                    model.faces.len()
                );
            }
        }
        let (net, skipped) = network_from_model(&model, faces.as_deref())
            .with_context(|| format!("{}", args.network.display()))?;
        for s in &skipped {
            eprintln!("{}: {s}", args.network.display());
        }
        Ok(net.with_file(args.network.display().to_string()))
    } else {
        if args.faces.is_some() {
            bail!("{}: --faces applies to CAD models only", args.network.display());
        }
        Ok(read_network(&args.network)?)
    }
}

/// The network of a CAD file with no face: its closed wires
/// ([`occt::load_wires`]), each a cycle; `no_face` is the error of reading it
/// for faces, given back when the file has no curve either.
fn load_wire_network(args: &CurvesArgs, no_face: anyhow::Error) -> Result<CurveNetwork> {
    let name = args.network.display();
    if args.faces.is_some() {
        bail!("{name}: --faces: the file has no face (a wireframe: its closed wires are the cycles)");
    }
    let wires = match occt::load_wires(&args.network) {
        Ok(w) => w,
        Err(occt::ImportError::NoFace { .. }) => return Err(no_face),
        Err(e) => return Err(e.into()),
    };
    let closed: Vec<Vec<WireCurveUse<'_>>> = wires
        .closed
        .iter()
        .map(|w| w.uses.iter().map(|u| (u.curve, u.forward, &u.points[..])).collect())
        .collect();
    let (net, note) =
        network_from_wires(&closed, &wires.open_curves).with_context(|| format!("{name}"))?;
    if let Some(note) = note.filter(|_| !args.quiet) {
        eprintln!("{name}: {note}");
    }
    Ok(net.with_file(name.to_string()))
}

/// The method's options from the arguments.
fn options(args: &CurvesArgs) -> Result<CurvesOptions> {
    let mut o = CurvesOptions {
        size: args.size,
        size_factor: args.size_factor.unwrap_or(1.0),
        skip_bad: args.skip_bad,
        network: !args.no_network,
        threads: args.threads,
        ..Default::default()
    };
    if let Some(d) = args.drop {
        if !(d > 1.0 && d.is_finite()) {
            bail!("--drop {d} must be a number above 1");
        }
        o.pairing.drop = d;
    }
    if let Some(d) = args.dom {
        if !(d > 0.0 && d.is_finite()) {
            bail!("--dom {d} must be a positive number");
        }
        o.pairing.dom = d;
    }
    for (name, v) in [("--size", args.size), ("--size-factor", args.size_factor)] {
        if let Some(v) = v {
            if !(v > 0.0 && v.is_finite()) {
                bail!("{name} {v} must be a positive number");
            }
        }
    }
    Ok(o)
}

/// Runs `quadrille curves`.
pub fn run(args: &CurvesArgs) -> Result<()> {
    let opts = options(args)?;
    let format = match &args.output {
        Some(o) => Some(files::check_output(o, &["msh", "vtu", "obj"])?),
        None if args.check => None,
        None => bail!("an output file is needed (-o OUT.msh|.vtu|.obj), or --check to validate only"),
    };
    for p in [&args.png, &args.layout, &args.write_network].into_iter().flatten() {
        let ext = files::extension(p);
        let allowed: &[&str] = match ext.as_str() {
            "png" => &["png"],
            "json" => &["json"],
            _ => &["obj"],
        };
        files::check_output(p, allowed)?;
    }
    let t0 = Instant::now();
    let net = load_network(args)?;
    let t_load = t0.elapsed().as_secs_f64();
    if let Some(w) = &args.write_network {
        write_network(&net, w)?;
    }
    if args.check {
        let problems = net.validate();
        for p in &problems {
            eprintln!("{p}");
        }
        if !problems.is_empty() {
            bail!("{} of {} cycles are invalid", problems.len(), net.cycles().len());
        }
        println!(
            "{}: {} curves, {} cycles, all valid",
            args.network.display(),
            net.curves().len(),
            net.cycles().len()
        );
        if format.is_none() {
            return Ok(());
        }
    }
    let t1 = Instant::now();
    let (mesh, report) = mesh_curve_network(&net, &opts)?;
    let t_mesh = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    if let (Some(out), Some(format)) = (&args.output, format.as_deref()) {
        match format {
            "msh" => mesh::msh::write_msh(
                out,
                &mesh,
                None,
                mesh::msh::MshWriteOptions::new(mesh::msh::MshEncoding::Ascii),
            )?,
            "vtu" => mesh::vtu::write_vtu(&mesh, None, out)?,
            _ => mesh::obj::write_obj(&mesh, out)?,
        }
    }
    if let Some(png) = &args.png {
        let title = args.network.file_name().map(|n| n.to_string_lossy().into_owned());
        let overlay = layout_overlay(&report);
        let ropts = mesh::render::RenderOptions {
            title: title.as_deref(),
            overlay: Some(&overlay),
            ..Default::default()
        };
        mesh::render::render_png(&mesh, &ropts, png)?;
    }
    if let Some(path) = &args.layout {
        write_layout_obj(&report, path)?;
    }
    let t_write = t2.elapsed().as_secs_f64();
    for s in &report.skipped {
        eprintln!("skipped: {}", s.1);
    }
    // Notes (rings, odd parties, fallbacks, the network stage's) are not
    // errors: `--quiet` keeps them off stderr; skipped cycles stay listed.
    if !args.quiet {
        for c in &report.cycles {
            for n in &c.notes {
                eprintln!("cycle {}: {n}", c.cycle);
            }
        }
        for n in &report.network.notes {
            eprintln!("network: {n}");
        }
    }
    if args.json {
        println!("{}", report_json(&report, mesh.quads.len()));
    } else if !args.quiet {
        print!("{}", summary_text(&report, mesh.quads.len()));
    }
    if args.timings {
        eprintln!("time: load {t_load:.3} s, mesh {t_mesh:.3} s, write {t_write:.3} s");
    }
    Ok(())
}

/// The text summary: a line per cycle, then the totals.
fn summary_text(r: &CurvesReport, quads: usize) -> String {
    let mut s = String::new();
    for c in &r.cycles {
        s += &format!(
            "cycle {}: {} segments, {} patches, interior valences {:?}, {} quads{}\n",
            c.cycle,
            c.segments,
            c.patches,
            c.interior_valences,
            c.quads,
            if c.midpoint_layout { " (midpoint layout)" } else { "" }
        );
    }
    let n = &r.network;
    let tj = &n.t_junctions;
    s += &format!(
        "network: {} shared curves, {} T-junctions merged, {} chords split, {} unresolved, {} secondary vertices ({} snapped), interval mismatch {}, intervals {:.3} s\n",
        tj.shared_curves, tj.merged, tj.split, tj.unresolved, tj.secondary, n.snapped, n.mismatch, n.interval_seconds
    );
    let o = &r.open_edges;
    s += &format!(
        "open edges: {} ({} between cycles, {} inside cycles, {} on unshared curves), {} non-manifold\n",
        o.total, o.between_cycles, o.inside_cycles, o.on_unshared_curves, o.non_manifold
    );
    s += &format!(
        "{} cycles meshed, {} skipped, {} quads, edge length {:.4}\n",
        r.cycles.len(),
        r.skipped.len(),
        quads,
        r.h
    );
    s
}

/// The `--json` report: per cycle its pairing and layout, and the totals in
/// the paper's Table 1 columns.
fn report_json(r: &CurvesReport, quads: usize) -> String {
    let cycles: Vec<serde_json::Value> = r
        .cycles
        .iter()
        .map(|c| {
            serde_json::json!({
                "cycle": c.cycle,
                "segments": c.segments,
                "parts": c.parts,
                "pairs": c.pairs.iter().map(|((i, j), cost)| serde_json::json!({"segments": [i, j], "cost": cost})).collect::<Vec<_>>(),
                "iterations": c.iterations,
                "patches": c.patches,
                "interior_valences": c.interior_valences,
                "fallbacks": c.fallbacks,
                "odd_parties": c.odd_parties,
                "connectors": c.connectors,
                "midpoint_layout": c.midpoint_layout,
                "quads": c.quads,
                "seconds": c.seconds,
            })
        })
        .collect();
    let total_segments: usize = r.cycles.iter().map(|c| c.segments).sum();
    let total_patches: usize = r.cycles.iter().map(|c| c.patches).sum();
    let seconds: f64 = r.cycles.iter().map(|c| c.seconds).sum();
    serde_json::to_string_pretty(&serde_json::json!({
        "cycles": cycles,
        "network": {
            "shared_curves": r.network.t_junctions.shared_curves,
            "skipped_curves": r.network.t_junctions.skipped_curves,
            "merged": r.network.t_junctions.merged,
            "split": r.network.t_junctions.split,
            "unresolved": r.network.t_junctions.unresolved,
            "secondary": r.network.t_junctions.secondary,
            "snapped": r.network.snapped,
            "chords": r.network.chords,
            "primary_segments": r.network.primary_segments,
            "joined": r.network.joined,
            "mismatch": r.network.mismatch,
            "intervals": r.network.intervals,
            "relaid": r.network.relaid,
            "interval_seconds": r.network.interval_seconds,
            "seconds": r.network.seconds,
        },
        "open_edges": {
            "total": r.open_edges.total,
            "between_cycles": r.open_edges.between_cycles,
            "on_unshared_curves": r.open_edges.on_unshared_curves,
            "inside_cycles": r.open_edges.inside_cycles,
            "non_manifold": r.open_edges.non_manifold,
            "by_cycle": r.open_edges.by_cycle.iter().map(|(c, b, i)| serde_json::json!({"cycle": c, "between_cycles": b, "inside_cycles": i})).collect::<Vec<_>>(),
        },
        "open_edges_between_cycles": r.open_edges.between_cycles,
        "open_edges_inside_cycles": r.open_edges.inside_cycles,
        "skipped": r.skipped.iter().map(|(c, why)| serde_json::json!({"cycle": c, "reason": why})).collect::<Vec<_>>(),
        "totals": {
            "cycles": r.cycles.len(),
            "segments": total_segments,
            "patches": total_patches,
            "quads": quads,
            "seconds": seconds,
            "welded_nodes": r.welded_nodes,
            "edge_length": r.h,
        }
    }))
    .unwrap_or_default()
}

/// The coarse layout drawn over the mesh (Fig. 1d): patch sides in green,
/// layout vertices as dots.
fn layout_overlay(r: &CurvesReport) -> mesh::render::Overlay {
    let mut o = mesh::render::Overlay { line_width: 2.5, ..Default::default() };
    for c in &r.cycles {
        for q in &c.layout_quads {
            for k in 0..4 {
                o.segments.push(mesh::render::OverlaySegment {
                    a: q[k],
                    b: q[(k + 1) % 4],
                    color: [20, 150, 60],
                    normal: None,
                });
            }
            for p in q {
                o.points.push(mesh::render::OverlayPoint { position: *p, color: [20, 150, 60] });
            }
        }
    }
    o
}

/// The coarse layout as OBJ: one quad face per patch (corners not shared
/// between patches), one group per cycle.
fn write_layout_obj(r: &CurvesReport, path: &std::path::Path) -> Result<()> {
    use std::fmt::Write as _;
    let mut text = String::from("# quadrille curves: the coarse layout, one quad per patch\n");
    let mut next = 1;
    for c in &r.cycles {
        let _ = writeln!(text, "g cycle_{}", c.cycle);
        for q in &c.layout_quads {
            for p in q {
                let _ = writeln!(text, "v {} {} {}", p[0], p[1], p[2]);
            }
            let _ = writeln!(text, "f {} {} {} {}", next, next + 1, next + 2, next + 3);
            next += 4;
        }
    }
    mesh::atomic::write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes()))
        .with_context(|| format!("could not write {}", path.display()))
}
