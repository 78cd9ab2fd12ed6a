# Fig. 1 of Bán and Valasek's auto-relaxation paper, for one scene and
# representation: per-pixel SDF evaluations (top row) and fallbacks (bottom
# row) of the primary rays, for enhanced (omega 0.88), relaxed (the paper's
# Algorithm 2, relaxed-bv, omega 1.5) and auto-relaxed (beta 0.3) sphere tracing; each row on one shared scale,
# green (few) to red (many), as `sdftrace render --heatmap` draws it.
# bench/study.sh sets: term, dir, scene, rep, smax, fmax, w, h, res, out.
# The maps are bench/study's uint32 planes, DIR/fig1-SCENE-REP-METHOD-{steps,fallbacks}.u32.
set terminal term size 1560, 640 font "sans,12"
set output out
set palette defined (0 '#00c800', 0.5 '#ffc800', 1 '#ff0000')
unset xtics; unset ytics; unset key
set border 0
set xrange [0:w]; set yrange [0:h]
array method[3] = ["enhanced0.88", "relaxed-bv1.5", "auto0.3"]
array label[3] = ["enhanced, ω = 0.88", "relaxed (Alg. 2), ω = 1.5", "auto-relaxed, β = 0.3"]
what = rep eq "procedural" ? "procedural" : sprintf("%s %d³", rep eq "band" ? "narrow band," : "full grid,", res)
set multiplot title sprintf("%s, %s: primary rays, no shadows, 1000 steps — each row on one scale", scene, what)
pw = 0.29; ph = 0.42
do for [row = 0:1] {
    kind = row == 0 ? "steps" : "fallbacks"
    set cbrange [0 : (row == 0 ? smax : fmax)]
    do for [col = 1:3] {
        set origin 0.005 + (col - 1) * pw, 0.47 - row * 0.46
        set size pw, ph
        set lmargin 0; set rmargin 0; set tmargin 1.5; set bmargin 0
        set title sprintf("%s: %s", label[col], row == 0 ? "SDF evaluations" : "fallbacks")
        if (col == 3) {
            set colorbox user origin 0.9, 0.49 - row * 0.46 size 0.015, 0.36
            set cbtics out
            set cblabel (row == 0 ? "evaluations per pixel" : "fallbacks per pixel")
        } else {
            unset colorbox
        }
        plot sprintf("%s/fig1-%s-%s-%s-%s.u32", dir, scene, rep, method[col], kind) \
            binary array=(w, h) format='%uint32' flipy with image
    }
}
unset multiplot
