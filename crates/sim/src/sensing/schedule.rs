//! Load balancing of the array's whiskers on the worker threads.
//!
//! The whiskers of [`super::physics::PhysicsArray`] share nothing, so each can run many
//! steps in one task; but their costs differ by an order of magnitude (a whisker pressed
//! against a surface costs many times a free one), and
//! rayon's default split of 18 tasks on 2 threads hands each thread runs of several
//! whiskers that cannot be stolen once begun: against the Box the second thread bought
//! only 1.3–1.8× where free whisking gets 1.9×.
//!
//! [`Balancer`] runs the steps in chunks: before each chunk it orders the whiskers by
//! what their last chunk cost, dearest first, and hands them out one at a time, oldest
//! task first (`rayon::scope_fifo`), so that the threads finish together and the last
//! task is a cheap one (the longest-processing-time-first rule). Only the order of the
//! tasks depends on the measured times: every whisker's steps, and so every sample, are
//! the same whatever the order, the chunking or the number of threads.
//!
//! It is a lever of the default path ([`crate::whisker::solver::Lever::LoadBalance`]):
//! without it, each whisker runs all its steps in one task, in rayon's split.

use rayon::prelude::*;
use std::time::Instant;

/// Steps per chunk: 50 ms of simulated time at 2 kHz, short enough for the order to
/// follow contacts as they come and go, long enough that the barrier between chunks
/// costs nothing measurable.
pub const CHUNK_STEPS: usize = 100;

/// The last measured cost of each whisker, which orders the next chunk's tasks.
#[derive(Debug, Clone)]
pub struct Balancer {
    /// Wall-clock seconds of each unit's last chunk (0 before the first).
    costs: Vec<f64>,
    /// False: one task per unit for the whole run, as before the lever.
    enabled: bool,
}

impl Balancer {
    /// A balancer, or (`enabled` false) one task per unit for the whole run in rayon's
    /// split, to measure what balancing brings.
    pub fn new(enabled: bool) -> Self {
        Self {
            costs: Vec::new(),
            enabled,
        }
    }

    /// Runs `step(unit, k)` for k in `0..steps` on every unit, in chunks of
    /// [`CHUNK_STEPS`]: each unit's steps in order in one task per chunk, the dearest
    /// units (by their last chunk) first. Returns, per unit in the order given, the
    /// values `step` returned.
    pub fn run<U: Send, T: Send>(
        &mut self,
        units: &mut [U],
        steps: usize,
        step: impl Fn(&mut U, usize) -> T + Sync,
    ) -> Vec<Vec<T>> {
        if !self.enabled {
            return units
                .par_iter_mut()
                .map(|u| (0..steps).map(|k| step(u, k)).collect())
                .collect();
        }
        self.costs.resize(units.len(), 0.0);
        let mut out: Vec<Vec<T>> = units.iter().map(|_| Vec::with_capacity(steps)).collect();
        let mut start = 0;
        while start < steps {
            let end = (start + CHUNK_STEPS).min(steps);
            let mut tasks: Vec<_> = units
                .iter_mut()
                .zip(out.iter_mut())
                .zip(self.costs.iter_mut())
                .collect();
            // Dearest first; ties (the first chunk) keep the units' order.
            tasks.sort_by(|((_, _), a), ((_, _), b)| b.total_cmp(a));
            let step = &step;
            rayon::scope_fifo(|scope| {
                for ((unit, out), cost) in tasks {
                    scope.spawn_fifo(move |_| {
                        let timer = Instant::now();
                        out.extend((start..end).map(|k| step(unit, k)));
                        *cost = timer.elapsed().as_secs_f64();
                    });
                }
            });
            start = end;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each unit's values come back in its own slot and step order, every step exactly
    /// once, whatever the chunking and the thread count (a unit that counts its own steps
    /// and sleeps unevenly, so that the order of the tasks changes between chunks), and
    /// so without balancing (here on 3 threads).
    #[test]
    fn every_unit_steps_in_order_once_per_step() {
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let steps = 2 * CHUNK_STEPS + 7;
            let mut units: Vec<(usize, usize)> = (0..5).map(|i| (i, 0)).collect();
            let mut balancer = Balancer::new(threads != 3);
            let out = pool.install(|| {
                balancer.run(&mut units, steps, |(id, count), k| {
                    // Unit 3 is dear in the second chunk only.
                    if *id == 3 && (CHUNK_STEPS..2 * CHUNK_STEPS).contains(&k) {
                        std::thread::sleep(std::time::Duration::from_micros(20));
                    }
                    *count += 1;
                    (*id, k, *count)
                })
            });
            assert_eq!(out.len(), units.len());
            for (i, values) in out.iter().enumerate() {
                let expected: Vec<_> = (0..steps).map(|k| (i, k, k + 1)).collect();
                assert_eq!(values, &expected, "unit {i} on {threads} threads");
                assert_eq!(units[i].1, steps);
            }
        }
    }

    /// On one thread the tasks run dearest first, ties in the units' order (the costs
    /// set by hand: timing is never a test).
    #[test]
    fn dearest_units_run_first() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let mut units: Vec<usize> = (0..5).collect();
        let mut balancer = Balancer {
            costs: vec![0.1, 0.3, 0.1, 0.5, 0.0],
            enabled: true,
        };
        let seen = std::sync::Mutex::new(Vec::new());
        pool.install(|| {
            balancer.run(&mut units, 1, |id, _| seen.lock().unwrap().push(*id));
        });
        assert_eq!(seen.into_inner().unwrap(), vec![3, 1, 0, 2, 4]);
    }
}
