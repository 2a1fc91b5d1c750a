//! Reading fuzz input as a stream of small choices; past the end every read is 0, so any
//! input, however short, is a complete case.

/// A cursor over the fuzz input.
#[derive(Clone)]
pub struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    /// A cursor at the start of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data }
    }

    /// True when every byte has been read.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The next byte (0 past the end).
    pub fn u8(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    /// The next byte as a signed number.
    pub fn i8(&mut self) -> i8 {
        self.u8() as i8
    }

    /// The next two bytes, little-endian.
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    /// The next four bytes as any `f32` bit pattern (NaN and infinities included).
    pub fn f32_bits(&mut self) -> f32 {
        f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    /// `scale * 2^(k / 16)` for a signed byte `k`: a factor from about 1/256 to 256.
    pub fn log_scale(&mut self, scale: f32) -> f32 {
        scale * (self.i8() as f32 / 16.0).exp2()
    }

    /// One of `special` (when the next byte says so), else a log-scaled value.
    pub fn value(&mut self, special: &[f32], scale: f32) -> f32 {
        let pick = self.u8() as usize;
        match special.get(pick) {
            Some(&v) => v,
            None => self.log_scale(scale),
        }
    }
}
