#!/usr/bin/env python3
"""Where a `fw_teapot` frame's instructions go, on the Cortex-M4F under QEMU.

    cargo build --release --example fw_teapot --target thumbv7em-none-eabihf
    scripts/fw_profile.py render 0      # frame 0's render, by function and by part
    scripts/fw_profile.py update 1      # frame 1's update
    scripts/fw_profile.py update 0 insert   # and the blocks of the functions named `*insert*`

QEMU logs every translated block once (`-d in_asm`: its guest instructions) and every block it
executes (`-d exec,nochain`: its address and symbol). Each execution is charged the block's
instruction count, so the total is the frame's guest instructions, as `-icount` counts them,
to within the blocks QEMU translates more than once. The window of a frame's update runs from
the demo's call of `teapot::update` to its call of `teapot::render` (both in
`examples/common/fw_teapot_frames.rs`, never inlined); its render from there to the next
`update` (the last frame's render to the end of the program). Needs `qemu-system-arm`,
`arm-none-eabi-nm` and Python 3; reads about 100 MB of log per million instructions through a pipe, nothing on disk.
"""

import collections
import subprocess
import sys

# `FW_TARGET=thumbv6m-none-eabi` profiles the ARMv6-M build (no FPU: `cargo build --release
# --example fw_teapot --target thumbv6m-none-eabi --no-default-features`), run as its runner
# in `.cargo/config.toml` runs it: on `mps2-an385` with a Cortex-M3.
import os

TARGET = os.environ.get("FW_TARGET", "thumbv7em-none-eabihf")
ELF = f"target/{TARGET}/release/examples/fw_teapot"
CPU, MACHINE = (("cortex-m3", "mps2-an385") if TARGET.startswith("thumbv6m")
                else ("cortex-m4", "mps2-an386"))
QEMU = [
    "qemu-system-arm", "-cpu", CPU, "-machine", MACHINE, "-nographic",
    "-icount", "shift=0", "-semihosting-config", "enable=on,target=native",
    "-d", "in_asm,exec,nochain", "-D", "/dev/stderr", "-kernel",
]

# Parts of a frame, by substrings of the (mangled) symbol names; the first match wins.
PARTS = [
    ("rasterising: set-up per band a triangle meets, rows, depth test, colours",
     ["rasterise", "band_scan", "FixedPlane"]),
    ("span set-up (corners beyond the 32-bit reach)", ["from_snapped"]),
    ("band loop: fill, push, display model", ["fw_teapot5frame", "6teapot6render",
                                              "hash_words"]),
    ("surface evaluation", ["frame_at", "8evaluate", "pole_at", "is_collapsed",
                            "fmaxf", "fminf"]),
    ("hierarchy walk and corner keys", ["each_written", "walk", "stream_keyed",
                                        "vertex_record", "written", "4sink4fill"]),
    ("corner cache, view transform, shading", ["CornerCache", "Setup6corner", "Setup5shade",
                                               "normalize", "sqrtf"]),
    ("clip test, projection, packing into the list", ["ListSink4take", "ListSink8try_push",
                                                      "contains", "keyed_triangle"]),
    ("list scan: decoding a band's listed triangles", ["for_each_listed", "ListedTriangle",
                                                        "draw_list"]),
    ("refinement below the bake", ["refine", "lattice", "patch_bounds", "PatchBounds"]),
    ("judging: bounds on screen, culling", ["judge", "deviation", "sqrt_above", "to_view",
                                            "rotate_to_view"]),
    ("selection: the walk, halving, bits", ["select", "bisect", "6teapot6update17h"]),
    ("memcpy, memclr", ["memcpy", "memclr", "memmove", "memset"]),
]


def function_addresses(name):
    """Entry addresses of the functions whose symbol contains `name` (Thumb bit cleared)."""
    symbols = subprocess.run(["arm-none-eabi-nm", ELF], capture_output=True, text=True,
                             check=True).stdout
    return {int(line.split()[0], 16) & ~1 for line in symbols.splitlines()
            if name in line and line.split()[1] in "tTwW"}


