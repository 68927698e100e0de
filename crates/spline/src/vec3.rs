//! 3-vector helpers on `[f64; 3]`: the workspace's [`geometry::vec3`], plus
//! the accumulation step of every evaluation.

pub use geometry::vec3::{add, cross, dist, dot, norm, scale, sub, Vec3};

/// A point in space.
pub type Point3 = [f64; 3];

/// `a + k · b`, the accumulation step of every evaluation.
pub fn axpy(a: Vec3, k: f64, b: Vec3) -> Vec3 {
    [a[0] + k * b[0], a[1] + k * b[1], a[2] + k * b[2]]
}
