#!/bin/sh
# The study (make bench): procedural against discrete, method by method.
# Regenerates bench/results/ from scratch:
#  1. machine.txt: CPU, cores, memory, compiler and flags, library versions,
#     commit, the load when the run began and when it ended;
#  2. the grids, each made once and timed (/usr/bin/time -v: wall seconds
#     and peak memory, kept beside the grid in GRID.made, so that a grid
#     kept by --keep-grids still reports what making it took): temple and
#     figure baked by `sdftrace bake` as a narrow band (the default far
#     bound) and as a full field (--full, the papers' dense 3D texture), at
#     RES^3 and, for the resolution sweep, RES/2 and RES/4; and each mesh of
#     MESHES (from tests/data/meshes) made into level sets at RES^3 by
#     OpenVDB's `vdb_tool -mesh2ls` and by mesh2sdf, a fourth representation;
#  3. measures every configuration in one process (bench/study: results.csv
#     with each row's `sdftrace render` command, table.md, the figures' data);
#  4. draws Figs. 1, 2, 3 and 5 and the step-cap sweep with gnuplot
#     (bench/fig1.gp, fig2.gp, fig3.gp, fig5.gp, caps.gp).
# table.md is the study's results page: it starts with the command that
# made it, the date, the machine and the commit. Everything is made in a
# staging folder and moved into place at the end; bench/results/README.md
# (the written reading of these files) is never touched, and nothing is
# committed.
#
# usage: bench/study.sh [--quick] [--out DIR] [--build DIR] [--grids DIR] [--keep-grids]
#   --quick       the same pipeline at small sizes (320x180, 64^3, 2 repeats,
#                 a 3-value sweep, cap 1000 only), into a temporary folder that
#                 is checked and removed (make bench-quick; ctest runs it)
#   --out DIR     where the results go (default bench/results; --quick: a temporary folder)
#   --build DIR   the build holding sdftrace, mesh2sdf and bench/study (default build)
#   --grids DIR   where the grids are made (default BUILD/study-grids)
#   --keep-grids  reuse grids already in the grid folder instead of making them
# env: RES WIDTH HEIGHT REPEATS SWEEP CAPS CAP_SWEEP SCENES MESHES override the sizes
#      (MESHES: names of tests/data/meshes/NAME.obj, space- or comma-separated; "" for none).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
# The command that made the results, with the sizes given in the environment.
command="bench/study.sh${1:+ $*}"
for var in MESHES SCENES CAP_SWEEP CAPS SWEEP REPEATS HEIGHT WIDTH RES; do
    eval "val=\${$var-unset}"
    [ "$val" = unset ] || command="$var=\"$val\" $command"
done
quick=0 out= build=$root/build grids= keep=0
die() { echo "study.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case $1 in
    --quick) quick=1 ;;
    --keep-grids) keep=1 ;;
    --out | --build | --grids)
        [ $# -ge 2 ] || die "$1 needs a value"
        case $1 in --out) out=$2 ;; --build) build=$2 ;; --grids) grids=$2 ;; esac
        shift ;;
    -h | --help) sed -n '2,/^set -eu/p' "$0" | sed 's/^# \{0,1\}//; /^set -eu/d'; exit 0 ;;
    *) die "unknown option '$1' (try: bench/study.sh --help)" ;;
    esac
    shift
done
if [ "$quick" = 1 ]; then
    res=${RES:-64} width=${WIDTH:-320} height=${HEIGHT:-180} repeats=${REPEATS:-2} sweep=${SWEEP:-3}
    caps=${CAPS:-1000} cap_sweep=${CAP_SWEEP:-16,64}
else
    res=${RES:-1024} width=${WIDTH:-1280} height=${HEIGHT:-720} repeats=${REPEATS:-5} sweep=${SWEEP:-10}
    caps=${CAPS:-1000,32} cap_sweep=${CAP_SWEEP:-16,64,128}
