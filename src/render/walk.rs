//! A span's pixels, one after another: its depth keys, shade levels and wireframe test in
//! fixed point, so that each pixel costs a few integer additions.
//!
//! The scan hands a row's attributes in fixed point already (`raster/scan.rs`); the spans of
//! far corners give depth and shade as `f32` ramps (`start + step * i` at the `i`-th pixel of
//! the span, [`Span`]), and here each such ramp becomes an `i32` with a fixed number of
//! fractional bits, its start and step rounded once per row. Either way the `i`-th value is
//! `start + i * step` in exact integer arithmetic. The wireframe test comes from the exact
//! integer edge functions either way, as a ramp whose sign is the test. So a pixel's value does not depend on where
//! a walk starts: a walk jumped to pixel `i` ([`SpanWalk::skip`]) and one stepped there agree,
//! and every output (run by run, or a band buffer) colours a pixel alike.
//!
//! Precision: a depth key keeps 14 fractional bits and a shade level 16, so over a span of `n`
//! pixels a value is off the `f32` ramp's by at most `n / 2^14` of a key (plus the ramp's own
//! rounding): 0.015 of a key across a 240-pixel row. Keys are 1 (far) to 65535 (near),
//! levels 0 to 255, as [`depth_key`] and the shade levels of `project` give them.

use super::raster::{Ramp, Span};

/// Fractional bits of a depth key.
pub(super) const DEPTH_BITS: u32 = 14;
/// Fractional bits of a shade level and of a distance to an edge.
pub(super) const LEVEL_BITS: u32 = 16;

/// `v * 2^bits`, rounded toward zero and saturated (NaN gives 0).
fn fixed(v: f32, bits: u32) -> i32 {
    (v * (1u32 << bits) as f32) as i32
}

/// A ramp in fixed point: its value at the span's first pixel and its step per pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct FixedRamp {
    pub at: i32,
    pub step: i32,
}

impl FixedRamp {
    /// `ramp + offset`, times `2^bits`.
    fn new(ramp: &Ramp, offset: f32, bits: u32) -> FixedRamp {
        FixedRamp {
            at: fixed(ramp.start + offset, bits),
            step: fixed(ramp.step, bits),
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        self.at = self.at.wrapping_add(self.step);
    }

    #[inline(always)]
    fn skip(&mut self, n: u32) {
        self.at = self.at.wrapping_add(self.step.wrapping_mul(n as i32));
    }
}

/// The pixels of one span, from its first: depth key, shade level and whether the pixel lies
/// on a wireframe edge.
#[derive(Clone, Copy, Debug)]
pub(super) struct SpanWalk {
    /// Depth key plus 1/2.
    depth: FixedRamp,
    /// Shade level (`255 * shade`) plus 1/2.
    level: FixedRamp,
    /// For each edge, a value below 0 on its wireframe line (`i32::MAX` and no step for the
    /// edges not drawn, and with no wireframe).
    wire: [FixedRamp; 3],
}

impl SpanWalk {
    /// The walk of `span` (its wireframe tests as the span has them).
    pub fn new(span: &Span) -> SpanWalk {
        let level = Ramp {
            start: 255.0 * span.shade.start.clamp(0.0, 1.0),
            step: 255.0 * span.shade.step,
        };
        SpanWalk {
            depth: FixedRamp::new(&span.depth, 0.5, DEPTH_BITS),
            level: FixedRamp::new(&level, 0.5, LEVEL_BITS),
            wire: span.wire,
        }
    }

    /// A walk from its ramps in fixed point: depth key plus 1/2 with [`DEPTH_BITS`] fractional
    /// bits, shade level plus 1/2 with [`LEVEL_BITS`], and for each edge a value below 0 on
    /// its line (`i32::MAX` and no step: never).
    pub fn from_ramps(depth: FixedRamp, level: FixedRamp, wire: [FixedRamp; 3]) -> SpanWalk {
        SpanWalk { depth, level, wire }
    }

    /// The current pixel's depth key, 1 (far) to 65535 (near).
    #[inline(always)]
    pub fn key(&self) -> u16 {
        (self.depth.at >> DEPTH_BITS).clamp(1, u16::MAX as i32) as u16
    }

    /// The current pixel's shade level, 0 to 255.
    #[inline(always)]
    pub fn level(&self) -> usize {
        (self.level.at >> LEVEL_BITS).clamp(0, 255) as usize
    }

