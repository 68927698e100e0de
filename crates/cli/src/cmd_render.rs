//! `quadrille render`: draw a mesh to a PNG picture.

use anyhow::Result;

use crate::files;
use crate::RenderArgs;

pub fn run(args: &RenderArgs) -> Result<()> {
    files::check_output(&args.output, &["png"])?;
    let m = files::read_mesh(&args.mesh)?;
    let model = args.cad.as_deref().map(files::load_model).transpose()?;
    let sicn = args
        .sicn
        .then(|| mesh::stats::quad_sicn_values(&m, model.as_ref()));
    let title = args
        .mesh
        .file_name()
        .map(|n| n.to_string_lossy().into_owned());
    let mut opts = mesh::render::RenderOptions {
        width: args.width,
        height: args.height,
        show_irregular: !args.no_irregular,
        quad_values: sicn.as_deref(),
        title: title.as_deref(),
        ..Default::default()
    };
    if let Some(v) = &args.view {
        opts.eye_dir = [-v[0], -v[1], -v[2]];
    }
    mesh::render::render_png(&m, &opts, &args.output)?;
    Ok(())
}
