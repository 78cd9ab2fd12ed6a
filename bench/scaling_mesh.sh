#!/bin/sh
# How one mesh2sdf call scales with threads, phase by phase, beside
# OpenVDB's vdb_tool; writes bench/results/scaling-mesh.md (and prints it).
#
# For THREADS = 1, 2, ... nproc, REPEAT rounds, the calls of a round in
# turns, each call restricted to that many cores (taskset) and, for
# mesh2sdf, as many threads (--threads); the median of each number is kept:
#   band     mesh2sdf MESH --voxel-size H (the mesh's longest side / RES,
#            its default winding sign, a 3-voxel band), beside
#            vdb_tool -read MESH -mesh2ls voxel=H width=3 -write;
#   full     mesh2sdf MESH --full --voxel-size H (longest side / FULL_RES);
#   samples  mesh2sdf MESH --samples ROWS.
# mesh2sdf's phases are its --json's: *start* (the process's start before
# its clock: its wall less its own), *read* (the file parsed, the
# triangles checked, the vertices welded), *orient*, *index* (the
# hierarchies built before the first distance or sample), *sweep* (the
# band, its signs, the tiles' signs and with full the dense pass) or
# *samples*, *write*; *wall* is the whole process, timed here. vdb_tool
# has no phases of its own to report: its wall. MESHES are meshes under
# tests/data/meshes, and spot-x16: spot split twice into four
# (bench/mesh_subdivide.awk, 93,696 faces).
#
# The rows, one number each (the format bench/scaling.sh's sections share):
#   SECTION <tab> SUBJECT <tab> TOOL <tab> THREADS <tab> ROUND <tab> METRIC <tab> MS
# and the page: per subject, a row per tool and metric, a column per
# thread count (the median [95% interval] of the rounds, bench/page.sh's
# page_stats) and the serial fraction that 1 and the most threads imply
# (Karp-Flatt's estimate of Amdahl's: e = (1/S - 1/p) / (1 - 1/p), S the
# speed-up on p threads); then the targets: band conversion at most 0.4x
# vdb_tool's wall, and the serial work of the intake (the process's start,
# the read's serial part by Karp-Flatt, orienting) at most 5% of a 1-thread
# call, for each mode.
#
# usage: bench/scaling_mesh.sh
# env:   BUILD (default build); OUT (default /tmp/sdftrace-scaling-mesh);
#        THREADS (default "1 2 4 ... nproc"); REPEAT rounds (default 5);
#        MESHES (default "spot-x16 stanford-bunny"); RES (default 1024);
#        FULL_RES (default 256); ROWS (default 250000); MODES (default
#        "band full samples"); PAGE_DIR (default bench/results).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
. "$root/bench/scaling_rows.sh"
build=${BUILD:-$root/build}
m2s=$build/mesh2sdf
for tool in "$m2s" vdb_tool taskset; do
    command -v "$tool" >/dev/null 2>&1 || { echo "scaling_mesh.sh: missing $tool" >&2; exit 1; }
done
out=${OUT:-/tmp/sdftrace-scaling-mesh}
mkdir -p "$out"
[ -n "${THREADS:-}" ] || THREADS=$(thread_counts)
repeat=${REPEAT:-5}
meshes=${MESHES:-spot-x16 stanford-bunny}
res=${RES:-1024}
full_res=${FULL_RES:-256}
sample_rows=${ROWS:-250000}
modes=${MODES:-band full samples}
command=$(page_command "bench/scaling_mesh.sh" THREADS REPEAT MESHES RES FULL_RES ROWS MODES)
rows=$out/rows.tsv
: >"$rows"
log() { echo "scaling_mesh.sh: $*" >&2; }
page_need_stats
round=0
max_threads=$(echo "$THREADS" | awk '{ print $NF }')

# ms SECONDS: in milliseconds.
ms() { awk -v s="$1" 'BEGIN { printf "%.1f", s * 1000 }'; }

# ---- mesh2sdf ---------------------------------------------------------------

# The mesh file of a name.
mesh_file() {
    if [ "$1" = spot-x16 ]; then
        [ -s "$out/spot-x16.obj" ] || awk -f "$root/bench/mesh_subdivide.awk" "$root/tests/data/meshes/spot.obj" |
            awk -f "$root/bench/mesh_subdivide.awk" >"$out/spot-x16.obj"
        echo "$out/spot-x16.obj"
    else
        echo "$root/tests/data/meshes/$1.obj"
    fi
}

# The mesh's longest side / N.
voxel_of() {
    awk -v n="$2" '$1 == "v" { for (k = 2; k <= 4; k++) { if (!(k in lo) || $k < lo[k]) lo[k] = $k; if (!(k in hi) || $k > hi[k]) hi[k] = $k } }
         END { m = 0; for (k = 2; k <= 4; k++) if (hi[k] - lo[k] > m) m = hi[k] - lo[k]; printf "%.9g\n", m / n }' "$1"
}

