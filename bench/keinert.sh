#!/bin/sh
# Keinert et al.'s techniques measured on our scenes, beside what the paper
# reports ("Enhanced sphere tracing", 2014, Sections 3 and 4):
#  - over-relaxation (3.1, Listing 2: `--method relaxed`; Bán–Valasek's
#    Algorithm 2, `relaxed-bv`, beside it) with and without the others, on
#    the jewel scene with 2 reflective and 8 refractive bounces, and each of
#    the others alone on top of it; the convex optimization (3.5) on the
#    jewel and on the glass dodecahedron, the paper's Fig. 11 scene;
#  - the dynamic epsilon (3.3): each eps_min with its evaluations, where
#    |f(p)| decided the offset, the secondary rays that re-hit their own
#    surface, and the image it costs against a converged render;
#  - the screen-space criterion (3.2) and discontinuity reduction (3.4)
#    where the paper claims quality: image error against a converged render
#    (100000 steps) at step caps 16-128, at silhouettes and far away, on the
#    city and the temple (bench/keinert-quality.gp draws it);
#  - the jewel from a grid baked with its materials.
# Times: every timed row runs once per round, REPEAT rounds, the rows of a
# round back to back in an order that rotates each round; a row's time is
# the median of its rounds' processor times with a 95% bootstrap interval,
# a technique's effect the median of its per-round ratios (bench/stats).
# Counts are exact, and every round must repeat them. Counted the papers'
# way (`--papers`). Writes bench/results/keinert.md, keinert-quality.png,
# jewel.png (and prints the page).
#
# usage: bench/keinert.sh [WIDTH HEIGHT]     (default 480 270)
# env:   SDFTRACE   the binary (default build/sdftrace; imgdiff and stats beside it in BUILD/bench)
#        THREADS    --threads for every render (default 1)
#        REPEAT     rounds of the timed rows, at least 5 (default 5)
#        GRID_RES   the jewel grid's resolution (default 512)
#        PAGE_DIR   where the page and the pictures go (default bench/results)
# Shell and awk only: a fresh Debian may lack python.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/bench/page.sh"
bin=${SDFTRACE:-$root/build/sdftrace}
build=$(cd "$(dirname "$bin")" && pwd)
imgdiff=$build/bench/imgdiff
PAGE_STATS=${PAGE_STATS:-$build/bench/stats}
width=${1:-480}
height=${2:-270}
threads=${THREADS:-1}
repeat=${REPEAT:-5}
grid_res=${GRID_RES:-512}
dir=${PAGE_DIR:-$root/bench/results}
die() { echo "keinert.sh: $*" >&2; exit 1; }
[ -x "$bin" ] || die "no sdftrace at $bin (run: make build)"
[ -x "$imgdiff" ] || die "no imgdiff at $imgdiff (run: make build)"
page_need_stats
command -v gnuplot >/dev/null 2>&1 || die "gnuplot is missing (apt-get install gnuplot-nox)"
[ "$repeat" -ge 5 ] 2>/dev/null || die "REPEAT must be a number >= 5, not '$repeat'"
command="bench/keinert.sh${1:+ $width $height}"
[ "$threads" = 1 ] || command="THREADS=$threads $command"
[ "$repeat" = 5 ] || command="REPEAT=$repeat $command"
[ "$grid_res" = 512 ] || command="GRID_RES=$grid_res $command"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
mkdir -p "$tmp/ms" "$tmp/json" "$tmp/img"

