//! A frame's search on a host's cores ([`Tessellator::update_parallel`], feature `std`): the
//! same mesh as [`Tessellator::update`], bit for bit.
//!
//! # How
//!
//! The roots (the triangles of each patch's cells) are cut into parts: runs of whole
//! patches, and runs of one patch's roots where a patch has more roots than a part takes (a
//! model of few patches). There are more parts than threads so that the threads' work evens
//! out. The parts are dealt out in runs, one a thread: each thread, with storage of its own,
//! searches its own run's parts, then takes the parts the others have not yet taken of
//! theirs until none is left. The calling thread searches the first run from the start while
//! rayon's threads wake for the others (measured on two cores, `frame_loop`'s best update of
//! the single-patch threejs model at 2.5e-4: 0.186 ms where the calling thread waited for
//! two of rayon's threads, each taking the next part none had taken, and 0.145 ms so).
//!
//! A part is searched as if its roots were the whole model: where they meet another part's
//! roots (a curve to a patch of another part, or a cell's side or diagonal) is a border, and
//! a leaf of the bake over the tolerance (which the run time would halve below the bake,
//! into the one pool) is left unjudged.
//!
//! Then, on the calling thread, the whole frame's search starts from the parts' halvings. It
//! is the coarsest conforming mesh within the tolerance that halves every triangle the parts
//! halved: each part's mesh is the coarsest of *its* roots, and the frame's mesh restricted
//! to a part's roots is one of them (conforming inside the part, every leaf within the
//! tolerance), so it halves at least what the part's halves. Each part noted what it left:
//! the halved triangles whose triangle across is another part's (the whole frame halves that
//! one, and coarser ones first, where it is whole), and the leaves it left unjudged (the whole
//! frame judges them). The search goes on from there as it would from the roots, and finds the
//! view's unique mesh.
//!
//! Only the figures of how the search went ([`FrameStats::judged`], `sweeps`, `stack_peak`)
//! differ from a search on one thread.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::vec;
use std::vec::Vec;

use super::bits::set;
use super::hierarchy::{Hierarchy, Pending};
use super::select::{FrameStats, Part, RootAt, Tessellator, UpdateError};
use super::storage::StackSlot;
use crate::bound::BoundingSphere;
use crate::math::max;
use crate::view::View;
use crate::Arithmetic;

/// Parts per thread: enough for the threads' work to even out, where the parts' roots differ
/// in what a view makes of them.
pub(super) const PARTS_PER_THREAD: usize = 8;

/// The parts of a frame's search in runs, one a thread, in order. A thread searches the
/// parts of its own run first, then takes what the others have not yet taken of theirs, until
/// none is left. (The same thread takes the same roots frame after frame where the view lets
/// the runs even out, and a run's roots lie together.)
pub(super) struct Runs {
    /// Each run's next part, and its end.
    runs: Vec<(AtomicUsize, usize)>,
}

impl Runs {
    /// `parts` parts cut into `threads` runs (at least one) of about as many parts each.
    pub(super) fn new(parts: usize, threads: usize) -> Runs {
        let threads = threads.clamp(1, parts.max(1));
        let end = |k: usize| k * parts / threads;
        Runs {
            runs: (0..threads)
                .map(|k| (AtomicUsize::new(end(k)), end(k + 1)))
                .collect(),
        }
    }

    /// How many runs (and threads searching them) there are.
    pub(super) fn count(&self) -> usize {
        self.runs.len()
    }

    /// The next part for thread `me` to search: its own run's next, else the next of the
    /// runs after it; `None` when every part is taken.
    pub(super) fn next(&self, me: usize) -> Option<usize> {
        let n = self.runs.len();
        (0..n).find_map(|j| {
            let (next, end) = &self.runs[(me + j) % n];
            let part = next.fetch_add(1, Ordering::Relaxed);
            (part < *end).then_some(part)
        })
    }
}

/// `work(k)` for each `k` of `0..threads`, the calling thread's `work(0)` begun at once while
/// rayon's threads wake for the others: their results, in order of `k`.
pub(super) fn on_threads<T: Send>(threads: usize, work: impl Fn(usize) -> T + Sync) -> Vec<T> {
    on_each((0..threads).collect(), work)
}

