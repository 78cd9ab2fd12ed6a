# Fig. 3 of Bán and Valasek's auto-relaxation paper: how each method's
# hyperparameter moves the cost, relative to sphere tracing, with the
# shadow ray (solid) and without (dashed). One axis holds all three ranges:
# beta in (0, 1/2] (auto), omega in [1/2, 1] (enhanced), omega in [1, 2)
# (relaxed: the paper's Algorithm 2, relaxed-bv, and Keinert's Listing 2). Rows: the SDF evaluations of each scene, per representation
# (exact counts, free of the machine's noise); last, the processor time on
# the paper's own panel (the temple's discrete version: our full grid), the
# median of the timed passes with its 95% bootstrap interval as error bars,
# and what the frame would cost a GPU (wavefronts of 8x4 lanes) on each
# scene's full grid.
# bench/study.sh sets: term, dir, scenes (space-separated), res, out; data:
# DIR/fig3-SCENE-REP.dat, one block per method and shadow setting (auto,
# enhanced, relaxed-bv, relaxed; shadows, none): value evaluations/ST
# gpu/ST time/ST lo hi. A file swept with the shadow ray only has empty
# blocks for "none", which gnuplot does not count: blocks(file) says
# whether a file holds one block per method or two.
array rep[3] = ["procedural", "band", "full"]
array name[4] = ["auto β", "enhanced ω", "relaxed ω (Alg. 2)", "relaxed ω (Keinert's Listing 2)"]
array colour[4] = ["#009E73", "#0072B2", "#D55E00", "#E69F00"]
nm = 4
n = words(scenes)
set terminal term size 1560, 430 * (n + 1) font "sans,12"
set output out
set xrange [0 : 2]
set grid
set arrow 1 from 0.5, graph 0 to 0.5, graph 1 nohead dt 3
set arrow 2 from 1, graph 0 to 1, graph 1 nohead dt 3
set xlabel "β (auto) | ω (enhanced) | ω (relaxed)"
set key top left font ",10"
# 2 if the file has a block per method and shadow setting, 1 if only the
# shadow ray's.
blocks(f) = (system(sprintf("awk 'BEGIN { b = 0; gap = 1 } /^[^#]/ && NF { if (gap) b++; gap = 0; next } !NF { gap = 1 } END { print b }' %s", f)) + 0 >= 2 * nm) ? 2 : 1
repname(r) = r == 1 ? "procedural" : sprintf("%s %d³", r == 2 ? "narrow band" : "full grid", res)
set multiplot layout n + 1, 3 title "The hyperparameter sweep at 1000 steps, relative to sphere tracing (solid: with the shadow ray; dashed: without)"
do for [s = 1:n] {
    do for [r = 1:3] {
        file = sprintf("%s/fig3-%s-%s.dat", dir, word(scenes, s), rep[r])
        set title sprintf("%s, %s: SDF evaluations / ST", word(scenes, s), repname(r))
        per = blocks(file)
        plot 1 with lines lc rgb "#777777" dt 2 notitle, \
             for [k = 0:nm - 1] file index per * k using 1:2 with linespoints pt 7 ps 0.6 lw 2 lc rgb colour[k + 1] title name[k + 1], \
             for [k = 0:(per == 2 ? nm - 1 : -1)] file index 2 * k + 1 using 1:2 with linespoints pt 6 ps 0.6 lw 2 dt 2 lc rgb colour[k + 1] notitle
    }
}
file = sprintf("%s/fig3-temple-full.dat", dir)
set title sprintf("temple, full grid %d³: processor time / ST (median, 95%% interval)", res)
per = blocks(file)
plot 1 with lines lc rgb "#777777" dt 2 notitle, \
     for [k = 0:nm - 1] file index per * k using 1:4:5:6 with yerrorlines pt 7 ps 0.6 lw 2 lc rgb colour[k + 1] title name[k + 1], \
     for [k = 0:(per == 2 ? nm - 1 : -1)] file index 2 * k + 1 using 1:4:5:6 with yerrorlines pt 6 ps 0.6 lw 2 dt 2 lc rgb colour[k + 1] notitle
do for [s = 1:(n < 2 ? n : 2)] {
    file = sprintf("%s/fig3-%s-full.dat", dir, word(scenes, s))
    set title sprintf("%s, full grid %d³: GPU cost / ST (8x4-lane wavefronts)", word(scenes, s), res)
    per = blocks(file)
    plot 1 with lines lc rgb "#777777" dt 2 notitle, \
         for [k = 0:nm - 1] file index per * k using 1:3 with linespoints pt 7 ps 0.6 lw 2 lc rgb colour[k + 1] title name[k + 1], \
         for [k = 0:(per == 2 ? nm - 1 : -1)] file index 2 * k + 1 using 1:3 with linespoints pt 6 ps 0.6 lw 2 dt 2 lc rgb colour[k + 1] notitle
}
unset multiplot
