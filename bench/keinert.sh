#!/bin/sh
# Keinert et al.'s techniques measured on our scenes, beside what the paper
# reports ("Enhanced sphere tracing", 2014, Section 4): over-relaxation
# (3.1) with and without the others on the jewel scene with 2 reflective
# and 8 refractive bounces, each of the others alone on top of it (the
# screen-space criterion 3.2, the dynamic epsilon 3.3, discontinuity
# reduction 3.4, the convex-object optimization 3.5), and the convex
# optimization's speed-up on the glass dodecahedron and the jewel. Counted
# the papers' way (`--papers`). Writes bench/results/keinert.md and the
# jewel's picture bench/results/jewel.png (and prints the page).
#
# usage: bench/keinert.sh [WIDTH HEIGHT]     (default 480 270)
# env:   SDFTRACE   the binary (default build/sdftrace)
#        THREADS    --threads for every render (default 1)
#        REPEAT     renders per row, the fastest one's processor time kept (default 3)
#        PAGE_DIR   where the page and the picture go (default bench/results)
# Shell and awk only: a fresh Debian may lack python.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
bin=${SDFTRACE:-$root/build/sdftrace}
width=${1:-480}
height=${2:-270}
threads=${THREADS:-1}
repeat=${REPEAT:-3}
[ -x "$bin" ] || { echo "bench: no sdftrace at $bin (run: make build)" >&2; exit 1; }
command="bench/keinert.sh${1:+ $width $height}"
[ "$threads" = 1 ] || command="THREADS=$threads $command"
[ "$repeat" = 3 ] || command="REPEAT=$repeat $command"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM

relaxed='--method relaxed --omega 1.2'
# id | scene | label | sdftrace options (all with --bounces 2,8 --papers)
rows="cast-sphere|jewel|ray casting alone, sphere tracing|--method sphere --depth-only
cast-relaxed|jewel|ray casting alone, over-relaxed (omega 1.2)|$relaxed --depth-only
plain-sphere|jewel|sphere tracing, no other technique|--method sphere --no-convex
plain-relaxed|jewel|over-relaxed, no other technique|$relaxed --no-convex
all-sphere|jewel|sphere tracing + 3.2-3.5|--method sphere --screen-space --smooth-iters 3
all-relaxed|jewel|over-relaxed + 3.2-3.5|$relaxed --screen-space --smooth-iters 3
screen|jewel|over-relaxed + screen-space criterion (3.2)|$relaxed --no-convex --screen-space
epsmin-below|jewel|over-relaxed, dynamic eps, eps_min 1e-5, below eps (3.3)|$relaxed --no-convex --eps-min 1e-5
epsmin-small|jewel|over-relaxed, dynamic eps, eps_min 1e-3 (3.3)|$relaxed --no-convex --eps-min 1e-3
epsmin-large|jewel|over-relaxed, dynamic eps, eps_min 1e-2 (3.3)|$relaxed --no-convex --eps-min 1e-2
smooth|jewel|over-relaxed + discontinuity reduction, 3 iterations (3.4)|$relaxed --no-convex --smooth-iters 3
convex|jewel|over-relaxed + convex optimization (3.5)|$relaxed
dodeca-plain|dodecahedron|glass dodecahedron, over-relaxed|$relaxed --materials --no-convex
dodeca-convex|dodecahedron|glass dodecahedron, over-relaxed + convex optimization (3.5)|$relaxed --materials"

# One JSON number by key.
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\": \([-0-9.eE+]*\).*/\1/p"; }

# Each row rendered $repeat times: the fastest processor time (cpu_ms: on a
# shared machine the wall time mostly measures the others' load), and the
# (exact, repeatable) counts.
measure() {
    printf '%s\n' "$rows" | while IFS='|' read -r id scene label opts; do
        best=
        i=0
        while [ "$i" -lt "$repeat" ]; do
            # shellcheck disable=SC2086 # opts is a list of words
            json=$("$bin" render --scene "$scene" $opts --bounces 2,8 --papers --width "$width" \
                --height "$height" --threads "$threads" -o "$tmp/out.exr" --json --quiet)
            ms=$(field "$json" cpu_ms)
            best=$(awk -v a="$ms" -v b="$best" 'BEGIN { print (b == "" || a < b) ? a : b }')
            i=$((i + 1))
        done
        printf '%s|%s|%s|%s|%s|%s|%s|%s|%s|%s\n' "$id" "$scene" "$label" "$best" \
            "$(field "$json" mean_primary_steps)" "$(field "$json" mean_shadow_steps)" \
            "$(field "$json" mean_secondary_steps)" "$(field "$json" mean_steps)" \
            "$(field "$json" secondary_rays)" "$(field "$json" primary_rays)" >>"$tmp/rows"
        echo "  $scene: $label done" >&2
    done
}

# The picture for the README: the jewel with the paper's settings.
picture() {
    dir=${PAGE_DIR:-$root/bench/results}
    "$bin" render --scene jewel $relaxed --bounces 2,8 --screen-space --smooth-iters 3 --soft-shadows 16 \
        --width "$width" --height "$height" --threads "$threads" -o "$tmp/jewel.exr" --png "$tmp/jewel.png" --quiet
    mkdir -p "$dir"
    mv -f "$tmp/jewel.png" "$dir/jewel.png"
    echo "$(basename "$0"): wrote $dir/jewel.png" >&2
}

