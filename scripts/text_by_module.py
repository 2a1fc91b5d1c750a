#!/usr/bin/env python3
"""Where the kernel's flash goes: the `.text` of a `fw_teapot` build, function by function
(`arm-none-eabi-nm --size-sort -S -C`), summed by the kernel module each function belongs to.

    scripts/text_by_module.py QUIET_ELF BASELINE_ELF

QUIET_ELF is `fw_teapot` built with `--cfg fw_quiet`, BASELINE_ELF the same program built with
`--cfg fw_quiet --cfg fw_baseline` (no kernel); `scripts/footprint.sh` builds both at
opt-level "s" and calls this. Prints a Markdown table.

A function is counted where its own name puts it (`spline_tess::render::band::...` under
`render`, the tessellator by submodule); what the compiler inlined into a caller is counted
with the caller, so the demo's frame loop (`fw_teapot::...`) holds the parts of the update it
inlined. Everything else (start-up, `core`, compiler builtins, `libm`) is given as the
difference from the baseline, so the rows add up to the kernel `.text` of the footprint table.
"""
import re
import subprocess
import sys
from collections import defaultdict


def text_symbols(elf):
    out = subprocess.run(
        ["arm-none-eabi-nm", "--size-sort", "-S", "-C", elf],
        check=True, capture_output=True, text=True,
    ).stdout
    for line in out.splitlines():
        parts = line.split(" ", 3)
        if len(parts) == 4 and parts[2] in ("t", "T"):
            yield int(parts[1], 16), parts[3].strip()


def section(elf, name):
    out = subprocess.run(
        ["arm-none-eabi-size", "-A", elf], check=True, capture_output=True, text=True
    ).stdout
    for line in out.splitlines():
        fields = line.split()
        if fields and fields[0] == name:
            return int(fields[1])
    return 0


def module_of(name):
    m = re.search(r"spline_tess::([a-z_0-9]+)(?:::([a-z_0-9]+))?", name)
    if m:
        top, sub = m.group(1), m.group(2)
        if top == "tessellator" and sub and sub[0].islower():
            return f"tessellator::{sub}"
        return top
    if name.startswith("fw_teapot::") or name.startswith("<fw_teapot::"):
        return "fw_teapot (the demo's frame loop, with what it inlined)"
    return None


def main():
    quiet, baseline = sys.argv[1], sys.argv[2]
    sums, largest = defaultdict(int), {}
    rest = 0
    for size, name in text_symbols(quiet):
        module = module_of(name)
        if module is None:
            rest += size
            continue
        sums[module] += size
        if size > largest.get(module, (0, ""))[0]:
            largest[module] = (size, name)
    kernel = section(quiet, ".text") - section(baseline, ".text")
    other = kernel - sum(sums.values())
    print("| Module | `.text` bytes | Largest function (bytes) |")
    print("|---|---|---|")
    for module, size in sorted(sums.items(), key=lambda kv: -kv[1]):
        big, name = largest[module]
        short = re.sub(r"::h[0-9a-f]{16}$", "", name)
        short = short.replace("spline_tess::", "").replace("<impl ", "<")
        print(f"| `{module}` | {size} | `{short[:70]}` ({big}) |")
    print(f"| start-up, `core`, builtins, `libm`, padding (beyond the baseline's) | {other} | |")
    print(f"| **kernel** | **{kernel}** | |")


if __name__ == "__main__":
    main()
