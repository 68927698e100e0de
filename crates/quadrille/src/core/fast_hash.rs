//! Hash maps keyed by small integers (node, quad and cell numbers) with a
//! hasher of one multiply per word instead of the standard SipHash: the
//! frontal point grid, the face triangulation's refinement and the curve
//! slide's overlays look keys up in their inner loops, where SipHash showed
//! as 4–6 % of a run in the profile. Not for keys an adversary chooses.
//!
//! No output depends on a map's iteration order (the standard maps are
//! randomly seeded per process, and runs are byte-identical), so swapping
//! the hasher changes speed only.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// A `HashMap` hashed by [`WordHasher`].
pub type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<WordHasher>>;

/// A `HashSet` hashed by [`WordHasher`].
pub type FastSet<K> = HashSet<K, BuildHasherDefault<WordHasher>>;

/// Multiplicative hashing, one 64-bit word at a time: the state is rotated,
/// xored with the word and multiplied by 2⁶⁴/φ; `finish` folds the high
/// half into the low bits, which pick the bucket.
#[derive(Default, Clone, Copy)]
pub struct WordHasher(u64);

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

impl WordHasher {
    fn mix(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(GOLDEN);
    }
}

impl Hasher for WordHasher {
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 32)
    }
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.mix(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.mix(u64::from_le_bytes(w) ^ ((rest.len() as u64) << 56));
        }
    }
    fn write_u8(&mut self, x: u8) {
        self.mix(u64::from(x));
    }
    fn write_u32(&mut self, x: u32) {
        self.mix(u64::from(x));
    }
    fn write_u64(&mut self, x: u64) {
        self.mix(x);
    }
    fn write_i64(&mut self, x: i64) {
        self.mix(x as u64);
    }
    fn write_usize(&mut self, x: usize) {
        self.mix(x as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::{BuildHasher, Hash};

    fn hash<T: Hash>(x: &T) -> u64 {
        BuildHasherDefault::<WordHasher>::default().hash_one(x)
    }

    #[test]
    fn maps_find_what_they_hold() {
        let mut m: FastMap<[i64; 3], u32> = FastMap::default();
        for i in -20..20i64 {
            for j in -20..20i64 {
                m.insert([i, j, i * j], (i * 100 + j) as u32);
            }
        }
        assert_eq!(m.len(), 1600);
        assert_eq!(m.get(&[-3, 7, -21]), Some(&((-300 + 7) as u32)));
        assert_eq!(m.get(&[-3, 7, 21]), None);
        let s: FastSet<(u32, u32)> = (0..1000u32).map(|i| (i, i + 1)).collect();
        assert!(s.contains(&(499, 500)) && !s.contains(&(500, 499)));
    }

    #[test]
    fn neighbouring_keys_spread_over_the_low_bits() {
        // cells of a grid, keys that differ in one coordinate: the low 10 bits
        // (a table of 1024 buckets) must not collapse onto a few values
        let mut buckets = std::collections::BTreeSet::new();
        for i in 0..32i64 {
            for j in 0..32i64 {
                buckets.insert(hash(&[i, j, 0i64]) & 1023);
            }
        }
        assert!(
            buckets.len() > 600,
            "{} distinct buckets of 1024",
            buckets.len()
        );
        // a trailing partial word counts: these two byte strings differ
        let mut a = WordHasher::default();
        a.write(&[1, 2, 3]);
        let mut b = WordHasher::default();
        b.write(&[1, 2, 3, 0]);
        assert_ne!(a.finish(), b.finish());
    }
}
