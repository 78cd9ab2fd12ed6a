#!/bin/sh
# sdftrace on a GPU, side by side in one Vulkan program per grid; writes
# bench/results/gpu.md (and prints it):
#  1. each bench grid (bench/grids.sh's: temple and figure baked, spot and
#     fandisk by vdb_tool -mesh2ls, the bunny by mesh2sdf, at RES^3) traced
#     from its scene's camera (temple, figure) or the front framing by
#     bench/gpu_bench: NanoVDB's own caster (PNanoVDB's GLSL HDDA) and
#     sdftrace's frame (sdft_gpu_render, auto-relaxed, the hull, the exact
#     root) on the same uploaded grid, depth only and shaded with the shadow
#     ray; the GPU's image against the CPU's (sdft_render) on the same grid;
#  2. the study's discrete Table rows (the six methods, the papers'
#     counting, hard shadows, 1000 steps) on the temple's and the figure's
#     grids, beside Bán and Valasek's RX 5700 figures (discrete 1024^3).
# Every time is the GPU's own (timestamps around the dispatch), the median
# of FRAMES frames after a warm-up and its 95% bootstrap interval
# (bench/stats.h), the rows of a grid in turns; a ratio is the median of
# the frames' ratios.
#
# usage: bench/gpu.sh [RES [WIDTH HEIGHT]]        (default 1024 1280 720)
# env:   BUILD   the build folder (default build); OUT  where the grids go
#                (default /tmp/sdftrace-grids, as grids.sh); KEEP=1 reuse
#                OUT's grids; FRAMES  timed frames per row (default 5);
#        GRIDS   which grids (default "temple figure spot fandisk bunny");
#        STUDY   the study's grids (default "temple figure"); FULL=1 adds
#                their --full grids (3.6 GiB at 1024^3);
#        DEVICE  the Vulkan device's index as vulkaninfo lists them
#                (default: the first GPU, else any);
#        PAGE_DIR  where the page goes (default bench/results).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
build=${BUILD:-$root/build}
res=${1:-1024}
width=${2:-1280}
height=${3:-720}
bin=$build/sdftrace
bench=$build/bench/gpu_bench
meshes=$root/tests/data/meshes
for tool in "$bin" "$bench" "$build/mesh2sdf" vdb_tool; do
    command -v "$tool" >/dev/null 2>&1 || { echo "gpu.sh: missing $tool (build with SDFT_WITH_VULKAN)" >&2; exit 1; }
done
out=${OUT:-/tmp/sdftrace-grids}
mkdir -p "$out"
command=$(page_command "bench/gpu.sh${1:+ $*}" FRAMES GRIDS STUDY FULL KEEP DEVICE)
frames=${FRAMES:-5}
grids=${GRIDS:-temple figure spot fandisk bunny}
study=${STUDY:-temple figure}
device=${DEVICE:--1}
log() { echo "gpu.sh: $*" >&2; }

# A grid as grids.sh makes it, unless KEEP=1 finds it: NAME FILE [--full].
make_grid() {
    if [ "${KEEP:-0}" = 1 ] && [ -s "$2" ]; then
        return 0
    fi
    log "making $2"
    case $1 in
    temple | figure) "$bin" bake --scene "$1" --res "$res" -o "$2" --quiet ${3:-} ;;
    spot | fandisk) vdb_tool -read "$meshes/$1.obj" -mesh2ls d="$res" w=3 -write "$2" >/dev/null ;;
    bunny) "$build/mesh2sdf" "$meshes/stanford-bunny.obj" -o "$2" --res "$res" --quiet ;;
    *) echo "gpu.sh: unknown grid $1" >&2; return 1 ;;
    esac
}

view_of() { case $1 in temple | figure) echo "$1" ;; *) echo front ;; esac; }

run_bench() { # GRID VIEW LABEL ROWS
    "$bench" "$1" "$2" --label "$3" --rows "$4" --device "$device" --width "$width" --height "$height" \
        --frames "$frames" 2>>"$out/gpu_bench.log"
}

