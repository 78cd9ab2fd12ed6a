# A badly oriented copy of an OBJ mesh, the inputs mesh2sdf's orientation
# rows measure (bench/mesh2sdf.sh):
#   awk -v kind=KIND [-v share=S] [-v seed=N] -f bench/mesh_variant.awk IN.obj > OUT.obj
# KIND: inside-out (every face reversed), reversed (a share S of the faces,
# drawn with seed N, reversed), soup (every face with its own vertices, no
# two faces sharing one), duplicated (the faces, then a reversed copy of a
# share S of them). Only "v" and "f" lines are kept; a face's corners keep
# their vertex numbers (texture and normal numbers are dropped).
BEGIN {
    if (kind !~ /^(inside-out|reversed|soup|duplicated)$/) {
        print "mesh_variant.awk: kind must be inside-out, reversed, soup or duplicated" > "/dev/stderr"
        exit 2
    }
    if (share == "")
        share = 0.5
    srand(seed == "" ? 1 : seed)
}
$1 == "v" { nv++; vx[nv] = $2; vy[nv] = $3; vz[nv] = $4; if (kind != "soup") print "v", $2, $3, $4; next }
$1 == "f" {
    nf++
    n[nf] = NF - 1
    for (k = 2; k <= NF; k++) {
        split($k, parts, "/")
        i = parts[1] + 0
        c[nf, k - 1] = i < 0 ? nv + 1 + i : i
    }
}
function face(f, reverse,    k, line) {
    line = "f"
    for (k = 1; k <= n[f]; k++)
        line = line " " c[f, reverse ? n[f] + 1 - k : k]
    print line
}
END {
    if (kind == "soup") {
        for (f = 1; f <= nf; f++) {
            line = "f"
            for (k = 1; k <= n[f]; k++) {
                print "v", vx[c[f, k]], vy[c[f, k]], vz[c[f, k]]
                line = line " " (++out)
            }
            print line
        }
        exit
    }
    for (f = 1; f <= nf; f++)
        face(f, kind == "inside-out" || (kind == "reversed" && rand() < share))
    if (kind == "duplicated")
        for (f = 1; f <= nf; f++)
            if (rand() < share)
                face(f, 1)
}
