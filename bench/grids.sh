#!/bin/sh
# sdftrace's grid benchmark (issue 3):
#  1. bake temple and figure at RES^3 (default 1024) with a 3-voxel narrow
#     band: wall time and peak memory from /usr/bin/time -v;
#  2. trace each .vdb at WIDTHxHEIGHT from its scene's camera three ways:
#     OpenVDB's vdb_render (its own timer, -v, -shader position), then in
#     one process NanoVDB's own HDDA level-set caster and sdftrace's four
#     variants (bench/hdda_caster: full renders and depth alone, constant
#     eps and screen-space criterion, with the far bound, the tree bound
#     alone and no bound), each depth map compared with the caster's and
#     vdb_render's.
#
# usage: bench/grids.sh [RES [WIDTH HEIGHT]]        (default 1024 1280 720)
# env:   BUILD  the build folder holding sdftrace and bench/hdda_caster
#               (default build); OUT  where the grids go (default a temp dir);
#        KEEP=1 reuse OUT's SCENE.vdb from an earlier run instead of baking;
#        REPEAT frames per tracer, the best counts (default 3);
#        BOUNDS=1 only the far-bound rows (2: and the tree bound's; default 3, all)
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$root/build}
res=${1:-1024}
width=${2:-1280}
height=${3:-720}
bin=$build/sdftrace
caster=$build/bench/hdda_caster
for tool in "$bin" "$caster" /usr/bin/time vdb_render; do
    command -v "$tool" >/dev/null 2>&1 || { echo "grids.sh: missing $tool" >&2; exit 1; }
done
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"

echo "== bake at ${res}^3, narrow band 3 voxels ($(nproc) cores)"
printf '%-8s %10s %12s  %s\n' scene wall_s peak_MiB summary
for scene in temple figure; do
    if [ "${KEEP:-0}" = 1 ] && [ -s "$out/$scene.vdb" ]; then
        printf '%-8s %10s %12s  %s\n' "$scene" - - "kept $out/$scene.vdb"
        continue
    fi
    /usr/bin/time -v "$bin" bake --scene "$scene" --res "$res" -o "$out/$scene.vdb" >"$out/$scene.bake" 2>"$out/$scene.time"
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$out/$scene.time")
    rss=$(awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$out/$scene.time")
    printf '%-8s %10s %12s  %s\n' "$scene" "$wall" "$rss" "$(cat "$out/$scene.bake")"
done

for scene in temple figure; do
    echo
    echo "== $scene.vdb traced at ${width}x${height} from the scene's camera"
    # OpenVDB's vdb_render first (its own timer, -v; the best of REPEAT
    # runs, as for the others; positions to compare depth with), then the
    # caster and sdftrace in one process.
    view=$("$caster" --view "$scene" "$width" "$height")
    : >"$out/$scene.vdb_render.log"
    i=0
    while [ "$i" -lt "${REPEAT:-3}" ]; do
        # shellcheck disable=SC2086 # $view is a list of options
        vdb_render "$out/$scene.vdb" "$out/${scene}_vdb_render.exr" $view -shader position -v >>"$out/$scene.vdb_render.log" 2>&1
        i=$((i + 1))
    done
    # vdb_render -v prints "ray-tracing NAME..." then "...completed in S sec".
    vr_ms=$(awk '/ray-tracing/ { t = 1; next } t && /completed in/ { ms = $(NF - 1) * 1000; if (best == "" || ms < best) best = ms; t = 0 }
                 END { if (best != "") printf "%.1f", best }' "$out/$scene.vdb_render.log")
    "$caster" "$out/$scene.vdb" "$scene" "$width" "$height" "$out/${scene}_hdda.pfm" "$out/${scene}_vdb_render.exr" |
        tee "$out/$scene.trace.txt"
    hdda_ms=$(awk '$1 == "nanovdb-hdda" { print $2 }' "$out/$scene.trace.txt")
    printf 'vdb_render: %s ms/frame, %s x the caster\n' "${vr_ms:-?}" \
        "$(awk -v a="${vr_ms:-0}" -v b="$hdda_ms" 'BEGIN { if (a > 0) printf "%.2f", a / b; else print "?" }')"
done
echo "(vdb_render's logs, grids and depth maps in $out)"
