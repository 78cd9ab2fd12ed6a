#!/usr/bin/env bash
# mesh2sdf side by side with what it replaces, in two Markdown tables;
# writes bench/results/mesh2sdf.md (and prints it).
#
# Narrow band: mesh2sdf against OpenVDB's `vdb_tool -mesh2ls`: wall time,
# peak memory (GNU time's maximum resident set) and the fraction of
# wrong-sign sample points (mesh2sdf --check-sign: uniform points in the
# mesh's box, exact winding number by brute force, clearly inside > 0.75 or
# outside < 0.25, at least one voxel from the surface). Every tool gets the
# same voxel size, the mesh's longest side / N, and the same band (3 voxels).
# mesh2sdf runs with --sign winding (its default) and --sign flood
# (OpenVDB's own sign, for comparison).
#
# Dense (--full): mesh2sdf --full --npy against the per-point query that
# libigl-style tools pay at every voxel (bench/mesh2sdf_points.cpp: nearest
# triangle through a bounding volume hierarchy and the fast winding number,
# per point), on the same voxels: mesh2sdf's wall time (loading, the band,
# the signs, the dense pass and writing the .vdb and .npy) against the
# per-point queries' own time (not loading), their ratio, and how far the two
# grids differ (largest distance difference in voxels, sign disagreements at
# clearly inside or outside voxels).
#
# Every timed command runs REPEAT times (default 3), the tools of a row in
# turns (vdb_tool, winding, flood, then again), and each keeps its fastest
# run's wall time and that run's peak memory: on a shared machine one run's
# time moves by 10% or more, and taking each tool's best the same way keeps
# the ratio side by side. The per-point queries run once (they time
# themselves and take ten times longer).
#
# Batches (a page of its own, bench/results/mesh2sdf-batch.md): meshes per
# minute of `mesh2sdf --batch` at BATCH voxels along the longest side, over
# every mesh of MESH_DIR listed BATCH_COPIES times (so that a process's
# start is not the whole of the time), in three ways: one process with all
# cores, two --shard processes at once with half the cores each, and
# `mpirun -np 2` with half the cores per rank; fastest of REPEAT runs each,
# every run into a fresh folder.
#
# Training samples (--samples, its own page, bench/results/mesh2sdf-samples.md):
# the sampling's own rate (--json's samples_per_second: drawing the points,
# their exact distances and winding-number signs, not reading or indexing)
# with 1 and 2 threads, and the whole run's wall time for POINT_ROWS
# samples with 2 threads (reading the mesh, orienting, indexing, sampling,
# writing), on the repository's meshes and on spot split twice into four
# (bench/mesh_subdivide.awk: 93,696 faces); beside them the per-point query
# (bench/mesh2sdf_points.cpp) on the same points with 2 threads, and how
# far its distances and signs are from the samples'. Each rate is the best
# of REPEAT runs.
#
# usage: bench/mesh2sdf.sh [RES...]   (narrow band; default: 256 512 1024)
# env:   BUILD=build  MESHES="spot ..."  SAMPLES=10000  THREADS=0  REPEAT=3
#        DENSE="128 256" (dense resolutions; empty: none)  NARROW=0 (no narrow-band table)
#        ORIENT=128 (the orientation table's resolution; empty: no such table)
#        BATCH=256 (the batch page's resolution; empty: no batch page)  BATCH_COPIES=4
#        POINT_ROWS=250000 (training samples per run; empty: no samples page)
#        PAGE_DIR (where the pages go; default bench/results)
# With NARROW=0 and ORIENT and DENSE empty, mesh2sdf.md is left as it is:
# NARROW=0 ORIENT= DENSE= POINT_ROWS= bench/mesh2sdf.sh makes the batch page alone,
# NARROW=0 ORIENT= DENSE= BATCH= bench/mesh2sdf.sh the samples page alone.
# Grids go to $BUILD/bench-mesh2sdf/.
set -euo pipefail
export LC_ALL=C # bash's EPOCHREALTIME and awk: a decimal point, not a comma
cd "$(dirname "$0")/.."
root=$PWD
. bench/page.sh
# The command that made the page, with the settings given in the environment.
command="bench/mesh2sdf.sh${1:+ $*}"
for var in POINT_ROWS BATCH_COPIES BATCH NARROW ORIENT DENSE REPEAT THREADS SAMPLES MESHES BUILD; do
    [ -z "${!var+set}" ] || command="$var=\"${!var}\" $command"
