# sdftrace — what bench/scaling.sh's and bench/scaling_mesh.sh's sections
# share: the clock, a number from a JSON file, one row of rows.tsv, and the
# page's tables and ratios from the rows. Sourced after bench/page.sh (its
# page_stats); `rows` (the rows' file) and `round` are the caller's.

now_ms() { echo $(($(date +%s%N) / 1000000)); }
# The thread counts a run takes when THREADS is not set: 1, the powers of
# two below nproc, and nproc.
thread_counts() {
    _cores=$(nproc) _list=1 _t=2
    while [ "$_t" -lt "$_cores" ]; do _list="$_list $_t" && _t=$((_t * 2)); done
    [ "$_cores" = 1 ] || _list="$_list $_cores"
    echo "$_list"
}
# json FILE KEY: the number KEY has in the JSON object of FILE.
json() { sed -n "s/.*\"$2\": \([-0-9.e]*\).*/\1/p" "$1"; }
# row SECTION SUBJECT TOOL THREADS METRIC VALUE: one number of this round.
row() { [ -z "$6" ] || printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$3" "$4" "$round" "$5" "$6" >>"$rows"; }

# samples SECTION SUBJECT TOOL THREADS METRIC: the numbers of every round.
samples() {
    awk -F'\t' -v a="$1" -v b="$2" -v c="$3" -v d="$4" -v e="$5" \
        '$1 == a && $2 == b && $3 == c && $4 == d && $6 == e { print $7 }' "$rows"
}

# pairs SECTION THREADS SUBJECT TOOL METRIC SUBJECT TOOL METRIC: "a b" for
# each round that has both numbers (for page_stats --ratio: a / b).
pairs() {
    awk -F'\t' -v s="$1" -v t="$2" -v s1="$3" -v t1="$4" -v m1="$5" -v s2="$6" -v t2="$7" -v m2="$8" '
        $1 != s || $4 != t { next }
        $2 == s1 && $3 == t1 && $6 == m1 { a[$5] = $7 }
        $2 == s2 && $3 == t2 && $6 == m2 { b[$5] = $7 }
        END { for (r in a) if (r in b) print a[r], b[r] }' "$rows"
}

# The median of samples on standard input ("" when there are none).
median() {
    awk 'NF { print }' | { read -r first || exit 0; { echo "$first"; cat; } | page_stats | cut -d' ' -f1; }
}

# stat_text: page_stats --text over standard input, "-" when empty.
stat_text() {
    awk 'NF { print }' | { read -r first || { echo -; exit 0; }; { echo "$first"; cat; } | page_stats --text "$@"; }
}

# table SECTION: per subject, each tool's metrics by threads (median [95%
# interval]) and Karp-Flatt's serial fraction between 1 and the most threads.
table() {
    awk -F'\t' -v s="$1" '$1 == s { print $2 }' "$rows" | sort -u | while IFS= read -r subject; do
        echo "### $subject"
        echo
        printf '| tool | ms'
        for t in $THREADS; do printf ' | %s threads' "$t"; done
        printf ' | serial fraction |\n|---|---'
        for t in $THREADS; do printf '|--:'; done
        printf '|--:|\n'
        awk -F'\t' -v s="$1" -v b="$subject" '$1 == s && $2 == b { print $3 "\t" $6 }' "$rows" | sort -u |
            while IFS="$(printf '\t')" read -r tool metric; do
                printf '| %s | %s' "$tool" "$metric"
                for t in $THREADS; do
                    printf ' | %s' "$(samples "$1" "$subject" "$tool" "$t" "$metric" | stat_text 1)"
                done
                one=$(samples "$1" "$subject" "$tool" 1 "$metric" | median)
                most=$(samples "$1" "$subject" "$tool" "$max_threads" "$metric" | median)
                awk -v a="${one:-0}" -v b="${most:-0}" -v p="$max_threads" 'BEGIN {
                    if (p > 1 && a >= 0.1 && b >= 0.1) printf " | %.2f |\n", (b / a - 1 / p) / (1 - 1 / p)
                    else print " | - |" }'
            done
        echo
    done
}

# met VALUE-TEXT OP BAR: "yes" or "no" for the median (the text's first word).
met() { awk -v v="${1%% *}" -v op="$2" -v bar="$3" 'BEGIN { ok = op == "<=" ? v + 0 <= bar : v + 0 >= bar; print ok ? "yes" : "no" }'; }

# largest_first: "NAME MS" lines on standard input as "NAME MS, NAME MS"
# (whole ms), the largest first, those under half a millisecond left out.
largest_first() { sort -k2 -g -r | awk 'NF == 2 && $2 >= 0.5 { printf "%s%s %.0f", n++ ? ", " : "", $1, $2 }'; }
