#!/bin/sh
# sdftrace's grid benchmark, side by side in one run; writes
# bench/results/grids.md (and prints it):
#  1. the grids: temple and figure baked at RES^3 (sdftrace bake, time and
#     peak memory), spot and fandisk made by OpenVDB's `vdb_tool -mesh2ls
#     d=RES w=3` (level sets nobody here made), the bunny by mesh2sdf;
#  2. each traced at WIDTHxHEIGHT, 2 threads, primary rays only, from its
#     scene's camera (temple, figure) or the front framing (the others):
#     OpenVDB's vdb_render (its own timer, best of REPEAT), then in one
#     process NanoVDB's HDDA caster with and without sub-voxel refinement
#     and sdftrace's rows (bench/hdda_caster: warm frames, best of REPEAT);
#     beside them one call of each from the .vdb, a new process (vdb_render,
#     sdftrace render --no-shadows), its wall, best of REPEAT;
#     the targets, row by row: sdftrace's default render (--no-shadows)
#     within 1/5 of vdb_render's time and 1/1.5 of the plain caster's, its
#     depth within 1.5 voxels of vdb_render's on 99% of the pixels both hit;
#  3. the cost of one evaluation (bench/sample_bench) on spot, against the
#     target of 1.5x a dense array's;
#  4. with BIG set, each big grid end to end, one process per frame: vdb_render
#     and sdftrace render --grid (as it comes, without shadows like
#     vdb_render, and --fp16), wall time, peak memory and the share of leaves
#     read, against the targets (within 1.5x vdb_render's time; peak memory
#     within 1.25x the NanoVDB grid's bytes).
#
# usage: bench/grids.sh [RES [WIDTH HEIGHT]]        (default 1024 1280 720)
# env:   BUILD   the build folder (default build); OUT  where the grids go
#                (default /tmp/sdftrace-grids); KEEP=1 reuse OUT's grids;
#        REPEAT  frames per tracer, the best counts (default 3);
#        GRIDS   which grids (default "temple figure spot fandisk bunny");
#        ROWS=variants  every variant row instead of the targets' rows;
#        BIG     big .vdb files for part 4, separated by spaces; "make" has
#                mesh2sdf --res 4096 write OUT/spot4096.vdb and
#                "make-vdb_tool" has vdb_tool -mesh2ls d=4096 w=3 write
#                OUT/fandisk4096.vdb (minutes each, 7 GiB peak for
#                vdb_tool); unset: no part 4;
#        PAGE_DIR  where the page goes (default bench/results).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
build=${BUILD:-$root/build}
res=${1:-1024}
width=${2:-1280}
height=${3:-720}
bin=$build/sdftrace
caster=$build/bench/hdda_caster
sampler=$build/bench/sample_bench
meshes=$root/tests/data/meshes
for tool in "$bin" "$caster" "$sampler" "$build/mesh2sdf" /usr/bin/time vdb_render vdb_tool; do
    command -v "$tool" >/dev/null 2>&1 || { echo "grids.sh: missing $tool" >&2; exit 1; }
done
out=${OUT:-/tmp/sdftrace-grids}
mkdir -p "$out"
# The command that made the page, with the settings given in the environment.
command=$(page_command "bench/grids.sh${1:+ $*}" REPEAT GRIDS ROWS KEEP BIG)
repeat=${REPEAT:-3}
grids=${GRIDS:-temple figure spot fandisk bunny}
export REPEAT="$repeat" OMP_NUM_THREADS=2
log() { echo "grids.sh: $*" >&2; }

now_ms() { echo $(($(date +%s%N) / 1000000)); }
# call_view GRID VIEW: render's options for the view (a scene's camera, or
# the front framing render gives a grid without a scene).
call_view() { case $2 in front) ;; *) echo "--scene $2" ;; esac; }

# Wall seconds and peak MiB of the last /usr/bin/time -v log.
wall() { awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$1"; }
peak() { awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$1"; }

# 1. The grids.
make_grids() {
    echo "## The grids, ${res}³"
    echo
    echo "| grid | made by | wall s | peak MiB |"
    echo "|---|---|--:|--:|"
    for g in $grids; do
        file=$out/$g.vdb
        if [ "${KEEP:-0}" = 1 ] && [ -s "$file" ]; then
            echo "| $g | kept from an earlier run | - | - |"
            continue
        fi
        case $g in
        temple | figure) how="sdftrace bake"; set -- "$bin" bake --scene "$g" --res "$res" -o "$file" ;;
        spot | fandisk) how="vdb_tool -mesh2ls w=3"; set -- vdb_tool -read "$meshes/$g.obj" -mesh2ls d="$res" w=3 -write "$file" ;;
        bunny) how="mesh2sdf"; set -- "$build/mesh2sdf" "$meshes/stanford-bunny.obj" -o "$file" --res "$res" --quiet ;;
        *) echo "grids.sh: unknown grid $g" >&2; exit 1 ;;
        esac
        log "making $file"
        /usr/bin/time -v "$@" >"$out/$g.make.log" 2>"$out/$g.time"
        echo "| $g | $how | $(wall "$out/$g.time") | $(peak "$out/$g.time") |"
    done
    echo
}

