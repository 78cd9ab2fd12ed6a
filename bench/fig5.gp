# Fig. 5 of Bán and Valasek's auto-relaxation paper: the mean step
# multiplier of the steps auto-relaxation (beta 0.3) takes along each
# pixel's primary ray, z / r = 2 / (1 - m) (Algorithm 4, line 14; a refused
# trial, a fallback, is no step taken), black for 1 (a plain
# sphere-tracing step) to white for 2 (the step that is right for a plane
# met head on). Pixels whose ray took no step (it left the scene's box at
# once) are dark blue. No shadows, 1000 steps.
# bench/study.sh sets: term, dir, res, out; the panels are the lines of
# DIR/fig5.txt (subject representation width height mean), each map a
# float32 plane DIR/fig5-SUBJECT-REP.f32.
panels = system(sprintf("grep -v '^#' %s/fig5.txt | awk '{ print $1 \"/\" $2 }' | xargs", dir))
np = words(panels)
w = real(system(sprintf("grep -v '^#' %s/fig5.txt | awk 'NR == 1 { print $3 }'", dir)))
h = real(system(sprintf("grep -v '^#' %s/fig5.txt | awk 'NR == 1 { print $4 }'", dir)))
cols = np < 3 ? np : 3
rows = (np + cols - 1) / cols
set terminal term size 520 * cols + 120, (520 * cols + 120) * 0 + 330 * rows + 60 font "sans,12"
set output out
set palette gray
set cbrange [1 : 2]
unset xtics; unset ytics; unset key
set border 0
set xrange [0 : w]; set yrange [0 : h]
set object 1 rectangle from graph 0, 0 to graph 1, 1 behind fillcolor rgb "#1f2f5f" fillstyle solid noborder
set multiplot layout rows, cols title "Auto-relaxation's mean step multiplier per pixel (β = 0.3; black 1, white 2; dark blue: no step)"
do for [p = 1:np] {
    panel = word(panels, p)
    slash = strstrt(panel, "/")
    subject = panel[1:slash - 1]
    rep = panel[slash + 1:]
    median = system(sprintf("awk '$1 == \"%s\" && $2 == \"%s\" { printf \"%%.2f, %%.1f%%%%\", $5, 100 * $6 }' %s/fig5.txt", subject, rep, dir))
    set title sprintf("%s, %s (median pixel, above 2: %s)", subject, rep eq "procedural" ? "procedural" : sprintf("%s %d³", rep, res), median) noenhanced
    if (p % cols == 0 || p == np) { set colorbox } else { unset colorbox }
    plot sprintf("%s/fig5-%s-%s.f32", dir, subject, rep) binary array=(w, h) format='%float32' flipy with image
}
unset multiplot
