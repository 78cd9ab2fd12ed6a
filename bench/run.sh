#!/bin/sh
# The tracing variants on the procedural scenes: every scene with each
# variant row of the papers' tables (sphere; relaxed omega 1.2 and 1.5, in
# Keinert's form and in Bán–Valasek's; enhanced omega 0.88; auto beta 0.3
# and 0.2), rendered with shadows at
# 1280x720, counted the papers' way, through `sdftrace render --papers
# --json` (grey, so that every scene, the jewel too, is a primary and a
# shadow ray per pixel). Writes bench/results/variants.md (and prints it):
# per row the frame's processor time, its ratio to `enhanced` on the same
# scene, the mean SDF evaluations and fallbacks per pixel (primary + shadow
# ray), the non-converged fraction of primary rays, and the evaluations'
# ratio to `enhanced`.
#
# Times: REPEAT rounds (at least 5); in each round every scene's rows run
# back to back, in an order shuffled anew each round, so that the machine's
# drift falls on all of them alike. A time is the median of the rounds with
# its 95% bootstrap interval (bench/stats), a ratio the median of the
# rounds' ratios (each row over `enhanced` in the same round) with its own.
# The counts must be the same in every round.
#
# usage: bench/run.sh [WIDTH HEIGHT]     (default 1280 720)
# env:   SDFTRACE   the binary (default build/sdftrace)
#        THREADS    --threads for every render (default 0: all cores)
#        SCENES     space-separated scene names (default: all)
#        REPEAT     rounds (default 5; at least 5)
#        PAGE_DIR   where the page goes (default bench/results)
# Shell and awk only: a fresh Debian may lack python.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
bin=${SDFTRACE:-$root/build/sdftrace}
width=${1:-1280}
height=${2:-720}
threads=${THREADS:-0}
repeat=${REPEAT:-5}
[ -x "$bin" ] || { echo "bench: no sdftrace at $bin (run: make build)" >&2; exit 1; }
page_need_stats
case $repeat in *[!0-9]* | '') repeat=0 ;; esac
[ "$repeat" -ge 5 ] || { echo "bench/run.sh: REPEAT must be a whole number of at least 5" >&2; exit 2; }
scenes=${SCENES:-$("$bin" scenes | awk '{ print $1 }')}
command="bench/run.sh${1:+ $width $height}"
[ "$threads" = 0 ] || command="THREADS=$threads $command"
[ "$repeat" = 5 ] || command="REPEAT=$repeat $command"
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

# Rows of $tmp/rows: round scene label cpu_ms ms mean_steps mean_fallbacks nonconverged
measure() {
    round=1
    while [ "$round" -le "$repeat" ]; do
        for scene in $scenes; do
            # This round's order of the scene's rows.
            printf '%s\n' "$variants" | awk -v r="$round" -v s="$scene" 'BEGIN { h = r; for (i = 1; i <= length(s); i++) h = (h * 31 + index("abcdefghijklmnopqrstuvwxyz", substr(s, i, 1))) % 2147483647; srand(h) }
                { print rand() "\t" $0 }' | sort -k1,1 | cut -f2- >"$tmp/order"
            while IFS='|' read -r label opts; do
                # shellcheck disable=SC2086 # opts is a list of words
                json=$("$bin" render --scene "$scene" $opts --papers --no-materials --width "$width" \
                    --height "$height" --threads "$threads" -o "$tmp/out.exr" --json --quiet)
                echo "$round $scene $label $(field "$json" cpu_ms) $(field "$json" ms) $(field "$json" mean_steps)" \
                    "$(field "$json" mean_fallbacks) $(field "$json" nonconverged)" >>"$tmp/rows"
            done <"$tmp/order"
            echo "  round $round of $repeat: $scene done" >&2
        done
        round=$((round + 1))
    done
}

# "MEDIAN [LO–HI]" of a row's processor times, and of its ratios to the
# scene's enhanced row round by round.
row_times() {
    awk -v s="$1" -v l="$2" '$2 == s && $3 == l { print $4 }' "$tmp/rows" | page_stats --text 1
}
row_ratios() {
    awk -v s="$1" -v l="$2" '$2 == s && $3 == l { t[$1] = $4 } $2 == s && $3 ~ /^enhanced/ { e[$1] = $4 }
        END { for (r in t) print t[r], e[r] }' "$tmp/rows" | page_stats --ratio --text 2
}

page() {
    page_header "The variants on the procedural scenes" "$command"
    cat <<EOF
Every scene rendered with each variant row of the papers' tables, ${width}x${height}, one hard
shadow ray per lit hit, \`--threads $threads\` ($(nproc) cores), counted the papers' way
(\`--papers\`: every ray from the eye, every step to ε). One \`sdftrace render --json\` call per
row and round, $repeat rounds; in each round a scene's rows run back to back in a shuffled order.
*cpu ms* is the frame's processor time (\`cpu_ms\`, both threads: on a shared machine the wall time
measures the others' load more than the work), the median of the rounds with its 95% bootstrap
interval in brackets; *cpu/enh* the median of the rounds' ratios to \`enhanced\` on the same scene,
with its interval: an interval that holds 1.00 is no difference this run can tell.
*evals/px* and *fallb/px* are SDF evaluations and fallbacks per pixel, primary plus shadow ray,
*nonconv %* the share of primary rays that reached the step cap, *evals/enh* the evaluations over
\`enhanced\`'s: exact, and the same in every round. *relaxed* is Keinert et al.'s Listing 2 (plain
sphere tracing after the first failed step), *relaxed-bv* Bán and Valasek's Algorithm 2 (relaxed
again after each fallback).

| scene | variant | cpu ms | cpu/enh | evals/px | fallb/px | nonconv % | evals/enh |
|---|---|--:|--:|--:|--:|--:|--:|
EOF
    for scene in $scenes; do
        printf '%s\n' "$variants" | while IFS='|' read -r label opts; do
            # The counts: the same in every round, or the page fails.
            awk -v s="$scene" -v l="$label" '
                $2 == s && $3 ~ /^enhanced/ { esteps = $6 }
                $2 == s && $3 == l { key = $6 " " $7 " " $8; if (seen != "" && key != seen) bad = 1; seen = key
                                     steps = $6; fb = $7; nc = $8 }
                END { if (bad) { print "bench/run.sh: counts differ between rounds: " s " " l > "/dev/stderr"; exit 1 }
                      printf "%.2f %.3f %.3f %.2f\n", steps, fb, 100 * nc, (esteps > 0 ? steps / esteps : 0) }
            ' "$tmp/rows" >"$tmp/counts"
            read -r steps fb nc rel <"$tmp/counts"
            echo "| $scene | $label | $(row_times "$scene" "$label") | $(row_ratios "$scene" "$label") | $steps | $fb | $nc | $rel |"
        done
    done
}

echo "bench/run.sh: ${width}x${height}, shadows on, threads ${threads} ($(nproc) cores), $repeat rounds" >&2
measure
page_write variants.md page
