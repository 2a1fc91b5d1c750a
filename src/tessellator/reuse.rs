//! Frame-to-frame reuse: judgements kept with a certificate of how far the camera may move
//! before they can change (`deviation/certificate.rs` derives it), so that a camera step
//! judges again only the triangles whose certificates ran out.
//!
//! # The odometer
//!
//! Each frame, the camera's step from the frame before is measured for the model's sphere
//! (centre `c`, radius `R`; [`Camera::moved_from`](crate::Camera::moved_from)): the centre
//! moves by at most `shift` in view coordinates and a unit direction turns by at most `ρ`,
//! so a point within `d` of the centre moves by at most `δ(d) = ρ d + shift` (with their
//! roundings). All of these add up along a path (the triangle inequality). The odometer of
//! reach `d`, `S_d`, the sum of each step's `ρ + shift / d`, then bounds the move between
//! any two frames by the difference of its readings: `ρ <= ΔS_d` and `δ(d) <= d ΔS_d`.
//!
//! A triangle whose corners lie within `d` of the centre (its *reach class*, the least of
//! [`REACHES`] that holds them, measured in the frame it is judged in), judged at reading
//! `S₀` with a certificate for steps up to `s` (of [`LEVELS`]: corners moving by at most
//! `s d`, vectors turning by at most `s`), keeps its judgement while its class's reading is
//! at most `S₀ + s`. Its slot holds that expiry, the class and the judgement; the search
//! reads it where it would judge (see `select`), and a frame's mesh is what a search judging
//! every triangle would find: exactly the view's unique mesh. (A turn moves a point near the
//! centre less than one at the sphere's edge: a near triangle's certificate lasts longer.)
//!
//! A view with another projection, viewport, near plane or tolerance (or none before, or an
//! odometer past [`RESET`]) empties every slot and starts the odometer again. Such a frame,
//! and one whose camera jumped past the longest certificate, asks for no certificates (a
//! certificate costs about what its judgement does): it costs a cold frame. The frame after
//! it, where the camera moved less, is searched from the roots and writes them; the frames
//! after that step.
//!
//! # Storage
//!
//! One [`Judgement`] per node of the hierarchy, the caller's
//! ([`Tessellator::with_reuse`](super::Tessellator::with_reuse)): 28 bytes a node (the
//! judgement, and for a step the node's trigger and its place in the list of the mesh's
//! nodes: see `step`). A tessellator without them judges every triangle of every frame.
//!
//! Slot `k` also holds entry `k` of the list, and that entry keeps a copy of what a step's
//! scan for lapsed judgements reads of its node: the expiry, the class, and whether the node
//! is a leaf, halved for its own sake or halved for another's. The scan then reads the list
//! in order, not the slots of the nodes it names, scattered over the hierarchy: 100
//! one-degree orbit updates of `frame_loop` at 2.5e-4 took 413.2M instructions against 428.1M
//! on the teapot and 492.7M against 515.6M on Gumbo, and their mean update about 10% less
//! time on either (for 8 bytes more a slot). The copy is made where the node is listed,
//! and kept in step where its judgement is kept ([`Reuse::keep`]), where it is halved
//! ([`Reuse::set_trigger`], with every halving a step keeps) and where a step takes the
//! halving away ([`Reuse::unhalved`]); an entry moved in the list takes it along.
//!
//! The list keeps the nodes whose own judgement is asked for (leaves, and nodes halved for
//! their own sake) before those halved for another's sake, moving an entry across where it
//! changes sides, and the scan reads the first part alone: about a third of the entries are
//! the other kind. 100 one-degree orbit updates of `frame_loop` at 2.5e-4 took 332.3M
//! instructions against 344.0M on the teapot and 204.3M against 216.1M on Gumbo.
//!
//! The scan counts the judgements that held as the entries it read less those that lapsed,
//! and looks for a leaf's that held (a frame that keeps one reports the tolerance as its
//! worst bound) only until it finds one, most often among the first few entries: the same
//! 100 updates took 322.1M instructions against 328.9M on the teapot, 195.1M against 200.9M
//! on Gumbo.

use glam::Vec3;

