# Fig. 2 of Bán and Valasek's auto-relaxation paper: the share of primary
# rays not yet finished after k SDF evaluations, one curve per method, for
# each scene (rows) and representation (columns). No shadows, 1000 steps.
# bench/study.sh sets: term, dir, scenes (space-separated), res, out; the
# data are bench/study's DIR/fig2-SCENE-REP.dat.
array rep[3] = ["procedural", "band", "full"]
array title[6] = ["ST", "ENH 0.88", "REL 1.2", "REL 1.5", "AR 0.3", "AR 0.2"]
array colour[6] = ["#000000", "#1f77b4", "#ff7f0e", "#d62728", "#2ca02c", "#17becf"]
n = words(scenes)
set terminal term size 1560, 480 * n font "sans,12"
set output out
set logscale y
set format y "10^{%T}"
set yrange [1e-4 : 1.2]
set xrange [0 : 150]
set grid
set xlabel "SDF evaluations k"
set ylabel "rays not finished after k"
set key top right
set multiplot layout n, 3 title "Share of primary rays still marching after k evaluations (no shadows, 1000 steps)"
do for [s = 1:n] {
    do for [r = 1:3] {
        file = sprintf("%s/fig2-%s-%s.dat", dir, word(scenes, s), rep[r])
        set title sprintf("%s, %s", word(scenes, s), r == 1 ? "procedural" : sprintf("%s %d³", r == 2 ? "narrow band" : "full grid", res))
        plot for [m = 1:6] file using 1:(column(m + 1) > 0 ? column(m + 1) : 1/0) with lines lw 2 lc rgb colour[m] title title[m]
    }
}
unset multiplot
