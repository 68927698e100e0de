//! A cross field sampled on a background triangulation, as `quadrille field`
//! writes it ([`crate::vtu::write_field_vtu`]) and draws it ([`render_field_png`]).
//!
//! The data is plain: triangles of all faces with their face, one unit
//! branch direction of the cross per triangle (the other branch is its
//! rotation by 90° about the triangle normal), an optional size per triangle,
//! and the singularities (position, index, face). Pictures show the shaded
//! triangulation (without its element edges, which would hide the glyphs)
//! with the CAD curves (boundary edges of each face's triangulation) drawn
//! thicker, cross glyphs (two short orthogonal segments) at the centroids of
//! an even subsample of triangles (no two closer than a spacing), and the
//! singularities as dots coloured by index: +1 blue, −1 red (the colours of
//! valence-3 and valence-5 vertices in mesh pictures), others orange.

use std::collections::HashMap;
use std::path::Path;

use geometry::vec3::{add, cross, dist, normalize, scale, sub, Vec3};
use geometry::{CurveId, FaceId};

use crate::quadmesh::{NodeClass, QuadMesh};
use crate::render::{self, Overlay, OverlayPoint, OverlaySegment, RenderError, RenderOptions};

/// One singularity of a cross field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSingularity {
    /// Its 3D position.
    pub position: Vec3,
    /// Its index in quad-mesh units (+1 ↔ valence 3, −1 ↔ valence 5).
    pub index: i32,
    /// The CAD face it belongs to.
    pub face: FaceId,
}

/// A cross field on the background triangulation of a model's faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CrossFieldMesh {
    /// Node positions (each face has its own nodes).
    pub nodes: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from their face's oriented normal.
    pub triangles: Vec<[u32; 3]>,
    /// The CAD face of each triangle.
    pub triangle_face: Vec<FaceId>,
    /// One unit branch direction of the cross at each triangle's centroid
    /// (`None` where the field vanishes, at a singularity).
    pub cross: Vec<Option<Vec3>>,
    /// A target size per triangle (the conformal size map), when known.
    pub size: Option<Vec<f64>>,
    /// The singularities.
    pub singularities: Vec<FieldSingularity>,
}

/// Colour of a singularity of index `k` in pictures: +1 blue, −1 red, others orange.
pub fn singularity_color(k: i32) -> [u8; 3] {
    match k {
        1 => render::valence_color(3),
        -1 => render::valence_color(5),
        _ => render::valence_color(2),
    }
}

/// Colour of the cross glyphs.
const GLYPH: [u8; 3] = [20, 24, 60];