/// `work(item)` for each of `items`, on a thread each: the calling thread's, for the first,
/// begun at once while rayon's threads wake for the others. Their results, in order. Done
/// with its own, a calling thread outside rayon's pool spins until the others are done too
/// (see [`spin_until`]).
pub(super) fn on_each<W: Send, T: Send>(items: Vec<W>, work: impl Fn(W) -> T + Sync) -> Vec<T> {
    let mut done: Vec<Option<T>> = items.iter().map(|_| None).collect();
    let spawned = items.len().saturating_sub(1);
    let finished = AtomicUsize::new(0);
    rayon::in_place_scope(|scope| {
        let (work, finished) = (&work, &finished);
        let mut items = items.into_iter().zip(done.iter_mut());
        let first = items.next();
        for (item, slot) in items {
            scope.spawn(move |_| {
                *slot = Some(work(item));
                finished.fetch_add(1, Ordering::Release);
            });
        }
        if let Some((item, slot)) = first {
            *slot = Some(work(item));
        }
        // (A thread of rayon's own waits at the scope's end by taking work, its threads' or
        // these jobs, where a thread outside the pool can only sleep.)
        if rayon::current_thread_index().is_none() {
            spin_until(|| finished.load(Ordering::Acquire) >= spawned);
        }
    });
    done.into_iter().flatten().collect()
}

/// Spins until `done`, for at most [`SPIN`]: the wait for rayon's threads at the end of a
/// scope puts a thread outside the pool to sleep, and it wakes 10-16 us after the last of
/// them is done (measured on two cores, a write of the single-patch threejs surface on two
/// threads: its threads done 41.6 us into it, the scope over at 58 us). With the spin, and
/// each thread's table of a write kept from write to write (see `parallel_write`), the
/// median of 3,000 frames of `frame_loop` (`PARALLEL=1`, the 2.5e-4 bake, 1024x768) went
/// from 0.354 to 0.316 ms on the rational torus and from 0.241 to 0.196 ms on that surface
/// (three turns of each build in one run; the best frames by 2-5%).
fn spin_until(done: impl Fn() -> bool) {
    let start = std::time::Instant::now();
    while !done() {
        for _ in 0..64 {
            core::hint::spin_loop();
        }
        if start.elapsed() > SPIN {
            return;
        }
    }
}

/// Longest a thread spins waiting for rayon's threads (then it waits as rayon waits).
const SPIN: std::time::Duration = std::time::Duration::from_micros(200);

/// A hierarchy of fewer nodes than this (whose frames within the bake have at most half as
/// many triangles) is searched on the calling thread: such a frame takes a few microseconds,
/// less than waking the threads (measured on two cores, `frame_loop` orbits:
/// `verb_quarter_cylinder`'s frames of 48 triangles, 0.008 ms on one thread and 0.033 ms on
/// both; the teaspoon's of 1,382 triangles, 0.22 ms and 0.18 ms). `verb_quarter_cylinder` at
/// 2.5e-4 of its diagonal has 368 nodes; the repository's next smallest hierarchy at that
/// bake, 9,214.
pub(super) const SMALL_HIERARCHY: usize = 1024;

/// Stack entries of a thread's parts (a part that finds it full walks its roots again).
const PART_STACK: usize = 512;

/// A part of a frame's search (see the module docs): its roots `lo..hi`, and what it leaves
/// to the whole frame.
#[derive(Debug)]
pub(super) struct Group<'s> {
    pub lo: RootAt,
    pub hi: RootAt,
    /// Halved triangles whose triangle across is another part's, and leaves of the bake over
    /// the tolerance, left unjudged.
    left: &'s mut Vec<Pending>,
    /// The part's walks gave up on leaves its stack had no room for: the whole frame walks
    /// the mesh for them.
    pub walk: bool,
}

impl Group<'_> {
    /// Notes `h` (see `Tessellator::leave_to_frame`).
    pub(super) fn leave(&mut self, h: &Pending) {
        self.left.push(*h);
    }
}

/// A thread's storage for its parts, and what they found.
struct Thread {
    bits: Vec<u32>,
    stack: Vec<StackSlot>,
    /// What each part it searched left to the whole frame, by the part's number.
    left: Vec<(usize, Vec<Pending>)>,
    walk: bool,
    stats: FrameStats,
    /// A part could not be searched (never: its storage fits the hierarchy).
    failed: bool,
}

impl Thread {
    fn new(words: usize) -> Thread {
        Thread {
            bits: vec![0; words],
            stack: vec![StackSlot::default(); PART_STACK],
            left: Vec::new(),
            walk: false,
            stats: FrameStats::default(),
            failed: false,
        }
    }

