//! Raw bindings to the C++ shim (`src/shim.cpp`) and owning wrappers that
//! free the OCCT objects on drop. Nothing here is public outside the crate.

use std::os::raw::{c_char, c_double, c_int, c_long};

/// Success.
pub const OK: c_int = 0;
/// The reader could not open or parse the file.
pub const ERR_OPEN: c_int = 1;
/// The file parsed but no shape could be built from it.
pub const ERR_TRANSFER: c_int = 2;
/// OCCT threw an exception (message in the error buffer when one was given).
pub const ERR_EXCEPTION: c_int = 3;

#[repr(C)]
pub struct OcctModel {
    _p: [u8; 0],
}
#[repr(C)]
pub struct OcctSurf {
    _p: [u8; 0],
}
#[repr(C)]
pub struct OcctCurve {
    _p: [u8; 0],
}
#[repr(C)]
pub struct OcctCurve2d {
    _p: [u8; 0],
}

/// Mirror of `OcctEdgeInfo` in shim.cpp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct EdgeInfo {
    pub first: c_double,
    pub last: c_double,
    pub tolerance: c_double,
    pub v_start: c_long,
    pub v_end: c_long,
    pub degenerate: c_int,
    pub same_parameter: c_int,
}

/// Mirror of `OcctUse` in shim.cpp.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct UseInfo {
    pub wire: c_long,
    pub edge: c_long,
    pub orientation: c_int,
    pub seam: c_int,
    pub first: c_double,
    pub last: c_double,
    pub pcurve: *mut OcctCurve2d,
}

impl Default for UseInfo {
    fn default() -> Self {
        UseInfo {
            wire: 0,
            edge: 0,
            orientation: 0,
            seam: 0,
            first: 0.0,
            last: 0.0,
            pcurve: std::ptr::null_mut(),
        }
    }
}

/// Mirror of `OcctBSplinePatch` in shim.cpp (pointers borrowed for the call).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct BSplinePatchRaw {
    pub degree_u: c_int,
    pub degree_v: c_int,
    pub n_u: usize,
    pub n_v: usize,
    pub knots_u: *const c_double,
    pub mults_u: *const c_int,
    pub nk_u: usize,
    pub knots_v: *const c_double,
    pub mults_v: *const c_int,
    pub nk_v: usize,
    pub poles: *const c_double,
}

/// Mirror of `OcctSewReport` in shim.cpp.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SewReport {
    pub faces: usize,
    pub shells: usize,
    pub free_edges: usize,
    pub shared_edges: usize,
    pub multiple_edges: usize,
}

/// `TopAbs_FORWARD`.
pub const TOPABS_FORWARD: c_int = 0;

/// The IGES half of the shim (`src/shim_iges.cpp`, the only code naming
/// OCCT's IGES toolkits) as a shared object, linked by `build.rs`; the shim
/// loads it on the first IGES read or write (see [`hand_over_iges`]).
static IGES_IMAGE: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/libquadrille_occt_iges.so"));

/// Hands the IGES half's image to the shim (once per process; before any
/// `occt_load` or `occt_write`), so that it can load it when a file is IGES.
pub fn hand_over_iges() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    // SAFETY: a 'static byte slice, valid for the life of the process.
    ONCE.call_once(|| unsafe { occt_iges_image(IGES_IMAGE.as_ptr(), IGES_IMAGE.len()) });
}

