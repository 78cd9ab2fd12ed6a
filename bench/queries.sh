#!/usr/bin/env bash
# Point queries and training samples beside Open3D's RaycastingScene
# (Embree's point queries) and a brute-force reference; writes
# bench/results/queries.md (and prints it).
#
# Meshes, small (about 12k faces) and large (about 100k): the repository's
# fandisk and spot split twice into four (bench/mesh_subdivide.awk), and two
# that Open3D made from the repository's meshes and wrote as binary PLY:
# the bunny decimated to 12,000 faces (quadric decimation) and the teapot
# loop-subdivided twice.
#
# Queries: POINTS points per mesh, half near the surface (area-weighted
# surface points moved by a Gaussian of 0.02 times the mesh sphere's radius)
# and half uniform in the cube around that sphere, float32, in random order.
# sdftrace (Mesh.signed_distance: the exact distance and the winding
# number's sign) against Open3D's compute_distance (unsigned) and
# compute_signed_distance (Embree's point query and a ray's parity), each
# called from one Python interpreter on the same array, THREADS CPUs
# (taskset). Every round runs each tool once, in a shuffled order; a rate is
# the median of REPEAT rounds with its 95% bootstrap interval (bench/stats),
# a ratio the median of the rounds' ratios. Errors against the brute force
# (numpy, double precision: the closest point of every triangle, and the
# winding number as a sum of every triangle's solid angle) on BRUTE of the
# points: the largest distance error in units of the sphere's radius, and
# the points whose sign disagrees with the brute-force winding number where
# it is clearly decided (below 0.25 or above 0.75).
#
# Samples: `mesh2sdf MESH --samples SAMPLES OUT.npy --json` with 1 thread
# and with THREADS, in turns, REPEAT times: the whole run's wall time and
# each phase's (read, orient, index, samples); the serial share of each
# phase follows from Amdahl's law, 1 - (1 - T_n / T_1) n / (n - 1). Beside
# it, in one interpreter after import (so without a process start):
# sdftrace.sample_near_surface and Open3D's equivalent (read the mesh,
# sample_points_uniformly, move the points by DeepSDF's two sigmas, add the
# uniform share, compute_signed_distance).
#
# On a busy machine wall times stretch with the other processes; the pages
# also give the CPU time of the same runs.
#
# Needs python3-open3d (Debian's; installed here with apt-get when missing
# and run as root) and the Python module (build/python).
#
# usage: bench/queries.sh
# env:   BUILD=build  POINTS=1000000  SAMPLES=250000  THREADS=2  REPEAT=5  BRUTE=1000
#        MESHES="fandisk spot-x16 bunny-o3d teapot-o3d"  PAGE_DIR (default bench/results)
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
root=$PWD
. bench/page.sh
command="bench/queries.sh"
for var in MESHES BRUTE REPEAT THREADS SAMPLES POINTS BUILD; do
    [ -z "${!var+set}" ] || command="$var=\"${!var}\" $command"
done
BUILD=${BUILD:-build}
POINTS=${POINTS:-1000000}
SAMPLES=${SAMPLES:-250000}
THREADS=${THREADS:-2}
REPEAT=${REPEAT:-5}
BRUTE=${BRUTE:-1000}
MESHES=${MESHES:-fandisk spot-x16 bunny-o3d teapot-o3d}
PYTHON=${PYTHON:-/usr/bin/python3}
PAGE_STATS=${PAGE_STATS:-$root/$BUILD/bench/stats}
export PAGE_STATS
page_need_stats
[ -x "$BUILD/mesh2sdf" ] || { echo "queries.sh: no $BUILD/mesh2sdf (build it first)" >&2; exit 1; }
[ -d "$BUILD/python/sdftrace" ] || { echo "queries.sh: no $BUILD/python/sdftrace (python3-dev, python3-numpy)" >&2; exit 1; }
if ! "$PYTHON" -c 'import open3d' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "queries.sh: installing python3-open3d" >&2
        DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-open3d >&2
    else
        echo "queries.sh: needs python3-open3d (apt-get install python3-open3d)" >&2
        exit 1
    fi
fi
[ "$THREADS" -le "$(nproc)" ] || { echo "queries.sh: THREADS=$THREADS is more than nproc" >&2; exit 1; }
cpus=0-$((THREADS - 1))
work=$BUILD/bench-queries
mkdir -p "$work"

