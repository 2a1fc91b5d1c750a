//! A camera step: the last frame's mesh changed where the view changed it, instead of a
//! search from the patches' roots (feature `reuse`, with room for a judgement per node).
//!
//! # What a step does
//!
//! A frame's mesh is the least fixed point of the search (see `select`): the least set of
//! halvings such that every triangle of the mesh or halved by it ("in the mesh", its parent
//! halved) that is over the tolerance is halved, and every halving has the halvings it needs
//! (the triangle across the hypotenuse, halved with it; coarser ones first). The search
//! makes each halving for a reason: a triangle judged over (its *trigger*), which halves its
//! diamond and every coarser diamond that one needs. A step keeps the reasons: every halved
//! node holds its trigger (in its [`Judgement`](super::Judgement) slot), and the list of the
//! nodes in the mesh is kept too.
//!
//! A step then:
//!
//! 1. judges again the nodes of the list whose judgement no longer holds (the odometer of
//!    `reuse` ran past its certificate), leaves and triggers, and notes those that *flip*:
//!    a leaf now over, a trigger now within;
//! 2. takes away, for each trigger now within, the halvings it made, coarsest first: one
//!    whose parents still stand and one of whose two triangles is over the tolerance by its
//!    own bound stays, that triangle its trigger now (the search halves coarse triangles for
//!    a fine one's sake before it has judged them: most are over by themselves); the others
//!    go, and with each the triangles it made leave the mesh, and with them every halving
//!    that one of them triggered;
//! 3. makes again the halvings that a halving still standing needs (its parent, taken away in
//!    2, with the same trigger);
//! 4. judges the triangles that became leaves of the mesh, and halves those over the tolerance
//!    and the leaves that flipped to over, as the search does.
//!
//! # Why it is the view's mesh
//!
//! After 2 and 3, every standing halving has a trigger that is in the mesh and over the
//! tolerance in this view, and the halvings it needs: ordered by when they were made (a
//! halving kept for its own triangle's sake by when its parents were), each is one the search
//! would make, so the set is within the view's least fixed point. Step 4
//! is the search itself from there, and every leaf it ends with is judged in this view (a
//! judgement that holds is this view's, by its certificate): the search's end, the least
//! fixed point, the view's unique mesh. A tessellator without reuse finds the same mesh, which
//! the tests check frame by frame along camera paths.
//!
//! A step needs the last frame whole (searched or stepped on one thread, within the bake:
//! no vertex in the pool, nothing left over, no walk for a full stack) and certified (not a
//! jump: see `reuse`), the camera within the longest certificate of it, the same lens and
//! tolerance and the same patches culled, float bounds (integer ones keep no certificate) and
//! the hierarchy's links. Where any of these fails, or a step runs out of room (its stack, or
//! its short lists of flips and repairs), the frame is searched from the roots: the same mesh,
//! at a cold frame's cost.
//!
//! # On a host's threads
//!
//! Most of a step is its first part, the judgements made again, each with its certificate;
//! each reads the frame and writes nothing but its own judgement. Called from
//! `update_parallel` (feature `std`), a step lists the lapsed nodes and what is asked of each,
//! judges them in pieces, taken by the calling thread at once and by rayon's threads as they
//! wake (each with its own cache of corners in view coordinates, which gives the same bits
//! as moving them again), then keeps and notes the judgements in
//! the list's order on the calling thread: the same judgements, kept in the same order, so the
//! same step and the same figures, which the tests check along camera paths. A step with
//! fewer than `STEP_THREADS_FROM` lapsed judgements stays on the calling thread.

use super::bits::{bit, clear, set};
use super::hierarchy::{Pending, RUN_TIME};
use super::judge::{judge, Judged};
use super::reuse::NO_NODE;
use super::select::Tessellator;
use crate::deviation::certificate::Asked;
use crate::math::max;
use crate::view::View;
use crate::Arithmetic;

/// Most nodes a step notes as flipped, and most halvings it makes again: a step needing more
/// is left to a search from the roots. (A one-degree orbit step flips a few dozen.)
const ROOM: usize = 1024;

