//! Stable roommates (spec §3, paper §3.1.3): Irving's two-phase algorithm
//! on strict preference lists, and the cost-matrix front end that leaves one
//! segment out when the count is odd and finds odd parties (ties) first.

use std::collections::VecDeque;

/// No stable matching exists: the agents of the odd cycle (phase 1) or of
/// the rotation whose elimination emptied a list (phase 2), ascending.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NoStableMatching {
    /// The phase that failed (1 or 2).
    pub phase: u8,
    /// The agents of the odd party or rotation, ascending.
    pub agents: Vec<usize>,
}

/// Irving's stable roommates on complete strict preference lists: `prefs[x]`
/// lists every other agent, most preferred first; the count must be even
/// (callers add a dummy). Returns each agent's mate.
pub fn irving(prefs: &[Vec<usize>]) -> Result<Vec<usize>, NoStableMatching> {
    let n = prefs.len();
    let mut rank = vec![vec![usize::MAX; n]; n];
    let mut alive = vec![vec![false; n]; n];
    for (x, list) in prefs.iter().enumerate() {
        for (r, &y) in list.iter().enumerate() {
            rank[x][y] = r;
            alive[x][y] = true;
        }
    }
    let table = Table { prefs, rank: &rank };
    // Phase 1: proposals.
    let mut holds: Vec<Option<usize>> = vec![None; n];
    let mut queue: VecDeque<usize> = (0..n).collect();
    while let Some(x) = queue.pop_front() {
        let Some(y) = table.nth_alive(&alive, x, 0) else {
            return Err(NoStableMatching { phase: 1, agents: proposal_cycle(&holds, x) });
        };
        match holds[y] {
            None => holds[y] = Some(x),
            Some(z) if rank[y][x] < rank[y][z] => {
                holds[y] = Some(x);
                delete(&mut alive, y, z);
                queue.push_back(z);
            }
            Some(_) => {
                delete(&mut alive, x, y);
                queue.push_back(x);
            }
        }
    }
    for y in 0..n {
        if let Some(x) = holds[y] {
            for &w in &prefs[y][rank[y][x] + 1..] {
                delete(&mut alive, y, w);
            }
        }
    }
    if let Some(x) = (0..n).find(|&x| table.count_alive(&alive, x) == 0) {
        return Err(NoStableMatching { phase: 1, agents: vec![x] });
    }
    // Phase 2: eliminate rotations until every list has one entry.
    while let Some(p) = (0..n).find(|&x| table.count_alive(&alive, x) >= 2) {
        let mut seq = Vec::new();
        let mut pos = vec![usize::MAX; n];
        let mut x = p;
        let cycle_from = loop {
            if pos[x] != usize::MAX {
                break pos[x];
            }
            pos[x] = seq.len();
            seq.push(x);
            let Some(q) = table.nth_alive(&alive, x, 1) else {
                return Err(NoStableMatching { phase: 2, agents: sorted(seq) });
            };
            let Some(next) = table.last_alive(&alive, q) else {
                return Err(NoStableMatching { phase: 2, agents: sorted(seq) });
            };
            x = next;
        };
        let rotation: Vec<usize> = seq[cycle_from..].to_vec();
        let seconds: Vec<usize> =
            rotation.iter().map(|&x| table.nth_alive(&alive, x, 1).unwrap_or(x)).collect();
        for (&xi, &y_next) in rotation.iter().zip(&seconds) {
            for &w in &prefs[y_next][rank[y_next][xi] + 1..] {
                delete(&mut alive, y_next, w);
            }
        }
        if (0..n).any(|a| table.count_alive(&alive, a) == 0) {
            return Err(NoStableMatching { phase: 2, agents: sorted(rotation) });
        }
    }
    let mate: Vec<usize> = (0..n).map(|x| table.nth_alive(&alive, x, 0).unwrap_or(x)).collect();
    if (0..n).any(|x| mate[mate[x]] != x || mate[x] == x) {
        return Err(NoStableMatching { phase: 2, agents: (0..n).filter(|&x| mate[mate[x]] != x).collect() });
    }
    Ok(mate)
}

/// Preference lists and ranks, read through the `alive` pairs.
struct Table<'a> {
    prefs: &'a [Vec<usize>],
    rank: &'a [Vec<usize>],
}

impl Table<'_> {
    fn nth_alive(&self, alive: &[Vec<bool>], x: usize, k: usize) -> Option<usize> {
        self.prefs[x].iter().copied().filter(|&y| alive[x][y]).nth(k)
    }
    fn last_alive(&self, alive: &[Vec<bool>], x: usize) -> Option<usize> {
        self.prefs[x].iter().rev().copied().find(|&y| alive[x][y])
    }
    fn count_alive(&self, alive: &[Vec<bool>], x: usize) -> usize {
        let _ = self.rank;
        self.prefs[x].iter().filter(|&&y| alive[x][y]).count()
    }
}

