//! Why meshing a model failed: the errors every method returns.

use geometry::{FaceId, ModelError};

/// Why meshing failed.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The requested size is not a positive finite number.
    #[error("invalid mesh size {0}: it must be a positive finite number")]
    InvalidSize(f64),
    /// The model has no face to mesh.
    #[error("the model has no faces to mesh")]
    NoFaces,
    /// The model refers to missing entities.
    #[error("invalid model: {0}")]
    Model(#[from] ModelError),
    /// One face could not be meshed (face numbers are 1-based, as in files).
    #[error("face {} could not be meshed: {reason}", face.0 + 1)]
    Face {
        /// The face.
        face: FaceId,
        /// What went wrong.
        reason: String,
    },
    /// The size-map options are invalid (bad gradient, bounds or entity sizes).
    #[error("size map: {0}")]
    Sizing(String),
    /// The coarse method cannot run on this input (a triangle, a non-manifold
    /// edge, an option out of range), naming the entity or option.
    #[error("coarse method: {0}")]
    Coarse(String),
    /// Topological regularization failed (the regular method).
    #[error("regularization: {0}")]
    Regularize(String),
    /// The size guard refused the run: the estimated quad count is above
    /// [`crate::MeshOptions::max_quads`] (nothing was meshed).
    #[error("{0}")]
    TooManyQuads(TooManyQuads),
    /// The thread pool could not be created.
    #[error("could not start a pool of {threads} threads: {reason}")]
    Threads {
        /// Requested thread count.
        threads: usize,
        /// The pool builder's message.
        reason: String,
    },
}

/// What the size guard found when it refused a run: the estimate, the
/// memory it would take, the limit and a size that would fit under it.
#[derive(Clone, Debug, PartialEq)]
pub struct TooManyQuads {
    /// Estimated quad count at the requested size.
    pub estimate: u64,
    /// The limit ([`crate::MeshOptions::max_quads`]).
    pub limit: u64,
    /// The requested target size (model units).
    pub size: f64,
    /// Estimated peak memory of the run, in bytes.
    pub memory: f64,
    /// A target size whose estimate is within the limit (model units) and
    /// the same as a multiple of the default size; `None` when no size
    /// tried brought the estimate under it (curvature and small features
    /// keep a floor of quads).
    pub fit: Option<(f64, f64)>,
}

impl TooManyQuads {
    /// The refusal as one line, naming the options as a front end spells
    /// them (`--size`, `--size-factor`, `--max-quads` for the command line).
    pub fn message(&self, size: &str, size_factor: &str, max_quads: &str) -> String {
        let fit = match self.fit {
            Some((h, f)) => format!(
                "{size} {} ({size_factor} {}) would fit",
                short(round_up(h)),
                short(round_up(f))
            ),
            None => "no larger size brings it under".to_string(),
        };
        format!(
            "about {} quads estimated at size {}, about {} of memory: above the limit of {} quads; \
             {fit}, {max_quads} 0 lifts the limit",
            count(self.estimate),
            short(self.size),
            bytes(self.memory),
            self.limit,
        )
    }
}

impl std::fmt::Display for TooManyQuads {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message("size", "size factor", "max_quads"))
    }
}

/// `x` rounded up to two significant digits (a size that still fits).
pub fn round_up(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let unit = 10f64.powi(x.log10().floor() as i32 - 1);
    let r = (x / unit).ceil() * unit;
    // the product may land a hair below `x`
    if r < x {
        r + unit
    } else {
        r
    }
}

