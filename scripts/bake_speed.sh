#!/usr/bin/env bash
# How long a bake takes on one thread and on all of this machine's (best of three runs of the
# `bake` example, its own `seconds`: the bake alone, buffers included), and whether the two
# bakes are the same bytes. A markdown table on stdout; run by scripts/figures.sh.
#
#   scripts/bake_speed.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release --example bake
bake=target/release/examples/bake
dir=target/bake_speed
mkdir -p "$dir"
best() { # MODEL TOLERANCE THREADS OUT: the least `seconds` of three runs
    local s
    for _ in 1 2 3; do
        RAYON_NUM_THREADS=$3 "$bake" "$1" --tolerance "$2" --relative --out "$4" |
            sed -n 's/.* seconds \([0-9.]*\).*/\1/p'
    done | sort -n | head -1
}
threads=$(nproc)
echo "| model, bake tolerance (of the diagonal) | triangles | 1 thread (s) | $threads threads (s) | same bytes |"
echo "|---|---|---|---|---|"
for case in "teapot 2.5e-4" "teapot 1e-3" "gumbo 2.5e-4" "gumbo 1e-3"; do
    set -- $case
    model=examples/models/$1.bpt
    one=$(best "$model" "$2" 1 "$dir/$1_$2_1.bin")
    all=$(best "$model" "$2" "$threads" "$dir/$1_$2_n.bin")
    nodes=$("$bake" "$model" --tolerance "$2" --relative | sed -n 's/.* triangles \([0-9]*\) .*/\1/p')
    same=no
    cmp -s "$dir/$1_$2_1.bin" "$dir/$1_$2_n.bin" && same=yes
    echo "| $1, $2 | $nodes | $one | $all | $same |"
done
