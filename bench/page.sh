# bench/page.sh: sourced by the benchmark scripts, which each write their
# own results page under bench/results/ (PAGE_DIR overrides the folder), so
# that a page always describes the run that wrote it.
#
#   page_header TITLE COMMAND   a Markdown title, then the command that made
#                               the page, the date, the machine, the commit
#                               and the load when the script began (the
#                               script sources this file before it measures)
#   page_write NAME FUNCTION [ARGS...]
#                               runs FUNCTION with its output going to a page
#                               (a temporary file beside PAGE_DIR/NAME); once
#                               it succeeds, adds the load at the end, prints
#                               the page and moves it into place; when it
#                               fails, the old page stays
#   page_stats [--ratio] [--text D] < SAMPLES
#                               the median of the samples and its 95%
#                               bootstrap interval, "MEDIAN LO HI N" (or
#                               "MEDIAN [LO–HI]"): bench/stats, the statistics
#                               bench/study uses, so that every time on every
#                               page is summarized one way. With --ratio each
#                               line is a pair A B timed side by side, and the
#                               samples are A/B.
#   page_need_stats             exits with one line unless bench/stats is built
#   page_load                   the load average now: "1 5 15" (minutes)
# The caller sets $root (the repository) first; PAGE_STATS names the stats
# program (default $root/build/bench/stats).

page_load() { cut -d' ' -f1-3 /proc/loadavg; }
_page_load_start=$(page_load)

# page_command BASE VAR...: BASE, the command that made a page, with each
# VAR that is set and not empty in front of it (VAR="value"), so that the
# page says how to run it again.
page_command() {
    _cmd=$1
    shift
    for _var in "$@"; do
        eval "_val=\${$_var:-}"
        [ -z "$_val" ] || _cmd="$_var=\"$_val\" $_cmd"
    done
    echo "$_cmd"
}

# The commit the run is from, "-dirty" when a tracked file outside
# bench/results differs from it (the pages a run writes are not a change
# to what made them).
page_commit() {
    _c=$(git -C "$root" rev-parse --short HEAD 2>/dev/null) || { echo unknown; return; }
    git -C "$root" diff --quiet HEAD -- . ':(exclude)bench/results' 2>/dev/null || _c="$_c-dirty"
    echo "$_c"
}

page_header() {
    printf '# %s\n\n' "$1"
    printf 'Made by `%s`\n\n' "$2"
    printf -- '- date: %s\n' "$(date -u '+%Y-%m-%d %H:%M UTC')"
    printf -- '- machine: %s, %s cores (`nproc`)\n' \
        "$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)" "$(nproc)"
    printf -- '- load average (1, 5, 15 minutes) when the run began: %s\n' "$_page_load_start"
    printf -- '- commit: %s\n\n' "$(page_commit)"
}

page_stats() { "${PAGE_STATS:-$root/build/bench/stats}" "$@"; }

page_need_stats() {
    [ -x "${PAGE_STATS:-$root/build/bench/stats}" ] ||
        { echo "$(basename "$0"): no ${PAGE_STATS:-$root/build/bench/stats} (build it: make build)" >&2; exit 1; }
}

page_write() {
    _page_dir=${PAGE_DIR:-$root/bench/results}
    _page=$_page_dir/$1
    shift
    mkdir -p "$_page_dir"
    _page_tmp=$(mktemp "$_page_dir/.$(basename "$_page").tmp-XXXXXX")
    # In a subshell with errexit of its own: a failing step stops the page.
    set +e
    (set -e; "$@") >"$_page_tmp"
    _page_rc=$?
    set -e
    if [ "$_page_rc" != 0 ]; then
        rm -f "$_page_tmp"
        echo "$(basename "$0"): failed; $_page left as it was" >&2
        exit "$_page_rc"
    fi
    printf '\nLoad average (1, 5, 15 minutes) when the run began: %s; at its end: %s (%s cores).\n' \
        "$_page_load_start" "$(page_load)" "$(nproc)" >>"$_page_tmp"
    chmod "$(printf '%o' $((0666 & ~$(umask))))" "$_page_tmp"
    cat "$_page_tmp"
    mv -f "$_page_tmp" "$_page"
    echo "$(basename "$0"): wrote $_page" >&2
}
