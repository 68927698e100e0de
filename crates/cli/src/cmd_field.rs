//! `quadrille field`: the cross field of every face of a CAD model on its
//! background triangulation, its singularities and the check of relation (2)
//! of the quasi-structured paper, written as VTU, drawn as PNG, reported as JSON.

use std::time::Instant;

use anyhow::{bail, Result};
use quadrille::field::SingularitySite;
use quadrille::field::SizeMapOptions;
use quadrille::field::{model_fields, FieldOptions, ModelFields};
use serde::Serialize;

use crate::files;
use crate::progress::FaceProgress;
use crate::FieldArgs;

/// Glyph spacing of the picture: the model's bounding-box diagonal / this.
const GLYPHS_PER_DIAGONAL: f64 = 60.0;

/// One singularity in the JSON report.
#[derive(Serialize)]
struct SingularityJson {
    /// +1 (valence 3) or −1 (valence 5).
    index: i32,
    position: [f64; 3],
    /// `vertex`, `triangle` or `acute_corner` (the artificial +1 of a corner below 45°).
    site: &'static str,
}

/// One face in the JSON report.
#[derive(Serialize)]
struct FaceJson {
    /// 1-based, as in mesh files.
    face: usize,
    /// Background triangles the field lives on (0 when it failed).
    triangles: usize,
    euler_characteristic: Option<i64>,
    singularities: Vec<SingularityJson>,
    /// `2 − n̄` for each CAD corner on the face boundary (n̄ its ideal valence).
    corner_indices: Vec<i64>,
    /// Σ singularity indices + Σ corner indices = 4χ (relation (2)).
    euler_ok: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// Totals of the JSON report.
#[derive(Serialize)]
struct TotalsJson {
    faces: usize,
    faces_euler_ok: usize,
    /// `faces_euler_ok / faces` (faces without a field count as not ok).
    euler_ok_share: f64,
    faces_failed: usize,
    triangles: usize,
    singularities_plus: usize,
    singularities_minus: usize,
}

/// One curve in the JSON report: its quantization against the size map.
#[derive(Serialize)]
struct CurveJson {
    /// 1-based, as in mesh files.
    curve: usize,
    /// ∫ dl / s over the curve, in mesh edges (before rounding and chords).
    ideal_edges: f64,
    /// Mesh edges the curve gets (even: 2 per coarse segment).
    edges: usize,
    /// Smallest and largest size map value on the curve.
    size_range: Option<[f64; 2]>,
}

/// The JSON report.
#[derive(Serialize)]
struct ReportJson {
    file: String,
    /// Target quad size (model units).
    size: f64,
    /// Background triangulation size (model units).
    background_size: f64,
    faces: Vec<FaceJson>,
    curves: Vec<CurveJson>,
    /// Smallest and largest value of the size map (absent without one).
    size_range: Option<[f64; 2]>,
    totals: TotalsJson,
}

/// Smallest and largest of `values`; `None` when empty.
fn range(values: impl IntoIterator<Item = f64>) -> Option<[f64; 2]> {
    values.into_iter().fold(None, |r, x| {
        Some(match r {
            None => [x, x],
            Some([a, b]) => [a.min(x), b.max(x)],
        })
    })
}

fn report(args: &FieldArgs, model: &geometry::Model, fields: &ModelFields) -> ReportJson {
    let faces: Vec<FaceJson> = fields
        .faces
        .iter()
        .map(|r| match &r.outcome {
            Ok(f) => FaceJson {
                face: r.face.idx() + 1,
                triangles: f.triangles(),
                euler_characteristic: Some(f.singularities.euler_characteristic),
                singularities: f
                    .singularities
                    .list
                    .iter()
                    .map(|s| SingularityJson {
                        index: s.index,
                        position: s.position,
                        site: match s.site {
                            SingularitySite::Vertex(_) => "vertex",
                            SingularitySite::Triangle(_) => "triangle",
                            SingularitySite::AcuteCorner(..) => "acute_corner",
                        },
                    })
                    .collect(),
                corner_indices: f.corner_indices(),
                euler_ok: r.euler_ok(),
                error: None,
            },
            Err(e) => FaceJson {
                face: r.face.idx() + 1,
                triangles: 0,
                euler_characteristic: None,
                singularities: Vec::new(),
                corner_indices: Vec::new(),
                euler_ok: false,
                error: Some(e.to_string()),
            },
        })
        .collect();
    let count = |k: i32| {
        faces
            .iter()
            .flat_map(|f| &f.singularities)
            .filter(|s| s.index == k)
            .count()
    };
    let totals = TotalsJson {
        faces: fields.faces.len(),
        faces_euler_ok: fields.faces_euler_ok(),
        euler_ok_share: fields.euler_ok_share(),
        faces_failed: fields.faces_failed(),
        triangles: fields.triangles(),
        singularities_plus: count(1),
        singularities_minus: count(-1),
    };
    let plan = fields.curve_plan(model);
    let profiles = fields
        .size_map
        .as_ref()
        .map(|m| m.curve_sizes(model, &fields.curves))
        .unwrap_or_default();
    let curves = (0..model.curves.len())
        .map(|c| CurveJson {
            curve: c + 1,
            ideal_edges: 2.0 * plan.ideal(geometry::CurveId(c as u32)),
            edges: 2 * plan.counts[c],
            size_range: profiles
                .get(c)
                .and_then(|p| p.as_ref())
                .and_then(|p| range(p.iter().map(|x| x[1]))),
        })
        .collect();
    let size_range = fields
        .size_map
        .as_ref()
        .and_then(|m| range(m.size.iter().copied()));
    ReportJson {
        file: args.model.display().to_string(),
        size: fields.size,
        background_size: fields.background_size,
        faces,
        curves,
        size_range,
        totals,
    }
}

/// Runs `quadrille field`: checks the outputs, computes the fields, writes
/// the VTU (and PNG), prints the JSON report and a summary.
pub fn run(args: &FieldArgs) -> Result<()> {
    // Everything that can be checked before the long work is checked first.
    if args.output.is_none() && args.png.is_none() && args.size_png.is_none() && !args.json {
        bail!(
            "{}: nothing to do: give -o FIELD.vtu, --png, --size-png or --json",
            args.model.display()
        );
    }
    if let Some(out) = &args.output {
        files::check_output(out, &["vtu"])?;
    }
    for png in args.png.iter().chain(&args.size_png) {
        files::check_output(png, &["png"])?;
    }
    let size = crate::size_arg(args.size, args.size_factor);
    let t0 = Instant::now();
    let model = files::load_model(&args.model)?;

    let bar = FaceProgress::new(args.quiet, model.faces.len(), "cross field");
    let progress = bar.callback();
    let sizing = SizeMapOptions {
        gradient: args.size_gradient,
        small_features: !args.no_small_features,
        min_size: args.min_size,
        max_size: args.max_size,
        entity_sizes: args.entity_sizes.clone(),
        quads_per_turn: (args.quads_per_turn != 0.0).then_some(args.quads_per_turn),
        floor_turn: None,
        floor_narrow: false,
    };
    let opts = FieldOptions {
        size,
        progress,
        sizing,
        ..Default::default()
    };
    let fields =
        model_fields(&model, &opts).map_err(|e| anyhow::anyhow!("{}: {e}", args.model.display()));
    bar.finish();
    let fields = fields?;
    let field_mesh = fields.to_field_mesh(&model);
    if field_mesh.triangles.is_empty() {
        let why = fields.first_failure().unwrap_or_default();
        bail!(
            "{}: no face could be given a cross field ({why})",
            args.model.display()
        );
    }

    let mut written = Vec::new();
    if let Some(out) = &args.output {
        mesh::vtu::write_field_vtu(&field_mesh, out)?;
        written.push(out.clone());
    }
    let name = args
        .model
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut pictures = || -> Result<(), mesh::render::RenderError> {
        if let Some(png) = &args.png {
            let title = format!(
                "{name}: cross field, Eq. (2) holds on {}/{} faces",
                fields.faces_euler_ok(),
                fields.faces.len()
            );
            let ropts = mesh::render::RenderOptions {
                title: Some(&title),
                ..Default::default()
            };
            let spacing = model.diagonal() / GLYPHS_PER_DIAGONAL;
            mesh::field::render_field_png(&field_mesh, spacing, &ropts, png)?;
            written.push(png.clone());
        }
        if let Some(png) = &args.size_png {
            let title = format!("{name}: size map (quad size {:.4})", fields.size);
            let ropts = mesh::render::RenderOptions {
                title: Some(&title),
                ..Default::default()
            };
            mesh::field::render_size_png(&field_mesh, &ropts, png)?;
        }
        Ok(())
    };
    if let Err(e) = pictures() {
        // no half-finished output set: what was written goes too
        for f in &written {
            let _ = std::fs::remove_file(f);
        }
        return Err(e.into());
    }
    let rep = report(args, &model, &fields);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rep)?);
    }
    if !args.quiet {
        let t = &rep.totals;
        eprintln!(
            "{}: {} faces, Eq. (2) holds on {} ({:.1} %), {} failed; {} background triangles; singularities +1: {}, -1: {}; {:.2} s",
            args.output.as_ref().unwrap_or(&args.model).display(),
            t.faces,
            t.faces_euler_ok,
            100.0 * t.euler_ok_share,
            t.faces_failed,
            t.triangles,
            t.singularities_plus,
            t.singularities_minus,
            t0.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