    /// Whether the current pixel lies on a drawn edge.
    #[inline(always)]
    pub fn on_wire(&self) -> bool {
        self.wire.iter().any(|w| w.at < 0)
    }

    /// On to the next pixel; with `WIRE` false the wireframe distances are left behind (a walk
    /// without a wireframe never asks them).
    #[inline(always)]
    pub fn step<const WIRE: bool>(&mut self) {
        self.depth.step();
        self.level.step();
        if WIRE {
            for w in &mut self.wire {
                w.step();
            }
        }
    }

    /// On by `n` pixels.
    pub fn skip(&mut self, n: u32) {
        self.depth.skip(n);
        self.level.skip(n);
        for w in &mut self.wire {
            w.skip(n);
        }
    }
}

/// Depth-tests the pixels of a span against `depth` (the band's values under it) and hands
/// each that passes, with its slot of `pixels`, to `paint` with its shade level, or `None` on
/// a wireframe edge; the pixels that passed. `WIRE`: whether the span has wireframe edges.
#[inline(always)]
pub(super) fn draw_span<const WIRE: bool, T>(
    depth: &mut [u16],
    pixels: impl Iterator<Item = T>,
    mut walk: SpanWalk,
    mut paint: impl FnMut(T, Option<usize>),
) -> u32 {
    let mut drawn = 0;
    for (d, slot) in depth.iter_mut().zip(pixels) {
        let key = walk.key();
        if key > *d {
            *d = key;
            let wire = WIRE && walk.on_wire();
            paint(slot, (!wire).then(|| walk.level()));
            drawn += 1;
        }
        walk.step::<WIRE>();
    }
    drawn
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(depth: Ramp, shade: Ramp, wire: [FixedRamp; 3]) -> Span {
        Span {
            x0: 0,
            x1: 200,
            depth,
            shade,
            wire,
        }
    }

    const NO_WIRE: FixedRamp = FixedRamp {
        at: i32::MAX,
        step: 0,
    };

    /// Stepping and skipping agree, and both stay within a small fraction of the `f32` ramps.
    #[test]
    fn a_walk_follows_the_ramps() {
        let s = span(
            Ramp {
                start: 1234.4,
                step: 37.3,
            },
            Ramp {
                start: 0.9,
                step: -0.0041,
            },
            // On the line from pixel 50 on.
            [FixedRamp { at: 49, step: -1 }, NO_WIRE, NO_WIRE],
        );
        let start = SpanWalk::new(&s);
        let mut walk = start;
        for i in 0..200u32 {
            let mut jumped = start;
            jumped.skip(i);
            assert_eq!(walk.key(), jumped.key(), "{i}");
            assert_eq!(walk.level(), jumped.level(), "{i}");
            assert_eq!(walk.on_wire(), jumped.on_wire(), "{i}");
            let key = s.depth.at(i) + 0.5;
            assert!((walk.key() as f32 - key.floor()).abs() <= 1.0, "{i}");
            assert!((walk.depth.at as f32 / 16384.0 - key).abs() < 0.02, "{i}");
            let level = 255.0 * s.shade.at(i).clamp(0.0, 1.0) + 0.5;
            assert!((walk.level() as f32 - level.floor()).abs() <= 1.0, "{i}");
            assert_eq!(walk.on_wire(), i >= 50, "{i}");
            walk.step::<true>();
        }
    }

    /// Keys saturate to 1..=65535 and levels to 0..=255, a NaN giving the far end.
    #[test]
    fn keys_and_levels_saturate() {
        let flat = |start: f32| Ramp { start, step: 0.0 };
        for (d, want) in [
            (-5.0, 1),
            (0.2, 1),
            (1.6, 2),
            (70000.0, 65535),
            (f32::NAN, 1),
            (f32::INFINITY, 65535),
        ] {
            let w = SpanWalk::new(&span(flat(d), flat(0.5), [NO_WIRE; 3]));
            assert_eq!(w.key(), want, "{d}");
            assert!(!w.on_wire());
        }
        for (s, want) in [(-1.0, 0), (0.0, 0), (0.5, 128), (1.0, 255), (7.0, 255)] {
            let w = SpanWalk::new(&span(flat(9.0), flat(s), [NO_WIRE; 3]));
            assert_eq!(w.level(), want, "{s}");
        }
    }
}
