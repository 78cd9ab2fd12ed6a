#!/bin/sh
# How one call's time scales with threads, phase by phase, beside the peers;
# writes bench/results/scaling.md (and prints it).
#
# For THREADS = 1, 2, ... nproc, each section runs its tools in turns,
# REPEAT rounds, and keeps the median of each number:
#  render   level sets made by OpenVDB's `vdb_tool -mesh2ls d=RES w=3` from
#           meshes (GRIDS), as `.vdb` and as `.nvdb` (NanoVDB's own
#           nanovdb_convert: no stored tables), each rendered at
#           WIDTHxHEIGHT without shadows from the front framing by
#             sdftrace render, one call: its wall (the process, timed
#               here) and its phases (--json: the read, the acceleration
#               structures, the first frame, the output), and with
#               --repeat 4 the warm frame;
#             OpenVDB's vdb_render: its read, its trace (its own timers,
#               leaves read as rays reach them), its wall;
#             NanoVDB's HDDA caster as one call (bench/hdda_caster
#               --single: one fread of the .nvdb, one frame), its wall.
# A section NAME is two functions: NAME_section runs its tools, REPEAT
# rounds (in $round) of every thread count, and appends rows to $rows with
# `row`, one number each:
#   SECTION <tab> SUBJECT <tab> TOOL <tab> THREADS <tab> ROUND <tab> METRIC <tab> MS
# NAME_page prints its part of the page from the rows alone: `table NAME`
# (a table per subject, a row per tool and metric, a column per thread
# count: the median and its 95% interval, bench/page.sh's page_stats; and
# the serial fraction the 1-thread and the most-thread medians imply,
# Karp-Flatt's estimate of Amdahl's: e = (1/S - 1/p) / (1 - 1/p), S the
# speed-up on p threads; 0 for work that halves with two threads, 1 for
# work that does not move), then its targets, as ratios of numbers of one
# round (`pairs`, `stat_text --ratio`). A section for mesh2sdf (read,
# orient, index, sweep or samples, write; vdb_tool beside) goes in the same
# way: mesh2sdf_section, mesh2sdf_page, and SECTIONS="render mesh2sdf".
#
# usage: bench/scaling.sh [RES [WIDTH HEIGHT]]        (default 1024 1280 720)
# env:   BUILD    the build folder (default build); OUT where the grids go
#                 (default /tmp/sdftrace-scaling); KEEP=1 reuses OUT's grids;
#        THREADS  thread counts (default "1 2 ... nproc", powers of two and
#                 nproc); REPEAT rounds (default 5); GRIDS meshes under
#                 tests/data/meshes (default "spot fandisk"); SECTIONS
#                 (default "render");
#        PAGE_DIR where the page goes (default bench/results).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
. "$root/bench/scaling_rows.sh"
build=${BUILD:-$root/build}
res=${1:-1024}
width=${2:-1280}
height=${3:-720}
bin=$build/sdftrace
caster=$build/bench/hdda_caster
meshes=$root/tests/data/meshes
for tool in "$bin" "$caster" vdb_render vdb_tool nanovdb_convert; do
    command -v "$tool" >/dev/null 2>&1 || { echo "scaling.sh: missing $tool" >&2; exit 1; }
done
out=${OUT:-/tmp/sdftrace-scaling}
mkdir -p "$out"
[ -n "${THREADS:-}" ] || THREADS=$(thread_counts)
repeat=${REPEAT:-5}
grids=${GRIDS:-spot fandisk}
sections=${SECTIONS:-render}
command=$(page_command "bench/scaling.sh${1:+ $*}" THREADS REPEAT GRIDS SECTIONS KEEP)
rows=$out/rows.tsv
: >"$rows"
log() { echo "scaling.sh: $*" >&2; }
page_need_stats
round=0


# ---- render ---------------------------------------------------------------

render_grids() {
    for g in $grids; do
        if [ "${KEEP:-0}" = 1 ] && [ -s "$out/$g.vdb" ] && [ -s "$out/$g.nvdb" ]; then
            continue
        fi
        log "making $g.vdb (vdb_tool -mesh2ls d=$res w=3) and $g.nvdb (nanovdb_convert)"
        vdb_tool -read "$meshes/$g.obj" -mesh2ls d="$res" w=3 -write "$out/$g.vdb" >/dev/null
        rm -f "$out/$g.nvdb"
        nanovdb_convert "$out/$g.vdb" "$out/$g.nvdb" >/dev/null
    done
}