relaxed='--method relaxed --omega 1.2'
bv='--method relaxed-bv --omega 1.2'
ss='--screen-space --smooth-iters 3'
# The timed rows: id | scene | label | sdftrace options (all with --bounces 2,8 --papers).
rows="cast-sphere|jewel|ray casting alone, sphere tracing|--method sphere --depth-only
cast-relaxed|jewel|ray casting alone, relaxed (omega 1.2)|$relaxed --depth-only
cast-relaxed-bv|jewel|ray casting alone, relaxed-bv (omega 1.2)|$bv --depth-only
plain-sphere|jewel|sphere tracing, no other technique|--method sphere --no-convex
plain-relaxed|jewel|relaxed, no other technique (eps_min: the default, 1e-3)|$relaxed --no-convex
plain-relaxed-bv|jewel|relaxed-bv, no other technique|$bv --no-convex
all-sphere|jewel|sphere tracing + 3.2-3.5|--method sphere $ss
all-relaxed|jewel|relaxed + 3.2-3.5|$relaxed $ss
screen|jewel|relaxed + screen-space criterion (3.2)|$relaxed --no-convex --screen-space
smooth|jewel|relaxed + discontinuity reduction, 3 iterations (3.4)|$relaxed --no-convex --smooth-iters 3
convex|jewel|relaxed + convex optimization (3.5)|$relaxed
dodeca-plain|dodecahedron|glass dodecahedron, relaxed|$relaxed --materials --no-convex
dodeca-convex|dodecahedron|glass dodecahedron, relaxed + convex optimization (3.5)|$relaxed --materials
eps-1e-5|jewel|relaxed, eps_min 1e-5 (below eps = 1e-4)|$relaxed --no-convex --eps-min 1e-5
eps-1e-4|jewel|relaxed, eps_min 1e-4|$relaxed --no-convex --eps-min 1e-4
eps-1e-2|jewel|relaxed, eps_min 1e-2|$relaxed --no-convex --eps-min 1e-2
ss-eps-1e-5|jewel|relaxed + 3.2 + 3.4, eps_min 1e-5|$relaxed --no-convex $ss --eps-min 1e-5
ss-eps-default|jewel|relaxed + 3.2 + 3.4, eps_min the default (1e-3)|$relaxed --no-convex $ss
ss-eps-1e-2|jewel|relaxed + 3.2 + 3.4, eps_min 1e-2|$relaxed --no-convex $ss --eps-min 1e-2
grid|jewel|relaxed, from a ${grid_res}^3 grid baked with its materials|--grid $tmp/jewel.nvdb $relaxed"

# One JSON number by key.
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\": \([-0-9.eE+]*\).*/\1/p"; }

# sdftrace render ARGS... --json, quiet, at the page's size.
render() {
    "$bin" render "$@" --width "$width" --height "$height" --threads "$threads" --json --quiet
}

# The counts a row must repeat every round.
counts() { printf '%s\n' "$1" | sed 's/.*"rays": \([0-9]*\).*"steps": \([0-9]*\).*"fallbacks": \([0-9]*\).*/\1 \2 \3/'; }

# REPEAT rounds of every timed row; round r starts at row r (mod the rows),
# so no row always runs first or after the same one.
measure() {
    n=$(printf '%s\n' "$rows" | wc -l)
    r=0
    while [ "$r" -lt "$repeat" ]; do
        k=0
        while [ "$k" -lt "$n" ]; do
            line=$(printf '%s\n' "$rows" | sed -n "$(((k + r) % n + 1))p")
            id=${line%%|*}
            rest=${line#*|}
            scene=${rest%%|*}
            opts=${line##*|}
            # shellcheck disable=SC2086 # opts is a list of words
            json=$(render --scene "$scene" $opts --bounces 2,8 --papers -o "$tmp/img/$id.exr")
            field "$json" cpu_ms >>"$tmp/ms/$id"
            if [ "$r" = 0 ]; then
                printf '%s\n' "$json" >"$tmp/json/$id"
            elif [ "$(counts "$json")" != "$(counts "$(cat "$tmp/json/$id")")" ]; then
                die "$id: round $((r + 1)) counted $(counts "$json"), round 1 $(counts "$(cat "$tmp/json/$id")")"
            fi
            k=$((k + 1))
        done
        r=$((r + 1))
        echo "  round $r of $repeat done" >&2
    done
}

# The converged jewel every colour row is held to: sphere tracing to eps
# 1e-5 with up to 100000 steps, eps_min 1e-4 (its rays leave 2e-4 off a
# hit refined onto the surface, far below a pixel).
reference() {
    render --scene jewel --method sphere --eps 1e-5 --eps-min 1e-4 --max-steps 100000 --no-convex --bounces 2,8 \
        --papers -o "$tmp/img/reference.exr" >"$tmp/json/reference"
}

# The quality rows: each scene, with its materials (a checker floor), at
# each step cap, the four configurations, against its converged render.
quality_scenes='city temple'
quality_caps='16 32 64 128'
quality() {
    : >"$tmp/quality.dat"
    for scene in $quality_scenes; do
        render --scene "$scene" --materials $relaxed --max-steps 100000 --papers -o "$tmp/q-ref.exr" >/dev/null
        for config in eps eps-smooth ss ss-smooth; do
            case $config in
            eps) extra= ;;
            eps-smooth) extra='--smooth-iters 3' ;;
            ss) extra=--screen-space ;;
            ss-smooth) extra='--screen-space --smooth-iters 3' ;;
            esac
            for cap in $quality_caps; do
                # shellcheck disable=SC2086 # extra is a list of words
                json=$(render --scene "$scene" --materials $relaxed --max-steps "$cap" $extra --papers -o "$tmp/q.exr")
                printf '%s %s %s %s %s\n' "$scene" "$config" "$cap" "$("$imgdiff" "$tmp/q-ref.exr" "$tmp/q.exr")" \
                    "$(field "$json" mean_steps)" >>"$tmp/quality.dat"
            done
            printf '\n\n' >>"$tmp/quality.dat"
        done
        echo "  quality: $scene done" >&2
    done
    term=png
    gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1 && term=pngcairo
    gnuplot -e "term='$term'; data='$tmp/quality.dat'; scenes='$quality_scenes'; out='$tmp/keinert-quality.png'" \
        "$root/bench/keinert-quality.gp"
}

