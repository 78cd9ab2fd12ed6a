#!/bin/sh
# The five tracing variants on the procedural scenes: every scene with each
# variant row of the papers' tables (sphere; relaxed omega 1.2 and 1.5, in
# Keinert's form and in Bán–Valasek's; enhanced omega 0.88; auto beta 0.3
# and 0.2), rendered with shadows at
# 1280x720, counted the papers' way, through `sdftrace render --papers
# --json` (grey, so that every scene, the jewel too, is a primary and a
# shadow ray per pixel). Writes bench/results/variants.md (and prints it): the frame's
# trace time, mean SDF evaluations and fallbacks per pixel (primary + shadow
# ray), the non-converged fraction of primary rays, and ratios to `enhanced`
# measured in the same run.
#
# usage: bench/run.sh [WIDTH HEIGHT]     (default 1280 720)
# env:   SDFTRACE   the binary (default build/sdftrace)
#        THREADS    --threads for every render (default 0: all cores)
#        SCENES     space-separated scene names (default: all)
#        PAGE_DIR   where the page goes (default bench/results)
# Shell and awk only: a fresh Debian may lack python.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
bin=${SDFTRACE:-$root/build/sdftrace}
width=${1:-1280}
height=${2:-720}
threads=${THREADS:-0}
[ -x "$bin" ] || { echo "bench: no sdftrace at $bin (run: make build)" >&2; exit 1; }
scenes=${SCENES:-$("$bin" scenes | awk '{ print $1 }')}
command="bench/run.sh${1:+ $width $height}"
[ "$threads" = 0 ] || command="THREADS=$threads $command"
[ -z "${SCENES:-}" ] || command="SCENES=\"$SCENES\" $command"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM

# variant label | sdftrace options
variants='sphere|--method sphere
relaxed-1.2|--method relaxed --omega 1.2
relaxed-1.5|--method relaxed --omega 1.5
relaxed-bv-1.2|--method relaxed-bv --omega 1.2
relaxed-bv-1.5|--method relaxed-bv --omega 1.5
enhanced-0.88|--method enhanced --omega 0.88
auto-0.3|--method auto --beta 0.3
auto-0.2|--method auto --beta 0.2'

# One JSON number by key.
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\": \([-0-9.eE+]*\).*/\1/p"; }

measure() {
    for scene in $scenes; do
        printf '%s\n' "$variants" | while IFS='|' read -r label opts; do
            # shellcheck disable=SC2086 # opts is a list of words
            json=$("$bin" render --scene "$scene" $opts --papers --no-materials --width "$width" --height "$height" \
                --threads "$threads" -o "$tmp/out.exr" --json --quiet)
            echo "$scene $label $(field "$json" ms) $(field "$json" mean_steps) $(field "$json" mean_fallbacks)" \
                "$(field "$json" nonconverged)" >>"$tmp/rows"
            echo "  $scene $label done" >&2
        done
    done
}

page() {
    page_header "The five variants on the procedural scenes" "$command"
    cat <<EOF
Every scene rendered with each variant row of the papers' tables, ${width}x${height}, one hard
shadow ray per lit hit, \`--threads $threads\` ($(nproc) cores), counted the papers' way
(\`--papers\`: every ray from the eye, every step to ε). One \`sdftrace render --json\` call per
row: *ms* is that call's frame, its trace time as the JSON reports it (the first frame of its
process; loading and writing the image not included). *evals/px* and *fallb/px* are SDF
evaluations and fallbacks per pixel, primary plus shadow ray; *nonconv %* is the share of primary
rays that reached the step cap; the last two columns are ratios to \`enhanced\` on the same scene.
*relaxed* is Keinert et al.'s Listing 2 (plain sphere tracing after the first failed step),
*relaxed-bv* Bán and Valasek's Algorithm 2 (relaxed again after each fallback).
The counts are exact and repeatable; on a shared machine the times move by up to 20% between runs.

EOF
    # Two passes over the rows: the first finds each scene's enhanced row.
    awk '
        NR == FNR { if ($2 ~ /^enhanced/) { ems[$1] = $3; esteps[$1] = $4 } next }
        FNR == 1 {
            print "| scene | variant | ms | evals/px | fallb/px | nonconv % | ms/enh | evals/enh |"
            print "|---|---|--:|--:|--:|--:|--:|--:|"
        }
        {
            printf "| %s | %s | %.1f | %.2f | %.3f | %.3f | %.2f | %.2f |\n", $1, $2, $3, $4, $5, 100 * $6,
                   (ems[$1] > 0 ? $3 / ems[$1] : 0), (esteps[$1] > 0 ? $4 / esteps[$1] : 0)
        }
    ' "$tmp/rows" "$tmp/rows"
}

echo "bench/run.sh: ${width}x${height}, shadows on, threads ${threads} ($(nproc) cores)" >&2
measure
page_write variants.md page
