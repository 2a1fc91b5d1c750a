//! spline-tess on a Raspberry Pi Pico (RP2040: a Cortex-M0+, no FPU) with a 240x240 ST7789
//! display on SPI, wired as on Waveshare's Pico-LCD-1.3: the Utah teapot orbiting a degree a
//! frame, tessellated at 1 px and drawn in 16-row bands, each band's bytes sent by DMA while
//! the next band is drawn.
//!
//! The display is brought up by `mipidsi` (reset, sleep out, pixel format, inversion); each
//! band then sets its address window with the display's commands and hands its bytes to a DMA
//! channel. The teapot's hierarchy is the firmware demo's (`examples/data/fw_bisect_baked.rs`,
//! baked at 2e-3 of the diagonal: 42 KB of flash), read in place from flash.
//!
//! Wiring (Pico-LCD-1.3): SPI1 clock GP10, data GP11, chip select GP9, data/command GP8,
//! reset GP12, backlight GP13. Flashing: see README.md beside this file.

#![no_std]
#![no_main]

use core::convert::Infallible;

use cortex_m::singleton;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::primitives::Rectangle;
use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiBus;
use hal::clocks::Clock;
use hal::dma::{single_buffer, DMAExt, SingleChannel, WriteTarget};
use hal::fugit::RateExtU32;
use hal::pac;
use mipidsi::interface::Interface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use panic_halt as _;
use rp2040_hal as hal;
use spline_tess::render::{ListSlot, Renderer, Shading, Style, Wireframe};
use spline_tess::tessellator::{bit_words_for, TessellatorStorage};
use spline_tess::{Camera, Hierarchy, PatchSet, Projection, Tessellator, Vec3, View};

mod baked {
    include!("../../data/fw_bisect_baked.rs");
}

/// The second-stage boot loader for the Pico's W25Q080 flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

const XTAL_FREQ_HZ: u32 = 12_000_000;
const WIDTH: u32 = 240;
const HEIGHT: u32 = 240;
/// Where the panel's pixels start in the controller's memory (the ST7789 has 240x320): 0 for
/// a 240x240 panel in this orientation; a 135x240 or 240x280 panel needs its own (and the
/// same in `display_offset` below).
const OFFSET: (u16, u16) = (0, 0);
/// Rows of a band, and its pixels.
const BAND_ROWS: u32 = 16;
const BAND: usize = (WIDTH * BAND_ROWS) as usize;
/// A band's bytes: big-endian Rgb565, what the display takes.
const BAND_BYTES: usize = 2 * BAND;
/// Slots of the frame's triangle list (8 bytes each): room for the closest views.
const LIST: usize = 4000;
/// Triangles waiting to be judged (32 bytes each).
const STACK: usize = 256;
/// Words of bits the hierarchy takes.
const BITS: usize = bit_words_for(
    baked::TEAPOT_NODE_COUNT,
    baked::TEAPOT_VERTEX_COUNT,
    baked::TEAPOT_HEADERS.len(),
);

/// What went wrong on the display's bus.
#[derive(Debug)]
enum DisplayError {
    /// The bus was lost to a transfer that never came back (not reached).
    Gone,
}

impl From<Infallible> for DisplayError {
    fn from(e: Infallible) -> Self {
        match e {}
    }
}

