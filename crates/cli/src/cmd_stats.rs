//! `quadrille stats`: quality statistics of any mesh; a high-order quad mesh
//! (MSH quads of order ≥ 2, as `--method coarse` writes) gets its own figures:
//! validity by det J, Jacobian ratio, CAD distance of nodes and Gauss points.

use anyhow::Result;

use crate::files;
use crate::StatsArgs;

pub fn run(args: &StatsArgs) -> Result<()> {
    let model = args.cad.as_deref().map(files::load_model).transpose()?;
    if files::extension(&args.mesh) == "msh" {
        if let Ok(ho) = mesh::msh::read_high_order_msh(&args.mesh) {
            if ho.order > 1 {
                let stats = mesh::high_order::HighOrderStats::compute(&ho, model.as_ref());
                if args.json {
                    println!("{}", serde_json::to_string_pretty(&stats)?);
                } else {
                    println!("{}", args.mesh.display());
                    print!("{stats}");
                }
                return Ok(());
            }
        }
    }
    let m = files::read_mesh(&args.mesh)?;
    let stats = mesh::stats::MeshStats::compute(&m, model.as_ref());
    if args.json {
        println!("{}", serde_json::to_string_pretty(&stats)?);
    } else {
        println!("{}", args.mesh.display());
        print!("{stats}");
    }
    Ok(())
}