# The meshes: the repository's, spot split twice, and two Open3D made.
make_meshes() {
    [ -s "$work/fandisk.obj" ] || cp tests/data/meshes/fandisk.obj "$work/fandisk.obj"
    [ -s "$work/spot-x16.obj" ] ||
        awk -f bench/mesh_subdivide.awk tests/data/meshes/spot.obj | awk -f bench/mesh_subdivide.awk >"$work/spot-x16.obj"
    "$PYTHON" - "$work" <<'PY'
import os, sys
import open3d as o3d
work = sys.argv[1]
made = {
    "bunny-o3d.ply": lambda: o3d.io.read_triangle_mesh("tests/data/meshes/stanford-bunny.obj")
    .simplify_quadric_decimation(target_number_of_triangles=12000),
    "teapot-o3d.ply": lambda: o3d.io.read_triangle_mesh("tests/data/meshes/teapot.obj").subdivide_loop(2),
}
for name, make in made.items():
    path = os.path.join(work, name)
    if not os.path.exists(path):
        o3d.io.write_triangle_mesh(path, make(), write_ascii=False)
PY
}

mesh_path() {
    case "$1" in
    *-o3d) echo "$work/$1.ply" ;;
    *) echo "$work/$1.obj" ;;
    esac
}

# The queries' table: one interpreter per mesh, pinned to the CPUs.
queries_table() {
    echo "| mesh | faces | sdftrace, queries/s | Open3D distance, queries/s | Open3D signed, queries/s |" \
        "sdftrace over Open3D signed | the same in CPU time | brute force, queries/s |" \
        "largest error (radius): sdftrace / Open3D | wrong signs: sdftrace / Open3D |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---|---|"
    for name in $MESHES; do
        PYTHONPATH=$BUILD/python taskset -c "$cpus" "$PYTHON" - "$(mesh_path "$name")" "$name" "$POINTS" "$REPEAT" \
            "$BRUTE" "$work" <<'PY'
import os, random, subprocess, sys, time
import numpy as np
import open3d as o3d
import sdftrace

path, name, n, repeat, brute, work = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
stats = os.environ["PAGE_STATS"]

def summary(samples, ratio=False, digits=0):
    lines = "\n".join(f"{a} {b}" for a, b in samples) if ratio else "\n".join(str(s) for s in samples)
    args = [stats] + (["--ratio"] if ratio else []) + ["--text", str(digits)]
    return subprocess.run(args, input=lines, capture_output=True, text=True, check=True).stdout.strip()

legacy = o3d.io.read_triangle_mesh(path)
V = np.asarray(legacy.vertices).astype(np.float32).astype(np.float64)
F = np.asarray(legacy.triangles)
centre = 0.5 * (V.min(0) + V.max(0))
radius = 0.5 * np.linalg.norm(V.max(0) - V.min(0))
rng = np.random.default_rng(1)
A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
area = 0.5 * np.linalg.norm(np.cross(B - A, C - A), axis=1)
half = n // 2
t = rng.choice(len(F), half, p=area / area.sum())
r1, r2 = np.sqrt(rng.random(half))[:, None], rng.random(half)[:, None]
near = (1 - r1) * A[t] + r1 * (1 - r2) * B[t] + r1 * r2 * C[t] + rng.normal(0, 0.02 * radius, (half, 3))
uniform = centre + rng.uniform(-radius, radius, (n - half, 3))
points = np.concatenate([near, uniform]).astype(np.float32)
points = points[rng.permutation(n)]

ours = sdftrace.Mesh(path)
ours.signed_distance(points[:1000])  # the hierarchies, built once
scene = o3d.t.geometry.RaycastingScene()
scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(legacy))
tensor = o3d.core.Tensor(points)
scene.compute_distance(tensor[:1000])
tools = {
    "ours": lambda: ours.signed_distance(points),
    "distance": lambda: scene.compute_distance(tensor).numpy(),
    "signed": lambda: scene.compute_signed_distance(tensor).numpy(),
}
seconds = {k: [] for k in tools}
cpu = {k: [] for k in tools}
results = {}
for _ in range(repeat):
    order = list(tools)
    random.shuffle(order)
    for k in order:
        start, start_cpu = time.perf_counter(), time.process_time()
        results[k] = tools[k]()
        seconds[k].append(time.perf_counter() - start)
        cpu[k].append(time.process_time() - start_cpu)