def builtin(symbol):
    """Whether `symbol` is a compiler builtin or `libm`'s."""
    return (symbol.startswith("__") or "compiler_builtins" in symbol
            or "4libm4math" in symbol)


def main():
    # Quiet when piped into `head`.
    import signal
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    if len(sys.argv) not in (3, 4) or sys.argv[1] not in ("update", "render"):
        sys.exit(__doc__)
    what, frame = sys.argv[1], int(sys.argv[2])
    blocks_of = sys.argv[3] if len(sys.argv) == 4 else None
    by_block = collections.Counter()
    start, stop = ("6teapot6update17h", "6teapot6render17h") if what == "update" else (
        "6teapot6render17h", "6teapot6update17h")
    stops = function_addresses(stop)
    qemu = subprocess.Popen(QEMU + [ELF], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True, errors="replace")
    sizes = {}
    block, count = None, 0
    seen, inside = 0, False
    entries = function_addresses(start)
    charged = collections.Counter()
    # Each builtin (soft floating point, 64-bit products, divisions, `libm`) charged to the
    # function that ran last before it: its caller, but for builtins called from builtins.
    with_builtins = collections.Counter()
    pairs = collections.Counter()
    caller = None
    for line in qemu.stderr:
        if line.startswith("Trace"):
            fields = line.split("[", 1)[1].split("/")
            pc = int(fields[1], 16)
            symbol = line.rsplit(" ", 1)[1].strip()
            # A call enters at the function's address (a return from a callee does not).
            entered = pc in entries
            if entered and not inside:
                if seen == frame:
                    inside = True
                seen += 1
            elif inside and pc in stops:
                break
            if inside:
                charged[symbol] += sizes.get(pc, 1)
                if not builtin(symbol):
                    caller = symbol
                with_builtins[caller or symbol] += sizes.get(pc, 1)
                if builtin(symbol) and caller:
                    pairs[(caller, symbol)] += sizes.get(pc, 1)
                if blocks_of and blocks_of in symbol:
                    by_block[pc] += sizes.get(pc, 1)
        elif line.startswith("0x"):
            try:
                address = int(line.split(":", 1)[0], 16)
            except ValueError:
                continue
            if block is None:
                block, count = address, 0
            count += 1
        elif block is not None:
            sizes[block] = count
            block = None
    qemu.kill()
    total = sum(charged.values())
    if total == 0:
        sys.exit(f"no {what} of frame {frame} found")
    print(f"fw_teapot ({TARGET}) frame {frame} {what}: {total} instructions")
    print("\nby part:")
    parts = collections.Counter()
    for symbol, n in charged.items():
        name = next((p for p, keys in PARTS if any(k in symbol for k in keys)), "other")
        parts[name] += n
    for name, n in parts.most_common():
        print(f"{n:>10} {100 * n / total:5.1f}%  {name}")
    print("\nby function:")
    for symbol, n in charged.most_common(25):
        print(f"{n:>10} {100 * n / total:5.1f}%  {symbol[:120]}")
    print("\nby function, with the builtins it calls:")
    for symbol, n in with_builtins.most_common(25):
        print(f"{n:>10} {100 * n / total:5.1f}%  {symbol[:120]}")
    print("\nbuiltins by caller:")
    for (c, b), n in pairs.most_common(25):
        print(f"{n:>10} {100 * n / total:5.1f}%  {c[:60]} <- {b[:50]}")
    if blocks_of:
        print(f"\nblocks of *{blocks_of}* (objdump -d the ELF at these addresses):")
        for pc, n in by_block.most_common(int(__import__("os").environ.get("BLOCKS", "40"))):
            print(f"{n:>10} {100 * n / total:5.1f}%  {pc:#x} ({n // sizes.get(pc, 1)} runs)")


if __name__ == "__main__":
    main()