/// Deepest recursion of a step's taking away (a hierarchy is 24 halvings deep in a cell, and
/// a coarser triangle is always at least one level up).
const DEEPEST: u32 = 64;

/// What a step has noted: flipped nodes, halvings to make again, and whether it ran out of
/// room.
struct Notes {
    flips: Nodes<ROOM>,
    repairs: Nodes<ROOM>,
    failed: bool,
}

/// Most halvings one trigger made that a step looks at (its own and the coarser ones it
/// needed: a few as a rule).
const CHAIN: usize = 64;

/// Lapsed nodes a step finds ahead of judging them, on a host (see `judge_the_lapsed`).
const LOOKAHEAD: usize = if cfg!(all(feature = "std", not(target_os = "none"))) {
    64
} else {
    1
};

/// Fewest lapsed judgements a step makes on the threads (fewer stay on the calling thread).
#[cfg(all(feature = "std", not(target_os = "none")))]
const STEP_THREADS_FROM: usize = 512;

/// Lapsed judgements a thread of a step takes at a time (see `judge_the_lapsed_on_threads`).
#[cfg(all(feature = "std", not(target_os = "none")))]
const STEP_PIECE: usize = 64;

/// What a thread of a step judges with (see `judge_the_lapsed_on_threads`): the
/// tessellator's hierarchy, arithmetic and culled patches, and a cache of its own.
#[cfg(all(feature = "std", not(target_os = "none")))]
struct StepThread<'a> {
    tree: super::hierarchy::Hierarchy<'a>,
    arithmetic: Arithmetic,
    /// The culled bits, where the model culls.
    culled: Option<&'a [u32]>,
    viewed: super::select::ViewedCorners,
}

#[cfg(all(feature = "std", not(target_os = "none")))]
impl super::judge::Frame for StepThread<'_> {
    fn tree(&self) -> &super::hierarchy::Hierarchy<'_> {
        &self.tree
    }

    fn arithmetic(&self) -> Arithmetic {
        self.arithmetic
    }

    fn is_culled(&self, patch: u32) -> bool {
        self.culled.is_some_and(|bits| bit(bits, patch))
    }

    fn position(&self, v: u32) -> [f32; 3] {
        // (A step's vertices are all the bake's: the pool is empty.)
        self.tree.position(v as usize).unwrap_or_default()
    }

    fn viewed(
        &self,
        v: u32,
        p: impl FnOnce() -> glam::Vec3,
        camera: &crate::view::Camera,
    ) -> glam::Vec3 {
        self.viewed
            .get(v, self.tree.vertex_count(), || camera.to_view(p()))
    }
}

/// A short list of nodes.
struct Nodes<const N: usize> {
    nodes: [u32; N],
    len: usize,
}

impl<const N: usize> Nodes<N> {
    const fn new() -> Self {
        Nodes {
            nodes: [0; N],
            len: 0,
        }
    }

    /// Adds `node`; false where the list is full.
    fn push(&mut self, node: u32) -> bool {
        let Some(slot) = self.nodes.get_mut(self.len) else {
            return false;
        };
        *slot = node;
        self.len += 1;
        true
    }

    fn len(&self) -> usize {
        self.len
    }

    fn get(&self, k: usize) -> u32 {
        self.nodes[k]
    }

    fn contains(&self, node: u32) -> bool {
        self.nodes[..self.len].contains(&node)
    }
}

impl Tessellator<'_, '_> {
    /// Adds baked node `node` to the list of the mesh's nodes, where reuse keeps one.
    pub(super) fn list(&mut self, node: u32) {
        if node == RUN_TIME {
            return;
        }
        // (A frame without certificates is not stepped from: it keeps no list.)
        let (bits, layout) = (&*self.bits, self.layout);
        if let Some(r) = self
            .reuse
            .as_mut()
            .filter(|r| cfg!(feature = "reuse") && r.certify)
        {
            r.list(node, bit(&bits[layout.halved..layout.judged], node));
        }
    }

