#!/usr/bin/env bash
# 3D elasticity at large sizes (docs/benchmarks.md, "Three dimensions"): every measurement of
# crates/vem-elastic/examples/scaling_3d.rs in its own process, so that its peak memory (VmHWM)
# is that of one solve, under a virtual-memory cap (default 22 GiB) and a time limit, the output
# appended to target/bench-3d/bench.log. A run the cap or the limit stops is reported as such.
#
# Usage: scripts/bench-3d.sh [RUN ...]
#   RUN is the argument list of one measurement, quoted, e.g. "--dofs 1e6" or
#   "--family voronoi --dofs 1e5 --faer"; without arguments: hexahedra at 1e5 and 1e6, Voronoi at
#   1e5, each solved by the project's solver and by faer alone.
# Environment: CAP_GIB (default 22), LIMIT (default 4h, a `timeout` duration).
set -uo pipefail
cd "$(dirname "$0")/.."
cargo build --quiet --release -p vem-elastic --example scaling_3d || exit 1
bin=target/release/examples/scaling_3d
out=target/bench-3d
mkdir -p "$out"
cap_kib=$(( ${CAP_GIB:-22} * 1024 * 1024 ))
limit=${LIMIT:-4h}
if [ $# -eq 0 ]; then
    set -- "--dofs 1e5" "--dofs 1e5 --faer" "--family voronoi --dofs 1e5" \
        "--family voronoi --dofs 1e5 --faer" "--dofs 1e6" "--dofs 1e6 --faer"
fi
for run in "$@"; do
    echo "== scaling_3d $run ($(date -u +%FT%TZ), load $(cut -d' ' -f1 /proc/loadavg))" | tee -a "$out/bench.log"
    # shellcheck disable=SC2086
    ( ulimit -v "$cap_kib"; exec timeout "$limit" "$bin" $run ) 2>&1 | tee -a "$out/bench.log"
    status=${PIPESTATUS[0]}
    if [ "$status" -ne 0 ]; then
        echo "== scaling_3d $run: failed with status $status (124: time limit; memory cap: allocation failure)" | tee -a "$out/bench.log"
    fi
done
