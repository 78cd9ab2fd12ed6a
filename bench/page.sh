# bench/page.sh: sourced by the benchmark scripts, which each write their
# own results page under bench/results/ (PAGE_DIR overrides the folder), so
# that a page always describes the run that wrote it.
#
#   page_header TITLE COMMAND   a Markdown title, then the command that made
#                               the page, the date, the machine and the commit
#   page_write NAME FUNCTION [ARGS...]
#                               runs FUNCTION with its output going to a page
#                               (a temporary file beside PAGE_DIR/NAME); once
#                               it succeeds, prints the page and moves it into
#                               place; when it fails, the old page stays
# The caller sets $root (the repository) first.

page_header() {
    printf '# %s\n\n' "$1"
    printf 'Made by `%s`\n\n' "$2"
    printf -- '- date: %s\n' "$(date -u '+%Y-%m-%d %H:%M UTC')"
    printf -- '- machine: %s, %s cores (`nproc`), load %s at the start\n' \
        "$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)" "$(nproc)" "$(cut -d' ' -f1 /proc/loadavg)"
    printf -- '- commit: %s\n\n' "$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
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
    chmod "$(printf '%o' $((0666 & ~$(umask))))" "$_page_tmp"
    cat "$_page_tmp"
    mv -f "$_page_tmp" "$_page"
    echo "$(basename "$0"): wrote $_page" >&2
}
