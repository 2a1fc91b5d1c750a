#!/usr/bin/env bash
# Every figure of README.md and BENCHMARKS.md, from one run on one machine.
#
#   scripts/figures.sh            # writes BENCHMARKS.md and the README blocks between
#                                 # `<!-- figures:NAME:start -->` and `<!-- figures:NAME:end -->`
#   scripts/figures.sh --full     # also the hierarchies' figures at 2.5e-4 (a few minutes more)
#
# About 8 minutes on the machine BENCHMARKS.md names, with the build cache warm (a cold build
# of the host examples and the firmware adds about 5). What it leaves out is listed at the
# end of BENCHMARKS.md.
set -euo pipefail
cd "$(dirname "$0")/.."

full=0
[ "${1:-}" = "--full" ] && full=1

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
T=thumbv7em-none-eabihf
rustup target list --installed | grep -qx "$T" || rustup target add "$T"
if ! command -v qemu-system-arm >/dev/null || ! command -v arm-none-eabi-size >/dev/null ||
    ! command -v cc >/dev/null || [ ! -f /usr/include/GL/glu.h ]; then
    as_root apt-get update -q
    # (As in `.ci/run`: a newer qemu-utils than the release's goes back to the release's.)
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q qemu-system-arm \
        binutils-arm-none-eabi gcc libglu1-mesa-dev ||
        DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q --allow-downgrades \
            qemu-system-arm "qemu-utils/$(. /etc/os-release && echo "$VERSION_CODENAME")" \
            binutils-arm-none-eabi gcc libglu1-mesa-dev
fi

start=$(date +%s)
out=target/figures
mkdir -p "$out"
step() { printf '== %s (%ds)\n' "$*" $(($(date +%s) - start)) >&2; }

cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
machine="$cpu, $(nproc) cores, $(free -g | awk '/^Mem:/ {print $2}') GiB; $(rustc -V); $(qemu-system-arm --version | head -1)"
today=$(date -u +%Y-%m-%d)

step "builds"
cargo build -q --release -p host-tests --example eval_speed --example error_figures --example oracle_saturated --example bintree_figures --example orbit_changes --example frame_loop --example host_call --example hierarchy_limits
mkdir -p target/glu
cc -O2 -o target/glu/glu_peer host-tests/glu/glu_peer.c -lGLU -lGL
cargo build -q --release --example teapot
cargo build -q --release --example fw_eval --example fw_bisect --example fw_teapot --target "$T"

step "evaluation on the host"
cargo run -q --release -p host-tests --example eval_speed >"$out/eval_speed.md"
step "firmware under QEMU"
cargo run -q --release --example fw_eval --target "$T" >"$out/fw_eval.txt"
cargo run -q --release --example fw_bisect --target "$T" >"$out/fw_bisect.txt"
arm-none-eabi-size -A "target/$T/release/examples/fw_eval" |
    awk '$1 ~ /^\.(vector_table|text|rodata|data|bss|uninit)$/ {printf "| `%s` | %s |\n", $1, $2}' >"$out/fw_eval_sizes.md"
step "bake speed, one thread and all"
scripts/bake_speed.sh >"$out/bake_speed.md"
step "fw_teapot per part class"
scripts/parts.sh >"$out/parts.md"
step "footprint of fw_teapot"
scripts/footprint.sh "$out/text_by_module.md" >"$out/footprint.md"
step "teapot main job"
rm -rf "$out/hierarchies"
cargo run -q --release --example teapot -- --size 480x360 --out "$out/teapot" --cache "$out/hierarchies" >"$out/teapot.txt" 2>/dev/null
# The second start, timed from start to exit (the binary is built already).
t0=$EPOCHREALTIME
target/release/examples/teapot --frames 1 --out "$out/teapot1" --cache "$out/hierarchies" >"$out/teapot_again.txt" 2>/dev/null
t1=$EPOCHREALTIME
python3 -c "print($t1 - $t0)" >"$out/teapot_again_s.txt"
step "error control, against the uniform grids and GLU"
# The grids depend on the case alone: the three tables share them.
grids="$out/grids.tsv"
rm -f "$grids"
GRID_CACHE="$grids" GLU_PEER=target/glu/glu_peer cargo run -q --release -p host-tests --example error_figures >"$out/error_1e-3.md"
GRID_CACHE="$grids" BAKE_REL=2.5e-4 GLU_PEER=target/glu/glu_peer cargo run -q --release -p host-tests --example error_figures >"$out/error_2.5e-4.md"
GRID_CACHE="$grids" SPLIT=1 cargo run -q --release -p host-tests --example error_figures >"$out/error_split_1e-3.md"
GRID_CACHE="$grids" cargo run -q --release -p host-tests --example hierarchy_limits >"$out/hierarchy_limits.md"
step "hierarchies, orbit steps, frame loop"
if [ "$full" = 1 ]; then
    cargo run -q --release -p host-tests --example bintree_figures -- 2e-3 1e-3 2.5e-4 >"$out/hierarchies.md"
