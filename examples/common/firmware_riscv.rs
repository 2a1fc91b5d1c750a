// What `fw_teapot` needs of a RISC-V part under QEMU `virt` (through `#[path]`): an
// instruction clock from `minstret` (exact under `-icount shift=0`), the semihosting exit, and
// the painted stack's high-water mark. The same functions as `firmware.rs` gives the
// Cortex-M. Hand-written.

use riscv_semihosting::debug;

/// Nothing to start: `minstret` counts from reset.
pub fn start_clock() {}

/// Instructions retired since reset.
pub fn instructions() -> u64 {
    riscv::register::minstret::read64()
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

/// The value the free stack is painted with.
const PAINT: u32 = 0xCCCC_CCCC;

extern "C" {
    // The top of the stack region, where the stack pointer starts at reset.
    static _stack_start: u32;
    // The bottom of `riscv-rt`'s stack region (its `.stack` section starts there).
    static __estack: u32;
}

fn stack_end() -> usize {
    // Only the address is taken (no read), which is safe.
    core::ptr::addr_of!(__estack) as usize
}

/// The top of the stack region: everything the program holds on the stack lies below.
#[allow(dead_code)]
pub fn stack_start() -> usize {
    // Only the address is taken (no read), which is safe.
    core::ptr::addr_of!(_stack_start) as usize
}

/// About the stack pointer of the caller: the address of a local of this function, which is
/// never inlined, so that its frame lies below all of its caller's (whose locals a paint below
/// it must not reach).
#[inline(never)]
fn stack_pointer() -> usize {
    let probe = 0u32;
    core::hint::black_box(core::ptr::addr_of!(probe)) as usize
}

/// Paints the free stack (from the bottom of the stack region to a little below the current
/// stack pointer) and returns that stack pointer: [`stack_used_below`] then measures what
/// runs after this call. (No interrupt is enabled here.)
#[allow(dead_code)]
pub fn repaint_stack() -> usize {
    let sp = stack_pointer();
    let top = sp.saturating_sub(256) & !3;
    let mut p = (stack_end() + 3) & !3;
    while p < top {
        // SAFETY: `__estack..sp` is the unused part of the stack region the linker script
        // reserves (word aligned, in RAM), and nothing else uses it.
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
    sp
}

/// Bytes of stack used below `sp` since the paint: the lowest word that changed marks the
/// deepest use.
#[allow(dead_code)]
pub fn stack_used_below(sp: usize) -> usize {
    let mut p = (stack_end() + 3) & !3;
    while p < sp {
        // SAFETY: as in `repaint_stack`; reading words below the stack pointer is harmless.
        let w = unsafe { core::ptr::read_volatile(p as *const u32) };
        if w != PAINT {
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
