//! The scene of a picture: the options checked, the irregular vertices
//! found, the layout and the camera fitted ([`Scene::new`]); the mesh
//! rasterized with its dots, text, legends and overlay ([`Scene::draw`]).

use std::collections::HashSet;

use geometry::vec3::{cross, dist, normalize, sub, Vec3};
use tiny_skia::{IntSize, Pixmap};

use super::camera::Camera;
use super::legend::draw_dot;
use super::raster::{Canvas, Edge, Shade};
use super::{
    font, valence_color, value_color, RenderError, RenderOptions, RenderedImage, BACK, BACKGROUND,
    EDGE, FRONT, MAX_CANVAS_SAMPLES,
};
use crate::quadmesh::QuadMesh;

/// Layout of the picture: font scale, margins, and the rectangle the mesh is fitted into.
pub(super) struct Layout {
    pub(super) k: u32,
    pub(super) margin: u32,
    pub(super) plot: [f64; 4],
}

/// Everything computed before drawing.
pub(crate) struct Scene {
    pub(crate) camera: Camera,
    pub(super) layout: Layout,
    pub(super) valences: Vec<u32>,
    pub(super) irregular: Vec<usize>,
    /// The supersampling factor actually used.
    pub(super) ss: u32,
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

        let camera = Camera::fitted(mesh, opts.eye_dir, opts.up, plot)?;
        Ok(Scene {
            camera,
            layout: Layout { k, margin, plot },
            valences,
            irregular,
            ss,
        })
    }

    /// Rasterizes the mesh and draws the overlays.
    pub(super) fn draw(&self, mesh: &QuadMesh, opts: &RenderOptions) -> RenderedImage {
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
}

/// Projected length of the edge (a, b) in canvas pixels.
fn l_px(proj: &[[f32; 3]], a: u32, b: u32) -> f64 {
    let (p, q) = (proj[a as usize], proj[b as usize]);
    ((p[0] - q[0]) as f64).hypot((p[1] - q[1]) as f64)
}
