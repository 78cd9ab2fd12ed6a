# The step cap swept: for each scene (two rows each) and representation
# (columns), the share of primary rays that reach the cap without
# converging (upper row) and what the frame costs a GPU in wavefronts of
# 8x4 lanes, per pixel (lower row), against the cap, one curve per method of
# the paper's table, with the hard shadow ray. The cap is where a real-time
# renderer spends its budget: Bán and Valasek's 32, Keinert's 64 and 80.
# bench/study.sh sets: term, dir, scenes (space-separated), res, out; data:
# DIR/caps.dat, one block per scene, representation and method:
# cap evaluations/px not_converged_% gpu_cost/px.
array rep[3] = ["procedural", "band", "full"]
array title[8] = ["", "", "", "", "", "", "", ""] # read from caps.dat below
# In the table's order: ST, ENH, REL 1.2, REL 1.5 (Algorithm 2: dashed), REL-K 1.2, REL-K 1.5
# (Keinert's Listing 2: dash-dotted, the same colours), AR 0.3, AR 0.2 (solid, thick).
array colour[8] = ["#000000", "#0072B2", "#E69F00", "#D55E00", "#E69F00", "#D55E00", "#009E73", "#CC79A7"]
array dash[8] = [1, 1, 2, 2, 4, 4, 1, 1]
file = sprintf("%s/caps.dat", dir)
methods = int(system(sprintf("grep -c '^# %s procedural ' %s", word(scenes, 1), file)))
do for [m = 1:methods] { title[m] = system(sprintf("grep '^# %s procedural ' %s | sed -n '%dp' | cut -d' ' -f4-", word(scenes, 1), file, m)) }
n = words(scenes)
set terminal term size 1560, 400 * 2 * n font "sans,12"
set output out
set logscale x 2
set xlabel "step cap"
set grid
set key top right font ",10"
repname(r) = r == 1 ? "procedural" : sprintf("%s %d³", r == 2 ? "narrow band" : "full grid", res)
set multiplot layout 2 * n, 3 title "The step cap: rays not converged and a GPU's cost (with the shadow ray)"
do for [s = 1:n] {
    do for [what = 1:2] {
        do for [r = 1:3] {
            set title sprintf("%s, %s: %s", word(scenes, s), repname(r), what == 1 ? "primary rays not converged, %" : "GPU cost, evaluations per pixel")
            base = ((s - 1) * 3 + (r - 1)) * methods
            plot for [m = 1:methods] file index base + m - 1 using 1:(what == 1 ? $3 : $4) with linespoints pt 7 ps 0.6 lw (m >= 7 ? 3 : 2) dt dash[m] lc rgb colour[m] title title[m]
        }
    }
}
unset multiplot