impl CrossFieldMesh {
    /// Checks lengths, indices and finiteness; returns the first problem.
    pub fn check(&self) -> Result<(), String> {
        let (n, nt) = (self.nodes.len(), self.triangles.len());
        if self.triangle_face.len() != nt {
            return Err(format!(
                "{} triangle faces for {nt} triangles",
                self.triangle_face.len()
            ));
        }
        if self.cross.len() != nt {
            return Err(format!(
                "{} cross directions for {nt} triangles",
                self.cross.len()
            ));
        }
        if let Some(s) = &self.size {
            if s.len() != nt {
                return Err(format!("{} sizes for {nt} triangles", s.len()));
            }
        }
        if let Some(i) = self
            .nodes
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(format!(
                "node {i} has non-finite coordinates {:?}",
                self.nodes[i]
            ));
        }
        if let Some(i) = self
            .triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= n))
        {
            return Err(format!(
                "triangle {i} {:?} refers to a node beyond the {n} nodes",
                self.triangles[i]
            ));
        }
        if let Some(i) = self
            .cross
            .iter()
            .position(|c| c.is_some_and(|d| !d.iter().all(|x| x.is_finite())))
        {
            return Err(format!("triangle {i} has a non-finite cross direction"));
        }
        if let Some(i) = self
            .singularities
            .iter()
            .position(|s| !s.position.iter().all(|c| c.is_finite()))
        {
            return Err(format!("singularity {i} has non-finite coordinates"));
        }
        Ok(())
    }

    /// Number of singularities of index `k`.
    pub fn count(&self, k: i32) -> usize {
        self.singularities.iter().filter(|s| s.index == k).count()
    }

    /// The triangulation as a (triangle-only) [`QuadMesh`] for the renderer;
    /// the boundary edges of each face's triangulation (its CAD curves) are
    /// its curve edges, so they are drawn thicker.
    pub fn surface(&self) -> QuadMesh {
        let curve_edges = self
            .boundary_edges()
            .into_iter()
            .map(|e| (e, CurveId(0)))
            .collect();
        QuadMesh {
            nodes: self.nodes.clone(),
            node_class: vec![NodeClass::Unclassified; self.nodes.len()],
            triangles: self.triangles.clone(),
            triangle_face: self.triangle_face.clone(),
            curve_edges,
            ..Default::default()
        }
    }

    /// Edges used by one triangle only (`[low, high]` node ids, sorted): the
    /// boundaries of the faces' triangulations, i.e. their CAD curves.
    pub fn boundary_edges(&self) -> Vec<[u32; 2]> {
        let mut uses: HashMap<[u32; 2], u32> = HashMap::new();
        for t in &self.triangles {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                *uses.entry([a.min(b), a.max(b)]).or_insert(0) += 1;
            }
        }
        let mut out: Vec<[u32; 2]> = uses
            .into_iter()
            .filter(|&(_, n)| n == 1)
            .map(|(e, _)| e)
            .collect();
        out.sort_unstable();
        out
    }

    /// Centroid and unit normal of triangle `t` (`None` for a degenerate one).
    fn centroid_normal(&self, t: usize) -> (Vec3, Option<Vec3>) {
        let p = self.triangles[t].map(|v| self.nodes[v as usize]);
        let c = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
        (c, normalize(cross(sub(p[1], p[0]), sub(p[2], p[0]))))
    }

    /// Triangles chosen for glyphs, in triangle order: a triangle with a
    /// cross and no node on a face boundary (so that glyphs do not stick out
    /// of their face) is kept when its centroid is at least `spacing` away
    /// from the centroids of all triangles kept before it. So glyphs never
    /// crowd, and every such triangle is within `spacing` of a glyph.
    pub fn glyph_triangles(&self, spacing: f64) -> Vec<usize> {
        if !(spacing.is_finite() && spacing > 0.0) {
            return Vec::new();
        }
        let mut on_boundary = vec![false; self.nodes.len()];
        for e in self.boundary_edges() {
            on_boundary[e[0] as usize] = true;
            on_boundary[e[1] as usize] = true;
        }
        let mut grid: HashMap<[i64; 3], Vec<Vec3>> = HashMap::new();
        let mut out = Vec::new();
        for t in 0..self.triangles.len() {
            if self.cross[t].is_none() || self.triangles[t].iter().any(|&v| on_boundary[v as usize])
            {
                continue;
            }
            let (c, _) = self.centroid_normal(t);
            let cell = c.map(|x| (x / spacing).floor() as i64);
            let crowded = (-1..=1).any(|i| {
                (-1..=1).any(|j| {
                    (-1..=1).any(|k| {
                        grid.get(&[cell[0] + i, cell[1] + j, cell[2] + k])
                            .is_some_and(|ps| ps.iter().any(|&p| dist(p, c) < spacing))
                    })
                })
            });
            if !crowded {
                grid.entry(cell).or_default().push(c);
                out.push(t);
            }
        }
        out
    }

    /// The picture overlay: a cross glyph (two segments of half-length
    /// `0.38 · spacing`) at each of [`Self::glyph_triangles`], the
    /// singularities as dots, and a legend with their counts.
    pub fn overlay(&self, spacing: f64) -> Overlay {
        let half = 0.38 * spacing;
        let mut segments = Vec::new();
        for t in self.glyph_triangles(spacing) {
            let (c, n) = self.centroid_normal(t);
            let (Some(d1), Some(n)) = (self.cross[t], n) else {
                continue;
            };
            let d2 = cross(n, d1);
            for d in [d1, d2] {
                segments.push(OverlaySegment {
                    a: add(c, scale(d, -half)),
                    b: add(c, scale(d, half)),
                    color: GLYPH,
                    normal: Some(n),
                });
            }
        }
        let points = self
            .singularities
            .iter()
            .map(|s| OverlayPoint {
                position: s.position,
                color: singularity_color(s.index),
            })
            .collect();
        let mut legend = vec![
            (
                singularity_color(1),
                format!("index +1 (valence 3): {}", self.count(1)),
            ),
            (
                singularity_color(-1),
                format!("index -1 (valence 5): {}", self.count(-1)),
            ),
        ];
        let others = self.singularities.len() - self.count(1) - self.count(-1);
        if others > 0 {
            legend.push((singularity_color(2), format!("other: {others}")));
        }
        Overlay {
            segments,
            points,
            legend,
            ..Default::default()
        }
    }
}

