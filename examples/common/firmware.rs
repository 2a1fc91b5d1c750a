// What the firmware examples share on the Cortex-M (through `#[path]`): an instruction clock
// from SysTick under QEMU `-icount shift=0`, the semihosting exit, and the painted stack's
// high-water mark. Hand-written.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::exception;
use cortex_m_semihosting::debug;

/// QEMU's mps2 boards clock SysTick at 25 MHz; with `-icount shift=0` one instruction takes
/// 1 ns, so one tick is 40 instructions.
pub const INSTRUCTIONS_PER_TICK: u64 = 40;
const RELOAD: u32 = 0x00FF_FFFF;
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    // A load and a store, not `fetch_add`: ARMv6-M (Cortex-M0+) has no atomic
    // read-modify-write, and only this handler writes the count.
    WRAPS.store(
        WRAPS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// Starts SysTick from the core clock, counting wraps in its interrupt.
pub fn start_clock(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Instructions since [`start_clock`] (to 40, the tick).
pub fn instructions() -> u64 {
    loop {
        let w = WRAPS.load(Ordering::Relaxed);
        let c = SYST::get_current();
        if WRAPS.load(Ordering::Relaxed) == w {
            // The counter reads 0 when just cleared (it reloads on the next tick) and on the
            // tick of a wrap, once the interrupt has counted it: both are a period's start.
            let c = if c == 0 { RELOAD + 1 } else { c };
            let ticks = (w as u64 + 1) * (RELOAD as u64 + 1) - c as u64;
            return ticks * INSTRUCTIONS_PER_TICK;
        }
    }
}

/// Exits QEMU with success or failure.
pub fn finish(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

extern "C" {
    // The top of the stack region, where the stack pointer starts at reset.
    static _stack_start: u32;
    static _stack_end: u32;
}

fn stack_end() -> usize {
    // Only the address is taken (no read), which is safe.
    core::ptr::addr_of!(_stack_end) as usize
}

/// The top of the stack region: everything the program holds on the stack lies below.
#[allow(dead_code)]
pub fn stack_start() -> usize {
    // Only the address is taken (no read), which is safe.
    core::ptr::addr_of!(_stack_start) as usize
}

/// Paints the free stack (from the bottom of the stack region to a little below the current
/// stack pointer) with cortex-m-rt's `STACK_PAINT_VALUE`, and returns that stack pointer:
/// [`stack_used_below`] then measures what runs after this call on top of what is already on
/// the stack. Interrupts are off while painting.
#[allow(dead_code)]
pub fn repaint_stack() -> usize {
    cortex_m::interrupt::free(|_| {
        let sp = cortex_m::register::msp::read() as usize;
        // Leave this function's own frame alone.
        let top = sp.saturating_sub(256) & !3;
        let mut p = stack_end();
        while p < top {
            // SAFETY: `_stack_end..sp` is the unused part of the stack region the linker
            // script reserves (word aligned, in RAM); interrupts are off, so nothing uses it
            // while it is painted.
            unsafe { core::ptr::write_volatile(p as *mut u32, cortex_m_rt::STACK_PAINT_VALUE) };
            p += 4;
        }
        sp
    })
}

/// Bytes of stack used below `sp` since the paint: the lowest word that changed marks the
/// deepest use.
#[allow(dead_code)]
pub fn stack_used_below(sp: usize) -> usize {
    let mut p = stack_end();
    while p < sp {
        // SAFETY: as in `repaint_stack`; reading words below the stack pointer is harmless.
        let w = unsafe { core::ptr::read_volatile(p as *const u32) };
        if w != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        p += 4;
    }
    sp.saturating_sub(p)
}

// Static RAM and flash from the linker script's symbols, which both runtimes define alike.
#[path = "firmware_memory.rs"]
mod memory;
#[allow(unused_imports)]
pub use memory::{flash_used, static_ram};