    /// Notes that the current trigger halved baked node `node`, where reuse keeps triggers.
    pub(super) fn note_trigger(&mut self, node: u32) {
        let trigger = self.trigger;
        if let Some(r) = self
            .reuse
            .as_mut()
            .filter(|r| cfg!(feature = "reuse") && r.certify)
        {
            r.set_trigger(node, trigger);
        }
    }

    /// Whether `h`, a triangle of the bake in the mesh, is over the tolerance by its own
    /// bound: by its judgement kept, or judged now (and kept).
    pub(super) fn over_by_itself(&mut self, h: &Pending) -> bool {
        let Some(view) = self.view else {
            return false;
        };
        let Some(r) = self.reuse.as_ref() else {
            return false;
        };
        if self.is_culled(h.tri.patch) {
            return false;
        }
        if let Some(over) = r.kept(h.node) {
            return over;
        }
        let j = self.judge_and_keep(&view, h, false);
        self.stats.judged += 1;
        is_over(&j, view.tolerance())
    }

    /// Judges `h` in `view` (see `judge`), with a certificate where reuse keeps judgements
    /// (and one is worth asking for: see [`Judgement`](super::Judgement)), and keeps what
    /// it certifies.
    pub(super) fn judge_and_keep(&mut self, view: &View, h: &Pending, exact: bool) -> Judged {
        let asked = match (self.ask(h), &self.reuse) {
            (Some((start, guess)), Some(r)) => r.asked_from(start, guess),
            _ => Asked::NONE,
        };
        let was_asked = !asked.is_empty();
        let j = judge(self, view, h, exact, asked);
        self.keep_judgement(h.node, was_asked, &j);
        j
    }

    /// The level from which a certificate is asked for `h`'s judgement, where one is (not a
    /// plain judgement: see [`Judgement`](super::Judgement)), and the judgement most likely
    /// made (see [`Asked::guess`]).
    fn asked_level(&self, h: &Pending) -> Option<(u8, bool)> {
        let r = self.reuse.as_ref().filter(|_| cfg!(feature = "reuse"))?;
        if h.node == RUN_TIME || r.is_plain(h.node) {
            return None;
        }
        let asked = r.asked(h.node);
        (!asked.is_empty()).then_some((asked.start, asked.guess))
    }

    /// [`asked_level`](Self::asked_level), counting a plain judgement (one that asks for
    /// nothing: where a certificate is asked for, there is nothing to count).
    fn ask(&mut self, h: &Pending) -> Option<(u8, bool)> {
        let level = self.asked_level(h);
        let reuse = self.reuse.as_mut().filter(|_| cfg!(feature = "reuse"));
        if let Some(r) = reuse.filter(|_| level.is_none() && h.node != RUN_TIME) {
            r.count_plain(h.node);
        }
        level
    }

    /// Keeps node `node`'s judgement `j`, or notes that it has no certificate, where one was
    /// `asked` for.
    fn keep_judgement(&mut self, node: u32, asked: bool, j: &Judged) {
        if let Some(r) = self.reuse.as_mut().filter(|_| asked) {
            match j.lasting {
                Some(lasting) => r.keep(node, lasting),
                None => r.missed(node),
            }
        }
    }

    /// At the end of a search from the roots: whether the next frame may step from this one.
    pub(super) fn mark_steady(&mut self) {
        let steady = cfg!(feature = "reuse")
            && self.part().is_none()
            && self.whole_within_the_bake()
            && self.arithmetic == Arithmetic::Float
            && self.tree.linked(0).is_some()
            && matches!(self.view, Some(View::Screen { .. }));
        if let Some(r) = self.reuse.as_mut() {
            // (A frame that wrote no certificates leaves every judgement to be made again:
            // the next is searched, and writes them.)
            r.steady = steady && r.certify;
        }
    }

    /// The frame searched or stepped every leaf within the bake: nothing left for a walk.
    fn whole_within_the_bake(&self) -> bool {
        !self.full && self.pool.used == 0 && self.stats.left_over == 0 && !self.recount
    }

