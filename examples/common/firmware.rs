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
    WRAPS.fetch_add(1, Ordering::Relaxed);
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

/// Bytes of stack ever used: cortex-m-rt's `paint-stack` fills `_stack_end.._stack_start`
/// with `0xCCCC_CCCC` at reset; the lowest word that changed marks the deepest use.
#[allow(dead_code)]
pub fn stack_high_water() -> usize {
    extern "C" {
        static _stack_end: u32;
        static _stack_start: u32;
    }
    let (end, start) = (
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    );
    let mut p = end;
    while p < start {
        // SAFETY: `end..start` is the stack region the linker script reserves, word aligned
        // and in RAM; reading it while running on it is fine (the words below the stack
        // pointer are not in use, the ones above are only read).
        let w = unsafe { core::ptr::read_volatile(p as *const u32) };
        if w != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        p += 4;
    }
    start - p
}