use super::hierarchy::Hierarchy;
use crate::bound::BoundingSphere;
use crate::deviation::certificate::{Asked, Lasting, Steps};
use crate::view::{Camera, View};

/// The steps a certificate may cover, in odometer units (of turn: the change of the camera's
/// rotation, about its angle in radians; or of move: the triangle's reach class), smallest
/// first: a judgement is certified for the largest it holds over, or a step between it and
/// the next where it holds over that too (`certificate::lasting`). A one-degree orbit step
/// around the model is about 0.018-0.03. (Six levels a factor of two apart, against three a
/// factor of four apart, cost each certificate more bounds and save more judgements: 737M
/// against 759M instructions for the updates of `frame_loop`'s 100 one-degree orbit steps,
/// 2,366 against 2,971 triangles judged a step. With certificates between levels, the first
/// level is 1/32, not 1/64, which is shorter than a one-degree step: 428.1M against 436.9M
/// instructions, 1,488 against 1,434 judged a step; three levels a factor of four apart
/// from 1/32 cost 450.8M, and these five taken 1.5 times longer 436.9M.)
pub const LEVELS: [f32; 5] = [1.0 / 32.0, 1.0 / 16.0, 1.0 / 8.0, 1.0 / 4.0, 1.0 / 2.0];

/// The reach classes, as fractions of the model sphere's radius `R` (decreasing): a
/// triangle whose corners lie within `f R` of the sphere's centre is certified for turns `s`
/// with moves of `s f R` (a camera's turn moves a point near the centre less), its judgement
/// read against the odometer of its class (see the module docs). (Eight classes against one,
/// all of `R`: 485.7M against 531.8M instructions for the updates of `frame_loop`'s 100
/// one-degree orbit steps, 1,558 against 1,907 triangles judged a step; twelve classes down
/// to `0.15 R` judge as many as eight.)
pub const REACHES: [f32; 8] = [1.0, 0.84, 0.71, 0.59, 0.5, 0.42, 0.35, 0.3];

/// Judgements made without asking for a certificate after one could not be given. (Eight
/// against four: the updates of `frame_loop`'s 100 one-degree orbit steps at 2.5e-4,
/// callgrind on `Tessellator::update`, took the teapot 371.1M against 374.5M instructions,
/// Gumbo 451.1M against 454.5M, though they judge more, 1,397 against 1,350 and 1,726
/// against 1,670 a step; sixteen took 386.2M and 461.5M, two 382.3M on the teapot.)
pub const PLAIN: u8 = 8;

/// The odometer reading past which every slot is emptied and it starts again (so that its
/// sums keep their precision).
pub const RESET: f32 = 64.0;

/// One node's kept judgement, and what the frame-to-frame step keeps of the node's place in
/// the mesh (see `step`): opaque, the caller only provides room for them
/// (`Tessellator::with_reuse`, feature `reuse`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Judgement {
    /// The odometer reading it holds to.
    expires: f32,
    /// Over the tolerance (else within).
    over: bool,
    /// The level of the last certificate, where the next search for one starts.
    level: u8,
    /// Judgements still to be made without asking for a certificate, after one was asked
    /// for and none could be given, or one shorter than the camera's last step (the triangle
    /// is near the tolerance: most likely no certificate that lasts a step can be given the
    /// next time either, and a judgement costs about half as much without).
    plain: u8,
    /// The reach class of the certificate (an index of [`REACHES`]).
    class: u8,
    /// Where the mesh halves this node: the node whose judgement over the tolerance halved
    /// it, itself or one finer that needed it halved (see `step`).
    trigger: u32,
    /// Where this node is in the mesh: its entry in the list of the mesh's nodes, or `NONE`.
    at: u32,
    /// The list's entry of this slot's number.
    entry: Entry,
}

/// An entry of the list of the mesh's nodes: the node it holds, with a copy of what the scan
/// for lapsed judgements reads of it (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct Entry {
    node: u32,
    /// Its node's `expires`.
    expires: f32,
    /// Its node's `class`.
    class: u8,
    /// How the mesh holds its node.
    held: Held,
}

impl Entry {
    /// No entry.
    const NONE: Entry = Entry {
        node: NO_NODE,
        expires: f32::NEG_INFINITY,
        class: 0,
        held: Held::Leaf,
    };
}