fn delete(alive: &mut [Vec<bool>], a: usize, b: usize) {
    alive[a][b] = false;
    alive[b][a] = false;
}

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v.dedup();
    v
}

/// When phase 1 fails at `stuck`: the cycle of held proposals (an odd party,
/// e.g. a→b→c→a in Irving's 4-agent example), else `stuck` alone.
fn proposal_cycle(holds: &[Option<usize>], stuck: usize) -> Vec<usize> {
    for start in 0..holds.len() {
        let mut seen = vec![usize::MAX; holds.len()];
        let mut path = Vec::new();
        let mut x = start;
        while let Some(y) = holds[x] {
            if seen[x] != usize::MAX {
                return sorted(path[seen[x]..].to_vec());
            }
            seen[x] = path.len();
            path.push(x);
            x = y;
        }
    }
    vec![stuck]
}

/// The result of matching segments by a symmetric cost matrix.
#[derive(Clone, Debug, PartialEq)]
pub enum MatchOutcome {
    /// A stable matching: each segment's mate, `None` for the one segment
    /// left out when the count is odd.
    Matched(Vec<Option<usize>>),
    /// No stable matching without an arbitrary tie-break: the segments of the
    /// odd party (an odd set of segments tied for each other), or of the
    /// rotation Irving's phase 2 could not eliminate. Ascending.
    OddParty(Vec<usize>),
}

/// Two costs are tied when they differ by at most `rel` of the larger one
/// (or of `floor`, for costs near zero).
fn tied(a: f64, b: f64, rel: f64, floor: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(floor)
}