    /// Finds `view`'s mesh by a step from the last frame's (see the module docs); false where
    /// it cannot, and then the caller searches from the roots.
    pub(super) fn step(&mut self, view: &View) -> bool {
        if !cfg!(feature = "reuse") {
            return false;
        }
        let View::Screen { camera, .. } = view else {
            return false;
        };
        let steady = self.reuse.as_ref().is_some_and(|r| r.steady);
        if !steady || self.arithmetic != Arithmetic::Float || !self.culls_alike(camera) {
            return false;
        }
        let last = self.view;
        let Some(r) = self.reuse.as_mut() else {
            return false;
        };
        r.advance(last.as_ref(), view);
        // (A search from here moves the odometer by nothing.)
        self.view = Some(*view);
        if !self.reuse.as_ref().is_some_and(|r| r.steady) {
            return false; // a view the judgements cannot carry over to
        }
        self.begin_step();
        let mut notes = Notes {
            flips: Nodes::new(),
            repairs: Nodes::new(),
            failed: false,
        };
        self.judge_the_lapsed(view, &mut notes);
        for k in 0..notes.flips.len() {
            let node = notes.flips.get(k);
            if bit(self.halved(), node) {
                if self.trigger_of(node) == node {
                    self.take_away(node, 0, &mut notes);
                }
            } else if self.in_mesh(node) {
                // A leaf now over: halved as the search halves it.
                let Some(h) = self.place(node) else {
                    notes.failed = true;
                    break;
                };
                self.forget_leaf(&h);
                self.push(h);
            }
        }
        for k in 0..notes.repairs.len() {
            let node = notes.repairs.get(k);
            if notes.failed || !bit(self.halved(), node) || self.in_mesh(node) {
                continue;
            }
            let Some(parent) = self.tree.linked(node).map(|l| l.parent) else {
                notes.failed = true;
                break;
            };
            let trigger = self.trigger_of(node);
            let before = core::mem::replace(&mut self.trigger, trigger);
            notes.failed |= !self.halve_down_to(parent, 1);
            self.trigger = before;
        }
        if notes.failed {
            return false;
        }
        self.drain_in_mesh(view);
        self.whole_within_the_bake()
    }

    /// The start of a step: the frame's figures but for its counts, which carry over.
    fn begin_step(&mut self) {
        let (triangles, hidden) = (self.stats.triangles, self.stats.hidden);
        self.stats = super::FrameStats {
            triangles,
            hidden,
            stepped: true,
            ..Default::default()
        };
        self.vertices = None;
        self.viewed.clear();
        self.len = 0;
        (self.full, self.dropped_below, self.recount) = (false, false, false);
        self.dropped_patches = 0;
    }

    /// Judges again every node of the mesh whose judgement lapsed (leaves, and halved nodes
    /// that are triggers), and notes those that flip.
    fn judge_the_lapsed(&mut self, view: &View, notes: &mut Notes) {
        #[cfg(all(feature = "std", not(target_os = "none")))]
        if self.step_threads && self.pool.used == 0 {
            return self.judge_the_lapsed_on_threads(view, notes);
        }
        let tolerance = view.tolerance();
        let mut from = 0;
        loop {
            // The next few lapsed nodes, found before any of them is judged, and their places
            // read once in a row: they lie scattered over the links, and reads made one after
            // another, each needing none before it, wait for memory together (on a host;
            // a microcontroller has no cache to wait on, and no room to spare on its stack).
            // Judging a node changes its own entry of the list alone: the same nodes, judged
            // in the same order.
            let mut batch = [0u32; LOOKAHEAD];
            let n;
            (n, from) = self.lapsed(from, &mut batch, tolerance);
            if LOOKAHEAD > 1 {
                let mut read = 0u32;
                for &node in &batch[..n] {
                    read ^= self.tree.linked(node).map_or(0, |l| l.place.node);
                }
                core::hint::black_box(read);
            }
            for &node in &batch[..n] {
                let Some(h) = self.place(node) else {
                    notes.failed = true;
                    return;
                };
                let j = self.judge_and_keep(view, &h, !self.halvable(&h));
                if !self.note_judged(node, &h, &j, tolerance, notes) {
                    return;
                }
            }
            if n < LOOKAHEAD {
                return;
            }
        }
    }

