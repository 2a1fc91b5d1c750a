// Static RAM and flash of a firmware example, from the linker script's symbols, which
// `cortex-m-rt` and `riscv-rt` define alike but for where flash starts: the vector table on the
// Cortex-M, the code on RISC-V. Included by `firmware.rs` and `firmware_riscv.rs`.

extern "C" {
    static __sdata: u32;
    static __edata: u32;
    static __sidata: u32;
    static __euninit: u32;
    #[cfg(target_arch = "arm")]
    #[link_name = "__vector_table"]
    static FLASH_START: u32;
    #[cfg(target_arch = "riscv32")]
    #[link_name = "__stext"]
    static FLASH_START: u32;
}

/// Bytes of static RAM: `.data`, `.bss` and `.uninit`.
#[allow(dead_code)]
pub fn static_ram() -> usize {
    // Only the addresses are taken (no read), which is safe.
    let start = core::ptr::addr_of!(__sdata) as usize;
    let end = core::ptr::addr_of!(__euninit) as usize;
    end.saturating_sub(start)
}

/// Bytes of flash the firmware takes: from its start to the end of the read-only data, and the
/// initial values of `.data` (kept in flash after them).
#[allow(dead_code)]
pub fn flash_used() -> usize {
    // Only the addresses are taken (no read), which is safe.
    let start = core::ptr::addr_of!(FLASH_START) as usize;
    let data_image = core::ptr::addr_of!(__sidata) as usize;
    let data = (core::ptr::addr_of!(__edata) as usize)
        .saturating_sub(core::ptr::addr_of!(__sdata) as usize);
    data_image.saturating_sub(start) + data
}