# One round of render's rows for grid $1 at $2 threads.
render_round() {
    g=$1
    t=$2
    for kind in vdb nvdb; do
        file=$out/$g.$kind
        subject="$g.$kind"
        j=$out/call.json
        start=$(now_ms)
        OMP_NUM_THREADS=$t "$bin" render --grid "$file" -o "$out/call.exr" --threads "$t" --no-shadows \
            --width "$width" --height "$height" --json --quiet >"$j"
        wall=$(($(now_ms) - start))
        row render "$subject" sdftrace "$t" "wall" "$wall"
        # Before main: the process's start, its libraries loaded.
        row render "$subject" sdftrace "$t" "start" "$(awk -v w="$wall" -v m="$(json "$j" wall_ms)" 'BEGIN { print w - m }')"
        for m in read serial directory tables far_bound hull first_frame write; do
            row render "$subject" sdftrace "$t" "$m" "$(json "$j" "${m}_ms")"
        done
        OMP_NUM_THREADS=$t "$bin" render --grid "$file" -o "$out/call.exr" --threads "$t" --no-shadows \
            --width "$width" --height "$height" --json --quiet --repeat 4 >"$j"
        row render "$subject" sdftrace "$t" "warm_frame" "$(json "$j" warm_frame_ms)"
    done
    subject="$g.vdb"
    log=$out/vdb_render.log
    start=$(now_ms)
    # shellcheck disable=SC2046 # the view's options, one word each
    vdb_render "$out/$g.vdb" "$out/vdb_render.exr" $(cat "$out/$g.view") -shader position -cpus "$t" -v >"$log" 2>&1
    wall=$(($(now_ms) - start))
    row render "$subject" vdb_render "$t" wall "$wall"
    # vdb_render -v: "reading ..." then "...completed in S sec", "ray-tracing ..." then the same.
    row render "$subject" vdb_render "$t" read \
        "$(awk '/reading/ { r = 1; next } r && /completed in/ { print $(NF - 1) * 1000; exit }' "$log")"
    row render "$subject" vdb_render "$t" trace \
        "$(awk '/ray-tracing/ { r = 1; next } r && /completed in/ { print $(NF - 1) * 1000; exit }' "$log")"
    subject="$g.nvdb"
    j=$out/hdda.json
    start=$(now_ms)
    OMP_NUM_THREADS=$t "$caster" --single "$out/$g.nvdb" front "$width" "$height" >"$j"
    wall=$(($(now_ms) - start))
    row render "$subject" hdda "$t" wall "$wall"
    row render "$subject" hdda "$t" read "$(json "$j" read_ms)"
    row render "$subject" hdda "$t" frame "$(json "$j" frame_ms)"
}

render_section() {
    render_grids
    for g in $grids; do
        "$caster" --view "$out/$g.vdb" front "$width" "$height" >"$out/$g.view"
    done
    round=0
    while [ "$round" -lt "$repeat" ]; do
        for t in $THREADS; do
            for g in $grids; do
                log "render: round $((round + 1)) of $repeat, $g, $t threads"
                render_round "$g" "$t"
            done
        done
        round=$((round + 1))
    done
}

render_page() {
    echo "## render: one call, phase by phase"
    echo
    echo "Level sets made by \`vdb_tool -mesh2ls d=$res w=3\` from tests/data/meshes ($grids), as \`.vdb\` and as"
    echo "\`.nvdb\` (NanoVDB's \`nanovdb_convert\`: no stored tables, so sdftrace builds them), rendered at"
    echo "${width}x${height} without shadows from the front framing, in ms. sdftrace's rows are one \`render\` call's phases (\`--json\`): *start*, the"
    echo "process's start before main (its wall less its own); *read*, the grid into memory (a \`.vdb\`: a"
    echo "reader process converts it into shared memory, which this one maps); *serial*, the part of *read*"
    echo "on one thread before the first parallel phase; then the leaf directory, the stored tables found"
    echo "and checked, the far bound and the hull built, the first frame, the output written; *warm_frame*"
    echo "is the best later frame of a \`--repeat 4\` call. vdb_render's *read* and *trace* are its own"
    echo "timers (it reads a leaf when a ray first reaches it); the HDDA caster reads the \`.nvdb\` with one"
    echo "\`fread\` and traces one frame. *wall*: the whole process, timed by the script. The last column is"
    echo "the serial fraction that 1 and $max_threads threads imply (Karp-Flatt; - for a number near 0)."
    echo "A cell is the median [95% interval] of the rounds."
    echo
    table render
    render_targets
}

# ---- the page --------------------------------------------------------------


