//! A small z-buffer triangle rasterizer with flat-shaded fill and
//! analytically antialiased element edges ("wireframe on shaded").
//!
//! Coordinates are in canvas (supersampled) pixels, y pointing down; depth
//! grows toward the viewer. Each polygon is drawn as triangles that all carry
//! the polygon's own edges, so a quad's diagonal never shows and an edge is
//! drawn exactly where its polygon is visible.

/// One polygon edge as a segment in canvas pixels, with its drawn half-width
/// and opacity (in final-image pixels).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Edge {
    /// Start point.
    pub a: [f32; 2],
    /// `b − a`.
    pub d: [f32; 2],
    /// `1 / |d|²` (0 for a degenerate edge).
    pub inv_len2: f32,
    /// Half-width in final pixels.
    pub half_width: f32,
    /// Opacity in [0, 1]; 0 means the edge is not drawn.
    pub alpha: f32,
}

impl Edge {
    /// The segment from `a` to `b` with the given half-width and opacity.
    pub(crate) fn new(a: [f32; 2], b: [f32; 2], half_width: f32, alpha: f32) -> Self {
        let d = [b[0] - a[0], b[1] - a[1]];
        let l2 = d[0] * d[0] + d[1] * d[1];
        Edge {
            a,
            d,
            inv_len2: if l2 > 0.0 { 1.0 / l2 } else { 0.0 },
            half_width,
            alpha,
        }
    }

    /// Distance from `p` to the segment, in canvas pixels.
    #[inline]
    fn distance(&self, p: [f32; 2]) -> f32 {
        let px = p[0] - self.a[0];
        let py = p[1] - self.a[1];
        let t = ((px * self.d[0] + py * self.d[1]) * self.inv_len2).clamp(0.0, 1.0);
        let ex = px - t * self.d[0];
        let ey = py - t * self.d[1];
        (ex * ex + ey * ey).sqrt()
    }
}

/// How to colour the pixels of one polygon.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shade {
    /// Fill colour (0..255 per channel, already lit).
    pub fill: [f32; 3],
    /// Colour of the edges.
    pub edge_color: [f32; 3],
    /// The polygon's edges (first `n_edges` used).
    pub edges: [Edge; 4],
    /// Number of edges in use.
    pub n_edges: usize,
}

/// An RGB colour buffer with a depth buffer.
pub(crate) struct Canvas {
    /// Width in canvas pixels.
    pub w: usize,
    /// Height in canvas pixels.
    pub h: usize,
    /// Canvas pixels per final pixel (supersampling factor).
    pub ss: f32,
    /// Colours, row-major.
    pub color: Vec<[u8; 3]>,
    /// Depths (larger is nearer), `-inf` where nothing was drawn.
    pub depth: Vec<f32>,
}

impl Canvas {
    /// A canvas cleared to `background`.
    pub(crate) fn new(w: usize, h: usize, ss: u32, background: [u8; 3]) -> Self {
        Canvas {
            w,
            h,
            ss: ss as f32,
            color: vec![background; w * h],
            depth: vec![f32::NEG_INFINITY; w * h],
        }
    }

    /// Rasterizes the triangle `p` (x, y, depth) with `shade`, keeping the
    /// nearest surface at each pixel centre.
    pub(crate) fn fill_triangle(&mut self, p: [[f32; 3]; 3], shade: &Shade) {
        let [v0, mut v1, mut v2] = p;
        if !v0
            .iter()
            .chain(v1.iter())
            .chain(v2.iter())
            .all(|c| c.is_finite())
        {
            return;
        }
        let mut area = (v1[0] - v0[0]) * (v2[1] - v0[1]) - (v1[1] - v0[1]) * (v2[0] - v0[0]);
        if area.abs() < 1e-9 {
            return;
        }
        if area < 0.0 {
            std::mem::swap(&mut v1, &mut v2);
            area = -area;
        }
        let minx = v0[0].min(v1[0]).min(v2[0]).floor().max(0.0);
        let maxx = v0[0].max(v1[0]).max(v2[0]).ceil().min(self.w as f32 - 1.0);
        let miny = v0[1].min(v1[1]).min(v2[1]).floor().max(0.0);
        let maxy = v0[1].max(v1[1]).max(v2[1]).ceil().min(self.h as f32 - 1.0);
        if minx > maxx || miny > maxy {
            return;
        }
        let inv_area = 1.0 / area;
        // Edge function of (a, b) at p: (b − a) × (p − a); positive inside.
        let ef = |a: [f32; 3], b: [f32; 3]| {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            // w(px, py) = dx * (py − ay) − dy * (px − ax) = A px + B py + C
            (-dy, dx, dy * a[0] - dx * a[1])
        };
        let e0 = ef(v1, v2);
        let e1 = ef(v2, v0);
        let e2 = ef(v0, v1);
        let inv_ss = 1.0 / self.ss;
        let edges = &shade.edges[..shade.n_edges.min(4)];
        let any_edge = edges.iter().any(|e| e.alpha > 0.0);
        let (x0, x1, y0, y1) = (minx as usize, maxx as usize, miny as usize, maxy as usize);
        for y in y0..=y1 {
            let py = y as f32 + 0.5;
            let row = y * self.w;
            for x in x0..=x1 {
                let px = x as f32 + 0.5;
                let w0 = e0.0 * px + e0.1 * py + e0.2;
                let w1 = e1.0 * px + e1.1 * py + e1.2;
                let w2 = e2.0 * px + e2.1 * py + e2.2;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = (w0 * v0[2] + w1 * v1[2] + w2 * v2[2]) * inv_area;
                let i = row + x;
                if z <= self.depth[i] {
                    continue;
                }
                self.depth[i] = z;
                let mut c = shade.fill;
                if any_edge {
                    let mut cov: f32 = 0.0;
                    for e in edges {
                        if e.alpha <= 0.0 {
                            continue;
                        }
                        let d = e.distance([px, py]) * inv_ss;
                        let k = (e.half_width + 0.5 - d).clamp(0.0, 1.0) * e.alpha;
                        cov = cov.max(k);
                    }
                    if cov > 0.0 {
                        for (cj, ej) in c.iter_mut().zip(shade.edge_color) {
                            *cj += (ej - *cj) * cov;
                        }
                    }
                }
                self.color[i] = [
                    c[0].clamp(0.0, 255.0) as u8,
                    c[1].clamp(0.0, 255.0) as u8,
                    c[2].clamp(0.0, 255.0) as u8,
                ];
            }
        }
    }