    /// Searches part `number`, the roots `lo..hi` of `tree`, in `view` (with the frame's
    /// `arithmetic` and culling `sphere`), adding to this thread's bits and figures.
    fn search(
        mut self,
        tree: Hierarchy<'_>,
        view: &View,
        number: usize,
        (lo, hi): Part,
        arithmetic: Arithmetic,
        sphere: Option<BoundingSphere>,
    ) -> Thread {
        let Ok(part) = Tessellator::from_slices_culling(
            tree,
            &mut self.bits,
            &mut self.stack,
            &mut [],
            sphere,
        ) else {
            self.failed = true;
            return self;
        };
        let mut part = part.with_arithmetic(arithmetic);
        let mut left = Vec::new();
        part.group = Some(Group {
            lo,
            hi,
            left: &mut left,
            walk: false,
        });
        let stats = part.select(view);
        let walk = part.group.take().is_some_and(|g| g.walk);
        self.left.push((number, left));
        self.walk |= walk;
        add(&mut self.stats, &stats);
        self
    }
}

/// Adds a part's figures to a frame's.
fn add(s: &mut FrameStats, part: &FrameStats) {
    s.triangles += part.triangles;
    s.judged += part.judged;
    s.hidden += part.hidden;
    s.sweeps += part.sweeps;
    s.stack_peak = s.stack_peak.max(part.stack_peak);
    s.worst_bound = max(s.worst_bound, part.worst_bound);
}

impl Tessellator<'_, '_> {
    /// [`update`](Self::update), with the search spread over rayon's threads (all cores, or
    /// those of the pool it is called in): the same mesh, bit for bit, and the same figures
    /// but for how the search went ([`FrameStats::judged`], `sweeps` and `stack_peak`). Each
    /// thread takes storage of its own for the frame (a hierarchy's bits and a stack).
    ///
    /// A tessellator keeping judgements from frame to frame ([`with_reuse`](Self::with_reuse))
    /// searches on one thread, and a step from the frame before makes its judgements again
    /// on the threads (the same judgements, the same figures). The threads pay where a frame is
    /// large and within the bake: a frame of a few hundred triangles costs more on threads
    /// than on one (waking them, and their storage), and the refinement below the bake stays
    /// on the calling thread. So a hierarchy of fewer than 1,024 nodes is searched on the
    /// calling thread; past that, which to call is the caller's choice (a frame's figures
    /// tell how large the last one was).
    pub fn update_parallel(&mut self, view: &View) -> Result<FrameStats, UpdateError> {
        if self.reuses() {
            self.step_threads = self.tree.node_count() >= SMALL_HIERARCHY;
            let stats = self.update(view);
            self.step_threads = false;
            return stats;
        }
        let parts = parts(self, rayon::current_num_threads() * PARTS_PER_THREAD);
        if parts.len() < 2 || self.tree.node_count() < SMALL_HIERARCHY {
            return self.update(view);
        }
        if self.is_last_view(view)? {
            return Ok(self.stats);
        }
        let (tree, arithmetic, sphere) = (self.tree, self.arithmetic, self.sphere);
        let words = tree.bit_words();
        // One storage a thread (rayon's `fold` would make storage for every piece of work it
        // splits off), and a run of parts a thread (see `Runs`): the calling thread searches
        // the first run from the start, while rayon's threads wake for the others.
        let runs = Runs::new(parts.len(), rayon::current_num_threads());
        let work = |me: usize| {
            let mut thread = Thread::new(words);
            while let Some(number) = runs.next(me) {
                thread = thread.search(tree, view, number, parts[number], arithmetic, sphere);
            }
            thread
        };
        let threads = on_threads(runs.count(), work);
        if threads.iter().any(|t| t.failed) {
            return self.update(view); // (never: the parts' storage fits the hierarchy)
        }
        Ok(self.select_from_parts(view, &threads))
    }

    /// Whether judgements are kept from frame to frame.
    fn reuses(&self) -> bool {
        cfg!(feature = "reuse") && self.reuse.is_some()
    }

    /// The frame of `view` searched from the threads' bits and figures (see the module docs).
    fn select_from_parts(&mut self, view: &View, threads: &[Thread]) -> FrameStats {
        self.begin(view);
        let tolerance = view.tolerance();
        let layout = self.layout;
        for t in threads {
            // Each node's bits are its root's part's alone; the patches' culled bits are the
            // same in every part that has roots of them.
            for (ours, theirs) in self.bits[..layout.seen].iter_mut().zip(&t.bits) {
                *ours |= theirs;
            }
            add(&mut self.stats, &t.stats);
        }
        // What the parts left, in the parts' order whichever thread searched them: the mesh
        // is the same in any order, and so the figures do not depend on the threads either
        // (`refined` counts a vertex asked for again).
        let mut left: Vec<&(usize, Vec<Pending>)> = threads.iter().flat_map(|t| &t.left).collect();
        left.sort_unstable_by_key(|(number, _)| *number);
        for (_, part) in left {
            for h in part {
                if self.is_split(h) {
                    self.halve_across(h);
                } else {
                    self.push(*h);
                }
                self.drain(view, tolerance);
            }
        }
        // Leaves a part's walks gave up on: the whole frame walks for them, as for those its
        // own stack had no room for (the parts' walks counted apart).
        let walks = core::mem::take(&mut self.stats.sweeps);
        if threads.iter().any(|t| t.walk) {
            self.walk_for_unjudged();
        }
        let mut stats = self.finish(view);
        stats.sweeps += walks;
        self.stats.sweeps = stats.sweeps;
        stats
    }

