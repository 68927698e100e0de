//! Turns an OCCT shape (read by the shim) into a [`geometry::Model`].
//!
//! Ids are `MapShapes` indices − 1. A curve's `start`/`end` are the vertices
//! of the FORWARD edge. Face loops come from the face taken FORWARD (so the
//! material is to the left in (u, v)), outer wire first, each ordered by
//! `BRepTools_WireExplorer`; a use is `forward` when the edge is FORWARD in
//! that face, and its pcurve is the one OCCT selects for that orientation
//! (which picks the right side of a seam).

use std::path::Path;
use std::sync::Arc;

use geometry::{
    Bounds2, Corner, CornerId, Curve, CurveEntity, CurveId, CurveUse, Face, Loop, Model,
};

use crate::ffi::{self, Curve2dPtr, CurvePtr, EdgeInfo, ModelPtr, SurfPtr, UseInfo};
use crate::geom::{OcctCurve, OcctCurve2d, OcctSurface, PcurveOnSurface};
use crate::ImportError;

/// A loaded model with OCCT's tolerances, indexed like the model's entities.
#[derive(Debug)]
pub struct Import {
    /// The B-rep.
    pub model: Model,
    /// `BRep_Tool::Tolerance` of each vertex (same index as `model.corners`).
    pub corner_tolerance: Vec<f64>,
    /// `BRep_Tool::Tolerance` of each edge (same index as `model.curves`): the
    /// distance within which its 3D curve and pcurves agree.
    pub curve_tolerance: Vec<f64>,
    /// `BRep_Tool::SameParameter` of each edge: false when OCCT does not
    /// guarantee that pcurves share the 3D curve's parameter.
    pub curve_same_parameter: Vec<bool>,
}

/// (faces, edges, vertices) of the shape.
pub(crate) fn counts(m: &ModelPtr) -> (usize, usize, usize) {
    let (mut nf, mut ne, mut nv) = (0, 0, 0);
    // SAFETY: live model; valid out-pointers.
    unsafe { ffi::occt_model_counts(m.ptr(), &mut nf, &mut ne, &mut nv) };
    (nf, ne, nv)
}

/// The corners and curves of a shape (3D geometry only; a curve with no 3D
/// curve has `geom: None` until a face's pcurve fills it) with OCCT's
/// tolerances: what [`build`] and `wires::build` share.
pub(crate) struct CurveSet {
    pub(crate) corners: Vec<Corner>,
    pub(crate) curves: Vec<CurveEntity>,
    pub(crate) corner_tolerance: Vec<f64>,
    pub(crate) curve_tolerance: Vec<f64>,
    pub(crate) curve_same_parameter: Vec<bool>,
}

/// Reads every vertex and edge of a loaded shape.
pub(crate) fn build_curves(m: &ModelPtr, path: &Path) -> Result<CurveSet, ImportError> {
    let invalid = |detail: String| ImportError::Invalid {
        path: path.to_path_buf(),
        detail,
    };
    let (_, ne, nv) = counts(m);
    // Corners.
    let mut corners = Vec::with_capacity(nv);
    let mut corner_tolerance = Vec::with_capacity(nv);
    for i in 0..nv {
        let mut p = [0.0; 3];
        let mut tol = 0.0;
        // SAFETY: live model, i < nv, valid buffers.
        if unsafe { ffi::occt_vertex(m.ptr(), i, p.as_mut_ptr(), &mut tol) } != ffi::OK {
            return Err(invalid(format!("vertex {} cannot be evaluated", i + 1)));
        }
        corners.push(Corner { point: p });
        corner_tolerance.push(tol);
    }

    // Curves (3D geometry may still be missing; filled from a pcurve below).
    let mut curves = Vec::with_capacity(ne);
    let mut curve_tolerance = Vec::with_capacity(ne);
    let mut curve_same_parameter = Vec::with_capacity(ne);
    for i in 0..ne {
        let mut info = EdgeInfo::default();
        let mut raw: *mut ffi::OcctCurve = std::ptr::null_mut();
        // SAFETY: live model, i < ne, valid out-pointers.
        let rc = unsafe { ffi::occt_edge(m.ptr(), i, &mut info, &mut raw) };
        let cptr = CurvePtr::new(raw);
        if rc != ffi::OK {
            return Err(invalid(format!("edge {} cannot be evaluated", i + 1)));
        }
        let vid =
            |v: std::os::raw::c_long| (v >= 0 && (v as usize) < nv).then_some(CornerId(v as u32));
        let (Some(start), Some(end)) = (vid(info.v_start), vid(info.v_end)) else {
            return Err(invalid(format!(
                "edge {} lacks a start or end vertex",
                i + 1
            )));
        };
        if !info.first.is_finite() || !info.last.is_finite() || info.first >= info.last {
            return Err(invalid(format!(
                "edge {} has an empty or infinite range [{}, {}]",
                i + 1,
                info.first,
                info.last
            )));
        }
        let range = (info.first, info.last);
        let degenerate = info.degenerate != 0;
        let geom: Option<Arc<dyn Curve>> = match (degenerate, cptr) {
            (false, Some(c)) => Some(Arc::new(OcctCurve::new(c, range))),
            _ => None,
        };
        curves.push(CurveEntity {
            geom,
            range,
            start,
            end,
            degenerate,
        });
        curve_tolerance.push(info.tolerance);
        curve_same_parameter.push(info.same_parameter != 0);
    }

    Ok(CurveSet {
        corners,
        curves,
        corner_tolerance,
        curve_tolerance,
        curve_same_parameter,
    })
}

