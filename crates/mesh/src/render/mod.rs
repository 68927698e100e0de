//! Pictures of a [`QuadMesh`]: a shaded, orthographic 3/4 view with element
//! edges, CAD feature curves, irregular vertices as coloured dots and,
//! optionally, a per-quad scalar (SICN) on a red → yellow → green colour map.
//!
//! Visibility comes from a small z-buffer rasterizer of our own
//! (the private `raster` module), supersampled for antialiasing; dots and legends are drawn
//! with `tiny-skia`, which also encodes the PNG. Text uses a built-in 5×7
//! bitmap font, so there is no font dependency.
//!
//! An optional [`Overlay`] adds 3D line segments (e.g. cross-field glyphs) and
//! coloured dots (e.g. singularities) with their own legend, hidden where the
//! surface covers them.
//!
//! Colours: front faces are light steel blue, back faces (seen from behind
//! their oriented normal) a darker brown so an open or inverted surface shows
//! at once. Irregular vertices (face-interior nodes whose quad valence ≠ 4 and
//! that touch no triangle): valence 3 blue, 5 red, 6+ magenta, others orange.
//!
//! Stages, one private module each: `camera` (view axes, light, fit,
//! projection), `scene` (checks, irregular vertices, layout; rasterizing the
//! mesh and its dots), `legend` (title, info line, colour bar, dot legends),
//! `overlay` ([`Overlay`] marks), `raster` (the z-buffer) and `font`.

mod camera;
mod font;
mod legend;
mod overlay;
mod raster;
mod scene;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use geometry::vec3::Vec3;
use tiny_skia::{IntSize, Pixmap};

use crate::atomic::write_atomically;
use crate::quadmesh::QuadMesh;
pub use overlay::{Overlay, OverlayPoint, OverlaySegment, MIN_FACING};
use scene::Scene;

/// Why a picture could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The mesh has no quads and no triangles.
    #[error("cannot render an empty mesh (no quads or triangles)")]
    EmptyMesh,
    /// The mesh is inconsistent (indices out of range, non-finite coordinates, …).
    #[error("cannot render an invalid mesh: {0}")]
    InvalidMesh(String),
    /// The options cannot be honoured (zero size, values of the wrong length, …).
    #[error("invalid render options: {0}")]
    InvalidOptions(String),
    /// PNG encoding failed.
    #[error("cannot encode PNG: {0}")]
    Encode(String),
    /// Writing the file failed; nothing was left at `path`.
    #[error("cannot write picture {}: {source}", path.display())]
    Io {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// What to draw and how. `Default` gives a 1600×1200 3/4 view with edges,
/// feature curves, irregular vertices and an info line.
#[derive(Clone, Debug)]
pub struct RenderOptions<'a> {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Direction from the model toward the viewer (orthographic view along
    /// its opposite). Default `[1.0, -1.25, 0.9]`: front-right-above, z up.
    pub eye_dir: Vec3,
    /// The world direction that points up in the picture (projected;
    /// another axis is used when it is parallel to `eye_dir`).
    pub up: Vec3,
    /// Supersampling factor per axis for antialiasing (1–4; default 2),
    /// lowered automatically when the supersampled canvas would exceed
    /// [`MAX_CANVAS_SAMPLES`].
    pub supersample: u32,
    /// Draw element edges (faded out where elements are only a few pixels wide).
    pub show_edges: bool,
    /// Draw mesh edges on CAD curves (`QuadMesh::curve_edges`) thicker.
    pub show_feature_edges: bool,
    /// Draw irregular face-interior vertices as dots coloured by valence.
    pub show_irregular: bool,
    /// Colour quads by these values (one per quad, e.g. SICN) on a
    /// red (0) → yellow (0.5) → green (1) map, negatives dark red, with a
    /// colour bar. Triangles keep the plain colour.
    pub quad_values: Option<&'a [f64]>,
    /// Colour triangles by these values (one per triangle, e.g. a size map
    /// scaled to [0, 1]) on the same map and colour bar as `quad_values`.
    pub triangle_values: Option<&'a [f64]>,
    /// Name shown above the colour bar.
    pub values_label: &'a str,
    /// Title line drawn at the top left (e.g. the file name).
    pub title: Option<&'a str>,
    /// Draw a line with the element, node and irregular-vertex counts.
    pub show_info: bool,
    /// Extra segments and dots drawn over the surface, with a legend.
    pub overlay: Option<&'a Overlay>,
}