# The picture for the README: the jewel with the paper's settings.
picture() {
    "$bin" render --scene jewel $relaxed --bounces 2,8 $ss --soft-shadows 16 --width "$width" --height "$height" \
        --threads "$threads" -o "$tmp/jewel.exr" --png "$tmp/jewel.png" --quiet
}

# id: the row's numbers, one line: label scene ms-text primary shadow
# secondary total secrays/px image-cost from-f self-hits eps-hits secondary
# steps... (the table's fields, | separated).
row_fields() {
    id=$1
    line=$(printf '%s\n' "$rows" | grep "^$id|")
    json=$(cat "$tmp/json/$id")
    ms=$(page_stats --text 1 <"$tmp/ms/$id")
    cost=-
    case $id in cast-* | dodeca-*) ;; *) cost=$("$imgdiff" "$tmp/img/reference.exr" "$tmp/img/$id.exr" | cut -d' ' -f1) ;; esac
    printf '%s|%s|%s|%s|%s|%s|%s|%s|%s|%s|%s|%s|%s\n' "$id" "$(printf '%s' "$line" | cut -d'|' -f3)" \
        "$(printf '%s' "$line" | cut -d'|' -f2)" "$ms" "$(field "$json" mean_primary_steps)" \
        "$(field "$json" mean_shadow_steps)" "$(field "$json" mean_secondary_steps)" "$(field "$json" mean_steps)" \
        "$(field "$json" secondary_rays) $(field "$json" primary_rays)" "$cost" \
        "$(field "$json" dynamic_eps_from_f) $(field "$json" dynamic_eps_hits)" \
        "$(field "$json" secondary_self_hits)" "$(field "$json" cpu_ms)"
}

# A technique's effect on time: the median of the per-round ratios A/B and
# its 95% interval, as percent changes.
effect() {
    paste -d' ' "$tmp/ms/$1" "$tmp/ms/$2" | page_stats --ratio |
        awk '{ printf "%+.1f%% [%+.1f%%, %+.1f%%]", 100 * ($1 - 1), 100 * ($2 - 1), 100 * ($3 - 1) }'
}

# A count's change A over B, in percent.
change() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%+.1f%%", (b > 0 ? 100 * (a - b) / b : 0) }'; }

# Mean evaluations per pixel of row id: total, secondary.
total() { field "$(cat "$tmp/json/$1")" mean_steps; }
secondary() { field "$(cat "$tmp/json/$1")" mean_secondary_steps; }
primary() { field "$(cat "$tmp/json/$1")" mean_primary_steps; }