/// Builds the model from a loaded shape.
pub(crate) fn build(m: &ModelPtr, path: &Path) -> Result<Import, ImportError> {
    let invalid = |detail: String| ImportError::Invalid {
        path: path.to_path_buf(),
        detail,
    };
    let (nf, ne, nv) = counts(m);
    if nf == 0 {
        return Err(ImportError::NoFace {
            path: path.to_path_buf(),
            detail: format!("the shape has {ne} edges and {nv} vertices but no face"),
        });
    }

    let CurveSet {
        corners,
        mut curves,
        corner_tolerance,
        curve_tolerance,
        curve_same_parameter,
    } = build_curves(m, path)?;

    // Faces.
    let mut faces = Vec::with_capacity(nf);
    for i in 0..nf {
        faces.push(build_face(m, i, &mut curves).map_err(invalid)?);
    }
    if let Some(i) = curves
        .iter()
        .position(|c| c.geom.is_none() && !c.degenerate)
    {
        return Err(invalid(format!(
            "edge {} has neither a 3D curve nor a pcurve",
            i + 1
        )));
    }
    Ok(Import {
        model: Model {
            corners,
            curves,
            faces,
        },
        corner_tolerance,
        curve_tolerance,
        curve_same_parameter,
    })
}

/// Builds face `i` (0-based); gives edges without a 3D curve one from this face.
fn build_face(m: &ModelPtr, i: usize, curves: &mut [CurveEntity]) -> Result<Face, String> {
    let mut reversed = 0;
    let mut b = [0.0; 4];
    let mut raw: *mut ffi::OcctSurf = std::ptr::null_mut();
    // SAFETY: live model, i < nf, valid out-pointers.
    let rc = unsafe { ffi::occt_face(m.ptr(), i, &mut reversed, b.as_mut_ptr(), &mut raw) };
    let sptr = SurfPtr::new(raw);
    let sptr = match (rc, sptr) {
        (ffi::OK, Some(s)) => s,
        _ => return Err(format!("face {} has no surface", i + 1)),
    };
    if !b.iter().all(|x| x.is_finite()) || b[0] > b[1] || b[2] > b[3] {
        return Err(format!("face {} has invalid uv bounds {:?}", i + 1, b));
    }
    let uv_bounds = Bounds2 {
        umin: b[0],
        umax: b[1],
        vmin: b[2],
        vmax: b[3],
    };
    let surface = Arc::new(OcctSurface::new(sptr, uv_bounds));

    let mut n = 0usize;
    // SAFETY: count mode (cap 0, null buffer is never written).
    if unsafe { ffi::occt_face_uses(m.ptr(), i, std::ptr::null_mut(), 0, &mut n) } != ffi::OK {
        return Err(format!("the wires of face {} cannot be explored", i + 1));
    }
    let mut buf = vec![UseInfo::default(); n];
    let mut got = 0usize;
    if n > 0 {
        // SAFETY: buf holds n entries.
        let rc = unsafe { ffi::occt_face_uses(m.ptr(), i, buf.as_mut_ptr(), n, &mut got) };
        if rc != ffi::OK {
            return Err(format!("the wires of face {} cannot be explored", i + 1));
        }
    }
    // Take ownership of every pcurve at once, so each is freed on any path.
    let pcurves: Vec<Option<Curve2dPtr>> = buf[..got]
        .iter()
        .map(|u| Curve2dPtr::new(u.pcurve))
        .collect();

    let mut loops: Vec<Loop> = Vec::new();
    let mut wire_of_loop: Vec<i64> = Vec::new();
    for (u, pc) in buf[..got].iter().zip(pcurves) {
        let e = u.edge;
        if e < 0 || e as usize >= curves.len() {
            return Err(format!(
                "face {} uses an edge missing from the edge map",
                i + 1
            ));
        }
        let e = e as usize;
        let Some(pc) = pc else {
            return Err(format!("edge {} has no pcurve on face {}", e + 1, i + 1));
        };
        let pcurve = Arc::new(OcctCurve2d::new(pc, (u.first, u.last), curves[e].range));
        let c = &mut curves[e];
        if c.geom.is_none() && !c.degenerate {
            c.geom = Some(Arc::new(PcurveOnSurface {
                surface: surface.clone(),
                pcurve: pcurve.clone(),
                range: c.range,
            }));
        }
        let cu = CurveUse {
            curve: CurveId(e as u32),
            forward: u.orientation == ffi::TOPABS_FORWARD,
            pcurve,
            seam: u.seam != 0,
        };
        if wire_of_loop.last() != Some(&{ u.wire }) {
            wire_of_loop.push(u.wire);
            loops.push(Loop {
                uses: Vec::new(),
                outer: u.wire == 0,
            });
        }
        if let Some(l) = loops.last_mut() {
            l.uses.push(cu);
        }
    }
    Ok(Face {
        surface,
        reversed: reversed != 0,
        loops,
        uv_bounds,
    })
}