# mesh2sdf_call SUBJECT THREADS SWEEP-KEY ARGS...: one call's rows.
mesh2sdf_call() {
    subject=$1
    t=$2
    sweep=$3
    shift 3
    j=$out/call.json
    start=$(now_ms)
    taskset -c "0-$((t - 1))" "$m2s" "$@" --threads "$t" --json --quiet >"$j"
    wall=$(($(now_ms) - start))
    row mesh2sdf "$subject" mesh2sdf "$t" wall "$wall"
    row mesh2sdf "$subject" mesh2sdf "$t" start "$(awk -v w="$wall" -v s="$(json "$j" seconds)" 'BEGIN { printf "%.1f", w - s * 1000 }')"
    for m in read orient index "$sweep" write; do
        row mesh2sdf "$subject" mesh2sdf "$t" "$m" "$(ms "$(json "$j" "${m}_seconds")")"
    done
}

mesh2sdf_round() {
    name=$1
    t=$2
    mesh=$(mesh_file "$name")
    for mode in $modes; do
        case $mode in
        band)
            h=$(voxel_of "$mesh" "$res")
            mesh2sdf_call "$name band" "$t" sweep "$mesh" -o "$out/band.vdb" --voxel-size "$h"
            start=$(now_ms)
            taskset -c "0-$((t - 1))" vdb_tool -read "$mesh" -mesh2ls voxel="$h" width=3 -write "$out/vdb_tool.vdb" >/dev/null
            row mesh2sdf "$name band" vdb_tool "$t" wall "$(($(now_ms) - start))"
            ;;
        full)
            h=$(voxel_of "$mesh" "$full_res")
            mesh2sdf_call "$name full" "$t" sweep "$mesh" -o "$out/full.vdb" --voxel-size "$h" --full
            ;;
        samples)
            mesh2sdf_call "$name samples" "$t" samples "$mesh" --samples "$sample_rows" "$out/samples.npy"
            ;;
        esac
    done
}

mesh2sdf_section() {
    round=0
    while [ "$round" -lt "$repeat" ]; do
        for t in $THREADS; do
            for name in $meshes; do
                log "mesh2sdf: round $((round + 1)) of $repeat, $name, $t threads"
                mesh2sdf_round "$name" "$t"
            done
        done
        round=$((round + 1))
    done
}

mesh2sdf_page() {
    echo "## mesh2sdf: one call, phase by phase"
    echo
    echo "Meshes: $meshes (spot-x16 is spot split twice into four, 93,696 faces). *band*: \`mesh2sdf\` at the"
    echo "voxel size of the mesh's longest side / $res (winding sign, 3-voxel band) and \`vdb_tool -mesh2ls\` at"
    echo "the same voxel size; *full*: \`mesh2sdf --full\` at the longest side / $full_res; *samples*:"
    echo "\`mesh2sdf --samples $sample_rows\`. Each call is held to its thread count's cores (\`taskset\`),"
    echo "mesh2sdf to as many threads (\`--threads\`). mesh2sdf's rows are its \`--json\` phases in ms:"
    echo "*start*, the process's start before its clock (its wall less its own); *read*, the file parsed,"
    echo "the triangles checked and the vertices welded; *orient*; *index*, the hierarchies built before"
    echo "the first distance or sample; *sweep*, the band, its signs and with full the dense pass, or"
    echo "*samples*; *write*, the files. *wall* is the whole process, timed by the script; vdb_tool reports"
    echo "no phases. The last column is the serial fraction that 1 and $max_threads threads imply"
    echo "(Karp-Flatt; - for a number near 0). A cell is the median [95% interval] of the rounds."
    echo
    table mesh2sdf
    mesh2sdf_targets
}