/// How the mesh holds a listed node, for the scan for lapsed judgements: as a leaf (its
/// judgement asked for), halved for its own sake (asked for too: it may no longer be over),
/// or halved for another's (not asked for).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Held {
    Leaf,
    Own,
    ForAnother,
}

impl Held {
    /// How node `node`, halved or not, with trigger `trigger`, is held.
    fn of(node: u32, halved: bool, trigger: u32) -> Held {
        match (halved, trigger == node) {
            (false, _) => Held::Leaf,
            (true, true) => Held::Own,
            (true, false) => Held::ForAnother,
        }
    }
}

impl Judgement {
    /// No judgement.
    pub const NONE: Judgement = Judgement {
        expires: f32::NEG_INFINITY,
        over: false,
        level: 0,
        plain: 0,
        class: 0,
        trigger: NO_NODE,
        at: NO_NODE,
        entry: Entry::NONE,
    };
}

/// No node (and no entry of the list).
pub(super) const NO_NODE: u32 = u32::MAX;

impl Default for Judgement {
    fn default() -> Self {
        Judgement::NONE
    }
}

impl Hierarchy<'_> {
    /// [`Judgement`]s a tessellator of this hierarchy keeps for frame-to-frame reuse: one per
    /// node.
    pub fn judgement_slots(&self) -> usize {
        self.node_count()
    }
}

/// A tessellator's kept judgements, its odometer, and the sphere it measures steps by; and
/// the list of the mesh's nodes (its leaves and the nodes it halves), with why each halved
/// node is, for the next frame's step (see `step`).
#[derive(Debug)]
pub(super) struct Reuse<'s> {
    slots: &'s mut [Judgement],
    /// Entries of the list of the mesh's nodes.
    len: usize,
    /// The first `asked` entries are the nodes whose own judgement is asked for (leaves, and
    /// nodes halved for their own sake); the rest are halved for another's sake, never
    /// judged by themselves, and a step's scan for lapsed judgements leaves them out (about
    /// a third of the list).
    asked: usize,
    /// The mesh, its list and its triggers are the last frame's, whole: a step may start
    /// from them.
    pub steady: bool,
    /// The odometer of each reach class.
    readings: [f32; REACHES.len()],
    /// The camera's last step, `[shift, ρ]` (see `Camera::shift_and_turn_from`).
    last_step: [f32; 2],
    sphere: BoundingSphere,
    /// What certificates are asked for: [`LEVELS`] and [`REACHES`] for this sphere, its
    /// centre in the view's coordinates.
    steps: Steps,
    /// This frame asks for certificates: the camera came a step within the longest
    /// certificate from the last frame's (after a jump, the next frame is most likely
    /// another jump or a step's start, and the certificates a jump would write cost as much
    /// as its judgements: a jump costs a cold frame, and the frame after it writes them).
    pub certify: bool,
}

impl<'s> Reuse<'s> {
    /// Reuse over the model within `sphere`, in `slots` (emptied).
    #[cfg_attr(not(feature = "reuse"), allow(dead_code))]
    pub fn new(slots: &'s mut [Judgement], sphere: BoundingSphere) -> Reuse<'s> {
        slots.fill(Judgement::NONE);
        // (The hierarchy's points are rounded, and a step's bound counts from the centre:
        // a little more radius covers both.)
        let sphere = BoundingSphere {
            radius: sphere.radius * (1.0 + 1.0 / 256.0),
            ..sphere
        };
        Reuse {
            slots,
            len: 0,
            asked: 0,
            steady: false,
            readings: [0.0; REACHES.len()],
            last_step: [0.0; 2],
            sphere,
            steps: Steps {
                levels: &LEVELS,
                reaches: &REACHES,
                radius: sphere.radius,
                centre: Vec3::ZERO,
            },
            certify: false,
        }
    }

    /// The steps a certificate for node `node` is asked for (none for a node with no slot).
    pub fn asked(&self, node: u32) -> Asked<'_> {
        match self.slots.get(node as usize).filter(|_| self.certify) {
            Some(j) => Asked {
                steps: Some(&self.steps),
                start: j.level,
                guess: j.over,
            },
            None => Asked::NONE,
        }
    }

