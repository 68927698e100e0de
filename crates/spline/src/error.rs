//! The crate's error: one variant per stage, each message one line naming the
//! place and the numbers.

/// Everything that can go wrong building, refining, checking or writing splines.
#[derive(Debug, thiserror::Error)]
pub enum SplineError {
    /// A knot vector that is not clamped, not non-decreasing, or too short.
    #[error("knot vector: {0}")]
    Knots(String),
    /// A curve or patch whose control points do not match its knot vectors.
    #[error("spline shape: {0}")]
    Shape(String),
    /// Curve least squares: bad samples or a singular system.
    #[error("curve fit: {0}")]
    Fit(String),
    /// Coons patch: incompatible boundary curves.
    #[error("coons patch: {0}")]
    Coons(String),
    /// Knot insertion or refinement with a bad knot or factor.
    #[error("refine: {0}")]
    Refine(String),
    /// A multipatch whose sides, arcs or indices do not fit together.
    #[error("multipatch: {0}")]
    Multipatch(String),
    /// A JSON multipatch file that cannot be read.
    #[error("json: {0}")]
    Json(String),
    /// Writing or reading a file failed.
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
}

/// The crate's result.
pub type Result<T> = std::result::Result<T, SplineError>;
