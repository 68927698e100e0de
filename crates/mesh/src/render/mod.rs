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

mod font;
mod raster;
#[cfg(test)]
mod tests;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use geometry::vec3::{cross, dist, dot, normalize, scale, sub, Vec3};
use tiny_skia::{FillRule, IntSize, Paint, PathBuilder, Pixmap, Stroke, Transform};

use crate::atomic::write_atomically;
use crate::quadmesh::QuadMesh;
use raster::{Canvas, Edge, Shade};

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

/// A 3D line segment of an [`Overlay`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlaySegment {
    /// One end.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Its colour.
    pub color: [u8; 3],
    /// The normal of the surface it lies on, when it lies on one: the
    /// segment is then left out where the surface is seen at a grazing angle
    /// (`|normal · view| <` [`MIN_FACING`]), where it would crowd the outline.
    pub normal: Option<Vec3>,
}

/// Overlay segments on a surface seen more obliquely than this (cosine of
/// the angle between the normal and the view direction) are not drawn.
pub const MIN_FACING: f64 = 0.3;

/// A coloured dot of an [`Overlay`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayPoint {
    /// Where it is.
    pub position: Vec3,
    /// Its fill colour (drawn with a thin dark outline).
    pub color: [u8; 3],
}

/// Marks drawn over the shaded surface: segments first, then dots, each
/// drawn only where it is not hidden behind the surface (tested at the
/// segment's midpoint and at the dot's centre against the depth buffer);
/// segments with a normal are also left out at grazing angles ([`MIN_FACING`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    /// Line segments.
    pub segments: Vec<OverlaySegment>,
    /// Segment width in pixels (0 means 1.5).
    pub line_width: f32,
    /// Dots.
    pub points: Vec<OverlayPoint>,
    /// Dot radius in pixels (0 means 4 times the text scale).
    pub point_radius: f32,
    /// Legend entries `(dot colour, text)`, drawn in a line at the bottom left.
    pub legend: Vec<([u8; 3], String)>,
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

/// The orthographic camera: world → final-image pixels (x right, y down) and depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Camera {
    right: Vec3,
    up: Vec3,
    eye: Vec3,
    light: Vec3,
    scale: f64,
    offset: [f64; 2],
}

impl Camera {
    /// `(x, y, depth)` of `p`: image pixels, depth growing toward the viewer.
    pub(crate) fn project(&self, p: Vec3) -> [f64; 3] {
        [
            dot(p, self.right) * self.scale + self.offset[0],
            self.offset[1] - dot(p, self.up) * self.scale,
            dot(p, self.eye),
        ]
    }

    /// The lit colour (0..255) of a surface of unit normal `n` and base colour `base`.
    pub(crate) fn shade(&self, n: Option<Vec3>, base: [f32; 3], darken_back: bool) -> [f32; 3] {
        let (lambert, back) = match n {
            Some(n) => {
                let facing = dot(n, self.eye);
                let nf = if facing < 0.0 { scale(n, -1.0) } else { n };
                (dot(nf, self.light).max(0.0) as f32, facing < 0.0)
            }
            None => (0.5, false),
        };
        let k = (0.38 + 0.62 * lambert) * if back && darken_back { 0.62 } else { 1.0 };
        [
            base[0] * k * 255.0,
            base[1] * k * 255.0,
            base[2] * k * 255.0,
        ]
    }

    /// True when the surface of normal `n` faces away from the viewer.
    pub(crate) fn is_back(&self, n: Option<Vec3>) -> bool {
        n.is_some_and(|n| dot(n, self.eye) < 0.0)
    }
}

/// Layout of the picture: font scale, margins, and the rectangle the mesh is fitted into.
struct Layout {
    k: u32,
    margin: u32,
    plot: [f64; 4],
}

/// Everything computed before drawing.
pub(crate) struct Scene {
    pub(crate) camera: Camera,
    layout: Layout,
    valences: Vec<u32>,
    irregular: Vec<usize>,
    /// The supersampling factor actually used.
    ss: u32,
}

