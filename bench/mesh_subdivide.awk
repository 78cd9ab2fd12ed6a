# Splits every triangle of an OBJ into four at its edges' midpoints (one
# shared vertex per edge, so a closed mesh stays closed), polygons fanned
# into triangles first: a mesh with four times the faces on the same
# surface, for benchmarks that need a larger mesh than the repository has.
# Reads v and f lines (v, v/t, v/t/n, negative indices); writes v and f.
#
# usage: awk -f bench/mesh_subdivide.awk IN.obj >OUT.obj
$1 == "v" { n++; x[n] = $2; y[n] = $3; z[n] = $4; print "v", $2, $3, $4; next }
# Faces wait for the end, so that every new vertex comes after the file's.
$1 == "f" {
    for (i = 2; i <= NF; i++) {
        split($i, part, "/")
        corner[i - 1] = part[1] < 0 ? n + 1 + part[1] : part[1]
    }
    for (i = 2; i + 1 <= NF - 1; i++)
        tri[++faces] = corner[1] " " corner[i] " " corner[i + 1]
    next
}
END {
    for (f = 1; f <= faces; f++) {
        split(tri[f], c, " ")
        split4(c[1], c[2], c[3])
    }
    for (l = 1; l <= lines; l++)
        print out[l]
}
function mid(a, b,    key) {
    key = a < b ? a "," b : b "," a
    if (!(key in made)) {
        n++
        x[n] = (x[a] + x[b]) / 2; y[n] = (y[a] + y[b]) / 2; z[n] = (z[a] + z[b]) / 2
        printf "v %.9g %.9g %.9g\n", x[n], y[n], z[n]
        made[key] = n
    }
    return made[key]
}
function split4(a, b, c,    ab, bc, ca) {
    ab = mid(a, b); bc = mid(b, c); ca = mid(c, a)
    out[++lines] = "f " a " " ab " " ca
    out[++lines] = "f " ab " " b " " bc
    out[++lines] = "f " ca " " bc " " c
    out[++lines] = "f " ab " " bc " " ca
}
