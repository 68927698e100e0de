//! [`UnionFind`]: disjoint sets over `0..n` with path halving, shared by the
//! curve chords ([`crate::curves::curve_chords`]) and the quad loops of the
//! coarse layout ([`crate::coarse::quad_loops`]).

/// Disjoint sets over `0..n`; each set is represented by its smallest member.
#[derive(Clone, Debug)]
pub(crate) struct UnionFind(Vec<usize>);

impl UnionFind {
    /// `n` singletons.
    pub(crate) fn new(n: usize) -> Self {
        UnionFind((0..n).collect())
    }

    /// The representative of `i`'s set (its smallest member).
    pub(crate) fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_represented_by_their_smallest_member() {
        let mut uf = UnionFind::new(6);
        uf.union(4, 2);
        uf.union(5, 4);
        uf.union(1, 3);
        assert_eq!(
            (0..6).map(|i| uf.find(i)).collect::<Vec<_>>(),
            vec![0, 1, 2, 1, 2, 2]
        );
        uf.union(3, 5);
        assert_eq!(
            (0..6).map(|i| uf.find(i)).collect::<Vec<_>>(),
            vec![0, 1, 1, 1, 1, 1]
        );
    }
}
