//! Mutations of a seed file: byte-level (flip, overwrite, insert, delete,
//! duplicate, splice with another seed, truncate) and token-level (a number
//! replaced by an edge value, a line deleted, repeated or swapped), the kinds
//! of damage a truncated download, a hand edit or another tool's bug leaves.

use crate::rng::Rng;

/// Numbers that tend to break readers: zero, negatives, counts past `u32` and
/// `usize`, huge and tiny floats, NaN and infinities.
const EDGE_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "-0",
    "65535",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "99999999999999999999",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e400",
    "0.5",
    "-3",
];

/// A mutant of `seed`: one to four mutations, chosen by `rng`; `others` are
/// the campaign's other seeds (for splicing).
pub fn mutant(seed: &[u8], others: &[Vec<u8>], rng: &mut Rng) -> Vec<u8> {
    let mut data = seed.to_vec();
    let n = 1 + rng.below(4);
    for _ in 0..n {
        mutate_once(&mut data, others, rng);
    }
    data
}

fn mutate_once(data: &mut Vec<u8>, others: &[Vec<u8>], rng: &mut Rng) {
    let len = data.len();
    match rng.below(11) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = rng.next_u64() as u8;
        }
        2 => {
            let i = rng.below(len + 1);
            let k = 1 + rng.below(16);
            let bytes: Vec<u8> = (0..k).map(|_| rng.next_u64() as u8).collect();
            data.splice(i..i, bytes);
        }
        3 if len > 0 => {
            let i = rng.below(len);
            let k = (1 + rng.below(64)).min(len - i);
            data.drain(i..i + k);
        }
        4 if len > 0 => {
            let i = rng.below(len);
            let k = (1 + rng.below(256)).min(len - i);
            let copy = data[i..i + k].to_vec();
            let at = rng.below(data.len() + 1);
            data.splice(at..at, copy);
        }
        5 if !others.is_empty() => {
            let other = &others[rng.below(others.len())];
            let cut = rng.below(len + 1);
            let from = rng.below(other.len() + 1);
            data.truncate(cut);
            data.extend_from_slice(&other[from..]);
        }
        6 if len > 0 => {
            let keep = rng.below(len);
            data.truncate(keep);
        }
        7 | 8 => replace_number(data, rng),
        9 => line_edit(data, rng),
        _ => {
            // a 4- or 8-byte little-endian integer overwritten with an edge
            // value (binary counts and sizes)
            if len >= 8 {
                let i = rng.below(len - 7);
                let v: u64 = match rng.below(5) {
                    0 => 0,
                    1 => u64::MAX,
                    2 => u32::MAX as u64,
                    3 => 1 << 31,
                    _ => rng.next_u64(),
                };
                let w = if rng.one_in(2) { 4 } else { 8 };
                data[i..i + w].copy_from_slice(&v.to_le_bytes()[..w]);
            }
        }
    }
}

/// Replaces one number token (a run of digits with its sign, point and
/// exponent) with an edge value.
fn replace_number(data: &mut Vec<u8>, rng: &mut Rng) {
    // runs of number bytes holding a digit
    let mut runs = Vec::new();
    let mut i = 0;
    while i < data.len() {
        if is_number_byte(data[i]) {
            let s = i;
            while i < data.len() && is_number_byte(data[i]) {
                i += 1;
            }
            if data[s..i].iter().any(u8::is_ascii_digit) {
                runs.push((s, i));
            }
        } else {
            i += 1;
        }
    }
    if runs.is_empty() {
        return;
    }
    let (s, e) = runs[rng.below(runs.len())];
    let value = EDGE_NUMBERS[rng.below(EDGE_NUMBERS.len())];
    data.splice(s..e, value.bytes());
}

fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-')
}

/// Deletes, repeats or swaps whole lines.
fn line_edit(data: &mut Vec<u8>, rng: &mut Rng) {
    let mut lines: Vec<Vec<u8>> = data
        .split_inclusive(|&b| b == b'\n')
        .map(|l| l.to_vec())
        .collect();
    if lines.is_empty() {
        return;
    }
    let i = rng.below(lines.len());
    match rng.below(3) {
        0 => {
            lines.remove(i);
        }
        1 => {
            let l = lines[i].clone();
            for _ in 0..1 + rng.below(3) {
                lines.insert(i, l.clone());
            }
        }
        _ => {
            let j = rng.below(lines.len());
            lines.swap(i, j);
        }
    }
    *data = lines.concat();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutants_are_deterministic_and_differ_from_the_seed() {
        let seed = b"solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nendloop\nendfacet\nendsolid a\n".to_vec();
        let mut changed = 0;
        for case in 0..200 {
            let a = mutant(&seed, &[], &mut Rng::for_case(5, case));
            let b = mutant(&seed, &[], &mut Rng::for_case(5, case));
            assert_eq!(a, b);
            changed += usize::from(a != seed);
        }
        // a mutation can undo itself (a swap of a line with itself), rarely
        assert!(changed > 180, "{changed} of 200 mutants differ");
    }

    #[test]
    fn a_number_is_replaced_whole() {
        let mut data = b"count -12.5e3 end".to_vec();
        let mut rng = Rng::for_case(1, 0);
        replace_number(&mut data, &mut rng);
        let s = String::from_utf8_lossy(&data).to_string();
        assert!(s.starts_with("count ") && s.ends_with(" end"), "{s}");
        let middle = &s["count ".len()..s.len() - " end".len()];
        assert!(EDGE_NUMBERS.contains(&middle), "{middle}");
    }
}