impl Scene {
    /// Checks the input, finds the irregular vertices and fits the camera.
    pub(crate) fn new(mesh: &QuadMesh, opts: &RenderOptions) -> Result<Scene, RenderError> {
        if mesh.quads.is_empty() && mesh.triangles.is_empty() {
            return Err(RenderError::EmptyMesh);
        }
        crate::vtu::check_mesh(mesh).map_err(RenderError::InvalidMesh)?;
        if opts.width < 16 || opts.height < 16 || opts.width > 16384 || opts.height > 16384 {
            return Err(RenderError::InvalidOptions(format!(
                "image size {}x{} (each side must be 16..16384)",
                opts.width, opts.height
            )));
        }
        if !(1..=4).contains(&opts.supersample) {
            return Err(RenderError::InvalidOptions(format!(
                "supersample {} (must be 1..4)",
                opts.supersample
            )));
        }
        let pixels = opts.width as u64 * opts.height as u64;
        if pixels > MAX_CANVAS_SAMPLES {
            return Err(RenderError::InvalidOptions(format!(
                "image size {}x{} is over {} pixels",
                opts.width, opts.height, MAX_CANVAS_SAMPLES
            )));
        }
        let mut ss = opts.supersample;
        while ss > 1 && pixels * (ss * ss) as u64 > MAX_CANVAS_SAMPLES {
            ss -= 1;
        }
        if let Some(v) = opts.quad_values {
            if v.len() != mesh.quads.len() {
                return Err(RenderError::InvalidOptions(format!(
                    "{} quad values for {} quads",
                    v.len(),
                    mesh.quads.len()
                )));
            }
        }
        if let Some(v) = opts.triangle_values {
            if v.len() != mesh.triangles.len() {
                return Err(RenderError::InvalidOptions(format!(
                    "{} triangle values for {} triangles",
                    v.len(),
                    mesh.triangles.len()
                )));
            }
        }
        if let Some(o) = opts.overlay {
            let finite = |p: &Vec3| p.iter().all(|c| c.is_finite());
            if !o.segments.iter().all(|s| finite(&s.a) && finite(&s.b))
                || !o.points.iter().all(|p| finite(&p.position))
            {
                return Err(RenderError::InvalidOptions(
                    "overlay with non-finite coordinates".into(),
                ));
            }
            if !(o.line_width.is_finite()
                && o.line_width >= 0.0
                && o.point_radius.is_finite()
                && o.point_radius >= 0.0)
            {
                return Err(RenderError::InvalidOptions(format!(
                    "overlay line width {} / point radius {}",
                    o.line_width, o.point_radius
                )));
            }
        }
        let eye = normalize(opts.eye_dir)
            .filter(|e| e.iter().all(|c| c.is_finite()))
            .ok_or_else(|| {
                RenderError::InvalidOptions(format!("view direction {:?}", opts.eye_dir))
            })?;
        let right = [opts.up, [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
            .into_iter()
            .filter_map(|u| normalize(cross(u, eye)).filter(|r| r.iter().all(|c| c.is_finite())))
            .find(|r| dot(*r, *r) > 0.5)
            .unwrap_or([1.0, 0.0, 0.0]);
        let up = cross(eye, right);
        let light = normalize([
            eye[0] + 0.5 * up[0] - 0.1 * right[0],
            eye[1] + 0.5 * up[1] - 0.1 * right[1],
            eye[2] + 0.5 * up[2] - 0.1 * right[2],
        ])
        .unwrap_or(eye);

        // irregular vertices: face-interior, in at least one quad, in no triangle, valence ≠ 4
        let valences = mesh.node_valences();
        let mut on_triangle = vec![false; mesh.nodes.len()];
        for t in &mesh.triangles {
            for &n in t {
                on_triangle[n as usize] = true;
            }
        }
        let irregular: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&n| {
                mesh.is_face_interior(n) && !on_triangle[n] && valences[n] != 4 && valences[n] > 0
            })
            .collect();

        // layout
        let (w, h) = (opts.width, opts.height);
        let k = ((w.min(h) as f64 / 600.0).round() as u32).max(1);
        let margin = 12 * k;
        let line = font::CELL_H * k;
        let text_lines = opts.title.is_some() as u32 + opts.show_info as u32;
        let top = margin + text_lines * line + if text_lines > 0 { 4 * k } else { 0 };
        let right_panel = if opts.quad_values.is_some() || opts.triangle_values.is_some() {
            (14 * k + 6 * k + font::text_width("0.75", k))
                .max(font::text_width(opts.values_label, k))
                + margin
        } else {
            0
        };
        let legend_lines = (opts.show_irregular && !irregular.is_empty()) as u32
            + opts.overlay.is_some_and(|o| !o.legend.is_empty()) as u32;
        let bottom = legend_lines * (line + 8 * k);
        let mut plot = [
            margin as f64,
            top as f64,
            (w - margin - right_panel.min(w / 3)) as f64,
            (h - margin - bottom.min(h / 3)) as f64,
        ];
        if plot[2] - plot[0] < 8.0 || plot[3] - plot[1] < 8.0 {
            plot = [0.0, 0.0, w as f64, h as f64];
        }

        // fit the used nodes into the plot rectangle
        let mut used = vec![false; mesh.nodes.len()];
        for q in &mesh.quads {
            for &n in q {
                used[n as usize] = true;
            }
        }
        for t in &mesh.triangles {
            for &n in t {
                used[n as usize] = true;
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (p, _) in mesh.nodes.iter().zip(&used).filter(|(_, u)| **u) {
            let s = [dot(*p, right), dot(*p, up)];
            for i in 0..2 {
                lo[i] = lo[i].min(s[i]);
                hi[i] = hi[i].max(s[i]);
            }
        }
        let span = [hi[0] - lo[0], hi[1] - lo[1]];
        let (pw, ph) = (plot[2] - plot[0], plot[3] - plot[1]);
        let mut s = f64::INFINITY;
        if span[0] > 1e-300 {
            s = s.min(pw / span[0]);
        }
        if span[1] > 1e-300 {
            s = s.min(ph / span[1]);
        }
        if !s.is_finite() || s <= 0.0 {
            s = 1.0;
        }
        let mid = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5];
        let offset = [
            (plot[0] + plot[2]) * 0.5 - mid[0] * s,
            (plot[1] + plot[3]) * 0.5 + mid[1] * s,
        ];
        let camera = Camera {
            right,
            up,
            eye,
            light,
            scale: s,
            offset,
        };
        Ok(Scene {
            camera,
            layout: Layout { k, margin, plot },
            valences,
            irregular,
            ss,
        })
    }

    /// Rasterizes the mesh and draws the overlays.
    fn draw(&self, mesh: &QuadMesh, opts: &RenderOptions) -> RenderedImage {
        let ss = self.ss as usize;
        let cam = &self.camera;
        let (w, h) = (opts.width as usize, opts.height as usize);
        let mut canvas = Canvas::new(w * ss, h * ss, self.ss, BACKGROUND);
        let ssf = ss as f64;
        let proj: Vec<[f32; 3]> = mesh
            .nodes
            .iter()
            .map(|&p| {
                let q = cam.project(p);
                [(q[0] * ssf) as f32, (q[1] * ssf) as f32, q[2] as f32]
            })
            .collect();
        let feature: HashSet<(u32, u32)> = if opts.show_feature_edges {
            mesh.curve_edges
                .iter()
                .map(|([a, b], _)| (*a.min(b), *a.max(b)))
                .collect()
        } else {
            HashSet::new()
        };
        let make_edges = |ids: &[u32], shade: &mut Shade| {
            let n = ids.len();
            shade.n_edges = n;
            let pts: Vec<[f32; 2]> = ids
                .iter()
                .map(|&i| [proj[i as usize][0], proj[i as usize][1]])
                .collect();
            // projected area in final pixels, to fade edges of tiny elements
            let mut area = 0.0f32;
            for i in 0..n {
                let (a, b) = (pts[i], pts[(i + 1) % n]);
                area += a[0] * b[1] - a[1] * b[0];
            }
            let size = (area.abs() * 0.5).sqrt() / ss as f32;
            let alpha = if opts.show_edges {
                ((size - 2.0) / 6.0).clamp(0.0, 1.0) * 0.9
            } else {
                0.0
            };
            for i in 0..n {
                let (a, b) = (ids[i], ids[(i + 1) % n]);
                let key = (a.min(b), a.max(b));
                shade.edges[i] = if feature.contains(&key) {
                    Edge::new(pts[i], pts[(i + 1) % n], 0.9, 0.95)
                } else {
                    Edge::new(pts[i], pts[(i + 1) % n], 0.45, alpha)
                };
            }
        };
        for (qi, q) in mesh.quads.iter().enumerate() {
            let p = q.map(|n| mesh.nodes[n as usize]);
            let n = normalize(cross(sub(p[2], p[0]), sub(p[3], p[1])));
            let base = match opts.quad_values {
                Some(v) => value_color(v[qi]),
                None if cam.is_back(n) => BACK,
                None => FRONT,
            };
            let mut shade = Shade {
                fill: cam.shade(n, base, opts.quad_values.is_some()),
                edge_color: EDGE,
                edges: [Edge::default(); 4],
                n_edges: 0,
            };
            make_edges(q, &mut shade);
            let v = q.map(|n| proj[n as usize]);
            canvas.fill_triangle([v[0], v[1], v[2]], &shade);
            canvas.fill_triangle([v[0], v[2], v[3]], &shade);
        }
        for (ti, t) in mesh.triangles.iter().enumerate() {
            let p = t.map(|n| mesh.nodes[n as usize]);
            let n = normalize(cross(sub(p[1], p[0]), sub(p[2], p[0])));
            let base = match opts.triangle_values {
                Some(v) => value_color(v[ti]),
                None if cam.is_back(n) => BACK,
                None => FRONT,
            };
            let mut shade = Shade {
                fill: cam.shade(n, base, opts.triangle_values.is_some()),
                edge_color: EDGE,
                edges: [Edge::default(); 4],
                n_edges: 0,
            };
            make_edges(t, &mut shade);
            canvas.fill_triangle(t.map(|n| proj[n as usize]), &shade);
        }

        let (ow, oh, rgba) = canvas.downsample(ss);
        let mut pixmap =
            match IntSize::from_wh(ow as u32, oh as u32).and_then(|s| Pixmap::from_vec(rgba, s)) {
                Some(p) => p,
                None => {
                    return RenderedImage {
                        width: ow as u32,
                        height: oh as u32,
                        rgba: vec![255; ow * oh * 4],
                    }
                }
            };
        let mut counts = [0usize; 4];
        if opts.show_irregular {
            counts = self.draw_dots(mesh, &canvas, &proj, &mut pixmap);
        }
        let (pw, ph) = (pixmap.width(), pixmap.height());
        self.draw_text_lines(mesh, opts, pixmap.data_mut(), pw, ph);
        if opts.quad_values.is_some() || opts.triangle_values.is_some() {
            self.draw_colour_bar(opts, pixmap.data_mut(), pw, ph);
        }
        if let Some(o) = opts.overlay {
            self.draw_overlay(o, &canvas, &mut pixmap);
        }
        let mut legend_y =
            pixmap.height() as i64 - self.layout.margin as i64 - (7 * self.layout.k) as i64;
        if opts.show_irregular && !self.irregular.is_empty() {
            self.draw_valence_legend(&counts, legend_y, &mut pixmap);
            legend_y -= ((font::CELL_H + 8) * self.layout.k) as i64;
        }
        if let Some(o) = opts.overlay.filter(|o| !o.legend.is_empty()) {
            self.draw_legend(&o.legend, legend_y, &mut pixmap);
        }
        RenderedImage {
            width: pw,
            height: ph,
            rgba: pixmap.take(),
        }
    }

    /// Draws the visible irregular vertices; returns how many of each kind
    /// (valence 3, 5, 6+, other) the mesh has.
    fn draw_dots(
        &self,
        mesh: &QuadMesh,
        canvas: &Canvas,
        proj: &[[f32; 3]],
        pixmap: &mut Pixmap,
    ) -> [usize; 4] {
        let mut counts = [0usize; 4];
        if self.irregular.is_empty() {
            return counts;
        }
        // mean incident edge length, in world units and projected (canvas pixels)
        let mut len_sum = vec![0.0f64; mesh.nodes.len()];
        let mut proj_sum = vec![0.0f64; mesh.nodes.len()];
        let mut len_cnt = vec![0u32; mesh.nodes.len()];
        for q in &mesh.quads {
            for i in 0..4 {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                let l = dist(mesh.nodes[a as usize], mesh.nodes[b as usize]);
                let lp = l_px(proj, a, b);
                for n in [a as usize, b as usize] {
                    len_sum[n] += l;
                    proj_sum[n] += lp;
                    len_cnt[n] += 1;
                }
            }
        }
        let k = self.layout.k as f64;
        let ss = canvas.ss as f64;
        let px_world = 1.0 / (self.camera.scale * ss);
        let mut dots: Vec<(f32, f64, f64, f64, [u8; 3])> = Vec::new();
        for &n in &self.irregular {
            let v = self.valences[n];
            counts[match v {
                3 => 0,
                5 => 1,
                v if v >= 6 => 2,
                _ => 3,
            }] += 1;
            let p = proj[n];
            let tol = (0.5 * len_sum[n] / len_cnt[n].max(1) as f64).max(3.0 * px_world) as f32;
            let (cx, cy) = (p[0].floor() as i64, p[1].floor() as i64);
            let mut visible = false;
            'look: for dy in -1..=1 {
                for dx in -1..=1 {
                    let (x, y) = (cx + dx, cy + dy);
                    if x < 0 || y < 0 || x >= canvas.w as i64 || y >= canvas.h as i64 {
                        continue;
                    }
                    if canvas.depth[y as usize * canvas.w + x as usize] <= p[2] + tol {
                        visible = true;
                        break 'look;
                    }
                }
            }
            if visible {
                // a dot a bit over a quarter of the local projected edge length
                let local = proj_sum[n] / len_cnt[n].max(1) as f64 / ss;
                let radius = (0.28 * local).clamp(1.6 * k, 4.5 * k);
                dots.push((
                    p[2],
                    p[0] as f64 / ss,
                    p[1] as f64 / ss,
                    radius,
                    valence_color(v),
                ));
            }
        }
        dots.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, x, y, r, c) in dots {
            draw_dot(pixmap, x as f32, y as f32, r as f32, c);
        }
        counts
    }

