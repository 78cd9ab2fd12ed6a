#!/bin/sh
# Every C and C++ source the repository tracks matches .clang-format:
#   tests/check_format.sh [CLANG_FORMAT]
# Names each file that does not (fix it with `clang-format -i FILE`) and
# exits non-zero; the test data and generated files are not sources.
cd "$(dirname "$0")/.." || exit 1
format=${1:-clang-format}
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    files=$(git ls-files '*.c' '*.h' '*.cpp' '*.hpp')
else
    files=$(find include src convert scenes bench tests -name '*.c' -o -name '*.h' -o -name '*.cpp' -o -name '*.hpp')
fi
checked=0 wrong=0
for f in $files; do
    [ -f "$f" ] || continue
    checked=$((checked + 1))
    if ! "$format" --dry-run --Werror "$f" >/dev/null 2>&1; then
        echo "not formatted: $f (clang-format -i $f)"
        wrong=$((wrong + 1))
    fi
done
echo "$((checked - wrong)) passed, $wrong failed"
[ "$wrong" -eq 0 ]
