//! Sliver curves: CAD edges far shorter than any mesh edge (a few 1e-7 of
//! the model, left behind by modelling tolerances). Meshed as they are, each
//! one gives the quads on both of its sides an edge of that length, so a
//! corner SICN of about 0. [`collapse_short_curves`] gives a copy of the
//! model in which every such curve is a point: its two corners are one
//! corner, the face loops skip it and it is marked degenerate, so a mesher
//! gives it no mesh edge. The ids of corners, curves and faces do not
//! change, so a mesh of the copy is classified on the original model; a
//! merged-away corner is simply not used by any curve of the copy.

use crate::model::{CornerId, CurveId, Model};
use crate::vec3;

/// Samples of the polyline that measures a curve's length.
const LENGTH_SAMPLES: usize = 32;

/// One curve collapsed by [`collapse_short_curves`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collapsed {
    /// The sliver curve.
    pub curve: CurveId,
    /// Its length.
    pub length: f64,
    /// The corner both of its ends became (the smaller id of the two).
    pub kept: CornerId,
    /// The other end, now unused by the copy's curves (`kept` for a curve
    /// whose ends had already been merged by another sliver).
    pub removed: CornerId,
}

/// Length of curve `c` on a polyline of `LENGTH_SAMPLES` (32) segments (`None`
/// for a curve without 3D geometry).
pub fn curve_length(model: &Model, c: CurveId) -> Option<f64> {
    let ce = &model.curves[c.idx()];
    let g = ce.geom.as_ref()?;
    let (t0, t1) = ce.range;
    let mut prev = g.eval(t0);
    let mut len = 0.0;
    for i in 1..=LENGTH_SAMPLES {
        let p = g.eval(t0 + (t1 - t0) * i as f64 / LENGTH_SAMPLES as f64);
        len += vec3::dist(prev, p);
        prev = p;
    }
    len.is_finite().then_some(len)
}