    /// Title and info lines at the top left.
    fn draw_text_lines(
        &self,
        mesh: &QuadMesh,
        opts: &RenderOptions,
        rgba: &mut [u8],
        w: u32,
        h: u32,
    ) {
        let k = self.layout.k;
        let m = self.layout.margin as i64;
        let mut y = m;
        if let Some(t) = opts.title {
            font::draw_text(rgba, w, h, m, y, t, k, TEXT);
            y += (font::CELL_H * k) as i64;
        }
        if opts.show_info {
            // a triangle-only mesh (a background triangulation) has no quad counts
            let s = if mesh.quads.is_empty() && !mesh.triangles.is_empty() {
                format!(
                    "{} triangles, {} nodes",
                    thousands(mesh.triangles.len()),
                    thousands(mesh.nodes.len())
                )
            } else {
                let mut s = format!("{} quads", thousands(mesh.quads.len()));
                if !mesh.triangles.is_empty() {
                    s += &format!(", {} triangles", thousands(mesh.triangles.len()));
                }
                s + &format!(
                    ", {} nodes, {} irregular vertices",
                    thousands(mesh.nodes.len()),
                    thousands(self.irregular.len())
                )
            };
            let mut s = s;
            if let Some(v) = opts.quad_values {
                let min = v
                    .iter()
                    .copied()
                    .filter(|x| !x.is_nan())
                    .fold(f64::INFINITY, f64::min);
                let neg = v.iter().filter(|x| **x < 0.0).count();
                if min.is_finite() {
                    s += &format!(
                        ", min {} {:.3}, {} < 0",
                        opts.values_label,
                        min,
                        thousands(neg)
                    );
                }
            }
            font::draw_text(rgba, w, h, m, y, &s, k, [90, 90, 90]);
        }
    }