else
    cargo run -q --release -p host-tests --example bintree_figures -- 2e-3 1e-3 >"$out/hierarchies.md"
fi
cargo run -q --release -p host-tests --example orbit_changes >"$out/orbit_changes.md"
cargo run -q --release -p host-tests --example frame_loop >"$out/frame_loop.txt"
{
    echo "eye (6,-6,4):        $(cargo run -q --release -p host-tests --example host_call)"
    echo "eye (2.2,-1.5,2.6):  $(EYE=2.2,-1.5,2.6 cargo run -q --release -p host-tests --example host_call)"
} >"$out/host_call.txt"
TABLE=1 GLU_PEER=target/glu/glu_peer cargo run -q --release -p host-tests --example frame_loop >"$out/frame_table_1e-3.md"
TABLE=1 BAKE_REL=2.5e-4 GLU_PEER=target/glu/glu_peer cargo run -q --release -p host-tests --example frame_loop >"$out/frame_table_2.5e-4.md"
step "where a cold frame's time goes (perf)"
if command -v perf >/dev/null; then
    scripts/frame_profile.sh >"$out/frame_profile.md"
else
    echo "(\`perf\` is not installed on this machine: no profile.)" >"$out/frame_profile.md"
fi
step "oracle"
cargo run -q --release -p host-tests --example oracle_saturated >"$out/oracle_saturated.md"
cp "$out/teapot/teapot_020.png" docs/teapot_frame.png
elapsed=$(($(date +%s) - start))
step "writing BENCHMARKS.md and README.md"

python3 - "$out" "$machine" "$today" "$elapsed" "$full" <<'PY'
import re, sys
out, machine, today, elapsed, full = sys.argv[1:]
read = lambda name: open(f"{out}/{name}").read().rstrip("\n")
minutes = f"{int(elapsed) / 60:.1f}"
stamp = (f"Generated by `scripts/figures.sh` on {today} in {minutes} minutes "
         f"(machine: {machine}).")

# The main job's table: a header and five frames; frame 20 is the README's picture.
lines = read("teapot.txt").splitlines()
header = next(l for l in lines if l.lstrip().startswith("frame"))
rows = {int(l.split()[0]): l for l in lines if re.match(r"^\s*\d+\s", l)}
picked = [rows[k] for k in (0, 1, 12, 20, 23) if k in rows]
teapot_table = "```text\n" + "\n".join([header] + picked) + "\n```"
tri20 = rows[20].split()[3]
picture = (
    "![The Utah teapot at 1 px tolerance, 480x360, Gouraud shading with the triangles "
    "overlaid](docs/teapot_frame.png)\n\n"
    "*Frame 20 of `cargo run --release --example teapot -- --size 480x360` (copied from "
    f"`out/teapot_020.png`): {tri20} triangles at 1 px tolerance, drawn by the kernel's band "
    f"renderer. {stamp}*")
first_start = next(l for l in lines if l.startswith("#"))
again = read("teapot_again.txt").splitlines()[0]
again_s = float(read("teapot_again_s.txt"))

blocks = {
    "teapot-picture": picture,
    "teapot-table": teapot_table,
    "parts": read("parts.md") + f"\n\n*{stamp}*",
    "bake": read("bake_speed.md") + f"\n\n*`scripts/bake_speed.sh`. {stamp}*",
}
readme = open("README.md").read()
for name, body in blocks.items():
    a, b = f"<!-- figures:{name}:start -->", f"<!-- figures:{name}:end -->"
    i, j = readme.index(a) + len(a), readme.index(b)
    readme = readme[:i] + "\n" + body + "\n" + readme[j:]
open("README.md", "w").write(readme)

scope = "2e-3, 1e-3 and 2.5e-4" if full == "1" else "2e-3 and 1e-3"
left = []
if full != "1":
    left.append("- The hierarchies' figures at 2.5e-4 of the diagonal (`scripts/figures.sh "
                "--full`).")