# The brute force on `brute` of the points, half near and half uniform.
check = np.concatenate([np.arange(min(brute // 2, n)), np.arange(n - min(brute - brute // 2, n), n)])
chosen = points.astype(np.float64)[check]
start = time.perf_counter()
truth, winding = np.empty(len(check)), np.empty(len(check))
ab, ac, bc = B - A, C - A, C - B
for i, p in enumerate(chosen):
    # the closest point of each triangle (Ericson's regions, the first that holds)
    ap, bp, cp = p - A, p - B, p - C
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        q = A + ab * (vb / denom)[:, None] + ac * (vc / denom)[:, None]
        for region, at in (
            ((va <= 0) & (d4 >= d3) & (d5 >= d6), lambda: B + bc * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None]),
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), lambda: A + ac * (d2 / (d2 - d6))[:, None]),
            ((d6 >= 0) & (d5 <= d6), lambda: C),
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), lambda: A + ab * (d1 / (d1 - d3))[:, None]),
            ((d3 >= 0) & (d4 <= d3), lambda: B),
            ((d1 <= 0) & (d2 <= 0), lambda: A),
        ):
            q = np.where(region[:, None], at(), q)
    truth[i] = np.sqrt(np.nanmin(((p - q) ** 2).sum(1)))
    # the winding number: Van Oosterom and Strackee's solid angles
    a, b, c = A - p, B - p, C - p
    la, lb, lc = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1), np.linalg.norm(c, axis=1)
    det = (a * np.cross(b, c)).sum(1)
    div = la * lb * lc + (a * b).sum(1) * lc + (a * c).sum(1) * lb + (b * c).sum(1) * la
    winding[i] = np.arctan2(det, div).sum() / (2 * np.pi)
brute_rate = len(check) / (time.perf_counter() - start)
clear = (winding < 0.25) | (winding > 0.75)
inside = winding > 0.5
def errors(values):
    values = values[check].astype(np.float64)
    return np.max(np.abs(np.abs(values) - truth)) / radius, int(np.sum(clear & ((values < 0) != inside)))
e_ours, s_ours = errors(results["ours"])
e_o3d, s_o3d = errors(results["signed"])
# Open3D's sign is its ray casting's parity; where that fails, nothing is inside.
failed = " (Open3D: no point inside; its ray casting failed)" if np.all(results["signed"] >= 0) and np.any(clear & inside) else ""
rate = lambda k: summary([n / s for s in seconds[k]])
ratio = summary(list(zip(seconds["signed"], seconds["ours"])), True, 2)
cpu_ratio = summary(list(zip(cpu["signed"], cpu["ours"])), True, 2)
with open(os.path.join(work, name + ".ratio"), "w") as f:
    f.write(f"{len(F)} {ratio.split()[0]}\n")
print(f"| {name} | {len(F)} | {rate('ours')} | {rate('distance')} | {rate('signed')} | {ratio} | {cpu_ratio} |"
      f" {brute_rate:.0f} |"
      f" {e_ours:.1e} / {e_o3d:.1e} | {s_ours} / {s_o3d} of {int(clear.sum())}{failed} |")
PY
    done
}

# Samples: mesh2sdf's phases at 1 and THREADS threads, in turns.
samples_table() {
    echo "| mesh | faces | threads | read, s | orient, s | index, s | samples, s | samples/s | end to end, s | CPU, s |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    local serial=""
    for name in $MESHES; do
        local mesh out
        mesh=$(mesh_path "$name")
        out=$work/$name-samples.npy
        : >"$work/$name-t1.json"
        : >"$work/$name-tn.json"
        for _ in $(seq "$REPEAT"); do
            for t in 1 "$THREADS"; do
                local start end
                start=$(date +%s.%N)
                /usr/bin/time -f '%U %S' -o "$work/cpu.txt" taskset -c "$cpus" "$BUILD/mesh2sdf" "$mesh" \
                    --samples "$SAMPLES" "$out" --threads "$t" --json >"$work/line.json"
                end=$(date +%s.%N)
                local wall cpu
                wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.6f", b - a }')
                cpu=$(awk '{ printf "%.3f", $1 + $2 }' "$work/cpu.txt")
                sed "s/}\$/, \"wall\": $wall, \"cpu\": $cpu}/" "$work/line.json" \
                    >>"$work/$name-$([ "$t" = 1 ] && echo t1 || echo tn).json"
            done
        done
        for t in t1 tn; do
            local row="| $name | $(field "$work/$name-$t.json" triangles | head -1) | $([ $t = t1 ] && echo 1 || echo "$THREADS") |"
            for f in read_seconds orient_seconds index_seconds samples_seconds samples_per_second wall cpu; do
                local digits=3
                [ "$f" = samples_per_second ] && digits=0
                row="$row $(field "$work/$name-$t.json" "$f" | page_stats --text $digits) |"
            done
            echo "$row"
        done
        serial="$serial$(amdahl "$name")"$'\n'
    done
    echo
    echo "Serial share of each phase (Amdahl's law from the medians at 1 and $THREADS threads; 0 is perfectly"
    echo "parallel, 1 serial; small phases are noisy):"
    echo
    echo "| mesh | read | orient | index | samples | end to end |"
    echo "|---|---:|---:|---:|---:|---:|"
    printf '%s' "$serial"
}