    /// A vertical colour bar with ticks at 0, 0.25, …, 1 and a "< 0" swatch.
    fn draw_colour_bar(&self, opts: &RenderOptions, rgba: &mut [u8], w: u32, h: u32) {
        let k = self.layout.k as i64;
        let bar_w = 14 * k;
        let x0 = self.layout.plot[2] as i64 + 4 * k;
        let bar_h = ((h as f64) * 0.4) as i64;
        let y0 = (h as i64 - bar_h) / 2;
        let put = |rgba: &mut [u8], x: i64, y: i64, c: [u8; 3]| put_px(rgba, w, h, x, y, c);
        for y in 0..bar_h {
            let v = 1.0 - y as f64 / (bar_h - 1).max(1) as f64;
            let c = value_color(v).map(|c| (c * 255.0) as u8);
            for x in 0..bar_w {
                put(rgba, x0 + x, y0 + y, c);
            }
        }
        let sw_y = y0 + bar_h + 6 * k;
        let swatch = value_color(-1.0).map(|c| (c * 255.0) as u8);
        for y in 0..bar_w {
            for x in 0..bar_w {
                put(rgba, x0 + x, sw_y + y, swatch);
            }
        }
        // frames and ticks
        for (fy, fh) in [(y0, bar_h), (sw_y, bar_w)] {
            for x in -1..=bar_w {
                put(rgba, x0 + x, fy - 1, TEXT);
                put(rgba, x0 + x, fy + fh, TEXT);
            }
            for y in -1..=fh {
                put(rgba, x0 - 1, fy + y, TEXT);
                put(rgba, x0 + bar_w, fy + y, TEXT);
            }
        }
        for (i, label) in ["1", "0.75", "0.5", "0.25", "0"].iter().enumerate() {
            let y = y0 + (bar_h - 1) * i as i64 / 4;
            for x in 0..3 * k {
                put(rgba, x0 + bar_w + x, y, TEXT);
            }
            font::draw_text(
                rgba,
                w,
                h,
                x0 + bar_w + 5 * k,
                y - 3 * k,
                label,
                k as u32,
                TEXT,
            );
        }
        font::draw_text(
            rgba,
            w,
            h,
            x0 + bar_w + 5 * k,
            sw_y + bar_w / 2 - 3 * k,
            "< 0",
            k as u32,
            TEXT,
        );
        font::draw_text(
            rgba,
            w,
            h,
            x0,
            y0 - 6 * k - (7 * k),
            opts.values_label,
            k as u32,
            TEXT,
        );
    }

