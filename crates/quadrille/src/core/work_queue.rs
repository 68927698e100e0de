//! Longest-processing-time-first scheduling of independent jobs on the
//! current rayon pool: one shared queue, each worker taking the next job
//! when it is done with its last.
//!
//! `par_iter` over a sorted list does not do this: rayon splits the list in
//! halves, so one worker runs the big jobs at the head while the other works
//! through the small ones of the tail, and a big job handed out late leaves
//! the others idle at the end (on i01o_m1, the biggest face started at two
//! thirds of the face stage). Here the jobs are handed out strictly in the
//! caller's order, so with the biggest first no worker is left with a big job
//! while the others have nothing to do. The results come back in job order:
//! the output does not depend on the number of threads.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Runs `job` on every item of `items`, handing the items out in their order
/// to the workers of the current rayon pool, and returns the results in the
/// order of `items`. A job may itself use rayon: a worker out of jobs helps
/// the others' inner parallel loops.
pub fn map_in_order<T, R, F>(items: &[T], job: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    let workers = rayon::current_num_threads().clamp(1, items.len().max(1));
    if workers == 1 {
        return items.iter().map(&job).collect();
    }
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    rayon::scope(|s| {
        for _ in 0..workers {
            s.spawn(|_| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(item) = items.get(k) else { break };
                let r = job(item);
                *slots[k].lock().unwrap_or_else(|e| e.into_inner()) = Some(r);
            });
        }
    });
    slots
        .into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every job ran: the workers stop only when the queue is empty")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_item_order_on_any_pool() {
        let items: Vec<u64> = (0..200).collect();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let out = pool.install(|| map_in_order(&items, |&x| x * x + 1));
            assert_eq!(out, items.iter().map(|x| x * x + 1).collect::<Vec<_>>());
        }
        assert!(map_in_order(&[] as &[u8], |&x| x).is_empty());
    }

    #[test]
    fn jobs_may_use_rayon_themselves() {
        use rayon::prelude::*;
        let items: Vec<u64> = (1..=20).collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let out = pool.install(|| map_in_order(&items, |&n| (1..=n).into_par_iter().sum::<u64>()));
        assert_eq!(
            out,
            items.iter().map(|n| n * (n + 1) / 2).collect::<Vec<_>>()
        );
    }
}