/// Draws `field` (see the module documentation) with glyph spacing
/// `spacing` (model units) and writes the PNG atomically to `path`. `opts`
/// gives the picture size, view and title; its overlay is replaced.
pub fn render_field_png(
    field: &CrossFieldMesh,
    spacing: f64,
    opts: &RenderOptions,
    path: &Path,
) -> Result<(), RenderError> {
    field.check().map_err(RenderError::InvalidMesh)?;
    let mut overlay = field.overlay(spacing);
    let k = ((opts.width.min(opts.height) as f32 / 600.0).round()).max(1.0);
    overlay.line_width = 1.2 * k;
    overlay.point_radius = 5.0 * k;
    // element edges would hide the glyphs; CAD curves stay
    let opts = RenderOptions {
        overlay: Some(&overlay),
        show_irregular: false,
        show_edges: false,
        ..opts.clone()
    };
    render::render_png(&field.surface(), &opts, path)
}

/// Draws the size map of `field` (its per-triangle `size`) as colours, red
/// for the smallest sizes to green for the largest (value = size / largest
/// size, named on the colour bar), with the singularities as dots, and writes
/// the PNG atomically to `path`. Fails when the field has no size map.
pub fn render_size_png(
    field: &CrossFieldMesh,
    opts: &RenderOptions,
    path: &Path,
) -> Result<(), RenderError> {
    field.check().map_err(RenderError::InvalidMesh)?;
    let sizes = field
        .size
        .as_ref()
        .ok_or_else(|| RenderError::InvalidOptions("the field has no size map".into()))?;
    let largest = sizes
        .iter()
        .copied()
        .filter(|s| s.is_finite())
        .fold(0.0, f64::max);
    if !(largest > 0.0) {
        return Err(RenderError::InvalidOptions(
            "the size map has no positive value".into(),
        ));
    }
    let values: Vec<f64> = sizes
        .iter()
        .map(|&s| if s.is_finite() { s / largest } else { f64::NAN })
        .collect();
    let label = format!("size / {largest:.3}");
    let mut overlay = field.overlay(f64::INFINITY);
    overlay.segments.clear();
    let k = ((opts.width.min(opts.height) as f32 / 600.0).round()).max(1.0);
    overlay.point_radius = 5.0 * k;
    let opts = RenderOptions {
        overlay: Some(&overlay),
        triangle_values: Some(&values),
        values_label: &label,
        show_irregular: false,
        show_edges: false,
        ..opts.clone()
    };
    render::render_png(&field.surface(), &opts, path)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::render::render_image;

    /// The unit square `[0, 1]²` split into `2n²` triangles, crosses along the
    /// axes, one +1 singularity at the centre and one −1 at (0.25, 0.25).
    pub(crate) fn square_field(n: usize) -> CrossFieldMesh {
        let mut f = CrossFieldMesh::default();
        for j in 0..=n {
            for i in 0..=n {
                f.nodes
                    .push([i as f64 / n as f64, j as f64 / n as f64, 0.0]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                f.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                f.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let nt = f.triangles.len();
        f.triangle_face = vec![FaceId(0); nt];
        f.cross = vec![Some([1.0, 0.0, 0.0]); nt];
        f.size = Some((0..nt).map(|t| 0.1 + t as f64 / nt as f64).collect());
        f.singularities = vec![
            FieldSingularity {
                position: [0.5, 0.5, 0.0],
                index: 1,
                face: FaceId(0),
            },
            FieldSingularity {
                position: [0.25, 0.25, 0.0],
                index: -1,
                face: FaceId(0),
            },
        ];
        f
    }

    #[test]
    fn check_finds_inconsistent_data() {
        let f = square_field(4);
        assert!(f.check().is_ok());
        let mut bad = f.clone();
        bad.cross.pop();
        assert!(bad.check().unwrap_err().contains("cross"));
        let mut bad = f.clone();
        bad.triangles[3][1] = 999;
        assert!(bad.check().unwrap_err().contains("triangle 3"));
        let mut bad = f.clone();
        bad.size = Some(vec![1.0]);
        assert!(bad.check().unwrap_err().contains("sizes"));
    }

    #[test]
    fn surface_marks_the_boundary_as_curve_edges() {
        let f = square_field(4);
        let m = f.surface();
        assert_eq!(m.triangles.len(), 32);
        assert_eq!(m.curve_edges.len(), 16, "the square's 4 × 4 boundary edges");
    }

    #[test]
    fn glyphs_are_an_even_subsample_with_orthogonal_arms() {
        let f = square_field(20);
        let all = f.glyph_triangles(1e-3);
        // every triangle except those with a node on the square's boundary
        let inner: Vec<usize> = (0..f.triangles.len())
            .filter(|&t| {
                f.triangles[t].iter().all(|&v| {
                    let p = f.nodes[v as usize];
                    p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.0
                })
            })
            .collect();
        assert_eq!(
            all, inner,
            "a tiny spacing keeps every triangle off the boundary"
        );
        let some = f.glyph_triangles(0.25);
        let centroid = |t: usize| f.centroid_normal(t).0;
        for (i, &a) in some.iter().enumerate() {
            for &b in &some[i + 1..] {
                assert!(dist(centroid(a), centroid(b)) >= 0.25);
            }
        }
        for &t in &inner {
            assert!(
                some.iter().any(|&g| dist(centroid(g), centroid(t)) < 0.25),
                "triangle {t} far from every glyph"
            );
        }
        assert!(
            (9..=30).contains(&some.len()),
            "{} glyphs on the unit square at spacing 0.25",
            some.len()
        );
        let o = f.overlay(0.25);
        assert_eq!(o.segments.len(), 2 * some.len());
        for pair in o.segments.chunks(2) {
            let (d1, d2) = (sub(pair[0].b, pair[0].a), sub(pair[1].b, pair[1].a));
            assert!(geometry::vec3::dot(d1, d2).abs() < 1e-12);
            assert!((geometry::vec3::norm(d1) - 2.0 * 0.38 * 0.25).abs() < 1e-12);
        }
        assert_eq!(o.points.len(), 2);
        assert_eq!(o.points[0].color, singularity_color(1));
        assert!(o.legend[0].1.ends_with(": 1") && o.legend[1].1.ends_with(": 1"));
    }

    #[test]
    fn picture_shows_glyphs_dots_and_legend() {
        let f = square_field(16);
        let mut overlay = f.overlay(0.125);
        overlay.point_radius = 6.0;
        let base = RenderOptions {
            width: 400,
            height: 400,
            eye_dir: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            show_info: false,
            ..Default::default()
        };
        let with = render_image(
            &f.surface(),
            &RenderOptions {
                overlay: Some(&overlay),
                ..base.clone()
            },
        )
        .unwrap();
        let without = render_image(&f.surface(), &base).unwrap();
        let near = |p: &[u8], c: [u8; 3]| (0..3).all(|i| (p[i] as i32 - c[i] as i32).abs() < 30);
        let count = |img: &render::RenderedImage, c: [u8; 3]| {
            img.rgba.chunks(4).filter(|p| near(p, c)).count()
        };
        // dots: blue and red pixels appear (in the plot and in the legend)
        assert!(count(&with, singularity_color(1)) > 50);
        assert!(count(&with, singularity_color(-1)) > 50);
        assert_eq!(count(&without, singularity_color(1)), 0);
        // glyphs: many more dark pixels than the plain triangulation has
        let dark = |img: &render::RenderedImage| {
            img.rgba
                .chunks(4)
                .filter(|p| (p[0] as u32 + p[1] as u32 + p[2] as u32) < 200)
                .count()
        };
        assert!(
            dark(&with) > dark(&without) + 1000,
            "{} vs {}",
            dark(&with),
            dark(&without)
        );
    }

    /// The size picture colours small sizes red and large ones green, and
    /// refuses a field without sizes.
    #[test]
    fn size_picture_colours_by_size() {
        // the square's size grows with the triangle index: small at y = 0, large at y = 1
        let f = square_field(16);
        let dir = std::env::temp_dir().join(format!("quadrille-size-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("size.png");
        let opts = RenderOptions {
            width: 400,
            height: 400,
            eye_dir: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            show_info: false,
            ..Default::default()
        };
        render_size_png(&f, &opts, &path).unwrap();
        let img = tiny_skia::Pixmap::decode_png(&std::fs::read(&path).unwrap()).unwrap();
        // the pixel column through the middle of the picture crosses the square
        let (w, h) = (img.width() as usize, img.height() as f64);
        let column: Vec<[u8; 3]> = (0..img.height() as usize)
            .map(|y| {
                let p = &img.data()[4 * (y * w + w / 2)..];
                [p[0], p[1], p[2]]
            })
            .collect();
        let coloured: Vec<usize> = (0..column.len())
            .filter(|&y| {
                let c = column[y];
                (c[0] as i32 - c[1] as i32).abs() > 40
            })
            .collect();
        assert!(
            coloured.len() as f64 > 0.3 * h,
            "only {} coloured rows",
            coloured.len()
        );
        let (top, bottom) = (column[coloured[2]], column[coloured[coloured.len() - 3]]);
        // image rows go down, so the top of the picture is y = 1 (large sizes: green)
        assert!(top[1] > top[0], "large sizes are green: {top:?}");
        assert!(bottom[0] > bottom[1], "small sizes are red: {bottom:?}");
        let mut no_size = f.clone();
        no_size.size = None;
        assert!(matches!(
            render_size_png(&no_size, &opts, &dir.join("none.png")),
            Err(RenderError::InvalidOptions(_))
        ));
        assert!(!dir.join("none.png").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn glyphs_seen_at_a_grazing_angle_are_left_out() {
        let f = square_field(16);
        let mut overlay = f.overlay(0.125);
        overlay.points.clear();
        overlay.legend.clear();
        let opts = |eye: Vec3| RenderOptions {
            width: 300,
            height: 300,
            eye_dir: eye,
            up: [0.0, 0.0, 1.0],
            show_info: false,
            ..Default::default()
        };
        let draw = |eye: Vec3, o: Option<&Overlay>| {
            render_image(
                &f.surface(),
                &RenderOptions {
                    overlay: o,
                    ..opts(eye)
                },
            )
            .unwrap()
            .rgba
        };
        // seen 11° above its plane: the glyphs would crowd, so none is drawn
        let grazing = [1.0, 0.3, 0.2];
        assert_eq!(draw(grazing, Some(&overlay)), draw(grazing, None));
        // seen from 60° above: drawn
        let steep = [0.3, 0.2, 1.0];
        assert_ne!(draw(steep, Some(&overlay)), draw(steep, None));
    }

    #[test]
    fn overlay_behind_the_surface_is_hidden() {
        // a square at z = 0 with its field, covered by an opaque square at z = 1
        let f = square_field(8);
        let mut cover = f.surface();
        let n = cover.nodes.len() as u32;
        cover
            .nodes
            .extend(f.nodes.iter().map(|p| [p[0], p[1], 1.0]));
        cover
            .node_class
            .extend(vec![NodeClass::Unclassified; f.nodes.len()]);
        cover
            .triangles
            .extend(f.triangles.iter().map(|t| t.map(|v| v + n)));
        cover.triangle_face.extend(f.triangle_face.iter().copied());
        let mut overlay = f.overlay(0.125);
        overlay.legend.clear();
        let opts = RenderOptions {
            width: 300,
            height: 300,
            eye_dir: [0.0, 0.0, 1.0],
            up: [0.0, 1.0, 0.0],
            show_info: false,
            ..Default::default()
        };
        let img = render_image(
            &cover,
            &RenderOptions {
                overlay: Some(&overlay),
                ..opts
            },
        )
        .unwrap();
        let blue = singularity_color(1);
        assert!(
            !img.rgba
                .chunks(4)
                .any(|p| (0..3).all(|i| (p[i] as i32 - blue[i] as i32).abs() < 20)),
            "hidden dot drawn"
        );
    }
}