/// The odd party of a symmetric cost matrix, if any: going up the costs as
/// the greedy matching does, a group of tied cheapest pairs among free
/// segments whose tie graph has a component of odd size ≥ 3 (an equilateral
/// triangle's three sides). Found before any tie-break by index, which would
/// hide it.
pub fn find_odd_party(c: &[Vec<f64>], rel: f64) -> Option<Vec<usize>> {
    let n = c.len();
    let floor = c.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())) * 1e-6;
    let mut free = vec![true; n];
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for i in 0..n {
            for j in i + 1..n {
                if free[i] && free[j] && best.is_none_or(|(b, _, _)| c[i][j] < b) {
                    best = Some((c[i][j], i, j));
                }
            }
        }
        let (m, bi, bj) = best?;
        // The tie graph of the cheapest group, its components by union-find.
        let mut parent: Vec<usize> = (0..n).collect();
        let mut in_group = vec![false; n];
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for i in 0..n {
            for j in i + 1..n {
                if free[i] && free[j] && tied(c[i][j], m, rel, floor) {
                    in_group[i] = true;
                    in_group[j] = true;
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut size = vec![0usize; n];
        for i in (0..n).filter(|&i| in_group[i]) {
            let r = root(&mut parent, i);
            size[r] += 1;
        }
        if let Some(r) = (0..n).find(|&r| size[r] >= 3 && size[r] % 2 == 1) {
            return Some((0..n).filter(|&i| in_group[i] && root(&mut parent, i) == r).collect());
        }
        free[bi] = false;
        free[bj] = false;
    }
}

/// Stable matching of segments by a symmetric cost matrix (lower is
/// preferred): odd parties first (ties within `tie_rel`), then Irving on
/// lists ordered by (cost, index). With an odd count a dummy that everyone
/// ranks last takes the segment whose best cost is worst.
pub fn match_by_cost(c: &[Vec<f64>], tie_rel: f64) -> MatchOutcome {
    let n = c.len();
    if n < 2 {
        return MatchOutcome::Matched(vec![None; n]);
    }
    if let Some(party) = find_odd_party(c, tie_rel) {
        return MatchOutcome::OddParty(party);
    }
    let m = n + n % 2;
    let mut prefs: Vec<Vec<usize>> = (0..n)
        .map(|x| {
            let mut l: Vec<usize> = (0..n).filter(|&y| y != x).collect();
            l.sort_by(|&a, &b| c[x][a].total_cmp(&c[x][b]).then(a.cmp(&b)));
            if m > n {
                l.push(n);
            }
            l
        })
        .collect();
    if m > n {
        let best = |x: usize| (0..n).filter(|&y| y != x).map(|y| c[x][y]).fold(f64::INFINITY, f64::min);
        let mut l: Vec<usize> = (0..n).collect();
        l.sort_by(|&a, &b| best(b).total_cmp(&best(a)).then(a.cmp(&b)));
        prefs.push(l);
    }
    match irving(&prefs) {
        Ok(mate) => MatchOutcome::Matched((0..n).map(|x| (mate[x] < n).then_some(mate[x])).collect()),
        Err(e) => MatchOutcome::OddParty(e.agents.into_iter().filter(|&a| a < n).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small xorshift generator, seeded, so the oracle test is repeatable.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The greedy cheapest-pair matching, written independently of the code
    /// under test: sort all pairs, take each whose two ends are free.
    fn greedy(c: &[Vec<f64>]) -> Vec<Option<usize>> {
        let n = c.len();
        let mut pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j))).collect();
        pairs.sort_by(|a, b| c[a.0][a.1].partial_cmp(&c[b.0][b.1]).unwrap());
        let mut mate = vec![None; n];
        for (i, j) in pairs {
            if mate[i].is_none() && mate[j].is_none() {
                mate[i] = Some(j);
                mate[j] = Some(i);
            }
        }
        mate
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn irving_equals_greedy_on_10000_random_symmetric_matrices() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut odd_sizes = 0;
        for _ in 0..10_000 {
            let n = 2 + (rng.next() % 15) as usize;
            let mut c = vec![vec![0.0; n]; n];
            for i in 0..n {
                for j in i + 1..n {
                    let v = rng.unit();
                    c[i][j] = v;
                    c[j][i] = v;
                }
            }
            odd_sizes += n % 2;
            let got = match_by_cost(&c, 1e-12);
            assert_eq!(got, MatchOutcome::Matched(greedy(&c)), "n = {n}");
        }
        assert!(odd_sizes > 3000, "odd sizes were drawn: {odd_sizes}");
    }

    #[test]
    fn irvings_four_agent_instance_has_no_stable_matching() {
        // Irving 1985: a: b c d, b: c a d, c: a b d, d: any order.
        let prefs = vec![vec![1, 2, 3], vec![2, 0, 3], vec![0, 1, 3], vec![0, 1, 2]];
        let err = irving(&prefs).unwrap_err();
        assert_eq!(err.agents, vec![0, 1, 2], "the odd party a, b, c");
    }

    /// All perfect matchings of `0..n` (n even), for the brute-force check.
    fn all_matchings(free: Vec<usize>, mate: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
        let Some((&x, rest)) = free.split_first() else {
            out.push(mate.clone());
            return;
        };
        for (k, &y) in rest.iter().enumerate() {
            let mut left = rest.to_vec();
            left.remove(k);
            mate[x] = y;
            mate[y] = x;
            all_matchings(left, mate, out);
        }
    }

    #[test]
    fn irving_agrees_with_brute_force_on_random_strict_lists() {
        let mut rng = Rng(12345);
        let (mut solvable, mut unsolvable) = (0, 0);
        for _ in 0..2000 {
            let n = 2 * (2 + (rng.next() % 3) as usize);
            let prefs: Vec<Vec<usize>> = (0..n)
                .map(|x| {
                    let mut l: Vec<usize> = (0..n).filter(|&y| y != x).collect();
                    for k in (1..l.len()).rev() {
                        l.swap(k, (rng.next() % (k as u64 + 1)) as usize);
                    }
                    l
                })
                .collect();
            let rank = |x: usize, y: usize| prefs[x].iter().position(|&z| z == y).unwrap();
            let stable = |m: &[usize]| {
                (0..n).all(|x| (0..n).all(|y| y == x || y == m[x] || !(rank(x, y) < rank(x, m[x]) && rank(y, x) < rank(y, m[y]))))
            };
            let mut all = Vec::new();
            all_matchings((0..n).collect(), &mut vec![0; n], &mut all);
            let exists = all.iter().any(|m| stable(m));
            match irving(&prefs) {
                Ok(m) => {
                    assert!(stable(&m), "{prefs:?}");
                    solvable += 1;
                }
                Err(_) => {
                    assert!(!exists, "Irving missed a stable matching: {prefs:?}");
                    unsolvable += 1;
                }
            }
        }
        assert!(solvable > 100 && unsolvable > 10, "{solvable} {unsolvable}");
    }

    #[test]
    fn a_tied_triangle_is_an_odd_party_and_a_tied_square_is_not() {
        let tri = vec![vec![0.0, 0.3, 0.3], vec![0.3, 0.0, 0.3 + 1e-14], vec![0.3, 0.3 + 1e-14, 0.0]];
        assert_eq!(match_by_cost(&tri, 1e-9), MatchOutcome::OddParty(vec![0, 1, 2]));
        let sq = vec![
            vec![0.0, 0.9, 0.1, 0.9],
            vec![0.9, 0.0, 0.9, 0.1],
            vec![0.1, 0.9, 0.0, 0.9],
            vec![0.9, 0.1, 0.9, 0.0],
        ];
        assert_eq!(match_by_cost(&sq, 1e-9), MatchOutcome::Matched(vec![Some(2), Some(3), Some(0), Some(1)]));
    }
}
