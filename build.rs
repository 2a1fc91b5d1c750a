//! Puts `memory.x` on the linker's search path for the crate's own firmware examples: on
//! bare-metal targets only, so host builds and `cargo test` are unaffected, and only where
//! `SPLINE_TESS_FIRMWARE_EXAMPLES` is set (this repository's `.cargo/config.toml` sets it), so
//! a firmware that depends on the crate links with its own `memory.x`, not QEMU's. The ARM
//! map, or `memory-riscv.x` (QEMU `virt`, with the region aliases `riscv-rt` asks for) for
//! RISC-V.

use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=memory-riscv.x");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=SPLINE_TESS_FIRMWARE_EXAMPLES");
    let examples = env::var_os("SPLINE_TESS_FIRMWARE_EXAMPLES").is_some();
    if examples && env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("none") {
        let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR is set by cargo"));
        // (RISC-V's under its own name: `riscv-rt` takes it as `-Tmemory-riscv.x`, and the
        // linker looks in the package's directory, where ARM's `memory.x` is, first.)
        let map = match env::var("CARGO_CFG_TARGET_ARCH").as_deref() {
            Ok("riscv32") => "memory-riscv.x",
            _ => "memory.x",
        };
        fs::copy(map, out.join(map)).expect("copy the memory map");
        println!("cargo:rustc-link-search={}", out.display());
    }
}
