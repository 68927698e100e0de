//! Overlays: 3D segments and dots drawn over the shaded surface where the
//! surface does not hide them, with their own legend line.

use geometry::vec3::{dist, dot, normalize, scale, Vec3};
use tiny_skia::{Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::legend::draw_dot;
use super::raster::Canvas;
use super::scene::Scene;

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

impl Scene {
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
    pub(super) fn draw_overlay(&self, overlay: &Overlay, canvas: &Canvas, pixmap: &mut Pixmap) {
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
