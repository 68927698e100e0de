//! The orthographic camera of a picture: the view axes and the light from
//! the options, the mesh fitted into the plot rectangle, world → image
//! projection and shading.

use geometry::vec3::{cross, dot, normalize, scale, Vec3};

use super::RenderError;
use crate::quadmesh::QuadMesh;

/// The orthographic camera: world → final-image pixels (x right, y down) and depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Camera {
    pub(super) right: Vec3,
    pub(super) up: Vec3,
    pub(super) eye: Vec3,
    pub(super) light: Vec3,
    pub(super) scale: f64,
    pub(super) offset: [f64; 2],
}

impl Camera {
    /// The camera looking along `-eye_dir`, with `up_hint` (projected; another
    /// axis when it is parallel to `eye_dir`) pointing up, the light above and
    /// a little left of the viewer, and the used nodes of `mesh` fitted into
    /// `plot` (`[x0, y0, x1, y1]`, image pixels).
    pub(super) fn fitted(
        mesh: &QuadMesh,
        eye_dir: Vec3,
        up_hint: Vec3,
        plot: [f64; 4],
    ) -> Result<Camera, RenderError> {
        let eye = normalize(eye_dir)
            .filter(|e| e.iter().all(|c| c.is_finite()))
            .ok_or_else(|| RenderError::InvalidOptions(format!("view direction {:?}", eye_dir)))?;
        let right = [up_hint, [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
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
        Ok(Camera {
            right,
            up,
            eye,
            light,
            scale: s,
            offset,
        })
    }

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