    /// "● 3: n  ● 5: n  ● 6+: n  ● other: n" at the left of text row `y`.
    fn draw_valence_legend(&self, counts: &[usize; 4], y: i64, pixmap: &mut Pixmap) {
        let items = [(3u32, "valence 3"), (5, "5"), (6, "6+"), (2, "other")];
        let entries: Vec<([u8; 3], String)> = items
            .iter()
            .zip(counts)
            .filter(|(_, &n)| n > 0)
            .map(|((v, name), &n)| (valence_color(*v), format!("{}: {}", name, thousands(n))))
            .collect();
        self.draw_legend(&entries, y, pixmap);
    }

    /// A row of "● text" entries at the left of text row `y`.
    fn draw_legend(&self, entries: &[([u8; 3], String)], y: i64, pixmap: &mut Pixmap) {
        let k = self.layout.k;
        let (w, h) = (pixmap.width(), pixmap.height());
        let mut x = self.layout.margin as i64;
        let r = 3.5 * k as f32;
        for (color, label) in entries {
            draw_dot(pixmap, x as f32 + r, y as f32 + 3.5 * k as f32, r, *color);
            x += (2.0 * r) as i64 + 3 * k as i64;
            font::draw_text(pixmap.data_mut(), w, h, x, y, label, k, TEXT);
            x += font::text_width(label, k) as i64 + 10 * k as i64;
        }
    }

