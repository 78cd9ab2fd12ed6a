#!/bin/sh
# The mesh component's layers (src/mesh, DEVELOPERS.md): each folder is a
# module that includes only the modules below it, never one above or the
# C API's files at the top (but tool/, the program's, which sits above them). A file that breaks the order fails make test.
# usage: check_mesh_layers.sh SRC_MESH_DIR
cd "${1:?usage: check_mesh_layers.sh src/mesh}" || exit 1
# module: the modules it may include (besides its own folder)
allowed() {
    case "$1" in
    geometry | progress) echo "" ;;
    io | distance) echo "geometry" ;;
    sign) echo "geometry distance" ;;
    orient) echo "geometry sign" ;;
    samples | grid) echo "geometry distance sign progress" ;;
    tool) echo "geometry io distance sign orient samples grid progress top" ;; # mesh2sdf's, above the API
    *) echo "?" ;;
    esac
}
status=0
for dir in */; do
    module=${dir%/}
    ok=$(allowed "$module")
    if [ "$ok" = "?" ]; then
        echo "src/mesh/$module: a folder the layer order does not know (tests/check_mesh_layers.sh)"
        status=1
        continue
    fi
    for file in "$module"/*; do
        # every quoted include with a folder, and the top's own files
        grep -n '#include "' "$file" | while IFS= read -r line; do
            target=$(echo "$line" | sed 's/.*#include "\([^"]*\)".*/\1/')
            case "$target" in
            sdftrace/*) continue ;;
            */*) used=${target%%/*} ;;
            *) [ -f "$target" ] && used=top || continue ;; # src/common and the same folder's
            esac
            case " $module $ok " in
            *" $used "*) ;;
            *)
                echo "src/mesh/$file: includes $target, a layer above $module"
                exit 1
                ;;
            esac
        done || status=1
    done
done
exit $status