page() {
    page_header "Enhanced sphere tracing: each technique against the paper" "$command"
    cat <<EOF
Keinert et al.'s jewel and convex-object measurements repeated on our scenes: \`jewel\` (a glass
brilliant, a red bead and a mirror ball over a checker floor) and \`dodecahedron\` with
\`--materials\` (a glass dodecahedron in its bounding sphere), ${width}x${height}, 2 reflective and
8 refractive bounces (\`--bounces 2,8\`), one hard shadow ray per lit hit, counted the papers' way
(\`--papers\`), \`--threads $threads\` ($(nproc) cores). *ms* is the processor time of the
fastest of $repeat renders (\`cpu_ms\`: on a shared machine the wall time measures the load
more than the work); the evaluations are per pixel and exact: *primary* (the settling iterations of 3.4
included), *shadow*, *secondary* (reflection and refraction rays), *total*; *sec. rays* is
reflection and refraction rays per pixel. The paper measured on a GPU at 1280x720 and timed
tracing alone; we trace on the CPU and time the whole frame, shading included. The times still
move between runs on a loaded machine; the counts do not.

![the jewel](jewel.png)

EOF
    awk -F'|' '
        BEGIN {
            print "| row | ms | primary | shadow | secondary | total | sec. rays |"
            print "|---|--:|--:|--:|--:|--:|--:|"
        }
        {
            printf "| %s (%s) | %.1f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", $3, $2, $4, $5, $6, $7, $8,
                   ($10 > 0 ? $9 / $10 : 0)
            ms[$1] = $4; total[$1] = $8; sec[$1] = $7; prim[$1] = $5; rays[$1] = ($10 > 0 ? $9 / $10 : 0)
        }
        function pct(a, b) { return b > 0 ? sprintf("%+.1f%%", 100 * (a - b) / b) : "n/a" }
        END {
            print ""
            print "Each technique beside the paper: the change it makes, in time and in evaluations, over the row"
            print "without it, measured in this run."
            print ""
            print "| technique | the paper reports | measured here: ms | evaluations |"
            print "|---|---|--:|--:|"
            printf "| over-relaxation, ray casting alone (3.1) | 2.978 vs 3.472 ms: -14.2%% | %s | %s (primary) |\n",
                   pct(ms["cast-relaxed"], ms["cast-sphere"]), pct(prim["cast-relaxed"], prim["cast-sphere"])
            printf "| over-relaxation, 2 + 8 bounces, with 3.2-3.5 (3.1) | 21.11 vs 22.47 ms: -6.1%% | %s | %s |\n",
                   pct(ms["all-relaxed"], ms["all-sphere"]), pct(total["all-relaxed"], total["all-sphere"])
            printf "| over-relaxation, 2 + 8 bounces, alone (3.1) | (not reported) | %s | %s |\n",
                   pct(ms["plain-relaxed"], ms["plain-sphere"]), pct(total["plain-relaxed"], total["plain-sphere"])
            printf "| screen-space criterion (3.2) | fewer artifacts, no time given | %s | %s |\n",
                   pct(ms["screen"], ms["plain-relaxed"]), pct(total["screen"], total["plain-relaxed"])
            printf "| dynamic eps: eps_min 1e-3 against 1e-2 (3.3) | too small an eps_min costs iterations | %s | %s |\n",
                   pct(ms["epsmin-small"], ms["epsmin-large"]), pct(total["epsmin-small"], total["epsmin-large"])
            printf "| dynamic eps: eps_min 1e-5, inside eps = 1e-4, against 1e-2 (3.3) | too small: numerical problems | %s | %s (%.1f secondary rays per pixel, not %.1f: rays re-hit their own surface) |\n",
                   pct(ms["epsmin-below"], ms["epsmin-large"]), pct(total["epsmin-below"], total["epsmin-large"]),
                   rays["epsmin-below"], rays["epsmin-large"]
            printf "| discontinuity reduction, 3 iterations (3.4) | a low, fixed cost | %s | %s |\n",
                   pct(ms["smooth"], ms["plain-relaxed"]), pct(total["smooth"], total["plain-relaxed"])
            printf "| convex optimization, jewel (3.5) | 2.73 vs 3.03 ms: -9.9%% | %s | %s (secondary %s) |\n",
                   pct(ms["convex"], ms["plain-relaxed"]), pct(total["convex"], total["plain-relaxed"]),
                   pct(sec["convex"], sec["plain-relaxed"])
            printf "| convex optimization, dodecahedron (3.5) | 2.73 vs 3.03 ms: -9.9%% | %s | %s (secondary %s) |\n",
                   pct(ms["dodeca-convex"], ms["dodeca-plain"]), pct(total["dodeca-convex"], total["dodeca-plain"]),
                   pct(sec["dodeca-convex"], sec["dodeca-plain"])
        }
    ' "$tmp/rows"
}

echo "bench/keinert.sh: ${width}x${height}, threads ${threads} ($(nproc) cores), best of ${repeat}" >&2
measure
picture
page_write keinert.md page