    /// [`judge_the_lapsed`](Self::judge_the_lapsed) with the judgements made on the threads
    /// (`rayon`'s), each with a cache of its own of the corners in view coordinates: the same
    /// judgements, kept and noted in the same order, so the same step. (Few are left to this
    /// thread: a thread's work costs more than it saves.)
    #[cfg(all(feature = "std", not(target_os = "none")))]
    fn judge_the_lapsed_on_threads(&mut self, view: &View, notes: &mut Notes) {
        use std::vec;
        use std::vec::Vec;
        let tolerance = view.tolerance();
        // The lapsed nodes, their places, whether they are judged in full and the level a
        // certificate is asked from (none for a plain judgement), in order.
        let mut lapsed = Vec::new();
        let mut from = 0;
        loop {
            let mut batch = [0u32; LOOKAHEAD];
            let n;
            (n, from) = self.lapsed(from, &mut batch, tolerance);
            for &node in &batch[..n] {
                let Some(h) = self.place(node) else {
                    notes.failed = true;
                    return;
                };
                lapsed.push((node, h, !self.halvable(&h), self.asked_level(&h)));
            }
            if n < LOOKAHEAD {
                break;
            }
        }
        let judged: Vec<Judged> = match self.reuse.as_ref() {
            Some(r) if lapsed.len() >= STEP_THREADS_FROM => {
                let (tree, arithmetic) = (self.tree, self.arithmetic);
                let culled = self
                    .sphere
                    .is_some()
                    .then(|| &self.bits[self.layout().culled..]);
                // Pieces of the list, each judged into its own place, taken by the calling
                // thread from the start and by rayon's threads as they wake.
                let mut judged = vec![Judged::bare(0.0, false); lapsed.len()];
                let pieces = std::sync::Mutex::new(
                    lapsed.chunks(STEP_PIECE).zip(judged.chunks_mut(STEP_PIECE)),
                );
                let work = |_| {
                    let frame = StepThread {
                        tree,
                        arithmetic,
                        culled,
                        viewed: super::select::ViewedCorners::new(),
                    };
                    while let Some((from, to)) = pieces.lock().ok().and_then(|mut p| p.next()) {
                        for (&(_, h, exact, asked), out) in from.iter().zip(to) {
                            let asked = asked
                                .map_or(Asked::NONE, |(start, guess)| r.asked_from(start, guess));
                            *out = judge(&frame, view, &h, exact, asked);
                        }
                    }
                };
                super::parallel::on_threads(rayon::current_num_threads(), work);
                judged
            }
            _ => Vec::new(),
        };
        for (k, &(node, h, exact, _)) in lapsed.iter().enumerate() {
            // (Where the threads did not judge, this one does, and keeps it.)
            let j = match judged.get(k) {
                Some(j) => {
                    let asked = self.ask(&h).is_some();
                    self.keep_judgement(node, asked, j);
                    *j
                }
                None => self.judge_and_keep(view, &h, exact),
            };
            if !self.note_judged(node, &h, &j, tolerance, notes) {
                return;
            }
        }
    }

    /// The nodes from entry `from` of the list on whose judgement lapsed, as many as `out`
    /// holds, counting the judgements that hold on the way: how many, and the entry to go on
    /// from (see [`Reuse::lapsed`](super::reuse::Reuse::lapsed)).
    #[inline(always)]
    fn lapsed(&mut self, from: usize, out: &mut [u32], tolerance: f32) -> (usize, usize) {
        let Some(r) = self.reuse.as_ref() else {
            return (0, from);
        };
        let (mut kept, mut leaf_kept) = (0, false);
        let found = r.lapsed(from, out, &mut kept, &mut leaf_kept);
        self.stats.kept += kept;
        if leaf_kept {
            self.stats.worst_bound = max(self.stats.worst_bound, tolerance);
        }
        found
    }