/// The bus, and what it is doing: idle (with the DMA channel and the band buffer), or sending a
/// band.
enum Bus<S: WriteTarget<TransmittedWord = u8>, CH: SingleChannel> {
    Idle(S, CH, &'static mut [u8; BAND_BYTES]),
    Sending(single_buffer::Transfer<CH, &'static mut [u8; BAND_BYTES], S>),
    Gone,
}

/// An ST7789 on an SPI bus with a data/command pin, its bands sent by DMA.
struct DmaDisplay<S: WriteTarget<TransmittedWord = u8>, DC, CH: SingleChannel> {
    bus: Bus<S, CH>,
    dc: DC,
}

impl<S, DC, CH> DmaDisplay<S, DC, CH>
where
    S: SpiBus<u8, Error = Infallible> + WriteTarget<TransmittedWord = u8>,
    DC: OutputPin<Error = Infallible>,
    CH: SingleChannel,
{
    /// The bus, once the band being sent (if any) has gone out of it.
    fn idle(&mut self) -> Result<(S, CH, &'static mut [u8; BAND_BYTES]), DisplayError> {
        match core::mem::replace(&mut self.bus, Bus::Gone) {
            Bus::Idle(spi, ch, buffer) => Ok((spi, ch, buffer)),
            Bus::Sending(transfer) => {
                let (ch, buffer, mut spi) = transfer.wait();
                // (The last bytes leave the FIFO after the transfer's last write.)
                spi.flush()?;
                Ok((spi, ch, buffer))
            }
            Bus::Gone => Err(DisplayError::Gone),
        }
    }

    /// A command byte, then its arguments as data.
    fn command(spi: &mut S, dc: &mut DC, command: u8, args: &[u8]) -> Result<(), DisplayError> {
        dc.set_low()?;
        spi.write(&[command])?;
        spi.flush()?;
        dc.set_high()?;
        spi.write(args)?;
        spi.flush()?;
        Ok(())
    }

    /// Sends a band: its address window, then its bytes, by DMA when it fills the buffer (the
    /// renderer draws the next band meanwhile), else at once.
    fn push_band(&mut self, area: &Rectangle, bytes: &[u8]) -> Result<(), DisplayError> {
        let (mut spi, ch, buffer) = self.idle()?;
        let x = area.top_left.x as u16 + OFFSET.0;
        let y = area.top_left.y as u16 + OFFSET.1;
        let (w, h) = (area.size.width as u16, area.size.height as u16);
        let span = |a: u16, n: u16| {
            let [a0, a1] = a.to_be_bytes();
            let [b0, b1] = (a + n.max(1) - 1).to_be_bytes();
            [a0, a1, b0, b1]
        };
        Self::command(&mut spi, &mut self.dc, 0x2A, &span(x, w))?; // column address set
        Self::command(&mut spi, &mut self.dc, 0x2B, &span(y, h))?; // row address set
        Self::command(&mut spi, &mut self.dc, 0x2C, &[])?; // memory write
        if bytes.len() == buffer.len() {
            buffer.copy_from_slice(bytes);
            self.bus = Bus::Sending(single_buffer::Config::new(ch, buffer, spi).start());
        } else {
            // (A shorter band: at once, and out of the FIFO before the next command's
            // data/command pin goes low.)
            spi.write(bytes)?;
            spi.flush()?;
            self.bus = Bus::Idle(spi, ch, buffer);
        }
        Ok(())
    }
}

/// What `mipidsi` brings the display up with: commands and pixels, sent at once.
impl<S, DC, CH> Interface for DmaDisplay<S, DC, CH>
where
    S: SpiBus<u8, Error = Infallible> + WriteTarget<TransmittedWord = u8>,
    DC: OutputPin<Error = Infallible>,
    CH: SingleChannel,
{
    type Word = u8;
    type Error = DisplayError;

    fn send_command(&mut self, command: u8, args: &[u8]) -> Result<(), DisplayError> {
        let (mut spi, ch, buffer) = self.idle()?;
        let sent = Self::command(&mut spi, &mut self.dc, command, args);
        self.bus = Bus::Idle(spi, ch, buffer);
        sent
    }

    fn send_pixels<const N: usize>(
        &mut self,
        pixels: impl IntoIterator<Item = [u8; N]>,
    ) -> Result<(), DisplayError> {
        let (mut spi, ch, buffer) = self.idle()?;
        for pixel in pixels {
            spi.write(&pixel)?;
        }
        spi.flush()?;
        self.bus = Bus::Idle(spi, ch, buffer);
        Ok(())
    }

    fn send_repeated_pixel<const N: usize>(
        &mut self,
        pixel: [u8; N],
        count: u32,
    ) -> Result<(), DisplayError> {
        self.send_pixels((0..count).map(|_| pixel))
    }
}

/// Stops here (the board has nothing to report on).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

#[hal::entry]
fn main() -> ! {
    let Some(mut pac) = pac::Peripherals::take() else {
        halt()
    };
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let Ok(clocks) = hal::clocks::init_clocks_and_plls(
        XTAL_FREQ_HZ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    ) else {
        halt()
    };
    let sio = hal::Sio::new(pac.SIO);
    let pins = hal::gpio::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );
    let mut timer = hal::Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

    // The display: SPI1 at 62.5 MHz (the ST7789's fastest write clock), chip select held low.
    let sclk = pins.gpio10.into_function::<hal::gpio::FunctionSpi>();
    let mosi = pins.gpio11.into_function::<hal::gpio::FunctionSpi>();
    let spi = hal::spi::Spi::<_, _, _, 8>::new(pac.SPI1, (mosi, sclk)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        62_500_000u32.Hz(),
        embedded_hal::spi::MODE_0,
    );
    let mut cs = pins.gpio9.into_push_pull_output();
    let dc = pins.gpio8.into_push_pull_output();
    let reset = pins.gpio12.into_push_pull_output();
    let mut backlight = pins.gpio13.into_push_pull_output();
    let (Ok(()), Ok(())) = (cs.set_low(), backlight.set_high());
    let dma = pac.DMA.split(&mut pac.RESETS);
    let Some(dma_buffer) = singleton!(: [u8; BAND_BYTES] = [0; BAND_BYTES]) else {
        halt()
    };
    let mut display = DmaDisplay {
        bus: Bus::Idle(spi, dma.ch0, dma_buffer),
        dc,
    };
    let up = mipidsi::Builder::new(ST7789, &mut display)
        .display_size(WIDTH as u16, HEIGHT as u16)
        .display_offset(OFFSET.0, OFFSET.1)
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(reset)
        .init(&mut timer)
        .is_ok();
    if !up {
        halt()
    }

    // The teapot, read in place from flash, and the tessellator's and renderer's storage.
    let Ok(patches) = PatchSet::new(&baked::TEAPOT_HEADERS, &baked::TEAPOT_POINTS, None) else {
        halt()
    };
    let Ok(hierarchy) = Hierarchy::from_bytes(patches, &baked::TEAPOT_HIERARCHY) else {
        halt()
    };
    let storage = singleton!(: TessellatorStorage<BITS, STACK, 0> = TessellatorStorage::new());
    let depth = singleton!(: [u16; BAND] = [0; BAND]);
    let colors = singleton!(: [u8; BAND_BYTES] = [0; BAND_BYTES]);
    let list = singleton!(: [ListSlot; LIST] = [ListSlot::default(); LIST]);
    let map = singleton!(: [u16; baked::TEAPOT_VERTEX_COUNT] = [0; baked::TEAPOT_VERTEX_COUNT]);
    let (Some(storage), Some(depth), Some(colors), Some(list), Some(map)) =
        (storage, depth, colors, list, map)
    else {
        halt()
    };
    let Ok(mut tess) = Tessellator::new(hierarchy, storage) else {
        halt()
    };
    let style = Style {
        shading: Shading::Gouraud,
        color: Rgb888::new(222, 196, 150),
        wireframe: Some(Wireframe {
            color: Rgb888::new(60, 40, 30),
            half_width: 0.35,
        }),
        background: Some(Rgb888::new(24, 28, 40)),
        ..Style::default()
    };
    let mut frame = 0u32;
    loop {
        // A degree a frame around the teapot's middle.
        let angle = (frame % 360) as f32 * (core::f32::consts::PI / 180.0);
        let eye = Vec3::new(15.0 * libm::cosf(angle), 15.0 * libm::sinf(angle), 7.0);
        let Ok(camera) = Camera::new(
            eye,
            Vec3::new(0.0, 0.0, 1.5),
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.05,
            [WIDTH, HEIGHT],
        ) else {
            halt()
        };
        let view = View::Screen {
            camera,
            tolerance_px: 1.0,
        };
        if tess.update(&view).is_err() {
            halt()
        }
        let drawn = Renderer::with_triangle_list(depth, list)
            .with_vertex_map(map)
            .draw_bands_rgb565(&tess, &camera, &style, colors, |area, bytes| {
                display.push_band(area, bytes)
            });
        if drawn.is_err() {
            halt()
        }
        frame = frame.wrapping_add(1);
    }
}
