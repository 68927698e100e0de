//! Chords of CAD curves (quasi-structured paper §4.3, spec §6.3): opposite
//! sides of a 4-sided CAD face should get the same number of mesh edges, or
//! the quad mesh needs an extra pair of irregular vertices to absorb the
//! difference. A chord is a class of curves linked through such faces
//! (union–find); every curve of a chord gets the same count, the rounded mean
//! of their ideal counts.

use geometry::Model;

/// Two opposite curves join a chord only when their ideal counts differ by at
/// most this fraction of the larger one (the spec's τ: "very different" means
/// more than a 2:1 ratio).
pub const CHORD_TOLERANCE: f64 = 0.5;

/// Union–find with path halving.
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// The curves of each 4-sided face taken as opposite pairs: faces with one
/// loop of exactly four uses, none of them a degenerate curve.
pub fn opposite_pairs(model: &Model) -> Vec<[usize; 2]> {
    let mut pairs = Vec::new();
    for f in &model.faces {
        if f.loops.len() != 1 || f.loops[0].uses.len() != 4 {
            continue;
        }
        let c: Vec<usize> = f.loops[0].uses.iter().map(|u| u.curve.idx()).collect();
        if c.iter().any(|&i| model.curves[i].degenerate) {
            continue;
        }
        pairs.push([c[0], c[2]]);
        pairs.push([c[1], c[3]]);
    }
    pairs
}

/// Chord class of every curve (the smallest curve index of its class), given
/// each curve's ideal count `ideal[c]`: opposite curves whose ideal counts
/// differ by at most [`CHORD_TOLERANCE`] × the larger are united.
pub fn chord_classes(model: &Model, ideal: &[f64]) -> Vec<usize> {
    let mut uf = UnionFind((0..model.curves.len()).collect());
    for [a, b] in opposite_pairs(model) {
        if (ideal[a] - ideal[b]).abs() <= CHORD_TOLERANCE * ideal[a].max(ideal[b]) {
            uf.union(a, b);
        }
    }
    (0..model.curves.len()).map(|i| uf.find(i)).collect()
}

/// Counts from ideal counts: each chord gets `round(mean ideal)`, at least 1.
pub fn chord_counts(classes: &[usize], ideal: &[f64]) -> Vec<usize> {
    let n = classes.len();
    let (mut sum, mut num) = (vec![0.0; n], vec![0usize; n]);
    for i in 0..n {
        sum[classes[i]] += ideal[i];
        num[classes[i]] += 1;
    }
    (0..n)
        .map(|i| {
            (sum[classes[i]] / num[classes[i]] as f64)
                .round()
                .clamp(1.0, 1.0e6) as usize
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    /// The paper's example: ideal counts [9.4, 4.1, 10.6, 3.9] on a
    /// rectangle give [10, 4, 10, 4], where plain rounding gives [9, 4, 11, 4].
    #[test]
    fn the_papers_rectangle_gets_equal_opposite_counts() {
        let m = primitives::square(1.0);
        let ideal = [9.4, 4.1, 10.6, 3.9];
        let classes = chord_classes(&m, &ideal);
        assert_eq!(chord_counts(&classes, &ideal), vec![10, 4, 10, 4]);
    }

    #[test]
    fn very_different_opposite_sides_stay_apart() {
        let m = primitives::square(1.0);
        let ideal = [9.0, 4.0, 20.0, 4.0];
        let classes = chord_classes(&m, &ideal);
        assert_eq!(chord_counts(&classes, &ideal), vec![9, 4, 20, 4]);
    }

    /// The lateral face of a cylinder is 4-sided: circle, seam, circle, seam.
    #[test]
    fn cylinder_circles_form_one_chord() {
        let m = primitives::cylinder(1.0, 2.0);
        let classes = chord_classes(&m, &[12.3, 12.4, 2.0]);
        assert_eq!(classes[0], classes[1]);
        assert_ne!(classes[0], classes[2]);
    }
}