    /// Halves leaf `x` of the bake where the bake halves it, alone (the triangle across its
    /// hypotenuse is halved already), and queues its halves.
    fn halve_alone(&mut self, x: &Pending) {
        let Some((_, v)) = self.tree.baked_halving(x) else {
            return;
        };
        set(self.bits, x.node);
        self.uncount_leaf(x);
        let [h0, h1] = self.tree.halves(x, v);
        self.push(h1);
        self.push(h0);
    }

    /// Halves the triangle across the hypotenuse of `h` (a halved triangle of the bake whose
    /// hypotenuse lies on a part's border), and coarser ones first, where that border left it
    /// whole.
    fn halve_across(&mut self, h: &Pending) {
        let tree = self.tree;
        let mate = tree.linked(h.node).and_then(|l| tree.linked(l.mate));
        if let Some(m) = mate {
            if !self.is_split(&m.place) && self.halve_down_to(m.parent, 1) {
                self.halve_alone(&m.place);
            }
            return;
        }
        let Some(n) = h.tri.across(|p, s| tree.link(p, s), |p| tree.cells(p)) else {
            return;
        };
        // A level a loop: the triangle across is at most 24 halvings down its cell. (Each
        // leaf found coarser is halved, and the search goes on from it.)
        let mut leaf = self.locate(&n);
        for _ in 0..32 {
            if leaf.tri == n {
                if !self.is_split(&leaf) {
                    self.halve_alone(&leaf);
                }
                return;
            }
            if !self.split(&leaf, 1) {
                return;
            }
            leaf = self.locate_from(leaf, &n);
        }
    }
}

/// The parts of a frame's search, about `count` of them with about as many roots each: runs
/// of whole patches, and a patch with more roots than a part takes cut into runs of its own.
pub(super) fn parts(t: &Tessellator<'_, '_>, count: usize) -> Vec<Part> {
    let tree = t.tree;
    let patches = tree.patch_count() as u32;
    let roots: usize = (0..patches).map(|p| tree.root_count(p)).sum();
    let each = roots.div_ceil(count.max(1)).max(1) as u32;
    let mut out = Vec::new();
    let (mut lo, mut taken) = ((0, 0), 0);
    for p in 0..patches {
        let n = tree.root_count(p) as u32;
        if n > each {
            if taken > 0 {
                out.push((lo, (p, 0)));
            }
            for k in (0..n).step_by(each as usize) {
                let end = k + each;
                out.push(((p, k), if end >= n { (p + 1, 0) } else { (p, end) }));
            }
            (lo, taken) = ((p + 1, 0), 0);
            continue;
        }
        taken += n;
        if taken >= each {
            out.push((lo, (p + 1, 0)));
            (lo, taken) = ((p + 1, 0), 0);
        }
    }
    if taken > 0 {
        out.push((lo, (patches, 0)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::Runs;
    use std::vec;

    /// Every part is taken once, whichever threads ask in whatever order; a thread takes its
    /// own run's parts first, in order.
    #[test]
    fn runs_give_every_part_once_own_run_first() {
        for (parts, threads) in [(16, 2), (4, 2), (7, 3), (1, 2), (3, 8), (0, 2)] {
            let runs = Runs::new(parts, threads);
            assert!(runs.count() >= 1 && runs.count() <= threads.max(1));
            let mut taken = vec![0u32; parts];
            // Thread 1 (where there is one) takes first: its own run, from its start.
            let second = runs.count() - 1;
            let first_of_second = second * parts / runs.count();
            if parts > 0 {
                let part = runs.next(second).unwrap();
                assert_eq!(part, first_of_second, "{parts} parts, {threads} threads");
                taken[part] += 1;
            }
            // Then the threads take turns until none is left.
            let mut me = 0;
            while let Some(part) = runs.next(me) {
                taken[part] += 1;
                me = (me + 1) % runs.count();
            }
            assert!(taken.iter().all(|&n| n == 1), "{parts} parts: {taken:?}");
            assert!((0..runs.count()).all(|k| runs.next(k).is_none()));
        }
    }
}
