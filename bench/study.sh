#!/bin/sh
# The study (make bench): procedural against discrete, method by method.
# Regenerates bench/results/ from scratch:
#  1. machine.txt: CPU, cores, memory, compiler and flags, library versions,
#     commit, load;
#  2. bakes temple and figure at RES^3 with `sdftrace bake`, as a narrow band
#     (the default far bound) and as a full field (--full, the papers' dense
#     3D texture), timed (/usr/bin/time -v), into the grid folder;
#  3. measures every configuration in one process (bench/study: results.csv
#     with each row's `sdftrace render` command, table.md, the figures' data);
#  4. draws Figs. 1-3 with gnuplot (bench/fig1.gp, fig2.gp, fig3.gp).
# table.md is the study's results page: it starts with the command that
# made it, the date, the machine and the commit. Everything is made in a
# staging folder and moved into place at the end; bench/results/README.md
# (the written reading of these files) is never touched, and nothing is
# committed.
#
# usage: bench/study.sh [--quick] [--out DIR] [--build DIR] [--grids DIR] [--keep-grids]
#   --quick       the same pipeline at small sizes (320x180, 128^3, 2 repeats,
#                 a 3-value sweep, cap 1000 only), into a temporary folder that
#                 is checked and removed (make bench-quick; ctest runs it)
#   --out DIR     where the results go (default bench/results; --quick: a temporary folder)
#   --build DIR   the build holding sdftrace and bench/study (default build)
#   --grids DIR   where the grids are baked (default BUILD/study-grids)
#   --keep-grids  reuse grids already in the grid folder instead of baking them
# env: RES WIDTH HEIGHT REPEATS SWEEP CAPS SCENES override the sizes.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
# The command that made the results, with the sizes given in the environment.
command="bench/study.sh${1:+ $*}"
for var in SCENES CAPS SWEEP REPEATS HEIGHT WIDTH RES; do
    eval "val=\${$var:-}"
    [ -z "$val" ] || command="$var=$val $command"
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
    res=${RES:-128} width=${WIDTH:-320} height=${HEIGHT:-180} repeats=${REPEATS:-2} sweep=${SWEEP:-3}
    caps=${CAPS:-1000}
else
    res=${RES:-1024} width=${WIDTH:-1280} height=${HEIGHT:-720} repeats=${REPEATS:-5} sweep=${SWEEP:-10}
    caps=${CAPS:-1000,32}
fi
scenes=${SCENES:-temple,figure}
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
for tool in "$bin" "$study"; do
    [ -x "$tool" ] || die "no $tool (build first: make build)"
done
command -v gnuplot >/dev/null 2>&1 || die "gnuplot is missing (apt-get install gnuplot-nox)"
[ -x /usr/bin/time ] || die "/usr/bin/time is missing (apt-get install time)"

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

# Every option checked before anything is baked: one line and exit 2 if bad.
"$study" --dry-run --out "$stage" --grids "$grids" --res "$res" --width "$width" --height "$height" \
    --repeats "$repeats" --sweep "$sweep" --caps "$caps" --scenes "$scenes" --cli "$bin" >/dev/null || exit 2

started=$(date +%s)
log() { echo "study.sh: $*" >&2; }

# 1. The machine, and the results page's header (as the run starts).
page_header "The study's tables" "$command" >"$stage/header.md"
{
    echo "command:         $command"
    echo "date (UTC):      $(date -u '+%Y-%m-%d %H:%M')"
    echo "commit:          $(git -C "$root" describe --always --dirty 2>/dev/null || echo '?')"
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
        libpng-dev libtbb-dev libgomp1 gnuplot-nox 2>/dev/null | sed 's/, $//')"
    echo "sizes:           ${width}x${height}, grids ${res}^3, caps $caps, 1 warm-up + $repeats repeats, sweep $sweep values per method"
    echo "load at start:   $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 minutes; $(nproc) cores)"
} >"$stage/machine.txt"

