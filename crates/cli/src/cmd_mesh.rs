//! `quadrille mesh`: mesh a CAD model and write the result.

use std::time::Instant;

use anyhow::{bail, Result};
use quadrille::MeshOptions;

use crate::files;
use crate::progress::FaceProgress;
use crate::{MeshArgs, Method};

pub fn run(args: &MeshArgs) -> Result<()> {
    // Everything that can be checked before meshing is checked first.
    let format = files::check_output(&args.output, &["msh", "vtu", "obj"])?;
    if let Some(png) = &args.png {
        files::check_output(png, &["png"])?;
    }
    let size = crate::size_arg(args.size, args.size_factor);
    let t0 = Instant::now();
    let model = files::load_model(&args.model)?;
    let t_load = t0.elapsed().as_secs_f64();

    let bar = FaceProgress::new(args.quiet, model.faces.len(), "meshing");
    let progress = bar.callback();
    let opts = MeshOptions { size, threads: args.threads, progress };
    let t1 = Instant::now();
    let method = match args.method {
        Method::Unstructured => quadrille::MeshMethod::Unstructured,
        Method::Baseline | Method::Regular => quadrille::MeshMethod::Baseline,
    };
    let (mut m, report) = quadrille::mesh_model_with(&model, &opts, method).map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    bar.finish();
    if !args.quiet {
        for (f, reason) in &report.fallback {
            eprintln!("face {}: unstructured meshing failed ({reason}); meshed with the baseline", f.0 + 1);
        }
        if let Method::Unstructured = args.method {
            let d = &report.defects;
            eprintln!(
                "{} of {} faces meshed by a pattern; {} of {} very irregular vertices replaced by disk quadrangulations",
                report.patterns.len(),
                model.faces.len(),
                d.replaced,
                d.found
            );
        }
    }
    let t_mesh = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    if let Method::Regular = args.method {
        let ropts = quadrille::regularize::RegularizeOptions { threads: args.threads, ..Default::default() };
        quadrille::regularize::regularize_mesh(&model, &mut m, &ropts)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()))?;
    }
    let t_improve = t2.elapsed().as_secs_f64();

    let t3 = Instant::now();
    let sicn = mesh::stats::quad_sicn_values(&m, Some(&model));
    match format.as_str() {
        "msh" => {
            let enc = if args.binary { mesh::msh::MshEncoding::Binary } else { mesh::msh::MshEncoding::Ascii };
            mesh::msh::write_msh(&args.output, &m, Some(&model), enc)?
        }
        "vtu" => mesh::vtu::write_vtu(&m, Some(&sicn), &args.output)?,
        "obj" => mesh::obj::write_obj(&m, &args.output)?,
        other => bail!("{}: unknown output extension '.{other}'", args.output.display()),
    }
    if let Some(png) = &args.png {
        let title = args.model.file_name().map(|n| n.to_string_lossy().into_owned());
        let ropts = mesh::render::RenderOptions { title: title.as_deref(), ..Default::default() };
        mesh::render::render_png(&m, &ropts, png)?;
    }
    let t_write = t3.elapsed().as_secs_f64();
    if args.timings {
        eprintln!(
            "timings:{{\"load\":{t_load:.4},\"mesh\":{t_mesh:.4},\"improve\":{t_improve:.4},\"write\":{t_write:.4},\"total\":{:.4}}}",
            t_load + t_mesh + t_improve
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
