# Fig. 3 of Bán and Valasek's auto-relaxation paper: how each method's
# hyperparameter moves the temple's frame time, relative to sphere tracing,
# with and without shadows (top row), and the SDF evaluations, relative to
# sphere tracing's (bottom row: exact counts, free of the machine's noise).
# One axis holds all three ranges: beta in (0, 1/2] (auto), omega in
# [1/2, 1] (enhanced), omega in [1, 2) (relaxed, the paper's Algorithm 2:
# relaxed-bv). Columns: representations.
# bench/study.sh sets: term, dir, res, out; data: DIR/fig3-REP.dat, one block
# per method and shadow setting (auto, enhanced, relaxed; shadows, none).
array rep[3] = ["procedural", "band", "full"]
array name[3] = ["auto β", "enhanced ω", "relaxed ω"]
array colour[3] = ["#2ca02c", "#1f77b4", "#d62728"]
set terminal term size 1560, 900 font "sans,12"
set output out
set xrange [0 : 2]
set grid
set arrow 1 from 0.5, graph 0 to 0.5, graph 1 nohead dt 3
set arrow 2 from 1, graph 0 to 1, graph 1 nohead dt 3
set multiplot layout 2, 3 title "temple, 1000 steps: the hyperparameter sweep, relative to sphere tracing"
do for [row = 1:2] {
    do for [r = 1:3] {
        file = sprintf("%s/fig3-%s.dat", dir, rep[r])
        set title sprintf("%s — %s", r == 1 ? "procedural" : sprintf("%s %d³", r == 2 ? "narrow band" : "full grid", res), row == 1 ? "frame time / ST" : "SDF evaluations / ST")
        set xlabel "β (auto) | ω (enhanced) | ω (relaxed)"
        if (row == 2) { set key top left font ",10" } else { unset key }
        plot 1 with lines lc rgb "#777777" dt 2 title "ST", \
             for [k = 0:2] file index 2 * k using 2:(column(3 + row)) with linespoints pt 7 ps 0.6 lw 2 lc rgb colour[k + 1] title name[k + 1] . ", shadows", \
             for [k = 0:2] file index 2 * k + 1 using 2:(column(3 + row)) with linespoints pt 6 ps 0.6 lw 2 dt 2 lc rgb colour[k + 1] title name[k + 1] . ", none"
    }
}
unset multiplot