page() {
    page_header "Enhanced sphere tracing: each technique against the paper" "$command"
    cat <<EOF
Keinert et al.'s jewel and convex-object measurements repeated on our scenes: \`jewel\` (a glass
brilliant, a red bead and a mirror ball over a checker floor) and \`dodecahedron\` with
\`--materials\` (a glass dodecahedron in its bounding sphere, the paper's Fig. 11 scene), ${width}x${height},
2 reflective and 8 refractive bounces (\`--bounces 2,8\`), one hard shadow ray per lit hit, counted
the papers' way (\`--papers\`), \`--threads $threads\` ($(nproc) cores). *relaxed* is Keinert et al.'s
Listing 2 (\`--method relaxed\`: after the first failed step, plain sphere tracing for the rest of the
ray), *relaxed-bv* Bán and Valasek's Algorithm 2 (relaxed again after each fallback); omega 1.2, the
paper's. *ms* is processor time (\`cpu_ms\`): the median of $repeat rounds, each running every row once
back to back in a rotating order, with its 95% bootstrap interval in brackets. The evaluations are
per pixel and exact (every round repeats them): *primary* (3.4's settling iterations included),
*shadow*, *secondary* (reflection and refraction rays), *total*; *sec. rays* is reflection and
refraction rays per pixel; *changed* is the share of pixels whose colour differs by more than 16/255
from a converged render (sphere tracing to eps 1e-5, 100000 steps, eps_min 1e-4). The paper measured
on a GPU at 1280x720 and timed tracing alone; we trace on the CPU and time the whole frame, shading
included.

![the jewel](jewel.png)

EOF
    for id in $(printf '%s\n' "$rows" | cut -d'|' -f1); do row_fields "$id"; done >"$tmp/fields"
    awk -F'|' '
        BEGIN {
            print "| row | ms | primary | shadow | secondary | total | sec. rays | changed |"
            print "|---|--:|--:|--:|--:|--:|--:|--:|"
        }
        {
            split($9, r, " ")
            printf "| %s (%s) | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n", $2, $3, $4, $5, $6, $7, $8,
                   (r[2] > 0 ? r[1] / r[2] : 0), ($10 == "-" ? "–" : sprintf("%.2f%%", 100 * $10))
        }
    ' "$tmp/fields"

    cat <<EOF

### Time, beside the paper's times

Each technique's effect on the frame's processor time: the median over the rounds of the ratio of
the two rows timed in that round, as a change, with its 95% bootstrap interval. An interval that
holds 0 is no measured effect. The paper's numbers are GPU times of tracing alone.

| technique | the paper's time | here: time |
|---|---|--:|
| over-relaxation, ray casting alone (3.1) | 2.978 vs 3.472 ms: -14.2% | $(effect cast-relaxed cast-sphere) |
| over-relaxation, 2 + 8 bounces, with 3.2-3.5 (3.1) | 21.11 vs 22.47 ms: -6.1% | $(effect all-relaxed all-sphere) |
| over-relaxation, 2 + 8 bounces, alone (3.1) | (not reported) | $(effect plain-relaxed plain-sphere) |
| Algorithm 2's form instead, 2 + 8 bounces, alone | (not in the paper) | $(effect plain-relaxed-bv plain-sphere) |
| screen-space criterion (3.2) | no time given | $(effect screen plain-relaxed) |
| discontinuity reduction, 3 iterations (3.4) | "a low, fixed cost", no time given | $(effect smooth plain-relaxed) |
| convex optimization, glass dodecahedron, the paper's Fig. 11 scene (3.5) | 2.73 vs 3.03 ms: -9.9% | $(effect dodeca-convex dodeca-plain) |
| convex optimization, jewel (3.5) | no jewel figure for 3.5 | $(effect convex plain-relaxed) |

### Evaluations (the paper reports none)

The same comparisons in exact SDF evaluations per pixel, all rays of the frame:

| technique | evaluations | of them |
|---|--:|---|
| over-relaxation, ray casting alone | $(change "$(primary cast-relaxed)" "$(primary cast-sphere)") | relaxed-bv: $(change "$(primary cast-relaxed-bv)" "$(primary cast-sphere)") |
| over-relaxation, 2 + 8 bounces, with 3.2-3.5 | $(change "$(total all-relaxed)" "$(total all-sphere)") | |
| over-relaxation, 2 + 8 bounces, alone | $(change "$(total plain-relaxed)" "$(total plain-sphere)") | relaxed-bv: $(change "$(total plain-relaxed-bv)" "$(total plain-sphere)") |
| screen-space criterion | $(change "$(total screen)" "$(total plain-relaxed)") | primary $(change "$(primary screen)" "$(primary plain-relaxed)") |
| discontinuity reduction, 3 iterations | $(change "$(total smooth)" "$(total plain-relaxed)") | |
| convex optimization, glass dodecahedron | $(change "$(total dodeca-convex)" "$(total dodeca-plain)") | secondary $(change "$(secondary dodeca-convex)" "$(secondary dodeca-plain)") |
| convex optimization, jewel | $(change "$(total convex)" "$(total plain-relaxed)") | secondary $(change "$(secondary convex)" "$(secondary plain-relaxed)") |

## The dynamic epsilon (3.3)

A secondary ray leaves hit p by 2 max(eps_min, |f(p)|) along the normal. *|f| decided* is the share
of the hits sending rays where |f(p)| > eps_min set that offset; *self-hits* the share of secondary
rays that hit within 2 eps_min of where they started, their own surface again; *changed* as above.
The default eps_min is the scene's feature size, the normal's difference step (1e-3 here).

EOF
    awk -F'|' '
        BEGIN {
            print "| eps_min | evaluations | sec. rays | \\|f\\| decided | self-hits | changed | ms |"
            print "|---|--:|--:|--:|--:|--:|--:|"
        }
        $1 ~ /^(eps-|ss-eps-|plain-relaxed$)/ {
            split($9, r, " "); split($11, f, " ")
            printf "| %s | %.2f | %.2f | %.1f%% | %.1f%% | %.2f%% | %s |\n", $2, $8, (r[2] > 0 ? r[1] / r[2] : 0),
                   (f[2] > 0 ? 100 * f[1] / f[2] : 0), (r[1] > 0 ? 100 * $12 / r[1] : 0), 100 * $10, $4
        }
    ' "$tmp/fields"
    awk -F'|' '
        { split($9, r, " "); split($11, f, " "); rays[$1] = r[2] > 0 ? r[1] / r[2] : 0
          self[$1] = r[1] > 0 ? $12 / r[1] : 0; fromf[$1] = f[2] > 0 ? f[1] / f[2] : 0; cost[$1] = $10; ev[$1] = $8 }
        END {
            print ""
            most = 0
            split("eps-1e-4 plain-relaxed eps-1e-2", constant, " ")
            for (k in constant)
                most = fromf[constant[k]] > most ? fromf[constant[k]] : most
            printf "With a constant eps and eps_min at or above it, every hit is refined onto the surface, so |f(p)|\n"
            printf "decides at most %.1f%% of the offsets: those rows sweep a fixed offset, the refinement making the\n",
                   100 * most
            print "|f(p)| term unnecessary there. Where hits are left off the surface, the screen-space criterion"
            printf "with 3.4 settling each on f = eps(t), |f(p)| decides %.1f%% of them at the default eps_min, and\n",
                   100 * fromf["ss-eps-default"]
            printf "there eps_min 1e-5 costs nothing: |f(p)| decides %.1f%%, %.2f%% of the secondary rays re-hit their\n",
                   100 * fromf["ss-eps-1e-5"], 100 * self["ss-eps-1e-5"]
            print "surface. With a constant eps, eps_min 1e-5 lies below the trace'"'"'s eps = 1e-4: a ray that starts"
            print "2e-5 off the surface is within eps of it at its first evaluation and hits where it starts (and"
            printf "|f(p)| = 2e-5 there decides the next offset: %.1f%% of that row'"'"'s hits). %.1f%% of its secondary\n",
                   100 * fromf["eps-1e-5"], 100 * self["eps-1e-5"]
            printf "rays are such self-hits, and each spends a bounce on the next ray: %.1f secondary rays per pixel\n",
                   rays["eps-1e-5"]
            printf "instead of %.1f, and %.2f%% of the pixels changed. eps_min 1e-2 saves %.1f%% of the default'"'"'s\n",
                   rays["plain-relaxed"], 100 * cost["eps-1e-5"],
                   100 * (ev["plain-relaxed"] - ev["eps-1e-2"]) / ev["plain-relaxed"]
            printf "evaluations and changes %.2f%% of the pixels (the default: %.2f%%).\n", 100 * cost["eps-1e-2"],
                   100 * cost["plain-relaxed"]
        }
    ' "$tmp/fields"

    cat <<EOF

## Quality where the paper claims it: 3.2 and 3.4

![image error against the step cap](keinert-quality.png)

The paper shows the screen-space criterion (3.2, Fig. 8: a thin layer of wrong pixels along a
silhouette disappears) and discontinuity reduction (3.4, Figs. 9-10) in pictures, at capped
iteration counts. Here, \`city\` and \`temple\` with their materials (a checker floor: a procedural
texture), relaxed omega 1.2, counted the papers' way, each image against the same scene traced to
eps = 1e-4 with 100000 steps: the share of pixels beyond 16/255, over all pixels, at the converged
image's silhouettes (a hit and a miss, or depths 5% apart, side by side) and in its farthest
quarter of depths. *eps*: a constant eps = 1e-4, where a ray that reaches the cap shows the sky (our
renderer does not shade its last point); *ss*: the screen-space criterion and its best candidate;
*+ 3.4*: three settling iterations on every hit. Evaluations per pixel, all rays, in brackets.

EOF
    awk '
        NF == 0 { next }
        { key = $1 " " $2; v[key, $3] = sprintf("%.2f%% / %.2f%% / %.2f%% (%.1f)", 100 * $4, 100 * $5, 100 * $6, $7)
          if (!(key in seen)) { seen[key] = 1; order[++n] = key } }
        END {
            print "| scene, configuration | cap 16 | cap 32 | cap 64 | cap 128 |"
            print "|---|--:|--:|--:|--:|"
            for (i = 1; i <= n; i++)
                printf "| %s | %s | %s | %s | %s |\n", order[i], v[order[i], 16], v[order[i], 32], v[order[i], 64],
                       v[order[i], 128]
            print ""
            print "Each cell: all pixels / silhouettes / far away, beyond 16/255 of the converged image."
        }
    ' "$tmp/quality.dat"
    awk -v caps="$quality_caps" '
        NF == 0 { next }
        { all[$1, $2, $3] = $4; far[$1, $2, $3] = $6; sil[$1, $2, $3] = $5 }
        END {
            print ""
            nc = split(caps, cap, " ")
            for (s = 1; s <= 2; s++) {
                sc = s == 1 ? "city" : "temple"
                better = ""; worse = ""
                for (k = 1; k <= nc; k++)
                    if (all[sc, "ss", cap[k]] < all[sc, "eps", cap[k]])
                        better = better (better == "" ? "" : ", ") cap[k]
                    else
                        worse = worse (worse == "" ? "" : ", ") cap[k]
                printf "On the %s the screen-space criterion leaves fewer pixels wrong than a constant eps at %s\n", sc,
                       (better == "" ? "no cap" : "caps " better)
                printf "and more at %s.\n", (worse == "" ? "none" : "caps " worse)
            }
            print "Where the cap cuts rays off, its candidate shows a surface where the plain trace shows the sky;"
            print "where rays converge anyway, its rays stop within half a pixel'"'"'s footprint of a surface they only"
            print "graze, so silhouettes and thin features grow by up to half a pixel (the inflation the paper"
            print "mentions), and the shadow rays, traced with the same criterion, grow the shadows of thin"
            print "features. 3.4 settles every hit on f = eps(t): with the screen-space criterion that lifts a hit"
            print "refined onto the surface half a pixel'"'"'s footprint off it again, which moves what is shaded"
            print "there; it helps only where the cap left a candidate short of the surface."
            print ""
            for (s = 1; s <= 2; s++) {
                sc = s == 1 ? "city" : "temple"
                printf "%s at 32 steps: the screen-space criterion changes %.2f%% of the pixels against %.2f%% without\n",
                       sc, 100 * all[sc, "ss", 32], 100 * all[sc, "eps", 32]
                printf "(silhouettes %.2f%% against %.2f%%, far away %.2f%% against %.2f%%); with 3.4 on top, %.2f%%.\n",
                       100 * sil[sc, "ss", 32], 100 * sil[sc, "eps", 32], 100 * far[sc, "ss", 32],
                       100 * far[sc, "eps", 32], 100 * all[sc, "ss-smooth", 32]
            }
        }
    ' "$tmp/quality.dat"

    awk -F'|' '
        $1 == "grid" || $1 == "plain-relaxed" { split($9, r, " "); ev[$1] = $8; cost[$1] = $10; ms[$1] = $4 }
        END {
            print ""
            print "## The jewel from a grid"
            print ""
            printf "`sdftrace bake --scene jewel --res '"$grid_res"' --materials` bakes the surface and, beside it, a grid of\n"
            print "material indices and their table; `render --grid` shades with them. The convex optimization does"
            print "not apply to a grid (it declares no convex parts), so the procedural row to compare with is the"
            printf "one without it: %.2f evaluations per pixel from the grid against %.2f procedural, %s ms against\n",
                   ev["grid"], ev["plain-relaxed"], ms["grid"]
            printf "%s ms, and %.2f%% of the pixels beyond 16/255 of the converged procedural render (procedural:\n",
                   ms["plain-relaxed"], 100 * cost["grid"]
            printf "%.2f%%), where the grid rounds the facets'"'"' edges to its voxels.\n", 100 * cost["plain-relaxed"]
        }
    ' "$tmp/fields"
}

echo "bench/keinert.sh: ${width}x${height}, threads ${threads} ($(nproc) cores), $repeat rounds" >&2
"$bin" bake --scene jewel --res "$grid_res" --materials --grid-name jewel -o "$tmp/jewel.nvdb" --quiet
reference
measure
quality
picture
page_write keinert.md page
mv -f "$tmp/jewel.png" "$dir/jewel.png"
mv -f "$tmp/keinert-quality.png" "$dir/keinert-quality.png"
echo "$(basename "$0"): wrote $dir/jewel.png, $dir/keinert-quality.png" >&2