    /// The steps of every certificate, from level `start` on, for a judgement most likely
    /// over the tolerance where `guess` (see [`Asked::guess`]).
    pub fn asked_from(&self, start: u8, guess: bool) -> Asked<'_> {
        Asked {
            steps: Some(&self.steps),
            start,
            guess,
        }
    }

    /// Whether node `node`'s next judgement goes without a certificate (see
    /// [`Judgement::plain`]), without counting it ([`count_plain`](Self::count_plain) does).
    pub fn is_plain(&self, node: u32) -> bool {
        !self.certify || self.slots.get(node as usize).is_some_and(|j| j.plain > 0)
    }

    /// Counts a judgement of node `node` made without a certificate after a miss.
    pub fn count_plain(&mut self, node: u32) {
        if let Some(j) = self.slots.get_mut(node as usize).filter(|_| self.certify) {
            j.plain = j.plain.saturating_sub(1);
        }
    }

    /// Notes that no certificate could be given to node `node`'s judgement: the next
    /// [`PLAIN`] go without asking.
    pub fn missed(&mut self, node: u32) {
        if let Some(j) = self.slots.get_mut(node as usize) {
            (j.level, j.plain) = (0, PLAIN);
        }
    }

    /// Moves the odometer from `last` (the frame before, if any) to `view`, or empties the
    /// slots where the judgements cannot carry over.
    pub fn advance(&mut self, last: Option<&View>, view: &View) {
        // The cameras before and now, where both frames are on screen at one tolerance.
        let cameras = match (last, view) {
            (
                Some(View::Screen {
                    camera: before,
                    tolerance_px: t0,
                }),
                View::Screen {
                    camera,
                    tolerance_px: t1,
                },
            ) if t0.to_bits() == t1.to_bits() => Some((before, camera)),
            _ => None,
        };
        if cameras.is_some_and(|(before, camera)| before.bits() == camera.bits()) {
            // The same view (a search after a step that gave up, or a frame drawn again):
            // nothing moved, and the frame asks for certificates as it did.
            return;
        }
        let step = cameras
            .filter(|(before, camera)| same_lens(before, camera))
            .map(|(before, camera)| camera.shift_and_turn_from(before, &self.sphere));
        if let View::Screen { camera, .. } = view {
            self.steps.centre = camera.to_view(self.sphere.center);
        }
        let moved = step.and_then(|step| self.readings_after(step));
        match (step, moved) {
            (Some(step), Some(readings)) => {
                // A jump past the longest certificate: no judgement holds, and a step would
                // judge every node again before a search from the roots.
                self.certify = readings[0] - self.readings[0] <= LEVELS[LEVELS.len() - 1];
                self.steady &= self.certify;
                (self.readings, self.last_step) = (readings, step);
            }
            _ => {
                self.slots.fill(Judgement::NONE);
                (self.readings, self.last_step) = ([0.0; REACHES.len()], [0.0; 2]);
                (self.len, self.asked) = (0, 0);
                // (The list is empty now: a search lists its mesh again.)
                (self.steady, self.certify) = (false, false);
            }
        }
    }

    /// Each class's odometer after a camera step `[shift, ρ]`, or `None` past [`RESET`]: a
    /// point within reach `d` moves by at most `ρ d (1 + 2^-16) + shift`, so the reading of
    /// reach `d` goes up by `(ρ (1 + 2^-16) + shift / d)`, rounded up.
    fn readings_after(&self, [shift, rho]: [f32; 2]) -> Option<[f32; REACHES.len()]> {
        let mut readings = self.readings;
        for (k, reading) in readings.iter_mut().enumerate() {
            let d = self.steps.reach(k);
            let s = (rho * (1.0 + 1.0 / 65536.0) + shift / d) * (1.0 + 1.0 / 65536.0);
            *reading = (*reading + s) * (1.0 + 1.0 / 4_194_304.0);
            if *reading > RESET || reading.is_nan() {
                return None;
            }
        }
        Some(readings)
    }

    /// The node that halved node `node` (see `step`), or [`NO_NODE`].
    pub fn trigger(&self, node: u32) -> u32 {
        self.slots.get(node as usize).map_or(NO_NODE, |j| j.trigger)
    }

    /// Notes that `trigger`'s judgement halved node `node` (it is halved).
    pub fn set_trigger(&mut self, node: u32, trigger: u32) {
        let Some(j) = self.slots.get_mut(node as usize) else {
            return;
        };
        j.trigger = trigger;
        self.hold(node, Held::of(node, true, trigger));
    }

    /// Notes that node `node` is no longer halved (a step took its halving away).
    pub fn unhalved(&mut self, node: u32) {
        self.hold(node, Held::Leaf);
    }

    /// Node `node`'s entry, if it is on the list, held `held` now: moved across the end of
    /// the asked entries where it crosses it.
    fn hold(&mut self, node: u32, held: Held) {
        let Some(e) = self.entry_of(node) else {
            return;
        };
        e.held = held;
        let at = self.slots[node as usize].at as usize;
        match (at < self.asked, held != Held::ForAnother) {
            (true, false) => {
                self.asked -= 1;
                self.swap_entries(at, self.asked);
            }
            (false, true) => {
                self.swap_entries(at, self.asked);
                self.asked += 1;
            }
            _ => {}
        }
    }

    /// The list's entry of node `node`, if it is on the list.
    fn entry_of(&mut self, node: u32) -> Option<&mut Entry> {
        let at = self.slots.get(node as usize)?.at as usize;
        let len = self.len;
        self.slots
            .get_mut(at)
            .filter(|_| at < len)
            .map(|e| &mut e.entry)
    }

    /// Entries `a` and `b` of the list trade places.
    fn swap_entries(&mut self, a: usize, b: usize) {
        let (ea, eb) = (self.slots[a].entry, self.slots[b].entry);
        self.place_entry(eb, a);
        self.place_entry(ea, b);
    }

    /// `entry` becomes entry `k` of the list.
    fn place_entry(&mut self, entry: Entry, k: usize) {
        self.slots[k].entry = entry;
        if let Some(j) = self.slots.get_mut(entry.node as usize) {
            j.at = k as u32;
        }
    }

    /// Empties the list of the mesh's nodes.
    pub fn unlist_all(&mut self) {
        for k in 0..self.len {
            let node = self.slots[k].entry.node;
            if let Some(j) = self.slots.get_mut(node as usize) {
                j.at = NO_NODE;
            }
        }
        (self.len, self.asked) = (0, 0);
    }

    /// Adds node `node` to the list of the mesh's nodes (if it is not on it), halved or
    /// not.
    pub fn list(&mut self, node: u32, halved: bool) {
        let len = self.len;
        let room = len < self.slots.len();
        let j = match self.slots.get_mut(node as usize) {
            Some(j) if j.at == NO_NODE && room => j,
            _ => return,
        };
        let entry = Entry {
            node,
            expires: j.expires,
            class: j.class,
            held: Held::of(node, halved, j.trigger),
        };
        self.len += 1;
        if entry.held == Held::ForAnother {
            self.place_entry(entry, len);
            return;
        }
        // At the end of the asked entries, the first of the others moved to the list's end.
        let first = self.asked;
        if first < len {
            self.place_entry(self.slots[first].entry, len);
        }
        self.place_entry(entry, first);
        self.asked += 1;
    }

    /// Takes node `node` off the list of the mesh's nodes (if it is on it).
    pub fn unlist(&mut self, node: u32) {
        let Some(at) = self.slots.get(node as usize).map(|j| j.at) else {
            return;
        };
        let at = at as usize;
        if at >= self.len {
            return;
        }
        // The hole filled from the end of its part of the list, and a hole there from the
        // list's end.
        let last = self.len - 1;
        if at < self.asked {
            let end = self.asked - 1;
            if end != at {
                self.place_entry(self.slots[end].entry, at);
            }
            if last != end {
                self.place_entry(self.slots[last].entry, end);
            }
            self.asked = end;
        } else if last != at {
            self.place_entry(self.slots[last].entry, at);
        }
        self.slots[node as usize].at = NO_NODE;
        self.len = last;
    }

    /// From entry `from` of the list of the mesh's nodes on, the nodes whose judgement is
    /// asked for (a leaf, or a node halved for its own sake) and no longer holds, in order,
    /// as many as `out` has room for: how many it wrote, and the entry after the last (where
    /// the next call goes on; the list's end where it wrote fewer). Counts in `kept` the
    /// judgements that hold on the way, and in `leaf_kept` whether one of them is a leaf's.
    /// (It reads the entries' copies only: see the module docs.)
    pub fn lapsed(
        &self,
        from: usize,
        out: &mut [u32],
        kept: &mut usize,
        leaf_kept: &mut bool,
    ) -> (usize, usize) {
        // (Only the asked entries: see `asked`.)
        let Some(entries) = self.slots.get(from..self.asked) else {
            return (0, from);
        };
        let mut n = 0;
        if out.is_empty() {
            return (0, from);
        }
        if !self.certify {
            // No judgement holds: every one asked for.
            for (k, j) in entries.iter().enumerate() {
                out[n] = j.entry.node;
                n += 1;
                if n == out.len() {
                    return (n, from + k + 1);
                }
            }
            return (n, self.asked);
        }
        // (Whether a leaf's judgement held is looked for only until one has: most steps find
        // one in the first few entries, and the rest of the scan goes without.)
        let (n, scanned) = match *leaf_kept {
            true => scan::<false>(entries, &self.readings, out, leaf_kept),
            false => scan::<true>(entries, &self.readings, out, leaf_kept),
        };
        // (The judgements that held are the entries scanned that did not lapse.)
        *kept += scanned - n;
        (n, from + scanned)
    }

    /// Node `node`'s kept judgement (over the tolerance or not), if it holds at this reading.
    pub fn kept(&self, node: u32) -> Option<bool> {
        let j = self.slots.get(node as usize)?;
        self.holds(j).then_some(j.over)
    }

    /// Whether judgement `j` holds at its class's reading. (A frame that asks for no
    /// certificates came by a jump or a reset: none holds.)
    #[inline(always)]
    fn holds(&self, j: &Judgement) -> bool {
        self.holds_until(j.class, j.expires)
    }

    /// Whether a judgement of class `class` expiring at `expires` holds (see
    /// [`holds`](Self::holds)).
    #[inline(always)]
    fn holds_until(&self, class: u8, expires: f32) -> bool {
        self.certify
            && self
                .readings
                .get(usize::from(class))
                .is_some_and(|reading| *reading <= expires)
    }

    /// Keeps node `node`'s judgement, certified for steps of `step` in its reach class (of
    /// level `level`: at least `LEVELS[level]`, where the next search for one starts).
    pub fn keep(&mut self, node: u32, lasting: Lasting) {
        let Lasting {
            over,
            level,
            class,
            step,
        } = lasting;
        let Some(reading) = self.readings.get(usize::from(class)) else {
            return;
        };
        if usize::from(level) >= LEVELS.len() {
            return;
        }
        let d = self.steps.reach(usize::from(class));
        let expires = (reading + step) * (1.0 - 1.0 / 4_194_304.0);
        // The class's last step (as `readings_after` took it).
        let [shift, rho] = self.last_step;
        let last = rho + shift / d;
        let Some(j) = self.slots.get_mut(node as usize) else {
            return;
        };
        (j.expires, j.over, j.level, j.class) = (expires, over, level, class);
        // Shorter than the camera's last step: most likely it will not outlast the next
        // one either, and the next judgements go without asking, as after a miss.
        if step < last {
            j.plain = PLAIN;
        }
        if let Some(e) = self.entry_of(node) {
            (e.expires, e.class) = (expires, class);
        }
    }
}