    /// Whether `h` can be halved (else it is judged in full).
    fn halvable(&self, h: &Pending) -> bool {
        self.tree.baked_first_half(h).is_some()
            || (cfg!(feature = "refine") && !self.pool.is_full())
    }

    /// Notes node `node`'s judgement `j` made again (in the mesh at `h`): a flip, whether it
    /// is hidden, the frame's bound; false where the step ran out of room (and then it
    /// failed).
    #[inline(always)]
    fn note_judged(
        &mut self,
        node: u32,
        h: &Pending,
        j: &Judged,
        tolerance: f32,
        notes: &mut Notes,
    ) -> bool {
        let hidden = self.layout().hidden;
        self.stats.judged += 1;
        let over = is_over(j, tolerance);
        if bit(self.halved(), node) {
            if !over && !notes.flips.push(node) {
                notes.failed = true;
                return false; // (a step this large is left to a search)
            }
            return true;
        }
        if j.hidden != bit(&self.bits[hidden..], node) {
            // Shown now and hidden before, or the other way round.
            let written = usize::from(self.is_written(h));
            if j.hidden {
                set(&mut self.bits[hidden..], node);
                self.stats.hidden += 1;
                self.stats.triangles -= written;
            } else {
                clear(&mut self.bits[hidden..], node);
                self.stats.hidden -= 1;
                self.stats.triangles += written;
            }
        }
        if over {
            if !notes.flips.push(node) {
                notes.failed = true;
                return false;
            }
        } else if !j.hidden {
            self.stats.worst_bound = max(self.stats.worst_bound, j.bound.value());
        }
        true
    }

    /// Takes away what trigger `t` halved (its own diamond, and every coarser one it
    /// needed), now that it is within the tolerance or no longer in the mesh: parents first,
    /// each halving stands where its parents do and one of its two triangles is over the
    /// tolerance by itself (it is kept, for that triangle's sake), and is taken away
    /// otherwise.
    fn take_away(&mut self, t: u32, depth: u32, notes: &mut Notes) {
        if depth > DEEPEST {
            notes.failed = true;
            return;
        }
        let mut chain = Nodes::<CHAIN>::new();
        self.halved_by(t, t, 0, &mut chain, notes);
        for k in 0..chain.len() {
            let x = chain.get(k);
            if notes.failed || !bit(self.halved(), x) || self.trigger_of(x) != t {
                continue; // (taken away with its mate already)
            }
            let Some(mate) = self.tree.linked(x).map(|l| l.mate) else {
                notes.failed = true;
                return;
            };
            let pair = [x, mate];
            let mate_too = mate != NO_NODE && bit(self.halved(), mate);
            if mate_too && self.trigger_of(mate) != t {
                // (A diamond's triangles are halved together, by one trigger.)
                notes.failed = true;
                return;
            }
            let standing = pair.iter().all(|&z| self.parent_halved(z));
            let mut own = None;
            if standing {
                for z in pair {
                    if z != t && z != NO_NODE && own.is_none() {
                        let Some(h) = self.place(z) else {
                            notes.failed = true;
                            return;
                        };
                        if self.over_by_itself(&h) {
                            own = Some(z);
                        }
                    }
                }
            }
            match own {
                Some(z) => {
                    if let Some(r) = self.reuse.as_mut() {
                        r.set_trigger(x, z);
                        if mate_too {
                            r.set_trigger(mate, z);
                        }
                    }
                }
                None => {
                    self.unhalve(x, t, depth, notes);
                    if mate_too {
                        self.unhalve(mate, t, depth, notes);
                    }
                }
            }
        }
    }

    /// Adds to `chain` halved node `x` and the coarser nodes above it that trigger `t`
    /// halved (one node of each diamond), parents before their halves.
    fn halved_by(
        &mut self,
        x: u32,
        t: u32,
        depth: u32,
        chain: &mut Nodes<CHAIN>,
        notes: &mut Notes,
    ) {
        if x == NO_NODE || !bit(self.halved(), x) || self.trigger_of(x) != t {
            return;
        }
        let Some(link) = self.tree.linked(x) else {
            notes.failed = true;
            return;
        };
        let mate = link.mate;
        if chain.contains(x) || (mate != NO_NODE && chain.contains(mate)) {
            return;
        }
        if depth > DEEPEST {
            notes.failed = true;
            return;
        }
        for z in [x, mate] {
            if let Some(parent) = self.tree.linked(z).map(|l| l.parent) {
                self.halved_by(parent, t, depth + 1, chain, notes);
            }
        }
        if !chain.contains(x) && !chain.push(x) {
            notes.failed = true;
        }
    }

