#!/usr/bin/env bash
# The winding number measured; writes bench/results/winding.md (and prints it).
#
# Accuracy: the fast evaluation's and the exact one's error against the sum
# over every triangle (bench/winding.cpp), median and largest, at NEAR
# points near the surface and UNIFORM ones around it, on the repository's
# meshes and on shapes made in code (a cut sphere, a scan-like patch,
# nested shells, a block of touching cubes, a gear train); the exact
# evaluation's largest proven bound; points signed wrong by either.
#
# Cost: microseconds a point of the fast value, the sign alone (fast and
# exact accuracy) and the exact value on one thread (median of ROUNDS
# rounds and its 95% interval, the four in turns each round); with
# valgrind, instructions a point (callgrind, machine-independent; without
# AVX2) on the bunny; the tree's build on 1 thread and on THREADS, in turns,
# on the bunny and on spot split twice into four (93,696 faces,
# bench/mesh_subdivide.awk).
#
# Assemblies: mesh2sdf --res RES with --sign winding against --sign flood
# (the conversion's seconds from --json, both in turns each round; the
# ratio of each round summarized), on the shapes of closed parts and on the
# bunny for contrast. The goal: at most 1.5 times flood.
#
# usage: bench/winding.sh
# env:   BUILD=build  ROUNDS=5  NEAR=1000  UNIFORM=500  THREADS=2  RES=128
#        PAGE_DIR (where the page goes; default bench/results)
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
root=$PWD
. bench/page.sh
command="bench/winding.sh"
for var in RES THREADS UNIFORM NEAR ROUNDS BUILD; do
    [ -z "${!var+set}" ] || command="$var=\"${!var}\" $command"
done
BUILD=${BUILD:-build}
ROUNDS=${ROUNDS:-5}
NEAR=${NEAR:-1000}
UNIFORM=${UNIFORM:-500}
THREADS=${THREADS:-2}
RES=${RES:-128}
WINDING=$BUILD/bench/winding
M2S=$BUILD/mesh2sdf
OUT=$BUILD/bench-winding
[ -x "$WINDING" ] || { echo "bench/winding.sh: build $WINDING first (cmake --build $BUILD --target winding)" >&2; exit 1; }
[ -x "$M2S" ] || { echo "bench/winding.sh: build $M2S first (cmake --build $BUILD --target mesh2sdf)" >&2; exit 1; }
page_need_stats
mkdir -p "$OUT"

MESHES=(tests/data/meshes/stanford-bunny.obj tests/data/meshes/spot.obj tests/data/meshes/teapot.obj
        tests/data/meshes/suzanne.obj tests/data/meshes/fandisk.obj)
SHAPES=(cut-sphere scan-patch nested-shells cube-block gear-train)
awk -f bench/mesh_subdivide.awk tests/data/meshes/spot.obj | awk -f bench/mesh_subdivide.awk >"$OUT/spot4.obj"

# Column k (1-based) of every line of a file, one a line.
column() { awk -v k="$2" '{ print $k }' "$1"; }

