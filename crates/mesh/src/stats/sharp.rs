//! CAD corners with a small interior angle in a face (cusps and near-cusps):
//! the quads touching them are excused from minimum-quality bars.

use geometry::vec3::{self, add, cross, dot, scale, Vec3};
use geometry::Model;

use super::SharpCorner;

/// Tangent directions closer than this (radians) to each other are tangent
/// curves for [`sharp_corners`], which then measures the angle on chords.
const TANGENT_ANGLE: f64 = 0.01;

/// Parameter step (share of a curve's range) of the chords [`sharp_corners`]
/// measures at tangent curves.
const CHORD_STEP: f64 = 1e-3;

/// Interior angles (degrees) of the CAD corners in each face where two
/// consecutive loop curves meet, measured in the face's tangent plane; only
/// the angles below `below_deg` are returned. Where the two curves are
/// tangent the angle is measured on short chords instead, so a cusp reads
/// as about 0°, not 360°.
pub fn sharp_corners(model: &Model, below_deg: f64) -> Vec<SharpCorner> {
    (0..model.faces.len())
        .flat_map(|fi| sharp_corners_in_face(model, fi, below_deg))
        .collect()
}

/// [`sharp_corners`] of the face with 0-based index `fi` (none when there is
/// no such face).
pub fn sharp_corners_in_face(model: &Model, fi: usize, below_deg: f64) -> Vec<SharpCorner> {
    let mut out: Vec<SharpCorner> = Vec::new();
    if let Some(face) = model.faces.get(fi) {
        for lp in &face.loops {
            let n = lp.uses.len();
            for k in 0..n {
                let (a, b) = (&lp.uses[k], &lp.uses[(k + 1) % n]);
                let (Some(ca), Some(cb)) = (
                    model.curves.get(a.curve.idx()),
                    model.curves.get(b.curve.idx()),
                ) else {
                    continue;
                };
                if ca.degenerate || cb.degenerate {
                    continue;
                }
                let (t_end, sa) = if a.forward {
                    (ca.range.1, 1.0)
                } else {
                    (ca.range.0, -1.0)
                };
                let (t_start, sb) = if b.forward {
                    (cb.range.0, 1.0)
                } else {
                    (cb.range.1, -1.0)
                };
                let corner = if a.forward { ca.end } else { ca.start };
                let uv = b.pcurve.eval(t_start);
                let d = face.surface.first_derivs(uv);
                let to3d = |w: [f64; 2]| add(scale(d.du, w[0]), scale(d.dv, w[1]));
                let da = a.pcurve.deriv(t_end);
                let db = b.pcurve.deriv(t_start);
                let t_in = scale(to3d(da), sa);
                let t_out = scale(to3d(db), sb);
                let Some(n0) = vec3::normalize(cross(d.du, d.dv)) else {
                    continue;
                };
                let w = scale(t_in, -1.0);
                if vec3::norm(w) < 1e-300 || vec3::norm(t_out) < 1e-300 {
                    continue;
                }
                // Counter-clockwise angle (about the uv-consistent normal) from
                // the outgoing tangent to the incoming curve's backward tangent:
                // the material lies in between.
                let ccw = |from: Vec3, to: Vec3| {
                    let a = dot(cross(from, to), n0).atan2(dot(from, to));
                    if a < 0.0 {
                        a + std::f64::consts::TAU
                    } else {
                        a
                    }
                };
                let mut ang = ccw(t_out, w);
                if !ang.is_nan()
                    && !(TANGENT_ANGLE..=std::f64::consts::TAU - TANGENT_ANGLE).contains(&ang)
                {
                    // tangent curves: 0° (a cusp the material fills) and 360°
                    // (a slit) differ by a rounding error of the tangents; the
                    // chords to points a little along each curve tell them apart
                    let step = |r: (f64, f64)| CHORD_STEP * (r.1 - r.0);
                    let back = a.pcurve.eval(t_end - sa * step(ca.range));
                    let ahead = b.pcurve.eval(t_start + sb * step(cb.range));
                    let chord = |x: [f64; 2]| to3d([x[0] - uv[0], x[1] - uv[1]]);
                    let (w2, t2) = (chord(back), chord(ahead));
                    if vec3::norm(w2) > 0.0 && vec3::norm(t2) > 0.0 {
                        ang = ccw(t2, w2);
                    }
                }
                let deg = ang.to_degrees();
                if deg < below_deg {
                    let entry = SharpCorner {
                        corner: corner.0,
                        face: fi as u32,
                        angle_deg: deg,
                    };
                    match out
                        .iter_mut()
                        .find(|s| s.corner == entry.corner && s.face == entry.face)
                    {
                        Some(s) => s.angle_deg = s.angle_deg.min(deg),
                        None => out.push(entry),
                    }
                }
            }
        }
    }
    out
}