    /// Whether node `z` (or no node) is in the mesh by its parent: a root, or its parent
    /// halved.
    fn parent_halved(&self, z: u32) -> bool {
        z == NO_NODE || self.in_mesh(z)
    }

    /// Takes away the halving of node `z` (halved by `t`): its halves leave the mesh, with
    /// the halvings they triggered; a halving of theirs made for another's sake is noted, to
    /// be made again if it still stands. `z` itself is queued, to be judged as a leaf if it
    /// still is in the mesh.
    fn unhalve(&mut self, z: u32, t: u32, depth: u32, notes: &mut Notes) {
        let judged = self.layout().judged;
        let hidden = self.layout().hidden;
        clear(self.bits, z);
        if let Some(r) = self.reuse.as_mut() {
            r.unhalved(z);
        }
        clear(&mut self.bits[judged..], z);
        clear(&mut self.bits[hidden..], z);
        let Some(h) = self.place(z) else {
            notes.failed = true;
            return;
        };
        let Some(first) = self.tree.baked_first_half(&h) else {
            notes.failed = true;
            return;
        };
        for c in [first, first + 1] {
            if let Some(r) = self.reuse.as_mut() {
                r.unlist(c);
            }
            if bit(self.halved(), c) {
                let u = self.trigger_of(c);
                if u == c {
                    // A trigger no longer in the mesh.
                    self.take_away(c, depth + 1, notes);
                } else if u == t {
                    // (In `t`'s chain, after its parents: taken away there.)
                } else if !notes.repairs.push(c) {
                    notes.failed = true;
                }
            } else if bit(&self.bits[judged..], c) {
                match self.place(c) {
                    Some(leaf) => self.forget_leaf(&leaf),
                    None => notes.failed = true,
                }
            }
        }
        self.push(h);
    }

    /// Judges the queued leaves that are still in the mesh, halving those over the
    /// tolerance.
    fn drain_in_mesh(&mut self, view: &View) {
        let tolerance = view.tolerance();
        while self.len > 0 {
            self.len -= 1;
            let h = self.stack[self.len].get();
            if h.node != RUN_TIME && !self.in_mesh(h.node) {
                continue;
            }
            self.process(view, tolerance, h);
        }
    }

    /// Whether node `node` is in the mesh: a root, or a half of a halved node.
    fn in_mesh(&self, node: u32) -> bool {
        match self.tree.linked(node) {
            Some(l) => l.parent == NO_NODE || bit(self.halved(), l.parent),
            None => false,
        }
    }

    /// Node `node` as the search names it, by its link.
    fn place(&self, node: u32) -> Option<Pending> {
        self.tree.linked(node).map(|l| l.place)
    }

    /// The trigger kept for halved node `node`.
    fn trigger_of(&self, node: u32) -> u32 {
        self.reuse.as_ref().map_or(NO_NODE, |r| r.trigger(node))
    }

    /// Takes leaf `h` off the frame's figures and clears its judged and hidden bits: it leaves
    /// the mesh, or is to be judged (again) as the search judges a leaf.
    fn forget_leaf(&mut self, h: &Pending) {
        self.uncount_leaf(h);
        let layout = self.layout();
        clear(&mut self.bits[layout.judged..], h.node);
        clear(&mut self.bits[layout.hidden..], h.node);
    }
}

/// Whether judgement `j` is over `tolerance`, as the search takes it: shown, and its bound
/// not within (a NaN bound is over).
fn is_over(j: &Judged, tolerance: f32) -> bool {
    !j.hidden && j.bound.is_over(tolerance)
}
