//! Tiny fixed-size vector helpers on `[f64; 3]`, used everywhere geometry is computed.

/// A 3D point or vector.
pub type Vec3 = [f64; 3];

/// `a + b`.
#[inline]
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// `a - b`.
#[inline]
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// `s * a`.
#[inline]
pub fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
/// Dot product.
#[inline]
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// Cross product.
#[inline]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// Euclidean norm.
#[inline]
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}
/// Distance between two points.
#[inline]
pub fn dist(a: Vec3, b: Vec3) -> f64 {
    norm(sub(a, b))
}
/// `a / |a|`, or `None` for a (near) zero vector.
#[inline]
pub fn normalize(a: Vec3) -> Option<Vec3> {
    let n = norm(a);
    if n > 1e-300 && n.is_finite() {
        Some(scale(a, 1.0 / n))
    } else {
        None
    }
}
/// Linear interpolation `a + t (b - a)`.
#[inline]
pub fn lerp(a: Vec3, b: Vec3, t: f64) -> Vec3 {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}

/// Distance from `p` to the segment `ab` (to `a` when the segment is a point).
pub fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    segment_closest(p, a, b).0
}

/// Distance from `p` to the segment `a b` and the parameter in [0, 1] of
/// the segment's point nearest to `p` (0 for a segment of zero length).
pub fn segment_closest(p: Vec3, a: Vec3, b: Vec3) -> (f64, f64) {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let t = if l2 > 0.0 {
        (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (dist(p, add(a, scale(ab, t))), t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_measures_to_the_nearest_point_of_the_segment() {
        let (a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        // above the middle, beyond an end, on the segment, a point segment
        assert_eq!(segment_distance([1.0, 3.0, 0.0], a, b), 3.0);
        assert_eq!(segment_distance([5.0, 0.0, 4.0], a, b), 5.0);
        assert_eq!(segment_distance([0.5, 0.0, 0.0], a, b), 0.0);
        assert_eq!(segment_distance([0.0, 3.0, 4.0], a, a), 5.0);
    }
}
