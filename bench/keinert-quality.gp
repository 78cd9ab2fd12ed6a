# Keinert et al.'s quality claims measured (bench/keinert.sh): the share of
# pixels that differ from a converged render (100000 steps) by more than
# 16/255, against the step cap, for the screen-space criterion (3.2) and
# discontinuity reduction (3.4), over all pixels, at the reference's
# silhouettes and in its farthest quarter of depths (columns), one scene a
# row. bench/keinert.sh sets: term, data (its .dat: one block per scene and
# configuration, in the order of `scenes` and of the labels below, each line
# scene config cap all silhouettes far evaluations), scenes, out.
# configurations, in the data's order: eps, eps-smooth, ss, ss-smooth
array label[4] = ["ε = 1e-4 (a ray at the cap shows the sky)", "ε + 3.4, 3 iterations", "screen-space (3.2)", "screen-space + 3.4"]
array colour[4] = ["#000000", "#7f7f7f", "#1f77b4", "#d62728"]
array dash[4] = [1, 2, 1, 2]
array region[3] = ["all pixels", "silhouettes", "far away (farthest quarter)"]
n = words(scenes)
set terminal term size 1560, 440 * n font "sans,12"
set output out
set logscale x 2
set xtics (16, 32, 64, 128)
set xrange [14 : 146]
set logscale y
set format y "%g%%"
set grid
set xlabel "step cap (most SDF evaluations per ray)"
set ylabel "pixels beyond 16/255"
set lmargin 10
set multiplot layout n, 3 title "Pixels beyond 16/255 of a converged render (100000 steps) against the step cap: the screen-space criterion (3.2) and discontinuity reduction (3.4); 0.01%: none"
do for [s = 1:n] {
    do for [r = 1:3] {
        set title sprintf("%s, %s", word(scenes, s), region[r])
        if (s == 1 && r == 1) { set key top right font ",10" } else { unset key }
        plot for [c = 1:4] data index (4 * (s - 1) + c - 1) using 3:(100 * column(3 + r) > 0.01 ? 100 * column(3 + r) : 0.01) \
             with linespoints pt 7 ps 0.8 lw 2 dt dash[c] lc rgb colour[c] title label[c]
    }
}
unset multiplot