/// A step's scan of the asked `entries` for lapsed judgements (see [`Reuse::lapsed`]): the
/// nodes of those that lapsed, written to `out` until it is full, how many, and how many
/// entries were scanned; with `LEAF`, `leaf_kept` is set where a leaf's judgement held. (An
/// entry's judgement lapses past its class's reading. A kept class is always one of them, and
/// an expiry is never NaN: see `keep`.) The loop has no branch on whether an entry lapsed
/// (about one in six does, at random): the node is written either way, and kept only where
/// it lapsed.
#[inline(always)]
fn scan<const LEAF: bool>(
    entries: &[Judgement],
    readings: &[f32; REACHES.len()],
    out: &mut [u32],
    leaf_kept: &mut bool,
) -> (usize, usize) {
    let mut n = 0;
    for (k, Judgement { entry: e, .. }) in entries.iter().enumerate() {
        let lapsed = readings[usize::from(e.class) % REACHES.len()] > e.expires;
        if let Some(slot) = out.get_mut(n) {
            *slot = e.node;
        }
        n += usize::from(lapsed);
        if LEAF && !lapsed && e.held == Held::Leaf {
            // The rest without looking. (This entry held: `out` has room still.)
            *leaf_kept = true;
            let (more, scanned) =
                scan::<false>(&entries[k + 1..], readings, &mut out[n..], leaf_kept);
            return (n + more, k + 1 + scanned);
        }
        if n == out.len() {
            return (n, k + 1);
        }
    }
    (n, entries.len())
}