# The goals: band conversion <= 0.4x vdb_tool's wall at the most threads;
# the intake's serial work (start, the read's serial part by Karp-Flatt,
# orient) <= 5% of a 1-thread call's wall, for each mode.
mesh2sdf_targets() {
    echo "### mesh2sdf: the targets"
    echo
    echo "*wall / vdb_tool's* is the median of the ratios of one round (the tools in turns) at $max_threads"
    echo "threads and its 95% interval. *serial intake / wall* is, at 1 thread, the process's start, the"
    echo "read's serial part (its 1-thread time times its serial fraction between 1 and $max_threads threads,"
    echo "Karp-Flatt, clamped to [0, 1]) and orienting (one thread), over the call's wall: the serial"
    echo "work before the parallel phases. *met* says whether the medians meet the goals."
    echo
    echo "| call | wall / vdb_tool's (<= 0.4) | serial intake / 1-thread wall (<= 0.05) | whole call's serial fraction | met |"
    echo "|---|---|---|---|---|"
    for s in $(awk -F'\t' '$1 == "mesh2sdf" { print $2 }' "$rows" | sort -u | tr ' ' '~'); do
        s=$(echo "$s" | tr '~' ' ')
        xv=-
        if [ "${s##* }" = band ]; then
            xv=$(pairs mesh2sdf "$max_threads" "$s" mesh2sdf wall "$s" vdb_tool wall | stat_text 2 --ratio)
        fi
        r1=$(samples mesh2sdf "$s" mesh2sdf 1 read | median)
        rp=$(samples mesh2sdf "$s" mesh2sdf "$max_threads" read | median)
        intake=$(awk -F'\t' -v s="$s" -v r1="${r1:-0}" -v rp="${rp:-0}" -v p="$max_threads" '
                     BEGIN { f = (p > 1 && r1 > 0) ? (rp / r1 - 1 / p) / (1 - 1 / p) : 1; f = f < 0 ? 0 : f > 1 ? 1 : f }
                     $1 == "mesh2sdf" && $2 == s && $3 == "mesh2sdf" && $4 == 1 {
                         if ($6 == "start" || $6 == "orient") a[$5] += $7; if ($6 == "read") a[$5] += f * $7
                         if ($6 == "wall") w[$5] = $7 }
                     END { for (r in a) if (r in w) print a[r], w[r] }' "$rows" | stat_text 3 --ratio)
        one=$(samples mesh2sdf "$s" mesh2sdf 1 wall | median)
        most=$(samples mesh2sdf "$s" mesh2sdf "$max_threads" wall | median)
        whole=$(awk -v a="${one:-0}" -v b="${most:-0}" -v p="$max_threads" 'BEGIN {
                    if (p > 1 && a > 0) printf "%.2f", (b / a - 1 / p) / (1 - 1 / p); else print "-" }')
        miss=
        [ "$xv" = - ] || [ "$(met "$xv" "<=" 0.4)" = yes ] || miss="$miss vdb_tool"
        [ "$(met "$intake" "<=" 0.05)" = yes ] || miss="$miss serial"
        echo "| $s | $xv | $intake | $whole | ${miss:+missed:}${miss:-all} |"
    done
    echo
    mesh2sdf_wall_parts
}

# Why: each call's serial intake at 1 thread, part by part, and where its
# wall goes at the most threads (medians, ms, largest first), beside
# vdb_tool's wall for the band.
mesh2sdf_wall_parts() {
    echo "Where the time goes, medians in ms: at 1 thread the serial intake part by part against 5% of"
    echo "the wall, and at $max_threads threads the process's start, then the phases, largest first (beside"
    echo "vdb_tool's wall and the goal, 0.4 of it, for the band)."
    echo
    for s in $(awk -F'\t' '$1 == "mesh2sdf" { print $2 }' "$rows" | sort -u | tr ' ' '~'); do
        s=$(echo "$s" | tr '~' ' ')
        med() { samples mesh2sdf "$s" mesh2sdf "$1" "$2" | median; }
        r1=$(med 1 read) rp=$(med "$max_threads" read)
        parts=$(for m in $(awk -F'\t' -v s="$s" '$1 == "mesh2sdf" && $2 == s && $3 == "mesh2sdf" { print $6 }' "$rows" |
                    sort -u | grep -v -e '^wall$' -e '^start$'); do
                printf '%s %s\n' "$m" "$(med "$max_threads" "$m")"
            done | largest_first)
        vt=-
        [ "${s##* }" != band ] || vt=$(samples mesh2sdf "$s" vdb_tool "$max_threads" wall | median)
        awk -v s="$s" -v w1="$(med 1 wall)" -v a="$(med 1 start)" -v r1="${r1:-0}" -v rp="${rp:-0}" \
            -v o="$(med 1 orient)" -v p="$max_threads" -v w="$(med "$max_threads" wall)" -v st="$(med "$max_threads" start)" \
            -v parts="$parts" -v vt="$vt" 'BEGIN {
            f = (p > 1 && r1 > 0) ? (rp / r1 - 1 / p) / (1 - 1 / p) : 1; f = f < 0 ? 0 : f > 1 ? 1 : f
            printf "- %s: at 1 thread start %.0f + serial read %.0f + orient %.0f = %.1f%% of %.0f; at %d threads wall %.0f",
                s, a, f * r1, o, 100 * (a + f * r1 + o) / w1, w1, p, w
            if (vt != "-") printf " against vdb_tool'"'"'s %.0f (goal %.0f)", vt, 0.4 * vt
            printf ": start %.0f, %s.\n", st, parts }'
    done
    echo
}


mesh2sdf_section

page() {
    page_header "How one mesh2sdf call scales with threads" "$command"
    echo "Threads: $THREADS; $repeat rounds, the calls in turns. OUT is \`$out\`, where \`rows.tsv\` (every"
    echo "number) stays."
    echo
    mesh2sdf_page
}

page_write scaling-mesh.md page
