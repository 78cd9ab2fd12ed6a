#!/usr/bin/env bash
# What the Python module costs over the command line: the same work through
# `import sdftrace` and through `mesh2sdf`, side by side; writes
# bench/results/python.md (and prints it).
#
# Rows: 250,000 training samples (mesh2sdf MESH --samples 250000 OUT.npy
# against sdftrace.sample_near_surface, then np.save) and a 256^3 narrow-band
# grid (mesh2sdf MESH -o OUT.vdb --res 256 against sdftrace.mesh_to_grid,
# then grid.save(OUT.vdb)), both reading the mesh from its file. The
# command line's time is its process's wall time (its start included); the
# Python call's is timed inside one interpreter, after `import sdftrace`
# (which a training script pays once). Each side runs REPEAT times and keeps its
# fastest run. Target: Python within +5% of the command line.
#
# usage: bench/python.sh
# env:   BUILD=build  MESH=tests/data/meshes/stanford-bunny.obj  REPEAT=5
#        PAGE_DIR (where the page goes; default bench/results)
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
root=$PWD
. bench/page.sh
command="bench/python.sh"
for var in REPEAT MESH BUILD; do
    [ -z "${!var+set}" ] || command="$var=\"${!var}\" $command"
done
BUILD=${BUILD:-build}
MESH=${MESH:-tests/data/meshes/stanford-bunny.obj}
REPEAT=${REPEAT:-5}
PYTHON=${PYTHON:-/usr/bin/python3}
work=$BUILD/bench-python
mkdir -p "$work"

# Fastest wall time of REPEAT runs of a command, seconds.
cli_best() {
    local best=1e9 start end
    for _ in $(seq "$REPEAT"); do
        start=$EPOCHREALTIME
        "$@" >/dev/null
        end=$EPOCHREALTIME
        best=$(awk -v a="$best" -v b="$(awk -v s="$start" -v e="$end" 'BEGIN { print e - s }')" \
            'BEGIN { print (b < a ? b : a) }')
    done
    echo "$best"
}

# Fastest time of REPEAT Python calls, seconds: KIND samples or grid.
python_best() {
    PYTHONPATH=$BUILD/python "$PYTHON" - "$1" "$MESH" "$work" "$REPEAT" <<'PY'
import sys, time
import numpy as np
import sdftrace
kind, mesh, work, repeat = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
best = float("inf")
for _ in range(repeat):
    start = time.perf_counter()
    if kind == "samples":
        points, sdf = sdftrace.sample_near_surface(sdftrace.Mesh(mesh), 250000, seed=1)
        np.save(work + "/py-samples.npy", np.column_stack([points, sdf]))
    else:
        sdftrace.mesh_to_grid(mesh, res=256).save(work + "/py-grid.vdb")
    best = min(best, time.perf_counter() - start)
print(best)
PY
}

table() {
    echo "| work | mesh2sdf (s) | Python (s) | Python over the CLI | target |"
    echo "|---|---:|---:|---:|---|"
    local cli py
    cli=$(cli_best "$BUILD/mesh2sdf" "$MESH" --samples 250000 "$work/cli-samples.npy" --seed 1 --quiet)
    py=$(python_best samples)
    awk -v c="$cli" -v p="$py" 'BEGIN { printf "| 250,000 samples | %.3f | %.3f | %+.1f%% | %s |\n",
        c, p, 100 * (p / c - 1), (p <= 1.05 * c ? "met (<= +5%)" : "missed (> +5%)") }'
    cli=$(cli_best "$BUILD/mesh2sdf" "$MESH" -o "$work/cli-grid.vdb" --res 256 --quiet)
    py=$(python_best grid)
    awk -v c="$cli" -v p="$py" 'BEGIN { printf "| 256^3 grid, written as .vdb | %.3f | %.3f | %+.1f%% | %s |\n",
        c, p, 100 * (p / c - 1), (p <= 1.05 * c ? "met (<= +5%)" : "missed (> +5%)") }'
}

page() {
    page_header "The Python module against the command line" "$command"
    echo "Mesh: \`$MESH\`; fastest of $REPEAT runs each. The command line's"
    echo "time includes its process start; the Python call's excludes \`import sdftrace\`."
    echo
    table
}

page_write python.md page
