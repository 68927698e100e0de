//! The network stage's interval assignment (spec §7.4): one integer per
//! poly-chord of every meshed part, so that the two sides of every shared
//! primary segment get the same number of intervals.
//!
//! The spec's integer QP with the square replaced by L1 (its [I] note): per
//! soft equality `Σ left − Σ right = e⁺ − e⁻` with `e± ≥ 0`, minimise
//! `w · Σ (e⁺ + e⁻) + Σ n` over integers `n ≥ lower`, `w` =
//! [`MISMATCH_WEIGHT`]; hard equalities (the two sides of a cut or a hole
//! connector) are constraints. At zero mismatch the optimum is the QP's.
//! Solved by HiGHS through `good_lp`.

use std::time::Instant;

use good_lp::{
    constraint, variable, Expression, ProblemVariables, Solution, SolverModel, Variable,
};

/// The weight of one interval of mismatch against one interval more in
/// total (the spec's w).
pub const MISMATCH_WEIGHT: f64 = 1000.0;

/// An interval program: integers `n[v] ≥ lower[v]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntervalProgram {
    /// The smallest count of each variable (at least 1 is enforced).
    pub lower: Vec<usize>,
    /// Soft equalities: the sum of the first list equals the sum of the
    /// second (variables may repeat: one term per segment).
    pub equal_sums: Vec<(Vec<usize>, Vec<usize>)>,
    /// Hard equalities between two variables.
    pub equal: Vec<(usize, usize)>,
}

/// The solution of an [`IntervalProgram`].
#[derive(Clone, Debug, PartialEq)]
pub struct IntervalSolution {
    /// The count of each variable.
    pub counts: Vec<usize>,
    /// `Σ |Σ left − Σ right|` over the soft equalities (0: watertight).
    pub mismatch: usize,
    /// Seconds in the solver.
    pub seconds: f64,
}

/// Solves `prog` (module docs). Errors name the solver's complaint.
pub fn solve_intervals(prog: &IntervalProgram) -> Result<IntervalSolution, String> {
    let started = Instant::now();
    let n = prog.lower.len();
    if n == 0 {
        return Ok(IntervalSolution {
            counts: vec![],
            mismatch: 0,
            seconds: 0.0,
        });
    }
    let mut vars = ProblemVariables::new();
    let xs: Vec<Variable> = prog
        .lower
        .iter()
        .map(|&l| vars.add(variable().integer().min(l.max(1) as f64)))
        .collect();
    let slacks: Vec<(Variable, Variable)> = prog
        .equal_sums
        .iter()
        .map(|_| (vars.add(variable().min(0.0)), vars.add(variable().min(0.0))))
        .collect();
    let total: Expression = xs.iter().copied().sum();
    let penalty: Expression = slacks.iter().map(|&(p, m)| p + m).sum();
    let mut model = vars
        .minimise(total + MISMATCH_WEIGHT * penalty)
        .using(good_lp::highs)
        .set_threads(1)
        .set_option("output_flag", false)
        .set_option("mip_rel_gap", 1e-9)
        .set_time_limit(30.0);
    for ((left, right), &(plus, minus)) in prog.equal_sums.iter().zip(&slacks) {
        let l: Expression = left.iter().map(|&v| xs[v]).sum();
        let r: Expression = right.iter().map(|&v| xs[v]).sum();
        model.add_constraint(constraint!(l - r - plus + minus == 0.0));
    }
    for &(a, b) in &prog.equal {
        model.add_constraint(constraint!(xs[a] - xs[b] == 0.0));
    }
    let solution = model
        .solve()
        .map_err(|e| format!("the interval program: HiGHS: {e}"))?;
    let counts: Vec<usize> = xs
        .iter()
        .zip(&prog.lower)
        .map(|(&x, &l)| (solution.value(x).round().max(1.0) as usize).max(l))
        .collect();
    let mismatch = prog
        .equal_sums
        .iter()
        .map(|(l, r)| {
            let sum = |vs: &[usize]| vs.iter().map(|&v| counts[v]).sum::<usize>();
            sum(l).abs_diff(sum(r))
        })
        .sum();
    Ok(IntervalSolution {
        counts,
        mismatch,
        seconds: started.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads sharing a side: quad A's chord across the shared side needs
    /// 3, quad B's 5; the other chords 2 and 4. Both shared chords get 5,
    /// the others stay at their minimum: total 16, no mismatch.
    #[test]
    fn two_quads_sharing_a_side_both_get_the_larger_minimum() {
        let prog = IntervalProgram {
            lower: vec![3, 2, 5, 4],
            equal_sums: vec![(vec![0], vec![2])],
            equal: vec![],
        };
        let s = solve_intervals(&prog).unwrap();
        assert_eq!(s.counts, vec![5, 2, 5, 4]);
        assert_eq!(s.mismatch, 0);
    }

    /// A T-junction: one side's single segment (minimum 1) against two
    /// secondary segments of the other (minimum 1 and 2): the single one
    /// rises to 3.
    #[test]
    fn a_primary_segment_gets_the_sum_of_its_secondary_segments() {
        let prog = IntervalProgram {
            lower: vec![1, 1, 2],
            equal_sums: vec![(vec![0], vec![1, 2])],
            equal: vec![],
        };
        let s = solve_intervals(&prog).unwrap();
        assert_eq!(s.counts, vec![3, 1, 2]);
        assert_eq!(s.mismatch, 0);
    }

    /// No watertight answer: x = y is hard, x = y + z soft with z ≥ 1. The
    /// least mismatch is 1 (z = 1), with x = y at their minimum 2.
    #[test]
    fn an_infeasible_wish_list_leaves_the_least_mismatch() {
        let prog = IntervalProgram {
            lower: vec![2, 1, 1],
            equal_sums: vec![(vec![0], vec![1, 2])],
            equal: vec![(0, 1)],
        };
        let s = solve_intervals(&prog).unwrap();
        assert_eq!(s.counts, vec![2, 2, 1]);
        assert_eq!(s.mismatch, 1);
    }
}