left += [
    "- Run-to-run spread: every host time is one median or best in one process on a shared "
    "machine; reruns differ by about 10%.",
    "- Real hardware: instruction counts come from QEMU's `-icount`, not from a board's cycle "
    "counter (flash wait states, caches and bus stalls are not modelled).",
    "- Speed against an earlier revision: `scripts/compare_speed.sh REV` builds REV's "
    "`tessellate` in a worktree and times both on one view in one run (a cold build of REV "
    "takes minutes, so it is not run here).",
    "- The GLU peer tessellates the kernel's Bezier patches (NURBS surfaces split at their "
    "knots), not the NURBS surfaces whole, and only in camera cases (`GLU_PARAMETRIC_ERROR` "
    "needs a projection).",
    "- The prefix run time (per-patch prefixes of baked samples, retired): its figures were "
    "last measured at commit d151dc0 (BENCHMARKS.md there; CHANGELOG.md has the summary).",
]
left_out = "## What this leaves out\n\n" + "\n".join(left)

bench = f"""# Benchmarks

{stamp} Rerun it to refresh every number here and in README.md.

## Error control

`cargo run --release -p host-tests --example error_figures` (its module docs say exactly what
is measured), with `GLU_PEER` set to libGLU's NURBS tessellator built from
`host-tests/glu/glu_peer.c` (`GLU_NURBS_TESSELLATOR`, `GLU_PARAMETRIC_ERROR` at the same pixel
tolerance, the same camera as OpenGL matrices, culling on). Each model's hierarchy is baked at
1e-3 of its diagonal; where a view is finer, the tessellator halves below the bake, evaluating
and bounding the new triangles itself. Every triangle is checked with the `f64` reference: the
surface against the triangle's linear interpolant at the same (u,v), 12 steps per side,
projected; only samples on screen count. *n x n grid* is the smallest uniform n x n grid per
patch whose error, checked the same way, is within the tolerance (a lower bound for uniform
tessellation with one factor a patch; it has cracks); *n_u x n_v grid* the same with a factor
per direction, chosen per patch to minimise triangles (as the Direct3D 11 tessellator may):
the stronger reference. *Ratio* is the kernel's triangles over the n_u x n_v grid, *ratio to n
x n* over the other. *Over* counts triangles above the tolerance; *bound / true* is
each triangle's bound in model units over its measured deviation (at least 1 is the soundness
claim); *off screen* counts the written triangles with no sample on screen; *full ms* is a
frame of a new tessellator over the hierarchy with its links (`Hierarchy::with_links`, as
`host::Baked` reads it), update and indexed write, best of eleven or of as many as take half
a second, and *all cores ms* the same with the update spread over the machine's cores
(`Tessellator::update_parallel`, the same mesh), the two timed in five turns each so that a
busy moment of the machine spoils at most one; GLU's time is its tessellation alone, best of
fifteen, and *full / GLU*, *all cores / GLU*
divide by it. Times vary 10-30% from run to run on this machine (GLU's too).

{read("error_1e-3.md")}

The same with a bake at 2.5e-4 of the diagonal (`BAKE_REL=2.5e-4`), which the teapot main job
uses:

{read("error_2.5e-4.md")}

The same with every patch split into four before baking (`SPLIT=1`; `PatchSet::split`, or
`--split` in the `tessellate` example). The grid is still the model's own patches', and every
triangle is checked against the model's own surface (GLU columns left out: they are the first
table's):

{read("error_split_1e-3.md")}

## What stands between the hierarchy and fewer triangles

The bake cuts each patch's square into `2^a x 2^b` cells (`a, b <= 3`; `bake/cells.rs` derives
the choice from the control net's second differences, one level per chord of shared curves), so
that a patch bent more in one direction gets triangles as long on screen as they are wide. With
`BakeSettings::max_cell_level = 0` every patch is one cell, the hierarchy before.

`cargo run --release -p host-tests --example hierarchy_limits` (its module docs say exactly what
is measured) selects the coarsest conforming mesh of the same hierarchy with an oracle that
knows each triangle's *measured* error, and with `f64` bounds of the kernel's kind. The oracle
culls nothing, so its counts compare with each other, not with the kernel's; in brackets, each
over the n_u x n_v grid.

{read("hierarchy_limits.md")}

Reading it: *one cell, measured* to *cells, measured* is what the cells gain on this hierarchy
with a perfect bound; *cells, measured* to *cells, bound, lattice* is what the directional bound
itself costs (it pairs the worst view ray of the triangle with the worst deviation vector, and
the nearest depth with both); *4 kept* is what keeping four vectors a node costs on top. Half
the n_u x n_v grid lies below even the measured column: what stands between is the structure
of a nested hierarchy of halvings, not its bounds. Each halving doubles a region's triangles
where a grid's factor moves by one (at a tolerance between two levels, a uniformly bent patch
takes up to twice the triangles its errors need); a triangle is also halved when its neighbour
is (conformity); and a patch's cells fix its triangles' aspect once, at the bake, where a ruled
surface (`verb_quarter_cylinder`) wants a thinner strip the finer the view. Getting closer
needs halvings whose direction follows each region's bend below the cells, kept conforming and
unique (not done: a split rule per node breaks the diamonds that make the mesh conforming), and
a bound that pairs each deviation with its own ray and depth.

## The hierarchies

`cargo run --release -p host-tests --example bintree_figures -- {scope.replace(",", "").replace(" and ", " ")}`:
every model's hierarchy at {scope} of its control-point diagonal. *Bytes* are its compact bytes
(`bake::encode_hierarchy`, read in place by `Hierarchy::from_bytes`: what a firmware keeps in
flash), *records* the bake's records at their in-memory sizes (what a firmware kept in flash
before the bytes, and what `Hierarchy::new` reads in RAM), and the bake's time on one core:

{read("hierarchies.md")}

## The main job

`cargo run --release --example teapot -- --size 480x360`, frames 0, 1, 12, 20 and 23 of 24
(the first start bakes the hierarchy at 2.5e-4 and keeps it in the cache folder):

{teapot_table}

Its first line, on the first start: `{first_start}`. A second start (`--frames 1`) reads the
hierarchy back from the cache: `{again}`; from start to exit, {again_s:.2} s.

## Frames on the host

`cargo run --release -p host-tests --example frame_loop`: the teapot baked at 2.5e-4, 1024x768,
1 px, eye (6,-6,4), the hierarchy with its links (`Hierarchy::with_links`); 200 frames, each an
update and an indexed write (frames depend on the view alone; every frame here is a cold one,
a new tessellator on the same storage):

```text
{read("frame_loop.txt")}
```

The one call a host program makes, `host::Baked::tessellate` (it sizes and allocates its
storage, searches on all cores, and writes the mesh with a face per triangle): `cargo run
--release -p host-tests --example host_call` (the teapot at `host::BAKE`, 1024x768, 1 px, best
of 200 calls; `EYE=2.2,-1.5,2.6` for the close-up, which goes below the bake):

```text
{read("host_call.txt")}
```

Where a cold frame's time goes: `scripts/frame_profile.sh` (`perf record` of 2,000 such
frames, by function, inlined code counted in its caller, the bake's functions left out):

{read("frame_profile.md")}

Cold frames, orbit steps and libGLU, side by side: `TABLE=1 GLU_PEER=target/glu/glu_peer cargo
run --release -p host-tests --example frame_loop` (`BAKE_REL` for the bake; see the example's
docs for what each column times). A frame is an update and an indexed write; GLU's is its
tessellation alone, at its nominal tolerance (it is not sound: see the error table). *Cold ms,
all cores* searches on this machine's two cores (`Tessellator::update_parallel`: parts of the
roots on threads of their own, then the whole frame across their borders; the same mesh),
which pays where a frame stays within the bake; below it (the close-up) the refinement stays
on one thread, and a small frame pays more for its threads than it saves. Without
reuse a tessellator keeps no work from one view to the next but for a view equal to the last
(*same view again*: the indexed write alone), so an orbit step costs what a cold frame of its
view costs, to this machine's noise. With `Tessellator::with_reuse` (*step with reuse*) it
keeps the judgements whose certificates still hold (*judgements kept*: of the triangles the
frames looked at). With the hierarchy's links too (as here), a frame within the bake is a
*step* from the one before (*frames stepped*; `src/tessellator/step.rs`): the last mesh is
kept, the judgements that ran out are made again, and the mesh changes only where one of them
flipped. A frame below the bake (the 0.5 px views and the close-up at 1e-3, where pool
vertices are made) is searched from the roots with the kept judgements. *Orbit update* times
the update alone, without the indexed write, for the orbit's cold frames and for its steps
with reuse: a step's update is then mostly its judgements made again, each with a certificate
(see the example's docs, and CHANGELOG for its instruction counts). *Orbit update, all
cores* times the same updates with `update_parallel`: the cold ones search on the threads,
and a step makes its lapsed judgements again on them (the same judgements and figures; a
search with reuse, as below the bake, stays on one thread). On the firmware,
`fw_teapot`'s frame 1 is an orbit step from frame 0 (its figures are in the display demo's
section below; it has no RAM for the reuse's slots).

Each model baked at 1e-3 of its diagonal (the error table's bake; the 0.5 px views and the
close-up go below it, where the run time refines):

{read("frame_table_1e-3.md")}

At 2.5e-4:

{read("frame_table_2.5e-4.md")}

What an orbit step changes: `cargo run --release -p host-tests --example orbit_changes` (the
teapot's hierarchy at `fw_teapot`'s bake, 2e-3 of the diagonal; 240x240 at 1 px; the eye of
`fw_teapot`'s first frame orbiting the target, 48 steps of each size). *Added* and *removed*
count the triangles of a frame that the frame before did not have, and the other way round:
what a frame-to-frame update would have to change, where the top-down search judges every
triangle of the mesh and the triangles it is cut from each frame (*judged*).

{read("orbit_changes.md")}

## `fw_teapot` per part class

`scripts/parts.sh` (run by this script): frame 0 a cold frame, frame 1 an orbit step from it
with the wireframe drawn; the ARMv6-M build (no FPU) runs on QEMU's `mps2-an385`, whose
Cortex-M3 executes v6-M code, so the count is what such a part runs, soft-float calls
included; the RV32IMC build (no FPU) on QEMU's `virt`, counted by `minstret` under `-icount`.
Flash counts the kernel's `.text` at opt-level "s" as the footprint below does, and the
teapot's hierarchy and patches. Every run is bit-identical to the host's frames.

{read("parts.md")}

## Footprint of the display demo (`fw_teapot`)

`scripts/footprint.sh` (run by this script).

{read("footprint.md")}

The kernel's `.text` at opt-level "s" by module (`scripts/text_by_module.py`, from the same
builds): each function counted where its name puts it, so what the compiler inlined is counted
with its caller, and the demo's frame loop holds the parts of the update it inlined.

{read("text_by_module.md")}

## The hierarchy on the Cortex-M4F (`fw_bisect`)

`cargo run --release --example fw_bisect --target thumbv7em-none-eabihf` (QEMU mps2-an386,
`-icount shift=0`; the teapot's hierarchy at 2e-3 in flash; four 240x240 views: a view, a small
orbit step, a dolly in, half the tolerance, the last below the bake; instructions cover the
frame's update and its indexed write; the storage line gives the tessellator's RAM: three
bits per node, one per vertex and one per patch, a stack of 256 waiting triangles, a pool of 2,048
vertices below the bake):

```text
{read("fw_bisect.txt")}
```

## Evaluation on the host

`cargo run --release -p host-tests --example eval_speed`: the kernel in `f32` and curvo 0.3 in
`f64` on the same patches and parameters (32 x 32 grid per patch), best of 7, in one run. The
kernel's `evaluate` computes position, both partials and the unit normal (with the pole-limit
logic); curvo's `normal_at` computes an unnormalised normal only.

{read("eval_speed.md")}

## Evaluation on the Cortex-M4F (QEMU mps2-an386)

`cargo run --release --example fw_eval --target thumbv7em-none-eabihf`. QEMU runs with
`-icount shift=0` (1 instruction = 1 ns of virtual time) and the 25 MHz SysTick advances once
every 40 instructions. Each evaluation is `BezierPatch::evaluate` (position, partials, normal)
on the teapot's bicubic patches.

```text
{read("fw_eval.txt")}
```

Sections of `fw_eval` (release, LTO, `opt-level = 3`), from `arm-none-eabi-size -A`, in bytes.
`.text` includes cortex-m-rt start-up, the semihosting printing of integers and the panic
handler besides the kernel; `.rodata` holds the teapot and the expected values.

| section | bytes |
|---|---|
{read("fw_eval_sizes.md")}

## A top-down selection without neighbours (oracle)

Whether a bisection tessellator could select its mesh without finding neighbours, so without a
state per triangle: `cargo run --release -p host-tests --example oracle_saturated` (its module
docs say exactly what is measured; Lindstrom and Pascucci's saturated errors over the
hierarchy's vertices):

{read("oracle_saturated.md")}

{left_out}
"""
open("BENCHMARKS.md", "w").write(bench)
PY
step "done"