# The values of one JSON field, one a line.
field() { sed -n "s/.*\"$2\": \\([0-9.e+-]*\\).*/\\1/p" "$1"; }

amdahl() {
    local row="| $1 |"
    for f in read_seconds orient_seconds index_seconds samples_seconds wall; do
        local one many
        one=$(field "$work/$1-t1.json" "$f" | page_stats | cut -d' ' -f1)
        many=$(field "$work/$1-tn.json" "$f" | page_stats | cut -d' ' -f1)
        row="$row $(awk -v a="$one" -v b="$many" -v n="$THREADS" \
            'BEGIN { if (a <= 0) print "-"; else printf "%.2f", 1 - (1 - b / a) * n / (n - 1) }') |"
    done
    echo "$row"
}

# One interpreter: sdftrace.sample_near_surface against Open3D's equivalent,
# each reading the mesh from its file, in turns.
python_samples_table() {
    echo "| mesh | sdftrace.sample_near_surface, s | Open3D (read, sample, compute_signed_distance), s | Open3D over sdftrace |"
    echo "|---|---:|---:|---:|"
    for name in $MESHES; do
        PYTHONPATH=$BUILD/python taskset -c "$cpus" "$PYTHON" - "$(mesh_path "$name")" "$name" "$SAMPLES" "$REPEAT" <<'PY'
import os, random, subprocess, sys, time
import numpy as np
import open3d as o3d
import sdftrace

path, name, n, repeat = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
stats = os.environ["PAGE_STATS"]

def summary(samples, ratio=False, digits=3):
    lines = "\n".join(f"{a} {b}" for a, b in samples) if ratio else "\n".join(str(s) for s in samples)
    args = [stats] + (["--ratio"] if ratio else []) + ["--text", str(digits)]
    return subprocess.run(args, input=lines, capture_output=True, text=True, check=True).stdout.strip()

def ours():
    sdftrace.sample_near_surface(path, n, seed=1)

def open3d():
    legacy = o3d.io.read_triangle_mesh(path)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(legacy))
    v = np.asarray(legacy.vertices)
    centre, radius = 0.5 * (v.min(0) + v.max(0)), 1.03 * np.linalg.norm(v - 0.5 * (v.min(0) + v.max(0)), axis=1).max()
    uniform = int(round(sdftrace.DEEPSDF_UNIFORM_SHARE * n))
    near = np.asarray(legacy.sample_points_uniformly(number_of_points=n - uniform).points)
    sigma = np.where(np.arange(n - uniform) % 2 == 0, *sdftrace.DEEPSDF_NEAR_SIGMA) * radius
    near = near + np.random.default_rng(1).normal(size=near.shape) * sigma[:, None]
    cube = centre + np.random.default_rng(2).uniform(-radius, radius, (uniform, 3))
    points = o3d.core.Tensor(np.concatenate([near, cube]).astype(np.float32))
    scene.compute_signed_distance(points).numpy()

seconds = {"ours": [], "open3d": []}
for _ in range(repeat):
    order = [("ours", ours), ("open3d", open3d)]
    random.shuffle(order)
    for k, run in order:
        start = time.perf_counter()
        run()
        seconds[k].append(time.perf_counter() - start)
ratio = summary(list(zip(seconds["open3d"], seconds["ours"])), True, 2)
print(f"| {name} | {summary(seconds['ours'])} | {summary(seconds['open3d'])} | {ratio} |")
PY
    done
}