# 2. Each grid traced; the caster's table kept in OUT/GRID.trace.txt.
trace_grids() {
    : >"$out/summary"
    echo "## Each grid traced: ${width}x${height}, 2 threads, primary rays"
    echo
    echo "\`bench/hdda_caster\` renders warm frames in one process and keeps the best of $repeat for each"
    echo "row; \`vdb_render\` times its own frame (best of $repeat runs). \`sdftrace-render\` is the"
    echo "default \`render --no-shadows\` (normals and shading, the hull, the exact root);"
    echo "\`-papers\` counts the papers' way. Beside them, in turns with \`vdb_render\`'s runs, one"
    echo "\`sdftrace render --grid GRID.vdb --no-shadows\` call per run, a new process: its wall (best of $repeat)."
    for g in $grids; do
        case $g in temple | figure) view=$g ;; *) view=front ;; esac
        log "tracing $g.vdb (view: $view)"
        opts=$("$caster" --view "$out/$g.vdb" "$view" "$width" "$height")
        : >"$out/$g.vdb_render.log"
        : >"$out/$g.calls"
        i=0
        while [ "$i" -lt "$repeat" ]; do
            # One call each, in turns, from the .vdb: vdb_render's wall, then
            # sdftrace render's (the default --no-shadows render, a new process).
            start=$(now_ms)
            # shellcheck disable=SC2086 # $opts is a list of options
            vdb_render "$out/$g.vdb" "$out/${g}_vdb_render.exr" $opts -shader position -cpus 2 -v \
                >>"$out/$g.vdb_render.log" 2>&1
            vr_wall=$(($(now_ms) - start))
            start=$(now_ms)
            "$bin" render --grid "$out/$g.vdb" $(call_view "$g" "$view") -o "$out/${g}_call.exr" --threads 2 \
                --no-shadows --width "$width" --height "$height" --quiet
            echo "$vr_wall $(($(now_ms) - start))" >>"$out/$g.calls"
            i=$((i + 1))
        done
        # vdb_render -v prints "ray-tracing NAME..." then "...completed in S sec".
        vr_ms=$(awk '/ray-tracing/ { t = 1; next } t && /completed in/ { ms = $(NF - 1) * 1000; if (best == "" || ms < best) best = ms; t = 0 }
                     END { if (best != "") printf "%.1f", best }' "$out/$g.vdb_render.log")
        "$caster" "$out/$g.vdb" "$view" "$width" "$height" "$out/${g}_hdda.pfm" "$out/${g}_vdb_render.exr" \
            >"$out/$g.trace.txt"
        echo
        echo "### $g.vdb, view: $view"
        echo
        echo '```'
        cat "$out/$g.trace.txt"
        echo "openvdb-vdb_render: ${vr_ms} ms/frame (its own timer, best of $repeat)"
        echo '```'
        awk -v g="$g" -v vr="$vr_ms" '
            $1 == "nanovdb-hdda" { h = $2 } $1 == "nanovdb-hdda-refined" { hr = $2 }
            $1 == "sdftrace-render" { s = $2; agree = $(NF - 3); ev = $NF }
            $1 == "sdftrace-render-no-exact-root" { evn = $NF }
            $1 == "sdftrace-render-papers" { evp = $NF }
            END { printf "%s %s %s %s %s %s %s %s %s", g, vr, h, hr, s, agree, ev, evn, evp }' \
            "$out/$g.trace.txt" >>"$out/summary"
        # One call each, best of the runs: vdb_render's wall and sdftrace's.
        echo " $(sort -n "$out/$g.calls" | awk 'NR == 1 { print $1 }') $(sort -n -k2 "$out/$g.calls" | awk 'NR == 1 { print $2 }')" \
            >>"$out/summary"
    done
    echo
}

