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
# A section is a function that appends rows to $rows, one number each:
#   SECTION <tab> SUBJECT <tab> TOOL <tab> THREADS <tab> METRIC <tab> MS
# and the page is made from the rows alone: a table per subject, a row per
# tool and metric, a column per thread count (medians), and the serial
# fraction the 1-thread and the most-thread times imply (Karp-Flatt's
# estimate of Amdahl's: e = (1/S - 1/p) / (1 - 1/p), S the speed-up on p
# threads; 0 for work that halves with two threads, 1 for work that does
# not move); then each section's targets. A section for mesh2sdf (read,
# orient, index, sweep or samples, write; vdb_tool beside) goes in the same
# way: a function, its name in SECTIONS, its targets.
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
cores=$(nproc)
if [ -z "${THREADS:-}" ]; then
    THREADS=1
    t=2
    while [ "$t" -lt "$cores" ]; do THREADS="$THREADS $t" && t=$((t * 2)); done
    [ "$cores" = 1 ] || THREADS="$THREADS $cores"
fi
repeat=${REPEAT:-5}
grids=${GRIDS:-spot fandisk}
sections=${SECTIONS:-render}
command="bench/scaling.sh${1:+ $*}"
for var in THREADS REPEAT GRIDS SECTIONS KEEP; do
    eval "val=\${$var:-}"
    [ -z "$val" ] || command="$var=\"$val\" $command"
done
rows=$out/rows.tsv
: >"$rows"
log() { echo "scaling.sh: $*" >&2; }
load_at_start=$(cut -d' ' -f1-3 /proc/loadavg)

now_ms() { echo $(($(date +%s%N) / 1000000)); }
# json FILE KEY: the number KEY has in the JSON object of FILE.
json() { sed -n "s/.*\"$2\": \([-0-9.e]*\).*/\1/p" "$1"; }
# row SECTION SUBJECT TOOL THREADS METRIC VALUE
row() { [ -z "$6" ] || printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$@" >>"$rows"; }

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
    i=0
    while [ "$i" -lt "$repeat" ]; do
        for t in $THREADS; do
            for g in $grids; do
                log "render: round $((i + 1)) of $repeat, $g, $t threads"
                render_round "$g" "$t"
            done
        done
        i=$((i + 1))
    done
}

render_page() {
    echo "## render: one call, phase by phase"
    echo
    echo "Level sets made by \`vdb_tool -mesh2ls d=$res w=3\` from tests/data/meshes ($grids), as \`.vdb\` and as"
    echo "\`.nvdb\` (NanoVDB's \`nanovdb_convert\`: no stored tables, so sdftrace builds them), rendered at"
    echo "${width}x${height} without shadows from the front framing. Each number is the median of $repeat rounds,"
    echo "the tools in turns, in ms. sdftrace's rows are one \`render\` call's phases (\`--json\`): *start*, the"
    echo "process's start before main (its wall less its own); *read*, the grid into memory (a \`.vdb\`: a"
    echo "reader process converts it into shared memory, which this one maps); *serial*, the part of *read*"
    echo "on one thread before the first parallel phase; then the leaf directory, the stored tables found"
    echo "and checked, the far bound and the hull built, the first frame, the output written; *warm_frame*"
    echo "is the best later frame of a \`--repeat 4\` call. vdb_render's *read* and *trace* are its own"
    echo "timers (it reads a leaf when a ray first reaches it); the HDDA caster reads the \`.nvdb\` with one"
    echo "\`fread\` and traces one frame. *wall*: the whole process, timed by the script. The last column is"
    echo "the serial fraction that 1 and $max_threads threads imply (Karp-Flatt; - for a number that is 0)."
    echo
    table render
    render_targets
}

