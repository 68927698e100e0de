//! `quadrille stats`: quality statistics of any mesh.

use anyhow::Result;

use crate::files;
use crate::StatsArgs;

pub fn run(args: &StatsArgs) -> Result<()> {
    let m = files::read_mesh(&args.mesh)?;
    let model = args.cad.as_deref().map(files::load_model).transpose()?;
    let stats = mesh::stats::MeshStats::compute(&m, model.as_ref());
    if args.json {
        println!("{}", serde_json::to_string_pretty(&stats)?);
    } else {
        println!("{}", args.mesh.display());
        print!("{stats}");
    }
    Ok(())
}