# The goals, met or missed by how much, from the runs above: queries at
# least 1.2 times Open3D's signed rate on the small meshes and ahead on the
# large ones; on the large meshes with THREADS threads at least 500,000
# samples/s and SAMPLES samples in at most 1 s end to end.
targets() {
    echo "| goal | mesh | measured | verdict |"
    echo "|---|---|---:|---|"
    for name in $MESHES; do
        local faces ratio
        read -r faces ratio <"$work/$name.ratio"
        if [ "$faces" -lt 50000 ]; then
            verdict "queries >= 1.2x Open3D signed" "$name" "$ratio" 1.2 x
        else
            verdict "queries ahead of Open3D signed" "$name" "$ratio" 1.0 x
            verdict "samples/s >= 500,000 ($THREADS threads)" "$name" \
                "$(field "$work/$name-tn.json" samples_per_second | page_stats | cut -d' ' -f1)" 500000 ""
            verdict "$SAMPLES samples end to end <= 1 s ($THREADS threads)" "$name" \
                "$(field "$work/$name-tn.json" wall | page_stats | cut -d' ' -f1)" 1 s
        fi
    done
}

# One goal's row: at least GOAL (unit x, or none: a rate), or at most GOAL s.
verdict() {
    awk -v goal="$1" -v mesh="$2" -v got="$3" -v want="$4" -v unit="$5" 'BEGIN {
        ok = unit == "s" ? got <= want : got >= want
        shown = unit == "" ? sprintf("%.0f", got) : sprintf("%.2f %s", got, unit)
        miss = sprintf("missed by %.0f%%", 100 * (unit == "s" ? got / want - 1 : 1 - got / want))
        printf "| %s | %s | %s | %s |\n", goal, mesh, shown, ok ? "met" : miss
    }'
}

page() {
    page_header "Point queries and training samples beside Open3D" "$command"
    cat <<EOF
Meshes (\`$work\`): \`fandisk\` (the repository's), \`spot-x16\` (spot split twice into four by
\`bench/mesh_subdivide.awk\`), and two that Open3D $("$PYTHON" -c 'import open3d; print(open3d.__version__)') made from the repository's
meshes and wrote as binary PLY: \`bunny-o3d\` (the bunny decimated to 12,000 faces) and \`teapot-o3d\`
(the teapot loop-subdivided twice). Every process is pinned to $THREADS CPUs (\`taskset\`); times are
medians of $REPEAT rounds with their 95% bootstrap intervals (\`bench/stats\`), the tools of a round in a
shuffled order.

**Queries.** $POINTS points a mesh, half near the surface (a Gaussian of 0.02 times the sphere's radius)
and half uniform in the sphere's cube, float32, through one Python interpreter: sdftrace's
\`Mesh.signed_distance\` (exact distance, winding-number sign) against Open3D's \`RaycastingScene\`
\`compute_distance\` (Embree's point query) and \`compute_signed_distance\` (the same, signed by a ray's
parity). *sdftrace over Open3D signed* is the median of the rounds' ratios of Open3D's time to ours
(above 1: we are faster), and the same ratio of the process's CPU time, steadier on a busy machine. The
brute force (numpy, double precision) checks $BRUTE of the points, half near
and half uniform: the largest distance error in units of the sphere's radius, and the signs that
disagree with the brute-force winding number where it is clearly decided (below 0.25 or above 0.75).

EOF
    queries_table
    cat <<EOF

**Samples.** \`mesh2sdf MESH --samples $SAMPLES OUT.npy --json\` with 1 and $THREADS threads, in turns: the
phases the program reports (reading and welding, orienting, building the point hierarchies, drawing and
evaluating the samples), its samples/s (the samples phase alone), the process's wall time, and its CPU
time (user and system, all threads: on a busy machine the steadier measure of the work).

EOF
    samples_table
    cat <<EOF

In one interpreter after \`import\` (no process start): \`sdftrace.sample_near_surface(path, $SAMPLES)\`
against the same work with Open3D (read, \`sample_points_uniformly\`, DeepSDF's two sigmas and uniform
share, \`compute_signed_distance\`), both reading the mesh from its file.

EOF
    python_samples_table
    cat <<EOF

**Goals** (on this machine, $THREADS CPUs; the 16-core goal, 1M samples in 0.6 s end to end, needs a
bigger machine: the serial shares above tell what limits it):

EOF
    targets
}

make_meshes
page_write queries.md page
