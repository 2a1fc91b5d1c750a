#!/usr/bin/env bash
# `fw_teapot` on each class of part it builds for, under QEMU with `-icount shift=0` (one
# instruction a nanosecond; RISC-V reads `minstret`): instructions of frame 0 (a cold frame)
# and frame 1 (an orbit step from it, with the wireframe), RAM as the firmware measures it,
# and flash (the kernel's `.text` at opt-level "s", as `scripts/footprint.sh` counts it, plus
# the model's hierarchy and patches). Each run checks every frame against the host's checksums
# (its exit code).
# Prints a Markdown table, which `scripts/figures.sh` puts into README.md and BENCHMARKS.md.
#
#   scripts/parts.sh
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
for t in thumbv7em-none-eabihf thumbv6m-none-eabi riscv32imc-unknown-none-elf; do
    rustup target list --installed | grep -qx "$t" || rustup target add "$t"
done
if ! command -v qemu-system-arm >/dev/null || ! command -v qemu-system-riscv32 >/dev/null; then
    as_root apt-get update -q
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q qemu-system-arm qemu-system-misc
fi
FEATURES=--no-default-features
# Size in bytes of section $2 of ELF $1 (any architecture).
section() {
    printf '%d\n' "0x$(readelf -SW "$1" | sed -n "s/.*\] $2 *[A-Z_]* *[0-9a-f]* [0-9a-f]* \([0-9a-f]*\) .*/\1/p")"
}
val() { sed -n "s/.* $1 \([0-9][0-9]*\).*/\1/p" <<<"$2" | head -1; }
# Update and render instructions of frame $1 in output $2.
frame() { sed -n "s/^fw_teapot: frame $1 triangles .* update_instructions \([0-9]*\) render_instructions \([0-9]*\) .*/\1 \2/p" <<<"$2"; }
fmt() { awk -v n="$1" 'BEGIN { printf "%.2fM", n / 1e6 }'; }

host=$(cargo run -q --example fw_teapot $FEATURES)
model=$(($(val baked "$host") + $(val control_points "$host")))

# $1: part class; $2: target; $3: QEMU machine and core (as the target's runner in
# `.cargo/config.toml`).
row() {
    local class=$1 t=$2 machine=$3
    local out
    out=$(cargo run -q --release --example fw_teapot --target "$t" $FEATURES)
    local dir=target/parts-s elf=target/parts-s/$t/release/examples/fw_teapot
    CARGO_TARGET_DIR=$dir cargo rustc -q --release --example fw_teapot --target "$t" $FEATURES \
        --config 'profile.release.opt-level="s"' -- --cfg fw_quiet
    local text
    text=$(section "$elf" .text)
    CARGO_TARGET_DIR=$dir cargo rustc -q --release --example fw_teapot --target "$t" $FEATURES \
        --config 'profile.release.opt-level="s"' -- --cfg fw_quiet --cfg fw_baseline
    local kernel=$((text - $(section "$elf" .text)))
    read -r u0 r0 < <(frame 0 "$out")
    read -r u1 r1 < <(frame 1 "$out")
    local ram
    ram=$(val total "$(grep '^fw_teapot: ram ' <<<"$out")")
    echo "| $class | \`$t\` | $machine | $(fmt "$u0") + $(fmt "$r0") = $(fmt $((u0 + r0))) | $(fmt "$u1") + $(fmt "$r1") = $(fmt $((u1 + r1))) | $ram | $kernel + $model = $((kernel + model)) |"
}

echo "| Part class | Target | QEMU | Frame 0: update + render | Frame 1 (orbit step, wireframe) | RAM (bytes) | Flash: kernel at \"s\" + model (bytes) |"
echo "|---|---|---|---|---|---|---|"
row "Cortex-M4F (STM32F4 class), FPU" thumbv7em-none-eabihf "\`mps2-an386\`, Cortex-M4"
row "Cortex-M0+ (RP2040 class), no FPU" thumbv6m-none-eabi "\`mps2-an385\`, Cortex-M3 running v6-M code"
row "RV32IMC (ESP32-C3 class), no FPU" riscv32imc-unknown-none-elf "\`virt\`, RV32"
