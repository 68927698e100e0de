//! Text and legends of a picture: the title and info lines, the colour
//! bar, the dot legends; the dot and pixel primitives they share with the
//! scene and the overlay.

use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::scene::Scene;
use super::{font, valence_color, value_color, RenderOptions, TEXT};
use crate::quadmesh::QuadMesh;

impl Scene {
    /// Title and info lines at the top left.
    pub(super) fn draw_text_lines(
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
    pub(super) fn draw_colour_bar(&self, opts: &RenderOptions, rgba: &mut [u8], w: u32, h: u32) {
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
    pub(super) fn draw_valence_legend(&self, counts: &[usize; 4], y: i64, pixmap: &mut Pixmap) {
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
    pub(super) fn draw_legend(&self, entries: &[([u8; 3], String)], y: i64, pixmap: &mut Pixmap) {
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

/// A filled, antialiased dot with a thin dark outline.
pub(super) fn draw_dot(pixmap: &mut Pixmap, x: f32, y: f32, r: f32, c: [u8; 3]) {
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
pub(super) fn thousands(n: usize) -> String {
    let digits: Vec<char> = n.to_string().chars().collect();
    let groups: Vec<String> = digits
        .rchunks(3)
        .rev()
        .map(|c| c.iter().collect())
        .collect();
    groups.join(",")
}
