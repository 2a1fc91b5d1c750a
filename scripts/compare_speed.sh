#!/usr/bin/env bash
# Times the `tessellate` example of this checkout against the one of an earlier revision, on
# the same views in one run on one machine, alternating the two binaries.
#
#   scripts/compare_speed.sh REV [RUNS]      # e.g. scripts/compare_speed.sh a21668d 5
#   NEW_ARGS="--bake-tolerance 2.5e-4" scripts/compare_speed.sh REV [RUNS]   # extra arguments here
#
# REV is built in a git worktree under target/compare (its own target directory, so the first
# run is a cold build of a few minutes). Each line gives the best of RUNS frame times (the
# example's "ms": update plus indexed write of one frame from a fresh tessellator; the bake
# happens before and is not timed) and the triangles.
set -euo pipefail
cd "$(dirname "$0")/.."
rev=${1:?usage: scripts/compare_speed.sh REV [RUNS]}
runs=${2:-5}
work=target/compare/$rev
if [ ! -d "$work" ]; then
    git worktree add --detach "$work" "$rev" >/dev/null
fi
(cd "$work" && CARGO_TARGET_DIR=../target-$rev cargo build -q --release --example tessellate)
cargo build -q --release --example tessellate
old=target/compare/target-$rev/release/examples/tessellate
new=target/release/examples/tessellate
obj=$(mktemp)
trap 'rm -f "$obj"' EXIT
view() {
    # model, then the example's view arguments.
    local model=$1
    shift
    for bin in "$old" "$new"; do
        best=""
        tris=""
        extra=()
        if [ "$bin" = "$new" ] && [ -n "${NEW_ARGS:-}" ]; then
            read -r -a extra <<<"$NEW_ARGS"
        fi
        for _ in $(seq "$runs"); do
            line=$("$bin" "$model" "$@" "${extra[@]}" --obj "$obj" | grep '^{' | head -1)
            ms=$(sed -n 's/.*"ms":\([0-9.]*\).*/\1/p' <<<"$line")
            tris=$(sed -n 's/.*"triangles":\([0-9]*\).*/\1/p' <<<"$line")
            best=$(awk -v a="$best" -v b="$ms" 'BEGIN { if (a == "" || b < a) print b; else print a }')
        done
        name=$([ "$bin" = "$old" ] && echo "$rev" || echo "this checkout ${NEW_ARGS:-}")
        printf '| %s | %s | %s | %s |\n' "$(basename "$model") $*" "$name" "$tris" "$best"
    done
}
echo "Machine: $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores; $(rustc -V)"
echo
echo "| view | build | triangles | best ms |"
echo "|---|---|---|---|"
cam=(--tolerance 1 --eye 6,-6,4 --target 0,0,1.2 --up 0,0,1 --fov 40 --viewport 1024x768)
view examples/models/teapot.bpt "${cam[@]}"
view examples/models/teapot.bpt "${cam[@]}" --bake-tolerance 2.5e-4
view examples/models/gumbo.bpt --tolerance 1 --eye 60,-50,40 --target 12,7,9.7 --up 0,0,1 --fov 40 --viewport 1024x768