    /// True when world point `p` is not behind the drawn surface: the depth
    /// buffer around its projection is at most `tol` (world units) nearer.
    fn visible(&self, canvas: &Canvas, p: Vec3, tol: f64) -> bool {
        let ss = canvas.ss as f64;
        let q = self.camera.project(p);
        let (cx, cy) = ((q[0] * ss).floor() as i64, (q[1] * ss).floor() as i64);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (x, y) = (cx + dx, cy + dy);
                if x < 0 || y < 0 || x >= canvas.w as i64 || y >= canvas.h as i64 {
                    continue;
                }
                let d = canvas.depth[y as usize * canvas.w + x as usize];
                if d == f32::NEG_INFINITY || d as f64 <= q[2] + tol {
                    return true;
                }
            }
        }
        false
    }

    /// Draws the visible segments, then the visible dots, of `overlay`.
    fn draw_overlay(&self, overlay: &Overlay, canvas: &Canvas, pixmap: &mut Pixmap) {
        let k = self.layout.k as f32;
        let px_world = 1.0 / self.camera.scale;
        let width = if overlay.line_width > 0.0 {
            overlay.line_width
        } else {
            1.5
        };
        let stroke = Stroke {
            width,
            line_cap: tiny_skia::LineCap::Round,
            ..Stroke::default()
        };
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        for s in &overlay.segments {
            if s.normal
                .and_then(normalize)
                .is_some_and(|n| dot(n, self.camera.eye).abs() < MIN_FACING)
            {
                continue;
            }
            let mid = scale([s.a[0] + s.b[0], s.a[1] + s.b[1], s.a[2] + s.b[2]], 0.5);
            if !self.visible(canvas, mid, 0.5 * dist(s.a, s.b) + 3.0 * px_world) {
                continue;
            }
            let (a, b) = (self.camera.project(s.a), self.camera.project(s.b));
            let mut pb = PathBuilder::new();
            pb.move_to(a[0] as f32, a[1] as f32);
            pb.line_to(b[0] as f32, b[1] as f32);
            if let Some(path) = pb.finish() {
                paint.set_color_rgba8(s.color[0], s.color[1], s.color[2], 255);
                pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
            }
        }
        let r = if overlay.point_radius > 0.0 {
            overlay.point_radius
        } else {
            4.0 * k
        };
        let mut dots: Vec<(f64, [f64; 3], [u8; 3])> = overlay
            .points
            .iter()
            .filter(|p| self.visible(canvas, p.position, (2.0 * r as f64 + 3.0) * px_world))
            .map(|p| {
                let q = self.camera.project(p.position);
                (q[2], q, p.color)
            })
            .collect();
        dots.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, q, c) in dots {
            draw_dot(pixmap, q[0] as f32, q[1] as f32, r, c);
        }
    }
}

