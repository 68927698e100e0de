//! The options every method takes: target size, threads, progress, the
//! size guard's limit, and the topology stages of the quasi-structured method.

use crate::core::options::{ProgressFn, Size};

/// Options of [`crate::mesh_model`] and [`crate::mesh_model_with`], for every method.
#[derive(Clone)]
pub struct MeshOptions {
    /// Target size (final quad edge length).
    pub size: Size,
    /// Worker threads; `None` uses rayon's global pool. The output does not depend on it.
    pub threads: Option<usize>,
    /// Called as faces are finished.
    pub progress: Option<ProgressFn>,
    /// Called as faces are regularized ([`crate::MeshMethod::Regular`], after
    /// the baseline mesh of every face, which reports to `progress`).
    pub regularize_progress: Option<ProgressFn>,
    /// Quads per full turn of the surface normal on curved faces (a 90°
    /// fillet gets a quarter of them across), within the size map's bounds
    /// of half to twice the target size; 0 turns the bound off. Used by the
    /// quasi-structured and unstructured methods.
    pub quads_per_turn: f64,
    /// The size guard: the most quads the run may be estimated to make
    /// before anything is meshed, else [`crate::MeshError::TooManyQuads`];
    /// 0 lifts the limit ([`crate::DEFAULT_MAX_QUADS`] by default).
    pub max_quads: u64,
    /// Annuli between two smooth loops meshed as ring grids
    /// ([`crate::direct::ring_face`]) by the quasi-structured method. The
    /// coarse method turns it off for its input: on i03o_m3 its layout
    /// placement (§5.3) finds no free input path for a layout edge of a ring
    /// grid in three rounds, and falls back to one block per quad.
    pub ring_grids: bool,
}

/// Default of [`MeshOptions::quads_per_turn`]: five quads across a 90°
/// fillet (18° of turn per quad). Without it a fillet narrower than the
/// target size was one quad wide (s12o_cube_rounded_1: 600 quads, its 12
/// fillets one quad across, average SICN 0.956). 16 (four across) left
/// s13o_cube_rounded_2 at 864 quads and average SICN 0.984 against Gmsh
/// quadqs's 0.986 at 1536: a quad bent over 22.5° has SICN at most
/// cos 11.25° = 0.981. With 20 it has Gmsh's 1536 quads and 0.987; over
/// the 26 shared models the quad count goes from 0.95 to 1.03 of Gmsh's
/// and the irregular-share ratio from 0.620 to 0.587 (BENCHMARKS.md,
/// "Five quads per 90° of turn").
pub const DEFAULT_QUADS_PER_TURN: f64 = 20.0;

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            size: Size::default(),
            threads: None,
            progress: None,
            regularize_progress: None,
            quads_per_turn: DEFAULT_QUADS_PER_TURN,
            max_quads: crate::methods::guard::DEFAULT_MAX_QUADS,
            ring_grids: true,
        }
    }
}

impl std::fmt::Debug for MeshOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshOptions")
            .field("size", &self.size)
            .field("threads", &self.threads)
            .field("progress", &self.progress.as_ref().map(|_| "callback"))
            .field(
                "regularize_progress",
                &self.regularize_progress.as_ref().map(|_| "callback"),
            )
            .field("quads_per_turn", &self.quads_per_turn)
            .field("max_quads", &self.max_quads)
            .field("ring_grids", &self.ring_grids)
            .finish()
    }
}

/// Which topology stages (paper §6) [`crate::MeshMethod::QuasiStructured`]
/// runs after the §5 mesh of each face; all of them by default
/// ([`Stages::ALL`]). With none ([`Stages::NONE`]) it is the plain
/// unstructured method, [`crate::MeshMethod::Unstructured`].
///
/// ```
/// use quadrille::Stages;
/// let no_cavities = Stages { cavities: false, ..Stages::ALL };
/// assert!(no_cavities.patterns && no_cavities.defects && !no_cavities.cavities);
/// assert_eq!(Stages::default(), Stages::ALL);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stages {
    /// Simple faces meshed directly by a pattern ([`crate::direct::pattern_face`], §6.1.2).
    pub patterns: bool,
    /// Very irregular vertices replaced by disk quadrangulations ([`crate::topology::defects`], §6.3).
    pub defects: bool,
    /// Cavity remeshing ([`crate::topology::cavity`], §6.2).
    pub cavities: bool,
    /// The regular method's operations on what the cavities left
    /// ([`crate::topology::regular_pass`]), faces not meshed by a pattern.
    pub regular_pass: bool,
}

impl Stages {
    /// The names of the stages switched off, in the order of the fields
    /// (`patterns`, `defects`, `cavities`, `regular_pass`): what a front end
    /// names when it refuses them for a method without topology stages.
    ///
    /// ```
    /// use quadrille::Stages;
    /// let s = Stages { defects: false, regular_pass: false, ..Stages::ALL };
    /// assert_eq!(s.switched_off(), ["defects", "regular_pass"]);
    /// assert!(Stages::ALL.switched_off().is_empty());
    /// ```
    pub fn switched_off(&self) -> Vec<&'static str> {
        [
            (self.patterns, "patterns"),
            (self.defects, "defects"),
            (self.cavities, "cavities"),
            (self.regular_pass, "regular_pass"),
        ]
        .into_iter()
        .filter(|(on, _)| !on)
        .map(|(_, name)| name)
        .collect()
    }

    /// Every stage: the quasi-structured method.
    pub const ALL: Stages = Stages {
        patterns: true,
        defects: true,
        cavities: true,
        regular_pass: true,
    };
    /// No stage: the unstructured mesh of §5 alone.
    pub const NONE: Stages = Stages {
        patterns: false,
        defects: false,
        cavities: false,
        regular_pass: false,
    };
}

impl Default for Stages {
    fn default() -> Self {
        Stages::ALL
    }
}