page() {
    for g in $grids; do
        make_grid "$g" "$out/$g.vdb"
    done
    for s in $study; do
        make_grid "$s" "$out/$s.vdb"
        [ "${FULL:-0}" != 1 ] || make_grid "$s" "$out/${s}_full.vdb" --full
    done
    : >"$out/gpu_bench.log"
    peer=$(for g in $grids; do
        log "tracing $g.vdb"
        run_bench "$out/$g.vdb" "$(view_of "$g")" "$g" peer
    done)
    table=$(for s in $study; do
        for rep in band full; do
            file=$out/$s.vdb
            if [ $rep = full ]; then
                [ "${FULL:-0}" = 1 ] || continue
                file=$out/${s}_full.vdb
            fi
            log "the study's rows on $(basename "$file")"
            run_bench "$file" "$s" "$s $rep" study
        done
    done)
    device_name=$(sed -n 's/^gpu_bench: .* on \(.*\), [0-9]*x[0-9]*$/\1/p' "$out/gpu_bench.log" | head -n 1)

    page_header "sdftrace on the GPU" "$command"
    echo "- device: $device_name"
    echo "- grids: ${res}³, images ${width}x${height}; times: the median of $frames frames after a warm-up"
    echo "  [its 95% bootstrap interval], the GPU's own timestamps around the frame's dispatch"
    echo
    case $device_name in
    llvmpipe* | *lavapipe* | *SwiftShader*)
        echo "**No GPU was lent to this run.** The device is a CPU's: Mesa's lavapipe runs the Vulkan"
        echo "compute shaders on this machine's cores (LLVM-compiled, 8 lanes a core). Its milliseconds"
        echo "compare the shaders with each other on one device; they say nothing of a GPU's speed, and"
        echo "the targets below are for a GPU. The same command on a machine with one (\`DEVICE=N\` picks"
        echo "it) writes this page with its numbers."
        echo
        ;;
    esac
    echo "## sdftrace's frame beside NanoVDB's HDDA, one program, one device"
    echo
    echo "*HDDA*: PNanoVDB's GLSL \`pnanovdb_hdda_zero_crossing\` (\`bench/hdda.comp\`), primary rays, the"
    echo "voxel where the sign changes. *ours, depth*: \`sdft_gpu_render\` with \`depth_only\` (auto-relaxed"
    echo "β 0.3, the hull, the exact last cell), the same work; *ours, shaded*: the default frame, normal,"
    echo "shading and a hard shadow ray per lit hit. Then the shaded frame's agreement with the CPU's"
    echo "(\`sdft_render\`, the same parameters and grid): the share of pixels whose hit masks differ (at"
    echo "silhouettes, where the GPU's rounding sends a grazing ray the other way) and the largest depth"
    echo "difference where both hit, in voxels. Target on a GPU: *ours/HDDA* <= 1."
    echo
    echo "| grid | HDDA ms | ours, depth ms | ours/HDDA | ours, shaded ms | depth within 1.5 voxels of HDDA's % | hit masks differ from the CPU's % | largest depth difference from the CPU's, voxels |"
    echo "|---|--:|--:|--:|--:|--:|--:|--:|"
    echo "$peer"
    echo
    echo "$peer" | awk -F'|' 'NF > 4 { n++; if ($5 + 0 <= 1.0) met++ }
        END { printf "ours/HDDA <= 1 on %d of %d grids.\n\n", met, n }'
    echo "## The study's discrete Table rows in GPU milliseconds"
    echo
    echo "The six methods of Bán and Valasek's table (\`bench/study\`'s Table rows): the papers' counting"
    echo "(\`--papers\`: every ray from the eye, every step to ε = 1e-4), a hard shadow ray per lit hit,"
    echo "1000 steps, the scene's camera and light; *rel* is the time over enhanced sphere tracing's"
    echo "(ω = 0.88), the median of the frames' ratios. *paper*: their RX 5700's frame on the discrete"
    echo "1024³ Temple and Girl (a dense 3D texture), and its rel. Target on a GPU: the Temple's AR 0.2"
    echo "row under 1 ms."
    echo
    echo "| grid | method | ms | rel | evaluations/px | paper ms | paper rel |"
    echo "|---|---|--:|--:|--:|--:|--:|"
    echo "$table" | awk -F' [|] ' '
        BEGIN {
            split("ST ENH REL_1.2 REL_1.5 AR_0.3 AR_0.2", m, " ")
            split("8.50 7.60 7.21 6.46 6.19 5.99", t, " "); split("112 100 95 85 81 79", tr, " ")
            split("5.54 5.43 5.18 4.93 4.71 4.72", f, " "); split("102 100 95 91 87 87", fr, " ")
            for (i = 1; i <= 6; i++) {
                k = m[i]; gsub("_", " ", k)
                ms["temple", k] = t[i]; rel["temple", k] = tr[i] "%"
                ms["figure", k] = f[i]; rel["figure", k] = fr[i] "%"
            }
        }
        NF > 3 {
            split($1, g, " "); scene = g[2]; sub(/^[|] */, "", scene)
            row = $0; sub(/ [|]$/, "", row)
            p = ms[g[2], $2]
            printf "%s | %s | %s |\n", row, p == "" ? "-" : p, p == "" ? "-" : rel[g[2], $2]
        }'
    echo
    echo "$table" | awk -F' [|] ' '$1 ~ /temple/ && $2 == "AR 0.2" { g = $1; sub(/^[|] */, "", g)
        printf "The Temple'"'"'s AR 0.2 row (%s grid): %s ms, %s the 1 ms target.\n", g, $3, $3 + 0 < 1 ? "under" : "over" }'
}

page_write gpu.md page