extern "C" {
    /// Hands over the IGES half's image (bytes living as long as the process).
    fn occt_iges_image(image: *const u8, len: usize);
    pub fn occt_load(
        path: *const c_char,
        kind: c_int,
        out: *mut *mut OcctModel,
        err: *mut c_char,
        errlen: usize,
    ) -> c_int;
    pub fn occt_model_free(m: *mut OcctModel);
    /// Turns faults inside OCCT into errors on this thread until the
    /// matching `occt_signals_end` (the process's signal handlers meanwhile
    /// OCCT's; one such scope at a time in the process).
    pub fn occt_signals_begin() -> *mut std::ffi::c_void;
    pub fn occt_signals_end(scope: *mut std::ffi::c_void);
    /// Faults inside OCCT caught in this process so far (each one leaves
    /// OCCT's frames by a jump that skips their destructors and unlocks).
    pub fn occt_faults_caught() -> std::ffi::c_ulong;
    pub fn occt_write(
        m: *const OcctModel,
        path: *const c_char,
        kind: c_int,
        err: *mut c_char,
        errlen: usize,
    ) -> c_int;
    pub fn occt_write_bspline_step(
        patches: *const BSplinePatchRaw,
        n: usize,
        sew_tol: c_double,
        path: *const c_char,
        report: *mut SewReport,
        err: *mut c_char,
        errlen: usize,
    ) -> c_int;
    pub fn occt_model_counts(m: *const OcctModel, nf: *mut usize, ne: *mut usize, nv: *mut usize);
    pub fn occt_vertex(
        m: *const OcctModel,
        i: usize,
        xyz: *mut c_double,
        tol: *mut c_double,
    ) -> c_int;
    pub fn occt_edge(
        m: *const OcctModel,
        i: usize,
        info: *mut EdgeInfo,
        curve: *mut *mut OcctCurve,
    ) -> c_int;
    pub fn occt_face(
        m: *const OcctModel,
        i: usize,
        reversed: *mut c_int,
        bounds: *mut c_double,
        surf: *mut *mut OcctSurf,
    ) -> c_int;
    pub fn occt_face_uses(
        m: *const OcctModel,
        i: usize,
        buf: *mut UseInfo,
        cap: usize,
        n: *mut usize,
    ) -> c_int;

    pub fn occt_surf_free(s: *mut OcctSurf);
    pub fn occt_surf_periods(s: *const OcctSurf, pu: *mut c_double, pv: *mut c_double) -> c_int;
    pub fn occt_surf_bounds(s: *const OcctSurf, b: *mut c_double) -> c_int;
    pub fn occt_surf_d0(s: *const OcctSurf, u: c_double, v: c_double, out: *mut c_double) -> c_int;
    pub fn occt_surf_d1(s: *const OcctSurf, u: c_double, v: c_double, out: *mut c_double) -> c_int;
    pub fn occt_surf_d2(s: *const OcctSurf, u: c_double, v: c_double, out: *mut c_double) -> c_int;
    pub fn occt_surf_project(
        s: *const OcctSurf,
        p: *const c_double,
        umin: c_double,
        umax: c_double,
        vmin: c_double,
        vmax: c_double,
        uv: *mut c_double,
        q: *mut c_double,
    ) -> c_int;

    pub fn occt_curve_free(c: *mut OcctCurve);
    pub fn occt_curve_d1(c: *const OcctCurve, t: c_double, out: *mut c_double) -> c_int;
    pub fn occt_curve_d2(c: *const OcctCurve, t: c_double, out: *mut c_double) -> c_int;
    pub fn occt_curve_project(
        c: *const OcctCurve,
        p: *const c_double,
        t0: c_double,
        t1: c_double,
        t: *mut c_double,
        q: *mut c_double,
    ) -> c_int;

    pub fn occt_curve2d_free(c: *mut OcctCurve2d);
    pub fn occt_curve2d_d1(c: *const OcctCurve2d, t: c_double, out: *mut c_double) -> c_int;
}

/// Generates an owning, thread-shareable wrapper around a shim pointer.
macro_rules! owner {
    ($(#[$m:meta])* $name:ident, $raw:ty, $free:ident) => {
        $(#[$m])*
        #[derive(Debug)]
        pub struct $name(*mut $raw);
        impl $name {
            /// Takes ownership of `p`; `None` when null.
            pub fn new(p: *mut $raw) -> Option<Self> {
                if p.is_null() { None } else { Some($name(p)) }
            }
            /// The raw pointer, valid while `self` lives.
            pub fn ptr(&self) -> *const $raw {
                self.0
            }
        }
        impl Drop for $name {
            fn drop(&mut self) {
                // SAFETY: the pointer came from the shim, is owned by us, and is freed once.
                unsafe { $free(self.0) }
            }
        }
        // SAFETY: the shim only ever reads through these pointers after
        // construction (const Geom evaluation, which keeps no caches in OCCT
        // 7.6; projectors are built per call), and OCCT's handle reference
        // counts are atomic, so sharing across threads is sound.
        unsafe impl Send for $name {}
        unsafe impl Sync for $name {}
    };
}

owner!(
    /// An OCCT shape read from a file, with its face/edge/vertex maps.
    ModelPtr, OcctModel, occt_model_free
);
owner!(
    /// A `Handle(Geom_Surface)`.
    SurfPtr, OcctSurf, occt_surf_free
);
owner!(
    /// A `Handle(Geom_Curve)`.
    CurvePtr, OcctCurve, occt_curve_free
);
owner!(
    /// A `Handle(Geom2d_Curve)`.
    Curve2dPtr, OcctCurve2d, occt_curve2d_free
);
