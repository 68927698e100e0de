//! Per-face adjustments of the curve plan's counts, by the shape of the
//! face that the counts must suit (quasi-structured paper §4.3 leaves the
//! counts to the size map; these are ours): grids on full tori and open
//! bands, one count on both loops of an annulus, square cells on bands.

use geometry::vec3;
use geometry::Model;

use crate::curves::curve_chords::{annulus_loops, CHORD_TOLERANCE};

/// (u, v) samples per direction for the mean widths of [`balance_seam_grids`].
const WIDTH_SAMPLES: usize = 16;

/// A face bounded by nothing but two seams of its own (a full torus: the
/// loop is seam A, seam B, A again, B again, and no other face uses A or B)
/// is meshed as a grid whose two counts are free. Measured on the seams
/// alone they follow the size map along two particular lines, which need
/// not be typical of the face (on a torus, the size map bends around the
/// cross field's singularities). Here the product of the two ideal counts
/// is kept and their ratio set to the ratio of the face's mean widths along
/// u and along v, so that the grid's cells are square on average.
pub(crate) fn balance_seam_grids(model: &Model, ideal: &mut [f64]) {
    let curve_faces = model.curve_faces();
    for (fi, face) in model.faces.iter().enumerate() {
        let [lp] = face.loops.as_slice() else {
            continue;
        };
        let u = &lp.uses;
        if u.len() != 4
            || u[0].curve != u[2].curve
            || u[1].curve != u[3].curve
            || u[0].curve == u[1].curve
            || !u.iter().all(|x| x.seam)
        {
            continue;
        }
        let (a, b) = (u[0].curve.idx(), u[1].curve.idx());
        let own = |c: usize| curve_faces[c].as_slice() == [geometry::FaceId(fi as u32)];
        if !own(a) || !own(b) || !(ideal[a] > 0.0 && ideal[b] > 0.0) {
            continue;
        }
        // mean lengths of the u-lines and of the v-lines across the face
        let bd = face.uv_bounds;
        let (mut su, mut sv) = (0.0, 0.0);
        for i in 0..WIDTH_SAMPLES {
            for j in 0..WIDTH_SAMPLES {
                let x = bd.umin + (bd.umax - bd.umin) * (i as f64 + 0.5) / WIDTH_SAMPLES as f64;
                let y = bd.vmin + (bd.vmax - bd.vmin) * (j as f64 + 0.5) / WIDTH_SAMPLES as f64;
                let d = face.surface.derivs([x, y]);
                su += vec3::norm(d.du);
                sv += vec3::norm(d.dv);
            }
        }
        let n2 = (WIDTH_SAMPLES * WIDTH_SAMPLES) as f64;
        let width_u = su / n2 * (bd.umax - bd.umin);
        let width_v = sv / n2 * (bd.vmax - bd.vmin);
        if !(width_u > 0.0 && width_v > 0.0) {
            continue;
        }
        // a seam along which u is constant runs in v, and counts v-cells
        let runs_in_v = |k: usize| {
            let ce = &model.curves[u[k].curve.idx()];
            let t = 0.5 * (ce.range.0 + ce.range.1);
            let d = u[k].pcurve.deriv(t);
            d[1].abs() > d[0].abs()
        };
        let (along_v, along_u) = match (runs_in_v(0), runs_in_v(1)) {
            (true, false) => (a, b),
            (false, true) => (b, a),
            _ => continue,
        };
        let product = ideal[a] * ideal[b];
        ideal[along_u] = (product * width_u / width_v).sqrt();
        ideal[along_v] = (product * width_v / width_u).sqrt();
    }
}

/// Every band of the model: a face whose one loop is four uses A, S, B, S
/// with S a seam run both ways between two other curves A ≠ B. Yields
/// `(face index, uses, k, [S, A, B])` with S at uses `k` and `k + 2`
/// (curve indices); a loop may give two (both pairs of opposite uses).
fn seam_bands(
    model: &Model,
) -> impl Iterator<Item = (usize, &[geometry::CurveUse], usize, [usize; 3])> {
    model.faces.iter().enumerate().flat_map(|(fi, face)| {
        let uses: &[geometry::CurveUse] = match face.loops.as_slice() {
            [lp] if lp.uses.len() == 4 => &lp.uses,
            _ => &[],
        };
        (0..2).filter(|_| !uses.is_empty()).filter_map(move |k| {
            let u = uses;
            let (s, a, b) = (
                u[k].curve.idx(),
                u[k + 1].curve.idx(),
                u[(k + 3) % 4].curve.idx(),
            );
            (u[k + 2].curve.idx() == s && u[k].seam && u[k + 2].seam && a != b).then_some((
                fi,
                u,
                k,
                [s, a, b],
            ))
        })
    })
}