# 2. The bakes, timed: scene, representation, wall seconds, peak MiB, file MiB, summary, command.
echo "scene,representation,wall_s,peak_mib,file_mib,summary,command" >"$stage/bakes.csv"
for scene in $(echo "$scenes" | tr ',' ' '); do
    for kind in band full; do
        file=$grids/$scene-$kind-$res.nvdb
        full=
        if [ $kind = full ]; then full=' --full'; fi
        cmd="$bin bake --scene $scene --res $res$full -o $file"
        if [ "$keep" = 1 ] && [ -s "$file" ]; then
            log "keeping $file"
            echo "$scene,$kind,,,$(du -m "$file" | cut -f1),kept from an earlier run,\"$cmd\"" >>"$stage/bakes.csv"
            continue
        fi
        log "baking $file"
        # shellcheck disable=SC2086 # cmd is a list of words
        /usr/bin/time -v $cmd >"$stage/bake.out" 2>"$stage/bake.time" ||
            { cat "$stage/bake.out" "$stage/bake.time" >&2; exit 1; }
        wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s }' "$stage/bake.time")
        rss=$(awk -F': ' '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$stage/bake.time")
        echo "$scene,$kind,$wall,$rss,$(du -m "$file" | cut -f1),$(tr ',' ';' <"$stage/bake.out"),\"$cmd\"" >>"$stage/bakes.csv"
    done
done
rm -f "$stage/bake.out" "$stage/bake.time"

# 3. The measurements, in one process.
log "measuring (bench/study)"
"$study" --out "$stage" --grids "$grids" --res "$res" --width "$width" --height "$height" --repeats "$repeats" \
    --sweep "$sweep" --caps "$caps" --scenes "$scenes" --cli "$bin" $([ "$quick" = 1 ] && echo --quiet)

# The page: the header, the study's tables (bench/study's own title line
# replaced by the header's), then the bakes' table.
{
    cat "$stage/header.md"
    tail -n +2 "$stage/table.md"
    printf '\n## Bakes (`sdftrace bake`, timed with /usr/bin/time -v)\n\n'
    echo '| scene | representation | s | peak MiB | file MiB | what it made | command |'
    echo '|---|---|--:|--:|--:|---|---|'
    awk -F, 'NR > 1 { cmd = $0; sub(/^[^"]*"/, "", cmd); sub(/"$/, "", cmd)
                      printf "| %s | %s | %s | %s | %s | %s | `%s` |\n", $1, $2, $3, $4, $5, $6, cmd }' "$stage/bakes.csv"
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
gnuplot -e "term='$term'; dir='$stage'; scenes='$(echo "$scenes" | tr ',' ' ')'; res=$res" \
    -e "out='$stage/fig2.png'" "$root/bench/fig2.gp"
if [ -f "$stage/fig3-procedural.dat" ]; then
    gnuplot -e "term='$term'; dir='$stage'; res=$res" -e "out='$stage/fig3.png'" "$root/bench/fig3.gp"
fi
rm -f "$stage"/fig1-*.u32

# Every file the pipeline makes must be there.
expect="machine.txt bakes.csv results.csv table.md fig1.txt fig2.png"
case ,$scenes, in *,temple,*) if [ "$sweep" -gt 0 ]; then expect="$expect fig3.png"; fi ;; esac
for scene in $(echo "$scenes" | tr ',' ' '); do
    for rep in procedural band full; do expect="$expect fig1-$scene-$rep.png fig2-$scene-$rep.dat"; done
done
for f in $expect; do
    [ -s "$stage/$f" ] || { echo "study.sh: the pipeline did not make $f" >&2; exit 1; }
done
rows=$(($(wc -l <"$stage/results.csv") - 1))
elapsed=$(($(date +%s) - started))
echo "took:            $((elapsed / 60)) min $((elapsed % 60)) s (bakes, measurements and figures); load at the end: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$stage/machine.txt"

# Into place: the generated files only (README.md is prose, not ours to touch).
rm -f "$out"/fig1-*.png "$out"/fig2-*.dat "$out"/fig3-*.dat
for f in "$stage"/*; do
    [ -f "$f" ] && mv -f "$f" "$out/"
done
if [ "$quick" = 1 ]; then
    echo "bench-quick: ok, $rows rows and every file ($(echo "$expect" | wc -w) checked) in $elapsed s"
else
    echo "study.sh: $rows rows, tables and figures in $out ($((elapsed / 60)) min $((elapsed % 60)) s)"
fi