/// Sets one opaque pixel of an RGBA buffer, ignoring positions outside it.
fn put_px(rgba: &mut [u8], w: u32, h: u32, x: i64, y: i64, c: [u8; 3]) {
    if x >= 0 && y >= 0 && x < w as i64 && y < h as i64 {
        let o = (y as usize * w as usize + x as usize) * 4;
        if let Some(p) = rgba.get_mut(o..o + 4) {
            p.copy_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }
}

/// Projected length of the edge (a, b) in canvas pixels.
fn l_px(proj: &[[f32; 3]], a: u32, b: u32) -> f64 {
    let (p, q) = (proj[a as usize], proj[b as usize]);
    ((p[0] - q[0]) as f64).hypot((p[1] - q[1]) as f64)
}

/// A filled, antialiased dot with a thin dark outline.
fn draw_dot(pixmap: &mut Pixmap, x: f32, y: f32, r: f32, c: [u8; 3]) {
    let Some(path) = PathBuilder::from_circle(x, y, r) else {
        return;
    };
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color_rgba8(c[0], c[1], c[2], 255);
    pixmap.fill_path(
        &path,
        &paint,
        FillRule::Winding,
        Transform::identity(),
        None,
    );
    paint.set_color_rgba8(20, 20, 20, 255);
    let stroke = Stroke {
        width: (r * 0.22).clamp(0.8, 2.0),
        ..Stroke::default()
    };
    pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
}

/// `1234567` → `"1,234,567"`.
fn thousands(n: usize) -> String {
    let digits: Vec<char> = n.to_string().chars().collect();
    let groups: Vec<String> = digits
        .rchunks(3)
        .rev()
        .map(|c| c.iter().collect())
        .collect();
    groups.join(",")
}