done
BUILD=${BUILD:-build}
MESH_DIR=${MESH_DIR:-tests/data/meshes}
MESHES=${MESHES:-"stanford-bunny spot teapot suzanne fandisk"}
SAMPLES=${SAMPLES:-10000}
THREADS=${THREADS:-0}
DENSE=${DENSE-"128 256"}
ORIENT=${ORIENT-128}
NARROW=${NARROW:-1}
BATCH=${BATCH-256}
BATCH_COPIES=${BATCH_COPIES:-4}
POINT_ROWS=${POINT_ROWS-250000}
REPEAT=${REPEAT:-3}
[[ $REPEAT =~ ^[1-9][0-9]*$ ]] || { echo "bench/mesh2sdf.sh: REPEAT must be a positive integer" >&2; exit 1; }
RESOLUTIONS=("$@")
[ ${#RESOLUTIONS[@]} -gt 0 ] || RESOLUTIONS=(256 512 1024)
M2S=$BUILD/mesh2sdf
POINTS=$BUILD/bench/mesh2sdf_points
OUT=$BUILD/bench-mesh2sdf
[ -x "$M2S" ] || { echo "bench/mesh2sdf.sh: build $M2S first (cmake --build $BUILD --target mesh2sdf)" >&2; exit 1; }
[ -z "$DENSE$POINT_ROWS" ] || [ -x "$POINTS" ] || { echo "bench/mesh2sdf.sh: build $POINTS first (cmake --build $BUILD --target mesh2sdf_points)" >&2; exit 1; }
{ [ "$NARROW" = 0 ] && [ -z "$ORIENT" ]; } || command -v vdb_tool >/dev/null || { echo "bench/mesh2sdf.sh: vdb_tool not found (libopenvdb-tools)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench/mesh2sdf.sh: /usr/bin/time not found (package time)" >&2; exit 1; }
mkdir -p "$OUT"

# Runs a command under GNU time; prints "seconds peak_MiB"; its stdout goes
# to $OUT/stdout.log.
measure() {
    local log=$OUT/time.log start end
    start=$EPOCHREALTIME
    /usr/bin/time -v -o "$log" "$@" >"$OUT/stdout.log" 2>"$OUT/stderr.log" || {
        echo "bench/mesh2sdf.sh: failed: $*" >&2; cat "$OUT/stderr.log" >&2; exit 1; }
    end=$EPOCHREALTIME
    # Wall time from bash's microsecond clock (GNU time's is in hundredths).
    awk -F': ' -v s="$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" \
        '/Maximum resident set size/ { m = $2 / 1024 } END { printf "%.3f %.0f\n", s, m }' "$log"
}

# Longest side of an OBJ's bounding box.
longest_side() {
    awk '$1 == "v" { for (k = 2; k <= 4; k++) { if (!(k in lo) || $k < lo[k]) lo[k] = $k; if (!(k in hi) || $k > hi[k]) hi[k] = $k } }
         END { m = 0; for (k = 2; k <= 4; k++) if (hi[k] - lo[k] > m) m = hi[k] - lo[k]; printf "%.9g\n", m }' "$1"
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", (b > 0 ? a / b : 0) }'; }

# Runs a command as measure does (or as $MEASURE names), in this shell (so
# that a failure stops the bench), and prints the faster of its "seconds
# peak_MiB ..." and $1's.
faster() {
    local best=$1
    shift
    ${MEASURE:-measure} "$@" >"$OUT/measure.txt"
    awk -v b="$best" '{ split(b, y, " "); print (b == "" || $1 + 0 <= y[1] + 0) ? $0 : b }' "$OUT/measure.txt"
}

# The narrow-band table.
narrow_table() {
echo "Narrow band (3 voxels), against vdb_tool -mesh2ls:"
echo
echo "| mesh | N | vdb_tool s | MiB | wrong sign | winding s | MiB | wrong sign | × vdb_tool | flood s | MiB | wrong sign | × vdb_tool |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for name in $MESHES; do
    mesh=$MESH_DIR/$name.obj
    side=$(longest_side "$mesh")
    declare -A T=() M=()
    grids=()
    for n in "${RESOLUTIONS[@]}"; do
        h=$(awk -v s="$side" -v n="$n" 'BEGIN { printf "%.9g", s / n }')
        vdb="" wind="" flood=""
        for ((r = 0; r < REPEAT; r++)); do
            faster "$vdb" vdb_tool -read "$mesh" -mesh2ls voxel="$h" width=3 -write "$OUT/$name-$n-vdbtool.vdb" >"$OUT/best.txt"
            vdb=$(<"$OUT/best.txt")
            faster "$wind" "$M2S" "$mesh" -o "$OUT/$name-$n-winding.vdb" --voxel-size "$h" --sign winding --threads "$THREADS" --quiet >"$OUT/best.txt"
            wind=$(<"$OUT/best.txt")
            faster "$flood" "$M2S" "$mesh" -o "$OUT/$name-$n-flood.vdb" --voxel-size "$h" --sign flood --threads "$THREADS" --quiet >"$OUT/best.txt"
            flood=$(<"$OUT/best.txt")
        done
        read -r "T[vdb$n]" "M[vdb$n]" <<<"$vdb"
        read -r "T[wind$n]" "M[wind$n]" <<<"$wind"
        read -r "T[flood$n]" "M[flood$n]" <<<"$flood"
        grids+=(--check-sign "$OUT/$name-$n-vdbtool.vdb" --check-sign "$OUT/$name-$n-winding.vdb" --check-sign "$OUT/$name-$n-flood.vdb")
    done
    declare -A W=()
    while read -r grid _ _ frac _; do
        W[$grid]=${frac#wrong_fraction=}
    done < <("$M2S" "$mesh" "${grids[@]}" --check-points "$SAMPLES")
    for n in "${RESOLUTIONS[@]}"; do
        echo "| $name | $n | ${T[vdb$n]} | ${M[vdb$n]} | ${W[$OUT/$name-$n-vdbtool.vdb]} | ${T[wind$n]} | ${M[wind$n]} | ${W[$OUT/$name-$n-winding.vdb]} | $(ratio "${T[wind$n]}" "${T[vdb$n]}") | ${T[flood$n]} | ${M[flood$n]} | ${W[$OUT/$name-$n-flood.vdb]} | $(ratio "${T[flood$n]}" "${T[vdb$n]}") |"
    done
    unset T M W
done
echo
}

# The orientation table: each mesh as it is, inside out, with half its
# faces reversed and as a soup of unwelded triangles (bench/mesh_variant.awk),
# converted by vdb_tool and by mesh2sdf at the same voxel size, each judged
# against the ORIGINAL mesh's brute-force winding number (--check-sign): the
# share of clear points with the wrong sign, and how many of them lie 3 or
# more voxels from the surface. "× as is" is mesh2sdf's time over its time
# on the mesh as it is; "× none" its time over --orient none on the same
# file (what orienting costs).
orient_table() {
local n=$ORIENT
echo "Orientation ($n voxels along the longest side), against vdb_tool -mesh2ls, judged by the original mesh:"
echo
echo "| mesh | faces | vdb_tool s | wrong sign | 3+ voxels off | mesh2sdf s | wrong sign | 3+ voxels off | × as is | × none |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for name in $MESHES; do
    mesh=$MESH_DIR/$name.obj
    side=$(longest_side "$mesh")
    h=$(awk -v s="$side" -v n="$n" 'BEGIN { printf "%.9g", s / n }')
    declare -A T=() W=() F=()
    grids=()
    for kind in as-is inside-out reversed soup; do
        file=$OUT/$name-$kind.obj
        if [ $kind = as-is ]; then cp "$mesh" "$file"; else awk -v kind=$kind -v share=0.5 -v seed=1 -f bench/mesh_variant.awk "$mesh" >"$file"; fi
        vdb="" wind="" none=""
        for ((r = 0; r < REPEAT; r++)); do
            faster "$vdb" vdb_tool -read "$file" -mesh2ls voxel="$h" width=3 -write "$OUT/$name-$kind-vdbtool.vdb" >"$OUT/best.txt"
            vdb=$(<"$OUT/best.txt")
            faster "$wind" "$M2S" "$file" -o "$OUT/$name-$kind-winding.vdb" --voxel-size "$h" --threads "$THREADS" --quiet >"$OUT/best.txt"
            wind=$(<"$OUT/best.txt")
            faster "$none" "$M2S" "$file" -o "$OUT/$name-$kind-none.vdb" --voxel-size "$h" --orient none --threads "$THREADS" --quiet >"$OUT/best.txt"
            none=$(<"$OUT/best.txt")
        done
        T[vdb$kind]=${vdb%% *} T[wind$kind]=${wind%% *} T[none$kind]=${none%% *}
        grids+=(--check-sign "$OUT/$name-$kind-vdbtool.vdb" --check-sign "$OUT/$name-$kind-winding.vdb")
    done
    while read -r grid _ _ frac far _; do
        W[$grid]=${frac#wrong_fraction=} F[$grid]=${far#wrong_far=}
    done < <("$M2S" "$mesh" "${grids[@]}" --check-points "$SAMPLES")
    faces=$(grep -c '^f ' "$mesh")
    for kind in as-is inside-out reversed soup; do
        v=$OUT/$name-$kind-vdbtool.vdb m=$OUT/$name-$kind-winding.vdb
        echo "| $name $kind | $faces | ${T[vdb$kind]} | ${W[$v]} | ${F[$v]} | ${T[wind$kind]} | ${W[$m]} | ${F[$m]} | $(ratio "${T[wind$kind]}" "${T[windas-is]}") | $(ratio "${T[wind$kind]}" "${T[none$kind]}") |"
    done
    unset T W F
done
echo
}
dense_table() {
echo "Dense (--full), against the per-point query on the same voxels:"
echo
echo "| mesh | N | box | mesh2sdf --full s | MiB | per-point s | × faster | largest difference, voxels | sign disagreements |"
echo "|---|---|---|---|---|---|---|---|---|"
for name in $MESHES; do
    mesh=$MESH_DIR/$name.obj
    side=$(longest_side "$mesh")
    for n in $DENSE; do
        h=$(awk -v s="$side" -v n="$n" 'BEGIN { printf "%.9g", s / n }')
        npy=$OUT/$name-$n-full.npy
        full=""
        for ((r = 0; r < REPEAT; r++)); do
            faster "$full" "$M2S" "$mesh" -o "$OUT/$name-$n-full.vdb" --npy "$npy" --voxel-size "$h" --full --threads "$THREADS" --quiet >"$OUT/best.txt"
            full=$(<"$OUT/best.txt")
        done
        read -r t m <<<"$full"
        box=$(awk -F'[][]' '/"shape"/ { gsub(/, /, "x", $2); print $2 }' "${npy%.npy}.json")
        line=$("$POINTS" "$mesh" "$npy" "$THREADS")
        p=$(sed -n 's/.*seconds=\([^ ]*\).*/\1/p' <<<"$line")
        e=$(sed -n 's/.*max_error_voxels=\([^ ]*\).*/\1/p' <<<"$line")
        d=$(sed -n 's/.*sign_disagreements=\([^ ]*\) clear=\([^ ]*\).*/\1 of \2/p' <<<"$line")
        echo "| $name | $n | $box | $t | $m | $p | $(ratio "$p" "$t") | $e | $d |"
    done
done
echo
}

# The training samples' table: rates, end to end, the per-point query.
samples_table() {
local big=$OUT/spot-x16.obj rows=$POINT_ROWS name mesh npy r1 r2 wall line p e d big_rate=0 big_wall=""
awk -f bench/mesh_subdivide.awk "$MESH_DIR/spot.obj" | awk -f bench/mesh_subdivide.awk >"$big"
echo "| mesh | faces | samples/s, 1 thread | samples/s, 2 threads | $rows samples end to end, s | per-point query, s | × faster | largest difference | sign disagreements |"
echo "|---|---|---|---|---|---|---|---|---|"
for name in $MESHES spot-x16; do
    mesh=$MESH_DIR/$name.obj
    [ "$name" != spot-x16 ] || mesh=$big
    npy=$OUT/$name-samples.npy
    r1=0 r2=0 wall=""
    for ((r = 0; r < REPEAT; r++)); do
        r1=$(rate "$r1" "$M2S" "$mesh" --samples "$rows" "$npy" --threads 1 --json)
        wall=$(faster "$wall" "$M2S" "$mesh" --samples "$rows" "$npy" --threads 2 --json)
        r2=$(rate "$r2" cat "$OUT/stdout.log")
    done
    line=$("$POINTS" "$mesh" --samples "$npy" 2)
    p=$(sed -n 's/.*seconds=\([^ ]*\).*/\1/p' <<<"$line")
    e=$(sed -n 's/.*max_error=\([^ ]*\).*/\1/p' <<<"$line")
    d=$(sed -n 's/.*sign_disagreements=\([^ ]*\) clear=\([^ ]*\).*/\1 of \2/p' <<<"$line")
    echo "| $name | $(faces "$mesh") | $r1 | $r2 | ${wall%% *} | $p | $(ratio "$p" "${wall%% *}") | $e | $d |"
    [ "$name" != spot-x16 ] || { big_rate=$r2; big_wall=${wall%% *}; }
done
echo
echo "Targets, on the $(faces "$big")-face mesh with 2 threads: at least 500,000 samples/s for the sampling:" \
    "$(awk -v r="$big_rate" 'BEGIN { print (r >= 500000 ? "met" : "missed") }') ($big_rate);" \
    "$rows samples end to end in at most 1 s:" \
    "$(awk -v s="$big_wall" 'BEGIN { print (s <= 1 ? "met" : "missed") }') ($big_wall s)."
echo
}

# The larger of $1 and the samples_per_second of the --json line a command prints.
rate() {
    local best=$1
    shift
    "$@" >"$OUT/rate.txt"
    sed -n 's/.*"samples_per_second": \([0-9]*\).*/\1/p' "$OUT/rate.txt" |
        awk -v b="$best" '{ print ($1 + 0 > b + 0) ? $1 : b }'
}

# The faces of an OBJ, after fanning its polygons.
faces() { awk '$1 == "f" { n += NF - 3 } END { print n }' "$1"; }

samples_page() {
page_header "mesh2sdf --samples: training samples against per-point queries" "$command"
cat <<EOF
**Training samples.** \`mesh2sdf MESH --samples $POINT_ROWS OUT.npy\` on the meshes of \`$MESH_DIR\` and on
spot split twice into four (\`bench/mesh_subdivide.awk\`). *samples/s* is the sampling's own rate
(\`--json\`'s \`samples_per_second\`: drawing the points, their exact distances and winding-number
signs; not reading, orienting or indexing the mesh), the best of $REPEAT runs. *end to end* is the
whole run's wall time with 2 threads (reading, orienting, indexing, sampling, writing the \`.npy\`
and its \`.json\`), the fastest of $REPEAT. *per-point query* is \`bench/mesh2sdf_points.cpp\` on the
same points with 2 threads (nearest triangle through a bounding volume hierarchy from its root and
the fast winding number, per point; its queries' own time, one run); *× faster* its time over
mesh2sdf's whole run. *largest difference* is between its distances and the samples' (mesh
units), *sign disagreements* where its winding number is clearly inside or outside.

EOF
samples_table
}

page() {
page_header "mesh2sdf against OpenVDB's vdb_tool and per-point queries" "$command"
cat <<EOF
Every time is wall-clock, the fastest of $REPEAT runs, the tools of a row run in turns; the ratios
are side by side. Peak memory is GNU time's maximum resident set of that run.

**Narrow band.** The meshes of \`$MESH_DIR\` converted by \`vdb_tool -mesh2ls\`, \`mesh2sdf --sign
winding\` and \`mesh2sdf --sign flood\`, with the same voxel size (the mesh's longest side / N) and
a 3-voxel band. *wrong sign* is the fraction of $SAMPLES uniform sample points that a brute-force
winding number calls clearly inside (> 0.75) or outside (< 0.25) and the grid gets wrong
(\`mesh2sdf --check-sign\`). *× vdb_tool* is the time over vdb_tool's.

**Orientation.** Each mesh as it is, inside out, with half its faces reversed and as a soup of
unwelded triangles (\`bench/mesh_variant.awk\`), converted by \`vdb_tool -mesh2ls\` and by mesh2sdf
at $ORIENT voxels along the longest side, each judged against the ORIGINAL mesh's brute-force
winding number: *wrong sign* as above, *3+ voxels off* how many of the wrong points lie 3 or more
voxels from the surface. *× as is* is mesh2sdf's time over its time on the mesh as it is (the soup's
file is about 3 times the size to read); *× none* its time over \`--orient none\` on the same file.

**Dense grids.** \`mesh2sdf --full --npy\` (its whole run: loading, band, signs, dense pass,
writing the \`.vdb\` and \`.npy\`) against the per-point signed distance query that libigl-style
tools pay at every voxel (\`bench/mesh2sdf_points.cpp\`: nearest triangle through a bounding volume
hierarchy searched from its root, and the fast winding number, nothing shared between points; its
own time, one run, on the voxels of mesh2sdf's \`.npy\`); how far the two grids differ.

EOF
[ "$NARROW" = 0 ] || narrow_table
[ -z "$ORIENT" ] || orient_table
[ -z "$DENSE" ] || dense_table
}

# The batch page: one row per way of running the batch.
# measure, and after its "seconds peak_MiB" the CPU seconds (user and
# system, the children's included): on a shared machine a process waits for
# a core, and the CPU time shows the work apart from the wait.
measure_cpu() {
    local m
    m=$(measure "$@")
    awk -F': ' -v m="$m" '/User time|System time/ { c += $2 } END { printf "%s %.2f\n", m, c }' "$OUT/time.log"
}
# The two shards at once, as one command for measure; fails if either does.
shards_at_once='"$0" "$@" --shard 0/2 & a=$!; "$0" "$@" --shard 1/2 & b=$!; s=0; wait $a || s=1; wait $b || s=1; exit $s'
batch_page() {
local cores half list=$OUT/batch-list.txt count=0 mpi=() args=(--res "$BATCH" --quiet) MEASURE=measure_cpu
cores=$(nproc)
half=$((cores > 1 ? cores / 2 : 1))
: >"$list"
for ((c = 0; c < BATCH_COPIES; c++)); do
    for mesh in "$MESH_DIR"/*.obj; do readlink -f "$mesh" >>"$list"; count=$((count + 1)); done
done
[ "$(id -u)" != 0 ] || mpi=(--allow-run-as-root)
page_header "mesh2sdf --batch: meshes per minute" "$command"
cat <<EOF
The $((count / BATCH_COPIES)) meshes of \`$MESH_DIR\`, each listed $BATCH_COPIES times ($count conversions, each into files
of its own), converted by \`mesh2sdf --batch\` at $BATCH voxels along the longest side, each run
into a fresh folder: the wall time of the whole run (processes started, every mesh read,
converted and written, the report written), the fastest of $REPEAT, and meshes per minute, and
that run's CPU time (user and system, every process of it). One
process has all $cores cores; the two shards (\`--shard 0/2\` and \`1/2\` at once, into one
folder) and the two ranks of \`mpirun -np 2\` have $half each (\`--threads $half\`). The shards
split LIST before they start (positions 0, 2, 4 ... and 1, 3, 5 ...); the ranks take the next
mesh, largest file first, as each is free. Open MPI binds each of 2 ranks to a core of its own;
the row with \`--bind-to none\` leaves them free to move, as the shards are.
On a machine other work shares, wall time also counts the waits for a core: the CPU time is the
work itself.

| run | processes | threads each | s | meshes per minute | × one process | CPU s |
|---|--:|--:|--:|--:|--:|--:|
EOF
local one="" shards="" ranks="" free=""
for ((r = 0; r < REPEAT; r++)); do
    rm -rf "$OUT"/batch-[12m]*/
    one=$(faster "$one" "$M2S" --batch "$list" --out-dir "$OUT/batch-1" "${args[@]}" --threads "$cores")
    shards=$(faster "$shards" bash -c "$shards_at_once" "$M2S" --batch "$list" --out-dir "$OUT/batch-2" "${args[@]}" --threads "$half")
    if command -v mpirun >/dev/null; then
        ranks=$(faster "$ranks" mpirun -np 2 --oversubscribe "${mpi[@]}" "$M2S" --batch "$list" --out-dir "$OUT/batch-mpi" "${args[@]}" --threads "$half")
        free=$(faster "$free" mpirun -np 2 --oversubscribe --bind-to none "${mpi[@]}" "$M2S" --batch "$list" --out-dir "$OUT/batch-mpi-free" "${args[@]}" --threads "$half")
    fi
done
local t1=${one%% *} name procs threads best t
for row in "one process|1|$cores|$one" "two shards at once|2|$half|$shards" "mpirun -np 2|2|$half|$ranks" "mpirun -np 2 --bind-to none|2|$half|$free"; do
    IFS='|' read -r name procs threads best <<<"$row"
    if [ -z "$best" ]; then
        echo "| $name | $procs | $threads | (no mpirun) | | | |"
        continue
    fi
    read -r t _ cpu <<<"$best"
    echo "| $name | $procs | $threads | $t | $(awk -v n="$count" -v t="$t" 'BEGIN { printf "%.1f", 60 * n / t }') | $(ratio "$t1" "$t") | $cpu |"
done
echo
}

{ [ "$NARROW" = 0 ] && [ -z "$ORIENT$DENSE" ]; } || page_write mesh2sdf.md page
[ -z "$POINT_ROWS" ] || page_write mesh2sdf-samples.md samples_page
[ -z "$BATCH" ] || page_write mesh2sdf-batch.md batch_page
