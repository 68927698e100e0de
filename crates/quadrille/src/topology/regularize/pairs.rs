//! The searches of the regularization loop that reach beyond one quad's
//! operations ([`Regularizer::run`] calls them once the sweeps stop):
//! translations (paper Fig. 5, [`Regularizer::translate_at`]), which move
//! an irregular vertex toward another by valence-neutral swaps, and the
//! pair search ([`Regularizer::cancel_pair_at`]), which looks for the
//! nearest vertex of opposite index and searches deeper sequences along
//! the path between them.

use super::driver::{better, Regularizer, Score};
use super::ops::{apply_topology, candidates_at, score_delta, Op};

/// A sequence found by the pair search: (score change, length) and the operations.
type Found = ((Score, usize), Vec<Op>);

impl Regularizer<'_> {
    /// Sign of the index of `v`: +1 when it has fewer edges than its ideal
    /// valence (a 3 inside), −1 when more (a 5 inside, a boundary vertex with an
    /// extra edge), 0 when regular or dead.
    pub fn index_sign(&self, v: u32) -> i64 {
        let x = &self.fq.verts[v as usize];
        if !x.alive {
            return 0;
        }
        (x.ideal as i64 - self.fq.valence(v) as i64).signum()
    }

    /// The shortest edge path (at most `radius` hops) from the irregular vertex
    /// `v` or one of its irregular links (its cluster) to the nearest vertex
    /// outside that cluster that could cancel with it: of opposite index when
    /// the cluster has a net index, any irregular vertex when it has none (a
    /// (3, 5) dipole cancels only with another dipole). The path's vertices,
    /// cluster and partner included; `None` when there is none that close.
    pub fn partner_path(&self, v: u32, radius: usize) -> Option<Vec<u32>> {
        let s = self.index_sign(v);
        if s == 0 {
            return None;
        }
        let mut cluster: Vec<u32> = std::iter::once(v)
            .chain(
                self.fq
                    .links(v)
                    .into_iter()
                    .filter(|&l| self.fq.is_irregular(l)),
            )
            .collect();
        cluster.sort_unstable();
        let net: i64 = cluster
            .iter()
            .map(|&c| self.fq.verts[c as usize].ideal as i64 - self.fq.valence(c) as i64)
            .sum();
        let wanted = |w: u32| {
            if net == 0 {
                self.index_sign(w) != 0
            } else {
                self.index_sign(w) == -net.signum()
            }
        };
        let mut parent: Vec<(u32, u32)> = cluster.iter().map(|&c| (c, c)).collect();
        let mut front = cluster.clone();
        for _ in 0..radius {
            let mut next = Vec::new();
            for &a in &front {
                for l in self.fq.links(a) {
                    if parent.iter().any(|p| p.0 == l) {
                        continue;
                    }
                    parent.push((l, a));
                    if wanted(l) {
                        let mut path = cluster.clone();
                        path.push(l);
                        let mut x = a;
                        while cluster.binary_search(&x).is_err() {
                            path.push(x);
                            x = match parent.iter().find(|p| p.0 == x) {
                                Some(p) => p.1,
                                None => break,
                            };
                        }
                        path.sort_unstable();
                        path.dedup();
                        return Some(path);
                    }
                    next.push(l);
                }
            }
            front = next;
        }
        None
    }

    /// Pair search (beyond the paper's star-local compositions, which leave
    /// "pairs of high-low valences which could balance out but are not
    /// detected", spec §11.1): finds the nearest vertex of opposite index to
    /// the irregular vertex `v` (an interior 5 for a 3, or a boundary vertex
    /// with an extra edge; within [`Regularizer::pair_radius`] hops) and
    /// searches sequences of up to [`Regularizer::pair_depth`] operations
    /// around the path between them (intermediate states at most two irregular
    /// vertices worse, [`Regularizer::pair_beam`] best operations expanded per
    /// level). The best sequence that lowers the score is applied with
    /// repositioning and validity checks, or rolled back. Returns whether one was kept.
    pub fn cancel_pair_at(&mut self, v: u32) -> bool {
        if (v as usize) >= self.fq.verts.len() || !self.fq.is_irregular(v) {
            return false;
        }
        // nothing changed within reach since the last failed search here: skip
        let reach = self.ball(v, self.pair_radius + 2);
        self.stamp.resize(self.fq.verts.len(), 0);
        self.pair_failed.resize(self.fq.verts.len(), 0);
        let failed = self.pair_failed[v as usize];
        if failed > 0 && reach.iter().all(|&w| self.stamp[w as usize] <= failed) {
            return false;
        }
        let Some(corridor) = self.partner_path(v, self.pair_radius) else {
            self.pair_failed[v as usize] = self.epoch;
            return false;
        };
        let mut found = Vec::new();
        let mut budget = self.pair_budget;
        self.update_quad_dir();
        self.pair_extend(
            &corridor,
            &mut Vec::new(),
            (0, 0, 0),
            &[],
            &mut found,
            &mut budget,
        );
        found.sort();
        found.dedup_by(|a, b| a.1 == b.1);
        for (_, ops) in found.iter().take(self.tries) {
            if self.try_sequence(ops) {
                self.counts.compositions += 1;
                return true;
            }
        }
        self.pair_failed[v as usize] = self.epoch;
        false
    }

    /// Depth-first search of [`Regularizer::cancel_pair_at`]: operations around
    /// the corridor and the vertices changed so far, each changing the valence
    /// of one of them; sequences that lower the score go to `found` with their
    /// score change and length. Topology only (rolled back after).
    #[allow(clippy::too_many_arguments)]
    fn pair_extend(
        &mut self,
        corridor: &[u32],
        path: &mut Vec<Op>,
        acc: Score,
        changed: &[u32],
        found: &mut Vec<Found>,
        budget: &mut usize,
    ) {
        let mut active: Vec<u32> = corridor
            .iter()
            .chain(changed)
            .copied()
            .filter(|&x| self.fq.verts[x as usize].alive)
            .collect();
        active.sort_unstable();
        active.dedup();
        let mut cands: Vec<Op> = self
            .fq
            .quads_around(&active)
            .into_iter()
            .flat_map(|q| candidates_at(self.fq, q))
            .collect();
        cands.sort_unstable();
        cands.dedup();
        let mut expand: Vec<(Score, Op, Vec<u32>)> = Vec::new();
        for op in cands {
            let Some(eff) = self.evaluate(op) else {
                continue;
            };
            let touches = eff
                .changes
                .iter()
                .any(|c| c.1 != c.2 && active.binary_search(&c.0).is_ok())
                || eff
                    .removed
                    .is_some_and(|r| active.binary_search(&r.0).is_ok());
            if !touches {
                continue;
            }
            let d1 = self.delta(&eff);
            let d = (acc.0 + d1.0, acc.1 + d1.1, acc.2 + d1.2);
            if better(d) {
                let mut ops = path.clone();
                ops.push(op);
                found.push(((d, ops.len()), ops));
                continue;
            }
            if path.len() + 1 < self.pair_depth && d.0 <= 2 {
                expand.push((
                    d,
                    op,
                    eff.changes
                        .iter()
                        .filter(|c| c.1 != c.2)
                        .map(|c| c.0)
                        .collect(),
                ));
            }
        }
        expand.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
        for (d, op, ch) in expand.into_iter().take(self.pair_beam) {
            if *budget == 0 || found.len() >= 8 || self.exhausted() {
                return;
            }
            *budget -= 1;
            self.count_trial();
            let cp = self.fq.checkpoint();
            if apply_topology(self.fq, op).is_some() {
                let mut next: Vec<u32> = changed
                    .iter()
                    .copied()
                    .chain(ch)
                    .chain(cp.verts_len() as u32..self.fq.verts.len() as u32)
                    .collect();
                next.sort_unstable();
                next.dedup();
                path.push(op);
                self.pair_extend(corridor, path, d, &next, found, budget);
                path.pop();
            }
            self.fq.rollback(cp);
        }
    }

    /// Hops from `from` to the nearest irregular vertex outside `exclude`
    /// (`radius + 1` when none is that close).
    fn hops_to_irregular(&self, from: &[u32], exclude: &[u32], radius: usize) -> usize {
        let mut seen: Vec<u32> = from.to_vec();
        seen.sort_unstable();
        let mut front = seen.clone();
        for h in 1..=radius {
            let mut next = Vec::new();
            for &v in &front {
                for l in self.fq.links(v) {
                    if seen.binary_search(&l).is_ok() {
                        continue;
                    }
                    if self.fq.is_irregular(l) && !exclude.contains(&l) {
                        return h;
                    }
                    let pos = seen.binary_search(&l).unwrap_or_else(|e| e);
                    seen.insert(pos, l);
                    next.push(l);
                }
            }
            front = next;
        }
        radius + 1
    }

    /// Translation (paper Fig. 5): moves the irregular vertex `v` (with its
    /// irregular links, e.g. a (3, 5) pair) by valence-neutral swaps, each
    /// bringing it strictly closer to another irregular vertex, until an
    /// operation or composition lowers the score; keeps the whole chain only
    /// then (and only if valid), else rolls it back.
    pub fn translate_at(&mut self, v: u32) -> bool {
        if (v as usize) >= self.fq.verts.len()
            || !self.fq.is_irregular(v)
            || self.fq.verts[v as usize].fixed
        {
            return false;
        }
        const RADIUS: usize = 8;
        let cp = self.fq.checkpoint();
        let mut moving: Vec<u32> = std::iter::once(v)
            .chain(
                self.fq
                    .links(v)
                    .into_iter()
                    .filter(|&l| self.fq.is_irregular(l)),
            )
            .collect();
        moving.sort_unstable();
        let mut dist = self.hops_to_irregular(&moving, &moving, RADIUS);
        if dist > RADIUS {
            return false;
        }
        for _ in 0..self.translation_steps {
            if self.exhausted() {
                break;
            }
            // neutral swaps that move the group closer to another irregular vertex
            let mut best: Option<(usize, Op, Vec<u32>)> = None;
            for q in self.fq.quads_around(&moving) {
                for op in candidates_at(self.fq, q) {
                    if !matches!(op, Op::Swap { .. }) {
                        continue;
                    }
                    let Some(eff) = self.evaluate(op) else {
                        continue;
                    };
                    let d = score_delta(self.fq, &eff);
                    if d.0 != 0
                        || d.1 > 0
                        || !eff
                            .changes
                            .iter()
                            .any(|c| moving.binary_search(&c.0).is_ok())
                    {
                        continue;
                    }
                    self.count_trial();
                    let cp2 = self.fq.checkpoint();
                    if apply_topology(self.fq, op).is_some() {
                        let mut group: Vec<u32> = eff
                            .changes
                            .iter()
                            .map(|c| c.0)
                            .filter(|&x| self.fq.is_irregular(x))
                            .collect();
                        group.sort_unstable();
                        let h = self.hops_to_irregular(&group, &group, RADIUS);
                        if h < dist && best.as_ref().is_none_or(|b| h < b.0) {
                            best = Some((h, op, group));
                        }
                    }
                    self.fq.rollback(cp2);
                }
            }
            let Some((h, op, group)) = best else { break };
            if !self.apply_repaired(op) {
                break;
            }
            dist = h;
            moving = group;
            // an improving operation or composition around the moved group?
            let start: Vec<Op> = self
                .fq
                .quads_around(&moving)
                .into_iter()
                .flat_map(|p| candidates_at(self.fq, p))
                .collect();
            let mut found = Vec::new();
            let mut budget = self.budget;
            self.singles_in_search = true;
            self.extend(
                &start,
                &mut Vec::new(),
                (0, 0, 0),
                &moving,
                2,
                &mut found,
                &mut budget,
            );
            self.singles_in_search = false;
            found.sort();
            found.dedup_by(|a, b| a.1 == b.1);
            for (_, ops) in found.iter().take(self.tries) {
                let cp3 = self.fq.checkpoint();
                if ops.iter().all(|&o| self.apply_repaired(o)) && self.settle(cp) {
                    self.fq.commit();
                    self.counts.compositions += 1;
                    return true;
                }
                self.fq.rollback(cp3);
            }
        }
        self.fq.rollback(cp);
        false
    }
}
