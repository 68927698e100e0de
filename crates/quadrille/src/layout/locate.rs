//! Point location in ψ: which triangle of Ω holds a point of the plane and
//! where, so a point of the layout maps back to the shell (barycentric in
//! 3D). A uniform bucket grid over the triangles' boxes; points just outside
//! ψ (on its boundary, up to rounding) go to the nearest triangle.

use crate::cut::CutMesh;
use crate::immersion::Immersion;
use crate::shell::Shell;

/// Locates points of ψ in the triangles of Ω.
#[derive(Clone, Debug)]
pub struct PsiLocator {
    uv: Vec<[f64; 2]>,
    corners: Vec<[usize; 3]>,
    lo: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    buckets: Vec<Vec<u32>>,
    /// ψ repeats with this period along x (an annulus cut open along its seam).
    period_x: Option<f64>,
}

fn barycentric(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 3] {
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if d == 0.0 {
        return [-1.0; 3];
    }
    let l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / d;
    let l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / d;
    [1.0 - l1 - l2, l1, l2]
}

impl PsiLocator {
    /// Buckets the triangles of Ω by their boxes in ψ.
    pub fn new(cut: &CutMesh, imm: &Immersion) -> PsiLocator {
        let uv = imm.uv.clone();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &uv {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let nt = cut.corners.len().max(1);
        let (w, h) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
        let cell = (w * h / nt as f64).sqrt().max(w.max(h) / 4096.0);
        let dims = [
            ((w / cell).ceil() as usize).clamp(1, 4096),
            ((h / cell).ceil() as usize).clamp(1, 4096),
        ];
        let mut buckets = vec![Vec::new(); dims[0] * dims[1]];
        for (f, c) in cut.corners.iter().enumerate() {
            let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for &v in c {
                for k in 0..2 {
                    a[k] = a[k].min(uv[v][k]);
                    b[k] = b[k].max(uv[v][k]);
                }
            }
            let idx = |x: f64, k: usize| (((x - lo[k]) / cell) as usize).min(dims[k] - 1);
            for j in idx(a[1], 1)..=idx(b[1], 1) {
                for i in idx(a[0], 0)..=idx(b[0], 0) {
                    buckets[j * dims[0] + i].push(f as u32);
                }
            }
        }
        PsiLocator {
            uv,
            corners: cut.corners.clone(),
            lo,
            cell,
            dims,
            buckets,
            period_x: None,
        }
    }

    /// The same locator for a ψ that repeats with period `c` along x: a
    /// point outside Ω is looked up again shifted by ±c and ±2c.
    pub fn with_period(mut self, c: f64) -> PsiLocator {
        self.period_x = Some(c);
        self
    }

    /// The triangle of Ω holding `p` and `p`'s barycentric coordinates there
    /// (the nearest triangle, coordinates clamped, when `p` is just outside ψ).
    pub fn locate(&self, p: [f64; 2]) -> Option<(usize, [f64; 3])> {
        let mut best = self.locate_scored(p);
        if let Some(c) = self.period_x {
            for k in [-1.0, 1.0, -2.0, 2.0] {
                if best.is_some_and(|b| b.0 >= -1e-12) {
                    break;
                }
                let shifted = self.locate_scored([p[0] + k * c, p[1]]);
                if shifted.is_some_and(|s| best.is_none_or(|b| s.0 > b.0)) {
                    best = shifted;
                }
            }
        }
        best.map(|(_, f, l)| {
            let l = l.map(|x| x.max(0.0));
            let s = l[0] + l[1] + l[2];
            (f, l.map(|x| x / s))
        })
    }

    /// The best triangle near `p` with its smallest barycentric coordinate
    /// (≥ 0 inside) and the raw coordinates.
    fn locate_scored(&self, p: [f64; 2]) -> Option<(f64, usize, [f64; 3])> {
        let bi = |x: f64, k: usize| -> i64 { ((x - self.lo[k]) / self.cell).floor() as i64 };
        let (ci, cj) = (bi(p[0], 0), bi(p[1], 1));
        let mut best: Option<(f64, usize, [f64; 3])> = None;
        for ring in 0..3i64 {
            for j in cj - ring..=cj + ring {
                for i in ci - ring..=ci + ring {
                    if (i - ci).abs() != ring && (j - cj).abs() != ring {
                        continue;
                    }
                    if i < 0 || j < 0 || i as usize >= self.dims[0] || j as usize >= self.dims[1] {
                        continue;
                    }
                    for &f in &self.buckets[j as usize * self.dims[0] + i as usize] {
                        let c = self.corners[f as usize];
                        let l = barycentric(p, self.uv[c[0]], self.uv[c[1]], self.uv[c[2]]);
                        let worst = l[0].min(l[1]).min(l[2]);
                        if best.is_none_or(|b| worst > b.0) {
                            best = Some((worst, f as usize, l));
                        }
                    }
                }
            }
            if best.is_some_and(|b| b.0 >= -1e-12) {
                break;
            }
        }
        best
    }

    /// The shell point under `p`: barycentric in the 3D triangle, and that
    /// triangle's index.
    pub fn to_shell(&self, shell: &Shell, p: [f64; 2]) -> Option<([f64; 3], usize)> {
        let (f, l) = self.locate(p)?;
        let t = shell.triangles[f];
        let mut x = [0.0; 3];
        for k in 0..3 {
            for m in 0..3 {
                x[m] += l[k] * shell.vertices[t[k]][m];
            }
        }
        Some((x, f))
    }
}