fi
scenes=${SCENES:-temple,figure}
meshes=$(echo "${MESHES-spot}" | tr ', ' '  ' | xargs)
# Folders given on the command line, made absolute before anything moves.
build=$(cd "$build" 2>/dev/null && pwd) || die "no build folder $build (build first: make build)"
if [ -n "$out" ]; then out=$(mkdir -p "$out" 2>/dev/null && cd "$out" && pwd) || die "cannot create $out"; fi
if [ -n "$grids" ]; then grids=$(mkdir -p "$grids" 2>/dev/null && cd "$grids" && pwd) || die "cannot create $grids"; fi
# Paths inside the repository are written relative to it (the commands in
# results.csv run from the repository's root), so everything runs from there.
cd "$root"
rel() { case $1 in "$root"/*) echo "${1#"$root"/}" ;; *) echo "$1" ;; esac; }
bin=$(rel "$build/sdftrace")
study=$(rel "$build/bench/study")
mesh2sdf=$(rel "$build/mesh2sdf")
for tool in "$bin" "$study"; do
    [ -x "$tool" ] || die "no $tool (build first: make build)"
done
for mesh in $meshes; do
    [ -s "tests/data/meshes/$mesh.obj" ] || die "MESHES: no tests/data/meshes/$mesh.obj"
    [ -x "$mesh2sdf" ] || die "no $mesh2sdf (build first: make build)"
    command -v vdb_tool >/dev/null 2>&1 || die "vdb_tool is missing (apt-get install libopenvdb-tools)"
done
command -v gnuplot >/dev/null 2>&1 || die "gnuplot is missing (apt-get install gnuplot-nox)"
[ -x /usr/bin/time ] || die "/usr/bin/time is missing (apt-get install time)"
mesh_list=$(echo "$meshes" | tr ' ' ',')

# The output folder: a temporary one for --quick (removed after the check)
# unless --out names one.
remove_out=0
if [ -z "$out" ]; then
    if [ "$quick" = 1 ]; then
        out=$(mktemp -d "${TMPDIR:-/tmp}/sdftrace-bench-quick.XXXXXX") remove_out=1
    else
        out=$root/bench/results
    fi
fi
mkdir -p "$out" 2>/dev/null || die "cannot create $out"
stage=$(mktemp -d "$out/.study-XXXXXX" 2>/dev/null) || die "cannot write into $out"
cleanup() {
    rm -rf "$stage"
    if [ "$remove_out" = 1 ]; then rm -rf "$out"; fi
}
trap cleanup EXIT
trap 'exit 1' INT TERM
grids=${grids:-$([ "$quick" = 1 ] && echo "$stage/grids" || echo "$build/study-grids")}
mkdir -p "$grids" 2>/dev/null || die "cannot create $grids"
grids=$(rel "$(cd "$grids" && pwd)")

# Every option checked before anything is made: one line and exit 2 if bad.
set -- --out "$stage" --grids "$grids" --res "$res" --width "$width" --height "$height" --repeats "$repeats" \
    --sweep "$sweep" --caps "$caps" --cap-sweep "$cap_sweep" --scenes "$scenes" --cli "$bin"
[ -z "$mesh_list" ] || set -- "$@" --meshes "$mesh_list"
"$study" --dry-run "$@" >"$stage/plan" || exit 2

started=$(date +%s)
log() { echo "study.sh: $*" >&2; }
log "$(cat "$stage/plan")"

# 1. The machine, and the results page's header (as the run starts).
page_header "The study's tables" "$command" >"$stage/header.md"
{
    echo "command:         $command"
    echo "date (UTC):      $(date -u '+%Y-%m-%d %H:%M')"
    echo "commit:          $(page_commit)"
    echo "CPU:             $(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo), $(nproc) cores"
    echo "memory:          $(awk '/^MemTotal/ { printf "%.1f GiB", $2 / 1048576 }' /proc/meminfo)"
    echo "kernel:          $(uname -srm)"
    cache=$build/CMakeCache.txt
    cc=$(sed -n 's/^CMAKE_C_COMPILER:[A-Z]*=//p' "$cache" 2>/dev/null)
    type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$cache" 2>/dev/null)
    flags=$(sed -n "s/^CMAKE_C_FLAGS_$(echo "$type" | tr a-z A-Z):[A-Z]*=//p" "$cache" 2>/dev/null)
    sanitize=$(sed -n 's/^SDFT_SANITIZE:[A-Z]*=//p' "$cache" 2>/dev/null)
    echo "compiler:        $("${cc:-cc}" --version 2>/dev/null | head -1)"
    echo "build:           $type, C flags '$flags' (the library adds -fno-math-errno; OpenMP), sanitizers ${sanitize:-OFF}"
    echo "libraries:       $(dpkg-query -W -f='${Package} ${Version}, ' libopenvdb-dev libnanovdb-dev libopenexr-dev \
        libpng-dev libtbb-dev libgomp1 gnuplot-nox libopenvdb-tools 2>/dev/null | sed 's/, $//')"
    echo "sizes:           ${width}x${height}, grids ${res}^3 (and $((res / 2))^3, $((res / 4))^3 for the resolution sweep), caps $caps, cap sweep $cap_sweep, 1 warm-up + $repeats timed repeats, sweep $sweep values per method, meshes: ${meshes:-none}"
    echo "plan:            $(cat "$stage/plan")"
    echo "load at start:   $(page_load) (1, 5, 15 minutes; $(nproc) cores)"
} >"$stage/machine.txt"
rm -f "$stage/plan"

# 2. The grids, timed: subject, representation, resolution, wall seconds,
# peak MiB, file MiB, what the tool said, command.
echo "subject,representation,res,wall_s,peak_mib,file_mib,summary,command" >"$stage/bakes.csv"
wall() { awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$1"; }
peak() { awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$1"; }
# make_grid SUBJECT REP RES FILE COMMAND...: runs the command under
# /usr/bin/time unless --keep-grids keeps FILE, and adds its row.
make_grid() {
    subject=$1 kind=$2 size=$3 file=$4
    shift 4
    if [ "$keep" = 1 ] && [ -s "$file" ] && [ -s "$file.made" ]; then
        log "keeping $file"
    else
        log "making $file"
        rm -f "$file.made"
        /usr/bin/time -v "$@" >"$stage/make.out" 2>"$stage/make.time" ||
            { cat "$stage/make.out" "$stage/make.time" >&2; exit 1; }
        summary=$(grep -v '^\s*$' "$stage/make.out" | tail -n 1 | tr ',"' ';'"'")
        echo "$(wall "$stage/make.time"),$(peak "$stage/make.time"),$summary" >"$file.made"
    fi
    echo "$subject,$kind,$size,$(cut -d, -f1-2 "$file.made"),$(du -m "$file" | cut -f1),$(cut -d, -f3- "$file.made"),\"$*\"" \
        >>"$stage/bakes.csv"
}
for scene in $(echo "$scenes" | tr ',' ' '); do
    for size in "$res" $((res / 2)) $((res / 4)); do
        for kind in band full; do
            full=
            if [ $kind = full ]; then full=--full; fi
            # shellcheck disable=SC2086 # $full is one word or none
            make_grid "$scene" "$kind" "$size" "$grids/$scene-$kind-$size.nvdb" \
                "$bin" bake --scene "$scene" --res "$size" $full -o "$grids/$scene-$kind-$size.nvdb"
        done
    done
done
for mesh in $meshes; do
    make_grid "$mesh" vdb_tool "$res" "$grids/$mesh-vdb_tool-$res.nvdb" \
        vdb_tool -read "tests/data/meshes/$mesh.obj" -mesh2ls d="$res" w=3 -write "$grids/$mesh-vdb_tool-$res.nvdb"
    make_grid "$mesh" mesh2sdf "$res" "$grids/$mesh-mesh2sdf-$res.nvdb" \
        "$mesh2sdf" "tests/data/meshes/$mesh.obj" -o "$grids/$mesh-mesh2sdf-$res.vdb" \
        --nvdb "$grids/$mesh-mesh2sdf-$res.nvdb" --res "$res"
done
rm -f "$stage/make.out" "$stage/make.time"

# 3. The measurements, in one process.
log "measuring (bench/study)"
/usr/bin/time -f '%e %U %S' -o "$stage/study.time" "$study" "$@" $([ "$quick" = 1 ] && echo --quiet)
read -r study_wall study_user study_sys <"$stage/study.time"
rm -f "$stage/study.time"

# The page: the header, the study's tables (bench/study's own title line
# replaced by the header's), then the grids' table.
{
    cat "$stage/header.md"
    tail -n +2 "$stage/table.md"
    printf '\n## The grids (`sdftrace bake`, `vdb_tool -mesh2ls`, `mesh2sdf`), each timed with /usr/bin/time -v when made\n\n'
    echo '*peak MiB* is the making process'"'"'s peak resident memory; *file MiB* the size of the grid file the study reads.'
    echo
    echo '| subject | representation | resolution | s | peak MiB | file MiB | what it made | command |'
    echo '|---|---|--:|--:|--:|--:|---|---|'
    awk -F, 'NR > 1 { cmd = $0; sub(/^[^"]*"/, "", cmd); sub(/"$/, "", cmd)
                      printf "| %s | %s | %s³ | %s | %s | %s | %s | `%s` |\n", $1, $2, $3, $4, $5, $6, $7, cmd }' \
        "$stage/bakes.csv"
} >"$stage/page.md"
mv -f "$stage/page.md" "$stage/table.md"
rm -f "$stage/header.md"

# 4. The figures.
log "drawing the figures (gnuplot)"
term=png
gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1 && term=pngcairo
while read -r scene smax fmax w h; do
    case $scene in '#'*) continue ;; esac
    for rep in procedural band full; do
        [ -f "$stage/fig1-$scene-$rep-auto0.3-steps.u32" ] || continue
        gnuplot -e "term='$term'; dir='$stage'; scene='$scene'; rep='$rep'; smax=$smax; fmax=$fmax; w=$w; h=$h; res=$res" \
            -e "out='$stage/fig1-$scene-$rep.png'" "$root/bench/fig1.gp"
    done
done <"$stage/fig1.txt"
subjects=$(echo "$scenes $meshes" | tr ',' ' ' | xargs)
gnuplot -e "term='$term'; dir='$stage'; subjects='$subjects'; res=$res" -e "out='$stage/fig2.png'" "$root/bench/fig2.gp"
if [ -n "$(find "$stage" -name 'fig3-*.dat' 2>/dev/null)" ]; then
    gnuplot -e "term='$term'; dir='$stage'; scenes='$(echo "$scenes" | tr ',' ' ')'; res=$res" \
        -e "out='$stage/fig3.png'" "$root/bench/fig3.gp"
fi
gnuplot -e "term='$term'; dir='$stage'; res=$res" -e "out='$stage/fig5.png'" "$root/bench/fig5.gp"
if [ -f "$stage/caps.dat" ]; then
    gnuplot -e "term='$term'; dir='$stage'; scenes='$(echo "$scenes" | tr ',' ' ')'; res=$res" \
        -e "out='$stage/caps.png'" "$root/bench/caps.gp"
fi
rm -f "$stage"/fig1-*.u32 "$stage"/fig5-*.f32

# Every file the pipeline makes must be there.
expect="machine.txt bakes.csv results.csv table.md fig1.txt fig2.png fig5.txt fig5.png caps.dat caps.png"
if [ "$sweep" -gt 0 ]; then expect="$expect fig3.png"; fi
for scene in $(echo "$scenes" | tr ',' ' '); do
    for rep in procedural band full; do
        expect="$expect fig1-$scene-$rep.png fig2-$scene-$rep.dat"
        if [ "$sweep" -gt 0 ]; then expect="$expect fig3-$scene-$rep.dat"; fi
    done
done
for mesh in $meshes; do expect="$expect fig2-$mesh-vdb_tool.dat fig2-$mesh-mesh2sdf.dat"; done
for f in $expect; do
    [ -s "$stage/$f" ] || { echo "study.sh: the pipeline did not make $f" >&2; exit 1; }
done
rows=$(($(wc -l <"$stage/results.csv") - 1))
elapsed=$(($(date +%s) - started))
echo "took:            $((elapsed / 60)) min $((elapsed % 60)) s (grids, measurements and figures)" >>"$stage/machine.txt"
awk -v w="$study_wall" -v u="$study_user" -v s="$study_sys" -v n="$(nproc)" 'BEGIN {
    printf "bench/study:     %.0f s wall, %.0f s of processor time (%.0f s on %d idle cores)\n", w, u + s, (u + s) / n, n }' \
    >>"$stage/machine.txt"
echo "load at end:     $(page_load) (1, 5, 15 minutes; $(nproc) cores)" >>"$stage/machine.txt"
printf '\nLoad average (1, 5, 15 minutes) when the run began: %s; at its end: %s (%s cores); the run took %d min %d s.\n' \
    "$_page_load_start" "$(page_load)" "$(nproc)" $((elapsed / 60)) $((elapsed % 60)) >>"$stage/table.md"

# Into place: the generated files only (README.md is prose, not ours to touch).
rm -f "$out"/fig1-*.png "$out"/fig2-*.dat "$out"/fig3-*.dat "$out"/fig3-*.dat
for f in "$stage"/*; do
    [ -f "$f" ] && mv -f "$f" "$out/"
done
if [ "$quick" = 1 ]; then
    echo "bench-quick: ok, $rows rows and every file ($(echo "$expect" | wc -w) checked) in $elapsed s"
else
    echo "study.sh: $rows rows, tables and figures in $out ($((elapsed / 60)) min $((elapsed % 60)) s)"
fi