targets() {
    echo "## The targets: sdftrace render --no-shadows against vdb_render and the HDDA caster"
    echo
    echo "Targets: sdftrace within 1/5 of vdb_render's time (*x vdb_render* >= 5) and 1/1.5 of the plain"
    echo "caster's (*x HDDA* >= 1.5), its depth within 1.5 voxels of vdb_render's on 99% of the pixels"
    echo "both hit. *x vdb_render* is vdb_render's ms over sdftrace's, *x HDDA* the caster's over"
    echo "sdftrace's; *met* names the targets a row misses. The frames are warm frames in one process"
    echo "(sdftrace's and the caster's; vdb_render's own timer); the last columns are one call of each"
    echo "from the \`.vdb\`, a new process, its wall: reading the file, building, tracing, writing."
    echo
    echo "| grid | vdb_render ms | HDDA ms | HDDA + refinement ms | sdftrace ms | x vdb_render (>= 5) | x HDDA (>= 1.5) | depth within 1.5 voxels of vdb_render (>= 0.99) | evals/px: default, no exact root, papers | met | one call: vdb_render wall ms | one call: sdftrace wall ms | one call: x vdb_render |"
    echo "|---|---|---|---|---|---|---|---|---|---|--:|--:|--:|"
    awk '{
        xv = $2 / $5; xh = $3 / $5
        met = (xv >= 5 ? "" : "x vdb_render ") (xh >= 1.5 ? "" : "x HDDA ") ($6 >= 0.99 ? "" : "depth ")
        printf "| %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %.4f | %.2f, %.2f, %.2f | %s | %.0f | %.0f | %.2f |\n", $1, $2, $3, $4,
               $5, xv, xh, $6, $7, $8, $9, met == "" ? "all" : "missed: " met, $10, $11, $10 / $11
    }' "$out/summary"
    echo
}

# 3. The cost of one evaluation.
evaluation_cost() {
    echo "## The cost of one trilinear evaluation, spot at ${res}³, 1 thread"
    echo
    if [ ! -s "$out/spot.vdb" ]; then
        echo "(no spot.vdb in GRIDS)"
        echo
        return 0
    fi
    echo "Points along primary rays in ray order (*ray*), random points in the band (*band*) and the"
    echo "points a trace evaluates (*trace*), each set timed independent (*indep*, throughput) and"
    echo "chained (*chain*, each point waiting on the last: latency); last, the ratios to a dense float"
    echo "array. \`sdftrace-batch\` is the library's batch call, \`sdft_field_distances\`, which hints"
    echo "each point's memory 16 points ahead. The target: within 1.5x of the dense array on the ray and"
    echo "band sets."
    echo
    log "timing evaluations on spot.vdb"
    OMP_NUM_THREADS=1 "$sampler" "$out/spot.vdb" 1000000 >"$out/sample_bench.txt"
    echo '```'
    cat "$out/sample_bench.txt"
    # Per row, the columns that miss the target (the trace set has no dense row).
    awk '$1 ~ /^sdftrace-/ && NF == 13 {
        miss = ""
        split("ray-indep ray-chain band-indep band-chain", name, " ")
        for (i = 1; i <= 4; i++)
            if ($(7 + i) > 1.5)
                miss = miss " " name[i] " " $(7 + i) "x"
        printf "within 1.5x of the dense array, %s: %s\n", $1, miss == "" ? "met" : "missed:" miss
    }' "$out/sample_bench.txt"
    echo '```'
    echo
}