# The goals, at the most threads: one call's first frame >= 5x vdb_render's
# trace and >= 1.5x the caster's frame; the wall <= 0.5x vdb_render's, from
# .vdb and .nvdb; serial work before the first parallel phase (the
# process's start and the read's serial part) <= 5% of a 1-thread call;
# the first frame <= 1.2x a warm one.
render_targets() {
    echo "### render: the targets, at $max_threads threads"
    echo
    echo "Each cell is the median of the ratios of one round (the tools in turns) and its 95% interval;"
    echo "*met* says whether the median meets the goal."
    echo
    echo "| call | first frame ms | vdb_render's trace / first frame (>= 5) | HDDA's frame / first frame (>= 1.5) | wall / vdb_render's wall (<= 0.5) | serial before the first parallel phase / 1-thread wall (<= 0.05) | first frame / warm frame (<= 1.2) | met |"
    echo "|---|---|---|---|---|---|---|---|"
    for g in $grids; do
        for kind in vdb nvdb; do
            s="$g.$kind"
            first=$(samples render "$s" sdftrace "$max_threads" first_frame | stat_text 1)
            xv=$(pairs render "$max_threads" "$g.vdb" vdb_render trace "$s" sdftrace first_frame | stat_text 2 --ratio)
            xh=$(pairs render "$max_threads" "$g.nvdb" hdda frame "$s" sdftrace first_frame | stat_text 2 --ratio)
            xw=$(pairs render "$max_threads" "$s" sdftrace wall "$g.vdb" vdb_render wall | stat_text 2 --ratio)
            serial=$(awk -F'\t' -v s="$s" '$1 == "render" && $2 == s && $3 == "sdftrace" && $4 == 1 {
                         if ($6 == "start" || $6 == "serial") a[$5] += $7; if ($6 == "wall") w[$5] = $7 }
                         END { for (r in a) if (r in w) print a[r], w[r] }' "$rows" | stat_text 3 --ratio)
            fw=$(pairs render "$max_threads" "$s" sdftrace first_frame "$s" sdftrace warm_frame | stat_text 2 --ratio)
            miss=
            [ "$(met "$xv" ">=" 5)" = yes ] || miss="$miss trace/vdb_render"
            [ "$(met "$xh" ">=" 1.5)" = yes ] || miss="$miss trace/HDDA"
            [ "$(met "$xw" "<=" 0.5)" = yes ] || miss="$miss wall"
            [ "$(met "$serial" "<=" 0.05)" = yes ] || miss="$miss serial"
            [ "$(met "$fw" "<=" 1.2)" = yes ] || miss="$miss first-frame"
            echo "| $s | $first | $xv | $xh | $xw | $serial | $fw | ${miss:+missed:}${miss:-all} |"
        done
    done
    echo
    render_wall_parts
}

# Why the wall and serial goals are missed: where one call's wall goes at
# the most threads, its phases by their medians, largest first, beside
# vdb_render's wall; and the serial part of a 1-thread call.
render_wall_parts() {
    echo "Where one call's wall goes, medians in ms, the largest phases first: at $max_threads threads beside"
    echo "vdb_render's wall (the goal is half of it), and at 1 thread the serial part (the process's start"
    echo "and the read's serial part, against 5% of the wall)."
    echo
    for g in $grids; do
        vr=$(samples render "$g.vdb" vdb_render "$max_threads" wall | median)
        for kind in vdb nvdb; do
            s="$g.$kind"
            parts=$(for m in start read directory tables far_bound hull first_frame write; do
                printf '%s %s\n' "$m" "$(samples render "$s" sdftrace "$max_threads" "$m" | median)"
            done | largest_first)
            wall=$(samples render "$s" sdftrace "$max_threads" wall | median)
            wall1=$(samples render "$s" sdftrace 1 wall | median)
            start1=$(samples render "$s" sdftrace 1 start | median)
            serial1=$(samples render "$s" sdftrace 1 serial | median)
            awk -v s="$s" -v w="$wall" -v v="$vr" -v p="$parts" -v w1="$wall1" -v a="$start1" -v b="$serial1" 'BEGIN {
                printf "- %s: wall %.0f against vdb_render'"'"'s %.0f (goal %.0f): %s. At 1 thread: start %.0f + serial read %.0f = %.1f%% of %.0f.\n",
                    s, w, v, v / 2, p, a, b, 100 * (a + b) / w1, w1 }'
        done
    done
    echo
}

max_threads=$(echo "$THREADS" | awk '{ print $NF }')
for s in $sections; do
    "${s}_section"
done

page() {
    page_header "How one call scales with threads" "$command"
    echo "Threads: $THREADS; $repeat rounds, the tools in turns. OUT is \`$out\`, where the grids and"
    echo "\`rows.tsv\` (every number) stay."
    echo
    for s in $sections; do
        "${s}_page"
    done
}

page_write scaling.md page
