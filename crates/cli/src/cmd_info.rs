//! `quadrille info`: what a CAD model holds.

use anyhow::Result;
use serde::Serialize;

use crate::files;
use crate::InfoArgs;

/// Summary of one face.
#[derive(Serialize)]
struct FaceInfo {
    id: usize,
    loops: usize,
    curve_uses: usize,
    seams: usize,
    reversed: bool,
    u_periodic: bool,
    v_periodic: bool,
    uv_bounds: [f64; 4],
}

/// Summary of a model.
#[derive(Serialize)]
struct ModelInfo {
    file: String,
    corners: usize,
    curves: usize,
    faces: usize,
    degenerate_curves: usize,
    seam_curves: usize,
    /// Curves used by exactly one face (excluding seams): the open boundary.
    boundary_curves: usize,
    /// Curves used by three or more faces (non-manifold).
    non_manifold_curves: usize,
    bounding_box: [[f64; 3]; 2],
    diagonal: f64,
    face_list: Vec<FaceInfo>,
}

pub fn run(args: &InfoArgs) -> Result<()> {
    let model = files::load_model(&args.model)?;
    let curve_faces = model.curve_faces();
    let seam_curve = |c: usize| {
        model
            .faces
            .iter()
            .any(|f| f.curve_uses().any(|u| u.seam && u.curve.idx() == c))
    };
    let (lo, hi) = model.bounding_box();
    let info = ModelInfo {
        file: args.model.display().to_string(),
        corners: model.corners.len(),
        curves: model.curves.len(),
        faces: model.faces.len(),
        degenerate_curves: model.curves.iter().filter(|c| c.degenerate).count(),
        seam_curves: (0..model.curves.len()).filter(|&c| seam_curve(c)).count(),
        boundary_curves: (0..model.curves.len())
            .filter(|&c| curve_faces[c].len() == 1 && !seam_curve(c) && !model.curves[c].degenerate)
            .count(),
        non_manifold_curves: curve_faces.iter().filter(|f| f.len() >= 3).count(),
        bounding_box: [lo, hi],
        diagonal: geometry::vec3::dist(lo, hi),
        face_list: model
            .faces
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let p = f.surface.periods();
                let b = f.uv_bounds;
                FaceInfo {
                    id: i + 1,
                    loops: f.loops.len(),
                    curve_uses: f.curve_uses().count(),
                    seams: f.curve_uses().filter(|u| u.seam).count() / 2,
                    reversed: f.reversed,
                    u_periodic: p[0].is_some(),
                    v_periodic: p[1].is_some(),
                    uv_bounds: [b.umin, b.umax, b.vmin, b.vmax],
                }
            })
            .collect(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
        return Ok(());
    }
    println!("{}", info.file);
    println!(
        "  faces {}   curves {}   corners {}",
        info.faces, info.curves, info.corners
    );
    println!(
        "  seam curves {}   degenerate curves {}   boundary curves {}   non-manifold curves {}",
        info.seam_curves, info.degenerate_curves, info.boundary_curves, info.non_manifold_curves
    );
    println!(
        "  bounding box [{:.4}, {:.4}, {:.4}] – [{:.4}, {:.4}, {:.4}]   diagonal {:.6}",
        lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], info.diagonal
    );
    println!(
        "  {}",
        if info.boundary_curves == 0 {
            "closed (watertight B-rep)"
        } else {
            "open (has boundary curves)"
        }
    );
    println!("  face  loops  uses  seams  periodic  reversed");
    for f in &info.face_list {
        let per = match (f.u_periodic, f.v_periodic) {
            (true, true) => "u,v",
            (true, false) => "u",
            (false, true) => "v",
            _ => "-",
        };
        println!(
            "  {:>4}  {:>5}  {:>4}  {:>5}  {:>8}  {:>8}",
            f.id, f.loops, f.curve_uses, f.seams, per, f.reversed
        );
    }
    Ok(())
}