/// A number as short as it reads: plain between 0.001 and 10⁶, else in
/// exponent form (`1e-5`, `2.5e7`).
fn short(x: f64) -> String {
    if (1e-3..1e6).contains(&x.abs()) {
        let decimals = (3 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{x:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        s
    } else {
        format!("{x:e}")
    }
}

/// A quad count: exact below a million, else with three significant digits.
fn count(n: u64) -> String {
    if n < 1_000_000 {
        n.to_string()
    } else {
        format!("{:.2e}", n as f64)
    }
}

/// A byte count in kB, MB, GB, TB or PB (powers of 1000).
fn bytes(b: f64) -> String {
    let units = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < units.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{v:.0} B")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

/// Why a method could not mesh one face, so that the face fell back to the
/// baseline ([`crate::MeshReport::fallback`]). The text of each variant is
/// what `quadrille mesh` prints.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FaceError {
    /// The face id is not in the model (1-based).
    #[error("no face {0}")]
    NoSuchFace(u32),
    /// The face's cross field, size map or background failed.
    #[error("{0}")]
    Field(String),
    /// The boundary polygon could not be triangulated in (u, v).
    #[error("boundary: {0}")]
    Boundary(String),
    /// The triangulation could not be refined to the size.
    #[error("refinement: {0}")]
    Refinement(String),
    /// The triangulation holds no triangle.
    #[error("the triangulation is empty")]
    EmptyTriangulation,
    /// Edges of these curves (1-based) are missing from the triangulation.
    #[error("boundary edges of curves {0:?} left out of the triangulation")]
    MissingBoundaryEdges(Vec<u32>),
    /// No way of stepping the front was given.
    #[error("no front spacing to try")]
    NoFrontSpacing,
    /// Quads stayed inverted after smoothing and untangling (their count).
    #[error("{0} quads stay inverted")]
    InvertedQuads(usize),
    /// The face's mesh had quads that the mesh statistics find inverted
    /// once assembled with its neighbours.
    #[error("inverted quads in the assembled mesh")]
    InvertedInAssembly,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_errors_read_as_the_cli_prints_them() {
        assert_eq!(FaceError::NoSuchFace(3).to_string(), "no face 3");
        assert_eq!(
            FaceError::MissingBoundaryEdges(vec![2, 7]).to_string(),
            "boundary edges of curves [2, 7] left out of the triangulation"
        );
        assert_eq!(
            FaceError::InvertedQuads(4).to_string(),
            "4 quads stay inverted"
        );
        assert_eq!(
            FaceError::Refinement("Fatal(\"x\")".into()).to_string(),
            "refinement: Fatal(\"x\")"
        );
        assert_eq!(
            FaceError::InvertedInAssembly.to_string(),
            "inverted quads in the assembled mesh"
        );
    }

    #[test]
    fn the_refusal_is_one_line_with_a_size_that_fits() {
        let e = MeshError::TooManyQuads(TooManyQuads {
            estimate: 2_345_678_901,
            limit: 50_000_000,
            size: 1e-5,
            memory: 3.4e12,
            fit: Some((0.012_31, 0.517)),
        });
        let text = e.to_string();
        assert!(!text.contains('\n'), "{text}");
        assert!(text.contains("2.35e9 quads"), "{text}");
        assert!(text.contains("size 1e-5"), "{text}");
        assert!(text.contains("3.4 TB"), "{text}");
        assert!(text.contains("50000000"), "{text}");
        // rounded up: still within the limit
        assert!(text.contains("size 0.013 (size factor 0.52)"), "{text}");
        assert!(text.contains("max_quads 0"), "{text}");
        let MeshError::TooManyQuads(mut t) = e else {
            unreachable!()
        };
        let cli = t.message("--size", "--size-factor", "--max-quads");
        assert!(cli.contains("--size 0.013 (--size-factor 0.52)"), "{cli}");
        assert!(cli.contains("--max-quads 0 lifts"), "{cli}");
        t.fit = None;
        assert!(t.to_string().contains("no larger size"), "{t}");
    }

    #[test]
    fn rounding_up_never_goes_below() {
        for x in [0.012_31, 1.0, 0.1, 7.77e-9, 123.4, 99.99, 0.3] {
            let r = round_up(x);
            assert!(r >= x && r < x * 1.11, "{x} -> {r}");
        }
        assert_eq!(short(round_up(0.012_31)), "0.013");
        assert_eq!(short(round_up(123.4)), "130");
        assert_eq!(bytes(512.0), "512 B");
        assert_eq!(bytes(18.7e9), "18.7 GB");
        assert_eq!(count(999_999), "999999");
    }

    #[test]
    fn mesh_errors_name_the_face_one_based() {
        let e = MeshError::Face {
            face: FaceId(4),
            reason: "x".into(),
        };
        assert_eq!(e.to_string(), "face 5 could not be meshed: x");
        assert_eq!(
            MeshError::Regularize("y".into()).to_string(),
            "regularization: y"
        );
    }
}
