#!/usr/bin/env bash
# Where a cold frame's time goes on the host: `perf record` of `frame_loop` (the teapot baked
# at 2.5e-4 of its diagonal, 1024x768, 1 px, eye (6,-6,4); 2,000 cold frames, each an update
# and an indexed write), by function (inlined code counts in its caller), the bake's own
# functions left out and the rest taken as the whole. A markdown table on stdout; run by
# scripts/figures.sh when `perf` is there.
#
#   scripts/frame_profile.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release -p host-tests --example frame_loop
data=target/frame_profile.perf
FRAMES=2000 perf record -q -F 2000 -o "$data" target/release/examples/frame_loop >/dev/null 2>&1
perf report -i "$data" --no-children --stdio --sort symbol 2>/dev/null | python3 -c '
import re, sys
rows = []
for line in sys.stdin:
    m = re.match(r"\s+([0-9.]+)%\s+\[\.\]\s+(.*)", line)
    if m:
        rows.append((float(m.group(1)), re.sub(r"\s+-\s+-\s*$", "", m.group(2)).strip()))
bake = ("bake::", "deviation::kept", "Baker", "BoundSource", "Hull", "rayon", "crossbeam")
frame = [(p, s) for p, s in rows if not any(b in s for b in bake)]
total = sum(p for p, _ in frame)
print("| function (spline_tess::...) | share of a cold frame |")
print("|---|---|")
shown = 0.0
for p, s in frame[:14]:
    name = re.sub(r"^spline_tess::", "", s)
    name = re.sub(r"<impl (spline_tess::)?([^>]*)>", r"\2", name)
    print(f"| `{name}` | {100 * p / total:.1f}% |")
    shown += p
print(f"| the rest | {100 * (total - shown) / total:.1f}% |")
parts = {
    "the indexed write": ("write_mesh", "output::"),
    "judging (judge, bounds on screen, planes)": ("judge", "screen::", "certificate"),
    "refinement below the bake": ("refine", "patch::", "patch_bounds", "lattice"),
    "the walk (halving, neighbours, vertices, stack)": ("select::", "hierarchy::", "address::", "format::"),
}
share = {k: 0.0 for k in parts}
for p, s in frame:
    for k, keys in parts.items():
        if any(x in s for x in keys):
            share[k] += p
            break
print()
print("By part: " + "; ".join(f"{k} {100 * v / total:.0f}%" for k, v in share.items()) + ".")
'
