//! Who computes a bake's bounds: most of a bake's time goes to the bound of each triangle, and
//! each depends on its triangle alone, so a batch of them may run in any order, on any
//! number of threads, and the hierarchy comes out the same bit for bit.

use super::BakeScratch;

/// Runs a batch of a bake's jobs (see [`bake_hierarchy_with`](super::bake_hierarchy_with)).
///
/// A job's result depends on the job alone, so an implementation may run them in any order
/// and side by side: [`InOrder`] runs them one after another, `Parallel` (feature `std`) on
/// rayon's threads. Another thread pool (an embedded host's own scheduler, say) implements
/// it the same way.
pub trait BakeRunner {
    /// Runs `work` once on every job of `jobs`, in place: it must not leave a job out
    /// (the bake then fails with [`BakeError::JobsSkipped`](super::BakeError::JobsSkipped)),
    /// nor move, copy or change the jobs itself.
    fn run(&self, jobs: &mut [BakeScratch], work: &(dyn Fn(&mut BakeScratch) + Sync));
}

/// Runs a bake's jobs one after another, on the calling thread.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InOrder;

impl BakeRunner for InOrder {
    fn run(&self, jobs: &mut [BakeScratch], work: &(dyn Fn(&mut BakeScratch) + Sync)) {
        for job in jobs {
            work(job);
        }
    }
}

/// Runs a bake's jobs on rayon's threads: all cores, or those of the pool the bake is
/// called in (`rayon::ThreadPool::install`).
#[cfg(all(feature = "std", not(target_os = "none")))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Parallel;

#[cfg(all(feature = "std", not(target_os = "none")))]
impl BakeRunner for Parallel {
    fn run(&self, jobs: &mut [BakeScratch], work: &(dyn Fn(&mut BakeScratch) + Sync)) {
        use rayon::prelude::*;
        // A job takes tens of microseconds: a few per task keep the threads' queues short.
        jobs.par_iter_mut().with_min_len(4).for_each(work);
    }
}