/// An open band (a lofted skin, a duct: one loop, curve A, a seam S, curve B,
/// S again, where A and B bound no other face and S is the band's own) is
/// meshed as a grid whose seam count is free. The size map's count for S
/// follows the size map along one line, while A and B are spaced by their
/// curvature (an airfoil's leading edge), so their cells can be several
/// times longer across than along. Here S's ideal count is set so that the
/// grid's cells are as long along S as they are wide along A and B on
/// average: `|S| / mean(|A| / ideal[A], |B| / ideal[B])`.
pub(crate) fn balance_band_seams(model: &Model, ideal: &mut [f64], lengths: &[f64]) {
    let curve_faces = model.curve_faces();
    for (fi, u, k, [s, a, b]) in seam_bands(model) {
        let own = |c: usize| curve_faces[c].as_slice() == [geometry::FaceId(fi as u32)];
        let band = !u[k + 1].seam && !u[(k + 3) % 4].seam && own(s) && own(a) && own(b);
        if !band || !(ideal[a] > 0.0 && ideal[b] > 0.0 && lengths[s] > 0.0) {
            continue;
        }
        let spacing = 0.5 * (lengths[a] / ideal[a] + lengths[b] / ideal[b]);
        if spacing > 0.0 {
            ideal[s] = lengths[s] / spacing;
        }
    }
}

/// An annulus of two closed curves (meshed as a ring grid by
/// `direct::ring_face`) needs one count on both loops; the chord of its two
/// curves would take their mean, which coarsens the longer loop below the
/// size map. Here both ideal counts are raised to the larger one, when they
/// are close enough to join a chord at all ([`CHORD_TOLERANCE`]), so the
/// ring's cells are at most the size map's along both loops.
pub(crate) fn balance_annuli(model: &Model, ideal: &mut [f64]) {
    for face in &model.faces {
        let Some(loops) = annulus_loops(model, face) else {
            continue;
        };
        let [[a], [b]] = [loops[0].as_slice(), loops[1].as_slice()] else {
            continue;
        };
        let (a, b) = (*a, *b);
        let top = ideal[a].max(ideal[b]);
        if (ideal[a] - ideal[b]).abs() <= CHORD_TOLERANCE * top {
            ideal[a] = top;
            ideal[b] = top;
        }
    }
}

/// Largest ratio of a band's cell length along its seam to its spacing along
/// its loops that [`square_band_seams`] leaves alone.
const BAND_ASPECT_TOLERANCE: f64 = 1.3;

/// A band (one loop: curve A, a seam S, curve B, S again, as a cylinder or
/// a cone between two circles) whose A and B share one count is meshed as a
/// grid, and its cells are as long along S as `|S| / counts[S]`. When the
/// chords have moved A and B's count away from their ideal (an annulus
/// beside the band takes the larger of its loops' counts, see
/// [`balance_annuli`]), those cells stretch, and a stretched quad's SICN
/// falls (2 : 1 gives 0.8). Here S, which bounds only this band and is in
/// no chord with another curve, is given the count that makes the cells
/// square on average, when they would otherwise be more than
/// [`BAND_ASPECT_TOLERANCE`] times longer one way than the other. A band
/// whose A was `raised` beyond the chord tolerance by a contained annulus
/// (`curve_chords::balance_composite_sides`: a hex nut's bore, raised to
/// the hexagon's count) keeps its seam count: squaring would multiply the
/// band's quads by the raise again.
pub(crate) fn square_band_seams(
    model: &Model,
    counts: &mut [usize],
    members: &impl Fn(usize) -> Vec<usize>,
    lengths: &[f64],
    raised: &[bool],
) {
    let curve_faces = model.curve_faces();
    for (fi, _, _, [s, a, b]) in seam_bands(model) {
        let band = counts[a] == counts[b]
            && !raised[a]
            && !raised[b]
            && curve_faces[s].as_slice() == [geometry::FaceId(fi as u32)]
            && members(s) == [s]
            && !model.curves[a].degenerate
            && !model.curves[b].degenerate;
        if !band || counts[a] == 0 || counts[s] == 0 {
            continue;
        }
        let spacing = 0.5 * (lengths[a] + lengths[b]) / counts[a] as f64;
        let along = lengths[s] / counts[s] as f64;
        if !(spacing > 0.0 && along > 0.0) {
            continue;
        }
        let aspect = along / spacing;
        if aspect > BAND_ASPECT_TOLERANCE || aspect < 1.0 / BAND_ASPECT_TOLERANCE {
            counts[s] = ((lengths[s] / spacing).round() as usize).max(1);
        }
    }
}