/// The model with every open curve shorter than `max_length` collapsed to a
/// point (see the module documentation), and the list of collapsed curves;
/// `None` when there is none. A curve stays when collapsing it would leave a
/// face loop without any curve.
///
/// ```
/// use geometry::slivers::collapse_short_curves;
/// let model = geometry::primitives::square(1.0);
/// // the square's sides are 1 long: nothing is a sliver at 1e-6
/// assert!(collapse_short_curves(&model, 1e-6).is_none());
/// ```
pub fn collapse_short_curves(model: &Model, max_length: f64) -> Option<(Model, Vec<Collapsed>)> {
    if !(max_length > 0.0) {
        return None;
    }
    let uses_in_loops: Vec<usize> = {
        let mut n = vec![0usize; model.curves.len()];
        for f in &model.faces {
            for u in f.curve_uses() {
                if let Some(k) = n.get_mut(u.curve.idx()) {
                    *k += 1;
                }
            }
        }
        n
    };
    // the representative of each corner: the smallest id it is merged with
    let mut rep: Vec<u32> = (0..model.corners.len() as u32).collect();
    fn find(rep: &mut [u32], c: u32) -> u32 {
        let mut r = c;
        while rep[r as usize] != r {
            r = rep[r as usize];
        }
        rep[c as usize] = r;
        r
    }
    let mut sliver = vec![false; model.curves.len()];
    let mut out = Vec::new();
    for (i, ce) in model.curves.iter().enumerate() {
        if ce.degenerate || ce.start == ce.end || uses_in_loops[i] == 0 {
            continue;
        }
        let Some(length) = curve_length(model, CurveId(i as u32)) else {
            continue;
        };
        if length >= max_length {
            continue;
        }
        // every loop using it must keep another curve
        sliver[i] = true;
        let loops_keep_a_curve = model.faces.iter().all(|f| {
            f.loops.iter().all(|l| {
                !l.uses.iter().any(|u| u.curve.idx() == i)
                    || l.uses.iter().any(|u| !sliver[u.curve.idx()])
            })
        });
        if !loops_keep_a_curve {
            sliver[i] = false;
            continue;
        }
        let (a, b) = (find(&mut rep, ce.start.0), find(&mut rep, ce.end.0));
        let (kept, removed) = (a.min(b), a.max(b));
        rep[removed as usize] = kept;
        out.push(Collapsed {
            curve: CurveId(i as u32),
            length,
            kept: CornerId(kept),
            removed: CornerId(removed),
        });
    }
    if out.is_empty() {
        return None;
    }
    let mut copy = model.clone();
    for (i, ce) in copy.curves.iter_mut().enumerate() {
        ce.start = CornerId(find(&mut rep, ce.start.0));
        ce.end = CornerId(find(&mut rep, ce.end.0));
        if sliver[i] {
            ce.degenerate = true;
            ce.geom = None;
            ce.end = ce.start;
        }
    }
    for c in &mut out {
        c.kept = CornerId(find(&mut rep, c.kept.0));
    }
    for f in &mut copy.faces {
        for l in &mut f.loops {
            l.uses.retain(|u| !sliver[u.curve.idx()]);
        }
    }
    Some((copy, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planar polygon through the (x, y) of `p`.
    fn polygon(p: &[[f64; 3]]) -> Model {
        let xy: Vec<[f64; 2]> = p.iter().map(|q| [q[0], q[1]]).collect();
        crate::primitives::polygon(&xy)
    }

    #[test]
    fn a_sliver_side_becomes_one_corner_and_leaves_the_loop() {
        // a unit square whose corner (1, 1) is cut by a side 1e-7 long
        let e = 1e-7;
        let m = polygon(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0 - e, 0.0],
            [1.0 - e, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        let (copy, list) = collapse_short_curves(&m, 1e-5).expect("one sliver");
        assert_eq!(list.len(), 1);
        let c = list[0];
        assert_eq!(c.curve, CurveId(2));
        assert!((c.length - e * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!((c.kept, c.removed), (CornerId(2), CornerId(3)));
        // ids unchanged; the sliver is a degenerate point at the kept corner
        assert_eq!(copy.curves.len(), 5);
        assert_eq!(copy.corners.len(), 5);
        let s = &copy.curves[2];
        assert!(s.degenerate && s.geom.is_none());
        assert_eq!((s.start, s.end), (CornerId(2), CornerId(2)));
        // the next side now starts at the kept corner; nothing uses corner 3
        assert_eq!(copy.curves[3].start, CornerId(2));
        assert!(copy
            .curves
            .iter()
            .all(|c| c.start != CornerId(3) && c.end != CornerId(3)));
        let loop_curves: Vec<u32> = copy.faces[0].loops[0]
            .uses
            .iter()
            .map(|u| u.curve.0)
            .collect();
        assert_eq!(loop_curves, [0, 1, 3, 4]);
        assert!(copy.validate().is_ok());
        // the original is untouched, and a smaller tolerance keeps the side
        assert!(!m.curves[2].degenerate);
        assert!(collapse_short_curves(&m, 1e-8).is_none());
    }

    #[test]
    fn two_slivers_in_a_row_merge_three_corners_into_the_smallest() {
        let e = 1e-7;
        let m = polygon(&[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, e, 0.0],
            [1.0, 2.0 * e, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        let (copy, list) = collapse_short_curves(&m, 1e-5).expect("two slivers");
        assert_eq!(list.len(), 2);
        assert!(list.iter().all(|c| c.kept == CornerId(1)));
        assert_eq!(copy.curves[3].start, CornerId(1));
        assert_eq!(copy.faces[0].loops[0].uses.len(), 3);
    }

    #[test]
    fn a_loop_made_only_of_slivers_keeps_a_curve() {
        let e = 1e-7;
        let m = polygon(&[[0.0, 0.0, 0.0], [e, 0.0, 0.0], [0.0, e, 0.0]]);
        let (copy, list) = collapse_short_curves(&m, 1e-5).expect("some slivers");
        assert!(list.len() < 3);
        assert!(!copy.faces[0].loops[0].uses.is_empty());
    }
}