# The goals, at the most threads: one call's frame >= 5x vdb_render's trace
# and >= 1.5x the caster's frame; the wall <= 0.5x vdb_render's, from .vdb and
# .nvdb; serial work before the first parallel phase <= 5% of a 1-thread
# call (its start, and the read's serial part); the first frame <= 1.2x a
# warm one.
render_targets() {
    echo "### render: the targets, at $max_threads threads"
    echo
    echo "| grid | first frame ms | x vdb_render's trace (>= 5) | x HDDA's frame (>= 1.5) | wall ms | x vdb_render's wall (<= 0.5) | serial before the first parallel phase, of a 1-thread call (<= 5%) | first frame / warm (<= 1.2) | met |"
    echo "|---|---|---|---|---|---|---|---|---|"
    awk -F'\t' -v top="$max_threads" '
        $1 != "render" { next }
        { key = $2 SUBSEP $3 SUBSEP $4 SUBSEP $5; v[key] = v[key] " " $6 }
        function median(s,    a, n, i, j, t) {
            n = split(s, a, " ")
            for (i = 2; i <= n; i++) for (j = i; j > 1 && a[j - 1] + 0 > a[j] + 0; j--) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
            return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
        }
        function m(s, tool, t, metric) { return median(v[s SUBSEP tool SUBSEP t SUBSEP metric]) }
        END {
            for (key in v) { split(key, k, SUBSEP); if (k[2] == "sdftrace") subj[k[1]] = 1 }
            n = 0; for (s in subj) list[++n] = s
            for (i = 2; i <= n; i++) for (j = i; j > 1 && list[j - 1] > list[j]; j--) { t = list[j]; list[j] = list[j - 1]; list[j - 1] = t }
            for (i = 1; i <= n; i++) {
                s = list[i]; g = s; sub(/\.n?vdb$/, "", g)
                first = m(s, "sdftrace", top, "first_frame"); warm = m(s, "sdftrace", top, "warm_frame")
                wall = m(s, "sdftrace", top, "wall")
                vtrace = m(g ".vdb", "vdb_render", top, "trace"); vwall = m(g ".vdb", "vdb_render", top, "wall")
                hframe = m(g ".nvdb", "hdda", top, "frame")
                serial = (m(s, "sdftrace", 1, "start") + m(s, "sdftrace", 1, "serial")) / m(s, "sdftrace", 1, "wall")
                xv = vtrace / first; xh = hframe / first; xw = wall / vwall; fw = first / warm
                miss = (xv >= 5 ? "" : "trace-x-vdb_render ") (xh >= 1.5 ? "" : "trace-x-HDDA ") (xw <= 0.5 ? "" : "wall ") \
                       (serial <= 0.05 ? "" : "serial ") (fw <= 1.2 ? "" : "first-frame")
                printf "| %s | %.1f | %.2f | %.2f | %.0f | %.2f | %.1f%% | %.2f | %s |\n", s, first, xv, xh, wall, xw, 100 * serial, fw,
                       miss == "" ? "all" : "missed: " miss
            }
        }' "$rows"
    echo
}

# ---- the page --------------------------------------------------------------

# table SECTION: per subject, the medians of each tool's metrics by threads,
# and Karp-Flatt's serial fraction between 1 and the most threads.
table() {
    awk -F'\t' -v section="$1" -v threads="$THREADS" '
        $1 != section { next }
        { key = $2 SUBSEP $3 SUBSEP $5; v[key SUBSEP $4] = v[key SUBSEP $4] " " $6; seen[key] = 1; subj[$2] = 1 }
        function median(s,    a, n, i, j, t) {
            n = split(s, a, " ")
            if (n == 0) return ""
            for (i = 2; i <= n; i++) for (j = i; j > 1 && a[j - 1] + 0 > a[j] + 0; j--) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
            return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
        }
        END {
            nt = split(threads, T, " ")
            ns = 0; for (s in subj) S[++ns] = s
            for (i = 2; i <= ns; i++) for (j = i; j > 1 && S[j - 1] > S[j]; j--) { t = S[j]; S[j] = S[j - 1]; S[j - 1] = t }
            for (i = 1; i <= ns; i++) {
                printf "### %s\n\n| tool | ms", S[i]
                for (k = 1; k <= nt; k++) printf " | %s thr", T[k]
                printf " | serial fraction |\n|---|---"
                for (k = 1; k <= nt; k++) printf "|--:"
                printf "|--:|\n"
                nk = 0
                for (key in seen) { split(key, p, SUBSEP); if (p[1] == S[i]) K[++nk] = p[2] SUBSEP p[3] }
                for (a = 2; a <= nk; a++) for (b = a; b > 1 && K[b - 1] > K[b]; b--) { t = K[b]; K[b] = K[b - 1]; K[b - 1] = t }
                for (a = 1; a <= nk; a++) {
                    split(K[a], p, SUBSEP)
                    printf "| %s | %s", p[1], p[2]
                    for (k = 1; k <= nt; k++) {
                        md = median(v[S[i] SUBSEP K[a] SUBSEP T[k]])
                        printf " | %s", md == "" ? "-" : sprintf("%.1f", md)
                        if (k == 1) one = md
                        if (k == nt) most = md
                    }
                    if (nt > 1 && one + 0 > 0 && most + 0 > 0) {
                        sp = one / most; pth = T[nt]
                        printf " | %.2f |\n", (1 / sp - 1 / pth) / (1 - 1 / pth)
                    } else {
                        printf " | - |\n"
                    }
                    delete K[a]
                }
                print ""
            }
        }' "$rows"
}

max_threads=$(echo "$THREADS" | awk '{ print $NF }')
for s in $sections; do
    "${s}_section"
done
load_at_end=$(cut -d' ' -f1-3 /proc/loadavg)

page() {
    page_header "How one call scales with threads" "$command"
    echo "Threads: $THREADS; $repeat rounds, the tools in turns; load average (1, 5, 15 min) $load_at_start at the"
    echo "start, $load_at_end at the end. OUT is \`$out\`, where the grids and \`rows.tsv\` (every number) stay."
    echo
    for s in $sections; do
        "${s}_page"
    done
}

page_write scaling.md page
