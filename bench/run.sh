#!/bin/sh
# sdftrace's first benchmark: every scene with each tracing variant of the
# papers' tables (sphere; relaxed omega 1.2 and 1.5; enhanced omega 0.88;
# auto beta 0.3 and 0.2), rendered with shadows at 1280x720 through
# `sdftrace render --json`. Prints wall time, mean SDF evaluations and
# fallbacks per pixel (primary + shadow ray), the non-converged fraction of
# primary rays, and ratios to `enhanced` measured in the same run.
#
# usage: bench/run.sh [WIDTH HEIGHT]     (default 1280 720)
# env:   SDFTRACE   the binary (default build/sdftrace)
#        THREADS    --threads for every render (default 0: all cores)
#        SCENES     space-separated scene names (default: all)
# Shell and awk only: a fresh Debian may lack python.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
bin=${SDFTRACE:-$root/build/sdftrace}
width=${1:-1280}
height=${2:-720}
threads=${THREADS:-0}
[ -x "$bin" ] || { echo "bench: no sdftrace at $bin (run: make build)" >&2; exit 1; }
scenes=${SCENES:-$("$bin" scenes | awk '{ print $1 }')}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM

# variant label | sdftrace options
variants='sphere|--method sphere
relaxed-1.2|--method relaxed --omega 1.2
relaxed-1.5|--method relaxed --omega 1.5
enhanced-0.88|--method enhanced --omega 0.88
auto-0.3|--method auto --beta 0.3
auto-0.2|--method auto --beta 0.2'

# One JSON number by key.
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\": \([-0-9.eE+]*\).*/\1/p"; }

echo "sdftrace bench: ${width}x${height}, shadows on, threads ${threads} ($(nproc) cores), $(date -u +%Y-%m-%d)" >&2
for scene in $scenes; do
    printf '%s\n' "$variants" | while IFS='|' read -r label opts; do
        # shellcheck disable=SC2086 # opts is a list of words
        json=$("$bin" render --scene "$scene" $opts --papers --width "$width" --height "$height" \
            --threads "$threads" -o "$tmp/out.exr" --json --quiet)
        echo "$scene $label $(field "$json" ms) $(field "$json" mean_steps) $(field "$json" mean_fallbacks)" \
            "$(field "$json" nonconverged)" >>"$tmp/rows"
        echo "  $scene $label done" >&2
    done
done

# Two passes over the rows: the first finds each scene's enhanced row.
awk '
    NR == FNR { if ($2 ~ /^enhanced/) { ems[$1] = $3; esteps[$1] = $4 } next }
    FNR == 1 {
        printf "%-13s %-14s %9s %9s %9s %8s %8s %8s\n", "scene", "variant", "ms", "evals/px", "fallb/px",
               "nonconv%", "ms/enh", "evals/enh"
    }
    $1 != last && FNR > 1 { print "" }
    {
        last = $1
        printf "%-13s %-14s %9.1f %9.2f %9.3f %8.3f %8.2f %8.2f\n", $1, $2, $3, $4, $5, 100 * $6,
               (ems[$1] > 0 ? $3 / ems[$1] : 0), (esteps[$1] > 0 ? $4 / esteps[$1] : 0)
    }
' "$tmp/rows" "$tmp/rows"