page() {
page_header "The winding number: accuracy and cost" "$command"
echo "Errors against the sum over every triangle (bench/winding.cpp), at $NEAR points near the surface"
echo "(1e-4 to 5e-2 of the size off it, either side) and $UNIFORM uniform in the box grown threefold."
echo "Signs wrong: points clear of 1/2 by more than 5e-3 (fast) or 1e-6 (exact) on the wrong side."
echo
echo "| mesh | triangles | fast median | fast max | exact median | exact max | exact's proven bound, max | signs wrong (fast, exact) |"
echo "|---|---|---|---|---|---|---|---|"
for m in "${MESHES[@]}" "${SHAPES[@]}"; do
    echo "| $(basename "$m" .obj) | $("$WINDING" "$m" accuracy "$NEAR" "$UNIFORM")"
done
echo
echo "Microseconds a point on one thread, median [95% interval] of $ROUNDS rounds:"
echo
echo "| mesh | fast value | sign alone | sign alone, exact | exact value |"
echo "|---|---|---|---|---|"
for m in tests/data/meshes/stanford-bunny.obj tests/data/meshes/fandisk.obj scan-patch cube-block; do
    "$WINDING" "$m" time "$ROUNDS" "$NEAR" "$UNIFORM" >"$OUT/time.txt"
    printf '| %s |' "$(basename "$m" .obj)"
    for k in 1 2 3 4; do printf ' %s |' "$(column "$OUT/time.txt" $k | page_stats --text 2)"; done
    echo
done
echo
if command -v valgrind >/dev/null; then
    echo "Instructions a point on the bunny (callgrind, $NEAR points near the surface; without AVX2,"
    echo "which callgrind does not run in full):"
    echo
    echo "| fast value | sign alone | sign alone, exact | exact value |"
    echo "|---|---|---|---|"
    printf '|'
    for mode in fast side side-exact exact; do
        n=$NEAR
        [ "$mode" = exact ] && n=$((NEAR / 5))
        valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$OUT/callgrind.out" \
            "$WINDING" tests/data/meshes/stanford-bunny.obj count "$mode" "$n" >/dev/null 2>"$OUT/callgrind.log"
        awk -v n="$n" '/Collected/ && $NF > c { c = $NF } END { printf " %.0f |", c / n }' "$OUT/callgrind.log"
    done
    echo
    echo
else
    echo "(valgrind not found: no instruction counts.)"
    echo
fi
echo "Building the tree, seconds, median [95% interval] of $ROUNDS rounds (1 and $THREADS threads in turns):"
echo
echo "| mesh | triangles | 1 thread | $THREADS threads | speed-up |"
echo "|---|---|---|---|---|"
for m in tests/data/meshes/stanford-bunny.obj "$OUT/spot4.obj"; do
    "$WINDING" "$m" build "$ROUNDS" 1 "$THREADS" >"$OUT/build.txt"
    printf '| %s | %s | %s | %s | %s |\n' "$(basename "$m" .obj)" "$(grep -c '^f ' "$m")" \
        "$(column "$OUT/build.txt" 1 | page_stats --text 3)" "$(column "$OUT/build.txt" 2 | page_stats --text 3)" \
        "$(page_stats --ratio --text 2 <"$OUT/build.txt")"
done
echo
echo "Assemblies of closed parts, mesh2sdf --res $RES: the conversion's seconds (--json), winding sign"
echo "against --sign flood, median [95% interval] of $ROUNDS rounds; goal: winding at most 1.5 x flood."
echo
echo "| mesh | triangles | winding s | flood s | winding / flood |"
echo "|---|---|---|---|---|"
for m in cube-block nested-shells gear-train stanford-bunny; do
    obj=tests/data/meshes/$m.obj
    [ -f "$obj" ] || { obj=$OUT/$m.obj; "$WINDING" "$m" obj "$obj"; }
    : >"$OUT/pairs.txt"
    for ((r = 0; r < ROUNDS; r++)); do
        w=$("$M2S" "$obj" -o "$OUT/w.vdb" --res "$RES" --sign winding --json 2>/dev/null |
            sed -n 's/.*"seconds": \([0-9.]*\).*/\1/p')
        f=$("$M2S" "$obj" -o "$OUT/f.vdb" --res "$RES" --sign flood --json 2>/dev/null |
            sed -n 's/.*"seconds": \([0-9.]*\).*/\1/p')
        echo "$w $f" >>"$OUT/pairs.txt"
    done
    printf '| %s | %s | %s | %s | %s |\n' "$m" "$(grep -c '^f ' "$obj")" \
        "$(column "$OUT/pairs.txt" 1 | page_stats --text 2)" "$(column "$OUT/pairs.txt" 2 | page_stats --text 2)" \
        "$(page_stats --ratio --text 2 <"$OUT/pairs.txt")"
done
}

page_write winding.md page