# 4. The big grids, each made here if asked: "make" is spot at 4096^3 by
# mesh2sdf, "make-vdb_tool" fandisk at 4096^3 by vdb_tool.
big_grids() {
    [ -n "${BIG:-}" ] || return 0
    echo "## Big grids end to end"
    echo
    echo "One process per frame, timed by \`/usr/bin/time -v\`: loading, conversion, the bounds and the"
    echo "render included. Every renderer runs $repeat times in turns; each row keeps its fastest run's"
    echo "wall time and that run's peak memory. Targets: within 1.5x vdb_render's time; peak memory"
    echo "within 1.25x the NanoVDB grid's bytes. *leaves read*: the share of the grid's leaves the frame's"
    echo "rays reached (a leaf is read from the file when a ray first reaches it)."
    echo
    bigs=
    for big in $BIG; do
        case $big in
        make)
            big=$out/spot4096.vdb
            if [ "${KEEP:-0}" != 1 ] || [ ! -s "$big" ]; then
                log "making $big (mesh2sdf --res 4096)"
                /usr/bin/time -v "$build/mesh2sdf" "$meshes/spot.obj" -o "$big" --res 4096 --quiet 2>"$out/big.make.time"
                echo "- \`mesh2sdf tests/data/meshes/spot.obj --res 4096\`: $(wall "$out/big.make.time") s, $(peak "$out/big.make.time") MiB"
            fi
            ;;
        make-vdb_tool)
            big=$out/fandisk4096.vdb
            if [ "${KEEP:-0}" != 1 ] || [ ! -s "$big" ]; then
                log "making $big (vdb_tool -mesh2ls d=4096 w=3)"
                /usr/bin/time -v vdb_tool -read "$meshes/fandisk.obj" -mesh2ls d=4096 w=3 -write "$big" \
                    >/dev/null 2>"$out/big.make.time"
                echo "- \`vdb_tool -read tests/data/meshes/fandisk.obj -mesh2ls d=4096 w=3\`: $(wall "$out/big.make.time") s, $(peak "$out/big.make.time") MiB"
            fi
            ;;
        esac
        bigs="$bigs $big"
    done
    for big in $bigs; do
        log "rendering $big end to end"
        echo
        echo "### $(basename "$big") ($(du -m "$big" | cut -f1) MiB), 2 threads, best of $repeat"
        echo
        opts=$("$caster" --view "$big" front "$width" "$height")
        echo "| renderer | wall s | peak MiB | NanoVDB MiB | x vdb_render's time (<= 1.5) | peak / NanoVDB (<= 1.25) | leaves read |"
        echo "|---|---|---|---|---|---|---|"
        # Every renderer REPEAT times, in turns (vdb_render, then each sdftrace
        # row), so that the machine's noise falls on all alike; each row keeps its
        # fastest run's wall time and that run's peak memory.
        rows="vdb_render sdftrace sdftrace--no-shadows sdftrace--fp16"
        rm -f "$out"/big.*.time
        i=0
        while [ "$i" -lt "$repeat" ]; do
            for row in $rows; do
                # shellcheck disable=SC2086 # $opts is a list of options
                case $row in
                    vdb_render) /usr/bin/time -v vdb_render "$big" "$out/big_vdb_render.exr" $opts -cpus 2 >/dev/null \
                        2>"$out/big.$row.$i.time" ;;
                    # The default render (a shadow ray per lit hit), the same
                    # without shadows (what vdb_render draws), and with Fp16
                    # leaves; each reads a leaf from the file when a ray first
                    # reaches it (deferred leaves, render's default).
                    *) /usr/bin/time -v "$bin" render --grid "$big" -o "$out/big.exr" --threads 2 --json --quiet \
                        ${row#sdftrace} >"$out/big.$row.json" 2>"$out/big.$row.$i.time" ;;
                esac
            done
            i=$((i + 1))
        done
        # The fastest run of a row: "wall peak".
        best() { for t in "$out/big.$1".*.time; do echo "$(wall "$t") $(peak "$t")"; done | sort -n | head -n 1; }
        # shellcheck disable=SC2046 # "wall peak": two words
        set -- $(best vdb_render)
        vw=$1
        printf '| vdb_render | %s | %s | - | - | - | - |\n' "$1" "$2"
        for row in sdftrace sdftrace--no-shadows sdftrace--fp16; do
            # shellcheck disable=SC2046 # "wall peak": two words
            set -- $(best "$row")
            json=$out/big.$row.json
            bytes=$(sed -n 's/.*"grid_bytes": \([0-9]*\).*/\1/p' "$json")
            leaves=$(sed -n 's/.*"grid_leaves": \([0-9]*\).*/\1/p' "$json")
            read=$(sed -n 's/.*"grid_leaves_read": \([0-9]*\).*/\1/p' "$json")
            awk -v w="$1" -v p="$2" -v vw="$vw" -v b="$bytes" -v q="${row#sdftrace}" -v l="$leaves" -v r="$read" 'BEGIN {
                printf "| sdftrace render %s | %s | %s | %.0f | %.2f | %.2f | %.1f%% |\n", q, w, p, b / 1048576, w / vw,
                       p / (b / 1048576), 100 * r / l }'
        done
    done
    echo
}

page() {
    page_header "Grids against OpenVDB's and NanoVDB's tracers" "$command"
    echo "Grids at ${res}³ traced at ${width}x${height}; OUT is \`$out\`, where each grid's raw output stays."
    echo
    make_grids
    trace_grids
    targets
    evaluation_cost
    big_grids
}

page_write grids.md page
