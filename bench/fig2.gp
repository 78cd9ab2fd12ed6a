# Fig. 2 of Bán and Valasek's auto-relaxation paper: the share of primary
# rays not yet finished after k SDF evaluations, one curve per method of the
# paper's table, for each subject (rows) and representation (columns). No
# shadows, 1000 steps. Both axes logarithmic, so that the whole range shows:
# the first evaluations, where the methods part, and the tail of rays that
# graze the surface, down to the last pixel. Each method has its own colour
# (Okabe and Ito's palette, told apart by colour-blind readers too) and its
# own dash pattern.
# bench/study.sh sets: term, dir, subjects (space-separated), res, out; the
# data are bench/study's DIR/fig2-SUBJECT-REP.dat, whose header line names
# the methods.
array scene_rep[3] = ["procedural", "band", "full"]
array mesh_rep[3] = ["vdb_tool", "mesh2sdf", ""]
# In the table's order: ST, ENH, REL 1.2, REL 1.5 (Algorithm 2: dashed), REL-K 1.2, REL-K 1.5
# (Keinert's Listing 2: dash-dotted, the same colours), AR 0.3, AR 0.2 (solid, thick).
array colour[8] = ["#000000", "#0072B2", "#E69F00", "#D55E00", "#E69F00", "#D55E00", "#009E73", "#CC79A7"]
array dash[8] = [1, 1, 2, 2, 4, 4, 1, 1]
array width[8] = [2, 2.5, 2, 2, 2, 2, 3.5, 2.5]
n = words(subjects)
set terminal term size 1560, 430 * n font "sans,12"
set output out
set logscale xy
set format y "10^{%T}"
set yrange [5e-7 : 1.3]
set xrange [1 : *]
set grid xtics ytics mxtics
set xlabel "SDF evaluations k"
set ylabel "rays not finished after k"
set key top right font ",10" samplen 3
set multiplot layout n, 3 title "Share of primary rays still marching after k evaluations (no shadows, 1000 steps)"
do for [s = 1:n] {
    subject = word(subjects, s)
    mesh = system(sprintf("test -f %s/fig2-%s-procedural.dat || echo 1", dir, subject)) eq "1"
    do for [r = 1:3] {
        rep = mesh ? mesh_rep[r] : scene_rep[r]
        file = sprintf("%s/fig2-%s-%s.dat", dir, subject, rep)
        if (rep eq "" || system(sprintf("test -f %s && echo 1", file)) ne "1") {
            set multiplot next
        } else {
            stats file using 1 nooutput
            methods = STATS_columns - 1
            set title sprintf("%s, %s", subject, rep eq "procedural" ? "procedural" : sprintf("%s %d³", rep eq "band" ? "narrow band" : rep eq "full" ? "full grid" : rep, res)) noenhanced
            plot for [m = 1:methods] file using ($1 >= 1 ? $1 : 1/0):(column(m + 1) > 0 ? column(m + 1) : 1/0) \
                with lines lw width[m] dt dash[m] lc rgb colour[m] title columnheader(m + 1)
        }
    }
}
unset multiplot
