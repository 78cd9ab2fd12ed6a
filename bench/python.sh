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
# (which a training script pays once). The sides run in turns, REPEAT times
# each, and each keeps its fastest run. Target: Python within +5% of the command line.
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

# The table, from one Python driver that alternates the two sides (CLI,
# Python, CLI, ...), so that a change in the machine's load falls on both,
# and keeps each side's fastest run.
table() {
    PYTHONPATH=$BUILD/python "$PYTHON" - "$BUILD/mesh2sdf" "$MESH" "$work" "$REPEAT" <<'PY'
import subprocess, sys, time
import numpy as np
import sdftrace
cli, mesh, work, repeat = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])

def timed(run):
    start = time.perf_counter()
    run()
    return time.perf_counter() - start

def samples_cli():
    subprocess.run([cli, mesh, "--samples", "250000", work + "/cli-samples.npy", "--seed", "1", "--quiet"], check=True)

def samples_python():
    points, sdf = sdftrace.sample_near_surface(mesh, 250000, seed=1)
    np.save(work + "/py-samples.npy", np.column_stack([points, sdf]))

def grid_cli():
    subprocess.run([cli, mesh, "-o", work + "/cli-grid.vdb", "--res", "256", "--quiet"], check=True)

def grid_python():
    sdftrace.mesh_to_grid(mesh, res=256).save(work + "/py-grid.vdb")

print("| work | mesh2sdf (s) | Python (s) | Python over the CLI | target |")
print("|---|---:|---:|---:|---|")
for label, a, b in (("250,000 samples", samples_cli, samples_python),
                    ("256^3 grid, written as .vdb", grid_cli, grid_python)):
    best_cli = best_py = float("inf")
    for _ in range(repeat):
        best_cli = min(best_cli, timed(a))
        best_py = min(best_py, timed(b))
    over = best_py / best_cli - 1
    verdict = "met (<= +5%)" if over <= 0.05 else "missed (> +5%)"
    print(f"| {label} | {best_cli:.3f} | {best_py:.3f} | {100 * over:+.1f}% | {verdict} |")
PY
}

page() {
    page_header "The Python module against the command line" "$command"
    echo "Mesh: \`$MESH\`; fastest of $REPEAT runs each, the two sides in turns. The command line's"
    echo "time includes its process start; the Python call's excludes \`import sdftrace\`."
    echo
    table
}

page_write python.md page