/// Whether two cameras project alike: the same projection, viewport and near plane.
fn same_lens(a: &Camera, b: &Camera) -> bool {
    let (x, y) = (a.bits(), b.bits());
    // Projection, near plane, viewport, focal length, slopes: every field after the frame.
    x[12..] == y[12..]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slot is the 28 bytes the docs give.
    #[test]
    fn a_slot_is_28_bytes() {
        assert_eq!(core::mem::size_of::<Judgement>(), 28);
    }

    /// The list's entries carry their nodes' expiry, class and how they are held, through
    /// listing, keeping, halving and moving in the list.
    #[test]
    fn entries_mirror_their_nodes() {
        let mut slots = [Judgement::NONE; 8];
        let sphere = BoundingSphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let mut r = Reuse::new(&mut slots, sphere);
        r.certify = true;
        r.list(5, false);
        r.list(2, false);
        r.list(7, false);
        r.keep(
            7,
            Lasting {
                over: true,
                level: 1,
                class: 3,
                step: 0.5,
            },
        );
        r.set_trigger(2, 6);
        r.set_trigger(5, 5);
        // Entry 0 is node 5 (own), 1 node 7 (a leaf, class 3), 2 node 2 (another's: moved
        // past the asked entries when it became so).
        let entry = |r: &Reuse<'_>, k: usize| {
            let e = r.slots[k].entry;
            (e.node, e.expires, e.class, e.held)
        };
        let expires7 = r.slots[7].expires;
        assert!(expires7 > 0.0);
        assert_eq!(entry(&r, 1), (7, expires7, 3, Held::Leaf));
        assert_eq!(entry(&r, 2).0, 2);
        assert_eq!(entry(&r, 2).3, Held::ForAnother);
        assert_eq!(entry(&r, 0).3, Held::Own);
        assert_eq!((r.asked, r.slots[2].at, r.slots[7].at), (2, 2, 1));
        // Node 5 leaves the list: node 7 (the last asked) moves to its entry, with its copy,
        // and node 2 (the last) to node 7's.
        r.unlist(5);
        assert_eq!(entry(&r, 0), (7, expires7, 3, Held::Leaf));
        assert_eq!(entry(&r, 1).0, 2);
        assert_eq!((r.asked, r.len, r.slots[7].at, r.slots[2].at), (1, 2, 0, 1));
        assert_eq!(r.slots[5].at, NO_NODE);
        // Node 2, halved for another's sake, is past the scan (never kept, it would lapse).
        let (mut kept, mut leaf_kept) = (0, false);
        let mut more = [0u32; 4];
        assert_eq!(r.lapsed(0, &mut more, &mut kept, &mut leaf_kept), (0, 1));
        r.unhalved(2);
        assert_eq!(entry(&r, 1).3, Held::Leaf);
        assert_eq!(r.asked, 2);
        // The scan finds node 2 (never kept: lapsed), then nothing past node 7 (it holds).
        let (mut kept, mut leaf_kept) = (0, false);
        let mut one = [0u32];
        assert_eq!(r.lapsed(0, &mut one, &mut kept, &mut leaf_kept), (1, 2));
        assert_eq!(one, [2]);
        assert_eq!((kept, leaf_kept), (1, true));
        assert_eq!(r.lapsed(2, &mut one, &mut kept, &mut leaf_kept), (0, 2));
        // Room for more: the same node, and the list's end.
        let (mut kept, mut leaf_kept) = (0, false);
        let mut more = [0u32; 4];
        assert_eq!(r.lapsed(0, &mut more, &mut kept, &mut leaf_kept), (1, 2));
        assert_eq!((more[0], kept, leaf_kept), (2, 1, true));
    }

    /// A step's scan, in batches of any size, finds exactly the asked entries whose judgement
    /// lapsed, in the list's order, counts the others as kept, and notes whether a leaf's
    /// judgement was kept, as reading every entry does.
    #[test]
    fn the_scan_finds_every_lapsed_judgement() {
        const N: usize = 64;
        let sphere = BoundingSphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let mut rng = crate::test_rng::TestRng::new(0x5ca_2026);
        let mut unit = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
        for case in 0..300 {
            let mut slots = [Judgement::NONE; N];
            let mut r = Reuse::new(&mut slots, sphere);
            r.certify = true;
            for node in 0..N as u32 {
                let pick = (unit() * 8.0) as u32;
                if pick < 5 {
                    r.list(node, pick >= 3);
                }
                if pick == 3 {
                    r.set_trigger(node, node);
                } else if pick == 4 {
                    r.set_trigger(node, (node + 1) % N as u32);
                }
                // (About 70% of the nodes kept in the first 200 cases, none after.)
                if unit() < 0.7 && case < 200 {
                    let class = (unit() * REACHES.len() as f32) as u8 % REACHES.len() as u8;
                    let lasting = Lasting {
                        over: unit() < 0.5,
                        level: 0,
                        class,
                        step: unit(),
                    };
                    r.keep(node, lasting);
                }
            }
            r.readings = core::array::from_fn(|_| unit());
            // What reading every entry gives.
            let (mut lapsed, mut kept, mut leaf_kept) = ([0u32; N], 0, false);
            let mut count = 0;
            for j in &r.slots[..r.asked] {
                let e = j.entry;
                if r.readings[usize::from(e.class)] > e.expires {
                    lapsed[count] = e.node;
                    count += 1;
                } else {
                    kept += 1;
                    leaf_kept |= e.held == Held::Leaf;
                }
            }
            for batch in [1, 2, 3, 5, 64] {
                let mut out = [0u32; 64];
                let (mut found, mut from, mut held, mut leaf) = (0, 0, 0, false);
                loop {
                    let (n, next) = r.lapsed(from, &mut out[..batch], &mut held, &mut leaf);
                    assert_eq!(&out[..n], &lapsed[found..found + n], "{case} {batch}");
                    found += n;
                    from = next;
                    if n < batch {
                        break;
                    }
                }
                assert_eq!((found, from), (count, r.asked), "{case} {batch}");
                assert_eq!((held, leaf), (kept, leaf_kept), "{case} {batch}");
            }
        }
    }

    /// Random listing, unlisting and halving keep the list whole: every listed node's entry
    /// is its own, the asked entries are exactly those not halved for another's sake, and
    /// they come first.
    #[test]
    fn the_asked_entries_come_first() {
        const N: usize = 24;
        let mut slots = [Judgement::NONE; N];
        let sphere = BoundingSphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let mut r = Reuse::new(&mut slots, sphere);
        let mut rng = crate::test_rng::TestRng::new(0x11_57ed);
        let mut listed = [false; N];
        for _ in 0..4000 {
            let node = rng.next_u32() % N as u32;
            match rng.next_u32() % 5 {
                0 | 1 => {
                    let halved = rng.next_u32() & 1 == 0;
                    r.list(node, halved);
                    listed[node as usize] = true;
                }
                2 => {
                    r.unlist(node);
                    listed[node as usize] = false;
                }
                3 => r.set_trigger(node, rng.next_u32() % N as u32),
                _ => r.unhalved(node),
            }
            assert_eq!(r.len, listed.iter().filter(|&&l| l).count());
            for (k, j) in r.slots[..r.len].iter().enumerate() {
                let e = j.entry;
                assert_eq!(r.slots[e.node as usize].at as usize, k);
                assert_eq!(k < r.asked, e.held != Held::ForAnother);
            }
            for (node, &l) in listed.iter().enumerate() {
                assert_eq!(r.slots[node].at != NO_NODE, l);
            }
        }
    }
}
