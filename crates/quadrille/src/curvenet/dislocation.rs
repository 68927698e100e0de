//! Flow dislocation (spec §5.4, Fig. 14): interior layout vertices are cycles
//! of the chord graph; a crossing ⟨(i,j),(k,l)⟩ on a cycle may be swapped to
//! {(i,l),(k,j)} or {(i,k),(l,j)}. A swap is valid when all three rules hold:
//! the layout's minimum scaled Jacobian improves, no new cycle appears (the
//! graph stays connected and has fewer cycles), and each new pair costs no
//! more than the worst pair before. The valid swap of least cost increase is
//! made, and the search repeated.

use super::geometry::layout_quality;
use super::layout::{chords_cross, chords_of, crossing_count, embed, validate, Chord, LayoutError};
use super::PairedCycle;

/// Everything the three rules look at for one candidate swap.
#[derive(Clone, Debug, PartialEq)]
pub struct SwapVerdict {
    /// The two pairs before.
    pub before: [Chord; 2],
    /// The two pairs after.
    pub after: [Chord; 2],
    /// Minimum layout scaled Jacobian before and after (−∞ after when the
    /// swapped pairing has no layout).
    pub quality: (f64, f64),
    /// Independent cycles of the chord graph before and after (`None` after
    /// when the graph falls apart).
    pub cycles: (usize, Option<usize>),
    /// The worst pair cost before the swap.
    pub worst_cost_before: f64,
    /// The costs of the two new pairs.
    pub new_costs: [f64; 2],
    /// Rule 1: quality improves.
    pub quality_improves: bool,
    /// Rule 2: no new cycle (connected, fewer cycles).
    pub no_new_cycle: bool,
    /// Rule 3: each new cost ≤ the worst cost before.
    pub costs_acceptable: bool,
    /// Sum of new costs minus sum of old.
    pub cost_increase: f64,
}

impl SwapVerdict {
    /// All three rules hold.
    pub fn valid(&self) -> bool {
        self.quality_improves && self.no_new_cycle && self.costs_acceptable
    }
}

/// Independent cycles of a connected chord graph: crossings − chords + 1;
/// `None` when disconnected.
pub fn chord_cycles(chords: &[Chord]) -> Option<usize> {
    let comps = super::layout::chord_components(chords);
    if comps.iter().any(|&c| c != 0) {
        return None;
    }
    Some(crossing_count(chords) + 1 - chords.len())
}

/// True when crossing (a, b) lies on a cycle of the chord graph: a and b stay
/// connected without it.
fn on_cycle(chords: &[Chord], a: usize, b: usize) -> bool {
    let mut seen = vec![false; chords.len()];
    let mut stack = vec![a];
    seen[a] = true;
    while let Some(x) = stack.pop() {
        for y in 0..chords.len() {
            if !seen[y]
                && chords_cross(chords[x], chords[y])
                && !((x == a && y == b) || (x == b && y == a))
            {
                seen[y] = true;
                stack.push(y);
            }
        }
    }
    seen[b]
}

fn ordered(a: usize, b: usize) -> Chord {
    (a.min(b), a.max(b))
}

/// The candidate swaps: per crossing (a, b) on a cycle, in index order, the
/// pair indices and the two new pairs of each of its two swaps.
pub fn swap_candidates(cycle: &PairedCycle) -> Vec<(usize, usize, [Chord; 2])> {
    let chords = chords_of(cycle);
    let mut out = Vec::new();
    for a in 0..chords.len() {
        for b in a + 1..chords.len() {
            if !chords_cross(chords[a], chords[b]) || !on_cycle(&chords, a, b) {
                continue;
            }
            let ((i, j), (k, l)) = (chords[a], chords[b]);
            out.push((a, b, [ordered(i, l), ordered(k, j)]));
            out.push((a, b, [ordered(i, k), ordered(l, j)]));
        }
    }
    out
}

/// The cycle with pairs `a` and `b` replaced by `new`, costs from `cost`.
pub fn swapped(
    cycle: &PairedCycle,
    a: usize,
    b: usize,
    new: [Chord; 2],
    cost: &dyn Fn(usize, usize) -> f64,
) -> PairedCycle {
    let mut out = cycle.clone();
    out.pairs[a] = new[0];
    out.pairs[b] = new[1];
    out.costs = out.pairs.iter().map(|&(i, j)| cost(i, j)).collect();
    out
}

/// Judges one swap by the three rules.
pub fn evaluate_swap(
    cycle: &PairedCycle,
    a: usize,
    b: usize,
    new: [Chord; 2],
    cost: &dyn Fn(usize, usize) -> f64,
) -> Result<SwapVerdict, LayoutError> {
    validate(cycle)?;
    let chords = chords_of(cycle);
    let before_layout = embed(cycle)?;
    let q_before = layout_quality(&before_layout).0;
    let after = swapped(cycle, a, b, new, cost);
    let after_chords = chords_of(&after);
    let cycles_before = chord_cycles(&chords).unwrap_or(0);
    let cycles_after = chord_cycles(&after_chords);
    let q_after = match cycles_after {
        Some(_) => embed(&after).map_or(f64::NEG_INFINITY, |l| layout_quality(&l).0),
        None => f64::NEG_INFINITY,
    };
    let worst = chords
        .iter()
        .map(|&(i, j)| cost(i, j))
        .fold(f64::NEG_INFINITY, f64::max);
    let new_costs = [cost(new[0].0, new[0].1), cost(new[1].0, new[1].1)];
    let old_sum = cost(chords[a].0, chords[a].1) + cost(chords[b].0, chords[b].1);
    Ok(SwapVerdict {
        before: [chords[a], chords[b]],
        after: new,
        quality: (q_before, q_after),
        cycles: (cycles_before, cycles_after),
        worst_cost_before: worst,
        new_costs,
        quality_improves: q_after > q_before + 1e-9,
        no_new_cycle: cycles_after.is_some_and(|c| c < cycles_before),
        costs_acceptable: new_costs.iter().all(|&c| c <= worst),
        cost_increase: new_costs[0] + new_costs[1] - old_sum,
    })
}

/// Makes valid swaps, least cost increase first, until none is left; returns
/// the final pairing and the swaps made in order.
pub fn remove_dislocations(
    cycle: &PairedCycle,
    cost: &dyn Fn(usize, usize) -> f64,
) -> Result<(PairedCycle, Vec<SwapVerdict>), LayoutError> {
    let mut cur = cycle.clone();
    let mut made = Vec::new();
    // Each swap lowers the cycle count, so this ends.
    loop {
        let mut best: Option<(f64, usize, usize, [Chord; 2], SwapVerdict)> = None;
        for (a, b, new) in swap_candidates(&cur) {
            let v = evaluate_swap(&cur, a, b, new, cost)?;
            if v.valid()
                && best
                    .as_ref()
                    .is_none_or(|bst| v.cost_increase < bst.0 - 1e-15)
            {
                best = Some((v.cost_increase, a, b, new, v));
            }
        }
        match best {
            Some((_, a, b, new, v)) => {
                cur = swapped(&cur, a, b, new, cost);
                made.push(v);
            }
            None => return Ok((cur, made)),
        }
    }
}