    /// Averages `ss × ss` blocks into an opaque RGBA image of
    /// `w / ss × h / ss` pixels.
    pub(crate) fn downsample(&self, ss: usize) -> (usize, usize, Vec<u8>) {
        let ss = ss.max(1);
        let (ow, oh) = (self.w / ss, self.h / ss);
        let mut out = vec![255u8; ow * oh * 4];
        let n = (ss * ss) as u32;
        for oy in 0..oh {
            for ox in 0..ow {
                let mut acc = [0u32; 3];
                for sy in 0..ss {
                    let row = (oy * ss + sy) * self.w + ox * ss;
                    for c in &self.color[row..row + ss] {
                        acc[0] += c[0] as u32;
                        acc[1] += c[1] as u32;
                        acc[2] += c[2] as u32;
                    }
                }
                let o = (oy * ow + ox) * 4;
                out[o] = ((acc[0] + n / 2) / n) as u8;
                out[o + 1] = ((acc[1] + n / 2) / n) as u8;
                out[o + 2] = ((acc[2] + n / 2) / n) as u8;
            }
        }
        (ow, oh, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(fill: [f32; 3]) -> Shade {
        Shade {
            fill,
            edge_color: [0.0; 3],
            edges: [Edge::default(); 4],
            n_edges: 0,
        }
    }

    #[test]
    fn nearer_triangle_wins_whatever_the_order() {
        for order in [0, 1] {
            let mut c = Canvas::new(20, 20, 1, [255, 255, 255]);
            let far = [[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [0.0, 20.0, 0.0]];
            let near = [[0.0, 0.0, 1.0], [0.0, 20.0, 1.0], [20.0, 0.0, 1.0]]; // clockwise on purpose
            let (a, b) = if order == 0 { (far, near) } else { (near, far) };
            let (sa, sb) = if order == 0 {
                (plain([10.0; 3]), plain([200.0; 3]))
            } else {
                (plain([200.0; 3]), plain([10.0; 3]))
            };
            c.fill_triangle(a, &sa);
            c.fill_triangle(b, &sb);
            assert_eq!(c.color[2 * 20 + 2], [200, 200, 200]);
            assert_eq!(
                c.color[19 * 20 + 19],
                [255, 255, 255],
                "outside stays background"
            );
        }
    }

    #[test]
    fn edges_darken_only_near_the_segment() {
        let mut c = Canvas::new(40, 40, 1, [255, 255, 255]);
        let mut s = plain([200.0; 3]);
        s.edges[0] = Edge::new([0.0, 20.0], [40.0, 20.0], 0.5, 1.0);
        s.n_edges = 1;
        c.fill_triangle([[0.0, 0.0, 0.0], [40.0, 0.0, 0.0], [0.0, 40.0, 0.0]], &s);
        c.fill_triangle([[40.0, 0.0, 0.0], [40.0, 40.0, 0.0], [0.0, 40.0, 0.0]], &s);
        assert!(
            c.color[20 * 40 + 10][0] <= 100 && c.color[19 * 40 + 10][0] <= 100,
            "on the edge: dark"
        );
        assert_eq!(
            c.color[22 * 40 + 10],
            [200, 200, 200],
            "two pixels off the edge: fill"
        );
        assert_eq!(
            c.color[10 * 40 + 10],
            [200, 200, 200],
            "far from the edge: fill"
        );
        let (w, h, img) = c.downsample(2);
        assert_eq!((w, h, img.len()), (20, 20, 20 * 20 * 4));
    }

    #[test]
    fn degenerate_and_offscreen_triangles_are_skipped() {
        let mut c = Canvas::new(10, 10, 1, [0, 0, 0]);
        c.fill_triangle(
            [[1.0, 1.0, 0.0], [2.0, 2.0, 0.0], [3.0, 3.0, 0.0]],
            &plain([9.0; 3]),
        );
        c.fill_triangle(
            [
                [-50.0, -50.0, 0.0],
                [-40.0, -50.0, 0.0],
                [-50.0, -40.0, 0.0],
            ],
            &plain([9.0; 3]),
        );
        c.fill_triangle(
            [[f32::NAN, 1.0, 0.0], [2.0, 2.0, 0.0], [3.0, 1.0, 0.0]],
            &plain([9.0; 3]),
        );
        assert!(c.color.iter().all(|p| *p == [0, 0, 0]));
    }
}