impl Default for RenderOptions<'_> {
    fn default() -> Self {
        RenderOptions {
            width: 1600,
            height: 1200,
            eye_dir: [1.0, -1.25, 0.9],
            up: [0.0, 0.0, 1.0],
            supersample: 2,
            show_edges: true,
            show_feature_edges: true,
            show_irregular: true,
            quad_values: None,
            triangle_values: None,
            values_label: "SICN",
            title: None,
            show_info: true,
            overlay: None,
        }
    }
}

/// A rendered picture: opaque RGBA pixels, row-major, top row first.
#[derive(Clone, Debug)]
pub struct RenderedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 4` bytes, RGBA, alpha always 255.
    pub rgba: Vec<u8>,
}

impl RenderedImage {
    /// The RGBA colour at `(x, y)`, or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let o = (y as usize * self.width as usize + x as usize) * 4;
        self.rgba.get(o..o + 4).map(|p| [p[0], p[1], p[2], p[3]])
    }

    /// The picture encoded as PNG bytes.
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        let size = IntSize::from_wh(self.width, self.height)
            .ok_or_else(|| RenderError::Encode("empty image".into()))?;
        let pixmap = Pixmap::from_vec(self.rgba.clone(), size)
            .ok_or_else(|| RenderError::Encode("pixel buffer of the wrong size".into()))?;
        pixmap
            .encode_png()
            .map_err(|e| RenderError::Encode(e.to_string()))
    }
}

/// Renders `mesh` and writes the picture as PNG to `path` (atomically: on
/// error no file is left there).
pub fn render_png(mesh: &QuadMesh, opts: &RenderOptions, path: &Path) -> Result<(), RenderError> {
    let png = render_image(mesh, opts)?.encode_png()?;
    write_atomically(path, |w| std::io::Write::write_all(w, &png)).map_err(|source| {
        RenderError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Renders `mesh` into an in-memory image.
pub fn render_image(mesh: &QuadMesh, opts: &RenderOptions) -> Result<RenderedImage, RenderError> {
    let scene = Scene::new(mesh, opts)?;
    Ok(scene.draw(mesh, opts))
}

/// The largest canvas (width × height × supersample²) drawn; beyond it the
/// supersampling is lowered, and an image larger than this even without
/// supersampling is refused.
pub const MAX_CANVAS_SAMPLES: u64 = 40_000_000;

/// Background colour.
const BACKGROUND: [u8; 3] = [255, 255, 255];
/// Base colour of front faces (0..1).
const FRONT: [f32; 3] = [0.60, 0.74, 0.92];
/// Base colour of back faces (0..1).
const BACK: [f32; 3] = [0.78, 0.52, 0.40];
/// Edge colour.
const EDGE: [f32; 3] = [22.0, 28.0, 40.0];
/// Text colour.
const TEXT: [u8; 3] = [30, 30, 30];

/// The dot colour of an irregular vertex of quad valence `v`.
pub(crate) fn valence_color(v: u32) -> [u8; 3] {
    match v {
        3 => [30, 90, 235],
        5 => [225, 25, 25],
        v if v >= 6 => [205, 30, 205],
        _ => [255, 150, 0],
    }
}

/// The colour map for per-quad values: red (0) → yellow (0.5) → green (1);
/// negative values dark red; NaN grey. Components in 0..1.
pub(crate) fn value_color(v: f64) -> [f32; 3] {
    const RED: [f32; 3] = [0.84, 0.10, 0.11];
    const YELLOW: [f32; 3] = [1.0, 0.88, 0.20];
    const GREEN: [f32; 3] = [0.10, 0.62, 0.26];
    if v.is_nan() {
        return [0.6, 0.6, 0.6];
    }
    if v < 0.0 {
        return [0.42, 0.0, 0.02];
    }
    let t = v.min(1.0) as f32;
    let (a, b, s) = if t < 0.5 {
        (RED, YELLOW, t * 2.0)
    } else {
        (YELLOW, GREEN, t * 2.0 - 1.0)
    };
    [
        a[0] + (b[0] - a[0]) * s,
        a[1] + (b[1] - a[1]) * s,
        a[2] + (b[2] - a[2]) * s,
    ]
}
