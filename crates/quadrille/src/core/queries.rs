//! Questions about the model's geometry that stages of several folders ask:
//! may a quad take a pole as a corner, is a face a full sphere, which corners
//! are too sharp for any good quad.

use geometry::{CornerId, FaceId, Model};

/// Largest spread of the normals around a pole ([`geometry::Face::pole_normal_spread`])
/// at which one quad may take the pole as a corner (a sphere's pole: 0; the
/// apex of i04o_m4's half cones: about 70°).
pub const MAX_POLE_CORNER_SPREAD_DEG: f64 = 30.0;

/// True when a quad cornered at the pole of segment `seg` would fold.
pub fn folds_at_pole(face: &geometry::Face, seg: [[f64; 2]; 2]) -> bool {
    face.pole_normal_spread(seg)
        .is_none_or(|a| a.to_degrees() > MAX_POLE_CORNER_SPREAD_DEG)
}

/// When face `fid` is a full sphere (one loop: seam, pole, the seam
/// again, pole), the positions in its loop of the two uses of the seam.
pub fn full_sphere_seam(model: &Model, fid: FaceId) -> Option<(usize, usize)> {
    let face = &model.faces[fid.idx()];
    let [lp] = face.loops.as_slice() else {
        return None;
    };
    let u = &lp.uses;
    if u.len() != 4 {
        return None;
    }
    let deg = |k: usize| model.curves[u[k].curve.idx()].degenerate;
    if deg(1) && deg(3) && u[0].curve == u[2].curve && u[0].seam {
        Some((0, 2))
    } else if deg(0) && deg(2) && u[1].curve == u[3].curve && u[1].seam {
        Some((1, 3))
    } else {
        None
    }
}

/// The corners of face `fid` whose interior angle there is below
/// `mesh::stats::SHARP_CORNER_DEG`: the ones the statistics excuse.
pub fn sharp_corners_of(model: &Model, fid: FaceId) -> Vec<CornerId> {
    mesh::stats::sharp_corners_in_face(model, fid.idx(), mesh::stats::SHARP_CORNER_DEG)
        .into_iter()
        .map(|s| CornerId(s.corner))
        .collect()
}
