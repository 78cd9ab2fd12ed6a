/* study — Fig. 5's instrument: the step multipliers a tracing variant
 * computes along each primary ray of a frame (study.h:
 * study_multiplier_map).
 *
 * The multiplier of a step is z / r, the step over the distance at the
 * point it leaves: auto-relaxation's 2 / (1 - m) (Bán–Valasek, Algorithm
 * 4, line 14), relaxation's omega, 1 for sphere tracing and for the plain
 * step after a fallback. A pixel's value is the mean over the steps its ray
 * took; a trial that was refused (a fallback, counted in Fig. 1) took none. Nothing in the library is changed to see
 * them: the library's own tracer traces each pixel's primary ray again through a field that logs every evaluation, t
 * along the ray and the value, and the march is replayed from the log: from the accepted point (t, r), the trial point
 * T with value R is the step z = T - t, accepted when z <= r + |R| (the unbounding spheres overlap: every variant's
 * line 7; `accepted` below), until an accepted r is within eps (the evaluations after it refine the hit). A multiplier
 * is exact to the rounding of t, a few parts in a thousand for the last steps before a hit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "study.h"

typedef struct eval_log {
    const sdft_field *inner;
    sdft_vec3 org, dir;
    double *t;
    float *r;
    uint32_t n, cap;
} eval_log;

static float logged_distance(const void *ctx, sdft_scratch *s, sdft_vec3 p)
{
    eval_log *log = (eval_log *)ctx;
    const float r = log->inner->distance(log->inner->ctx, s, p);
    if (log->n < log->cap) {
        const sdft_vec3 d = sdft_sub(p, log->org);
        log->t[log->n] = (double)d.x * log->dir.x + (double)d.y * log->dir.y + (double)d.z * log->dir.z;
        log->r[log->n] = r;
    }
    log->n++;
    return r;
}

static void logged_scratch_init(const void *ctx, sdft_scratch *s)
{
    const eval_log *log = ctx;
    if (log->inner->scratch_init)
        log->inner->scratch_init(log->inner->ctx, s);
}

/* Whether the march accepted trial k, from (t, r). The tracer decides
 * z <= r + |R| with its own z, of which T - t is z rounded once more (T =
 * t + z in float): where the two sides lie within a few units in the last
 * place of t, the next trial says what was decided, as after a fallback
 * sphere tracing, enhanced, auto-relaxed and Algorithm 2 step z = r from
 * the point they stayed at (Keinert's Listing 2 steps back from the failed
 * point instead, so its replay is exact only away from such ties). */
static int accepted(const eval_log *log, uint32_t k, double t, float r)
{
    const double z = log->t[k] - t, slack = (double)r + fabs((double)log->r[k]);
    const double ulps = 8.0 * fmax(fabs(t), fabs(log->t[k])) * 0x1p-24;
    if (fabs(z - slack) > ulps || k + 1 >= log->n || k + 1 >= log->cap)
        return z <= slack;
    return fabs(log->t[k + 1] - (t + (double)r)) > ulps;
}

/* The mean multiplier of the steps the logged march took (its accepted
 * trials), and their number; NAN when it took none. */
static float replay(const eval_log *log, float eps, uint32_t *steps)
{
    *steps = 0;
    if (log->n < 2)
        return NAN;
    double t = log->t[0], sum = 0.0;
    float r = log->r[0];
    for (uint32_t k = 1; k < log->n && k < log->cap && r > eps; k++)
        if (accepted(log, k, t, r)) {
            sum += (log->t[k] - t) / (double)r;
            ++*steps;
            t = log->t[k], r = log->r[k];
        }
    return *steps ? (float)(sum / *steps) : NAN;
}

int study_multiplier_map(const sdft_field *f, const sdft_trace_params *tp, const sdft_camera *camera, int width,
                         int height, const uint32_t *expect_steps, float *map, uint32_t *steps, char *msg,
                         size_t msg_len)
{
    eval_log log = {.inner = f, .cap = tp->max_steps + 64};
    log.t = malloc(log.cap * sizeof *log.t);
    log.r = malloc(log.cap * sizeof *log.r);
    int rc = 0;
    if (!log.t || !log.r) {
        snprintf(msg, msg_len, "out of memory");
        rc = -1;
    }
    sdft_field logged = *f;
    logged.distance = logged_distance, logged.scratch_init = logged_scratch_init, logged.ctx = &log;
    logged.normal = NULL, logged.material = NULL;
    sdft_scratch s;
    sdft_scratch_init(&logged, &s);
    const sdft_view view = sdft_camera_view(camera, width, height);
    for (int y = 0; y < height && !rc; y++)
        for (int x = 0; x < width && !rc; x++) {
            const size_t i = (size_t)y * (size_t)width + (size_t)x;
            const sdft_ray ray = sdft_view_ray(&view, (float)x + 0.5f, (float)y + 0.5f);
            log.org = ray.org, log.dir = ray.dir, log.n = 0;
            const sdft_hit hit = sdft_trace(&logged, &s, &ray, tp);
            if (hit.status == SDFT_INVALID || log.n != hit.steps || (expect_steps && hit.steps != expect_steps[i])) {
                snprintf(msg, msg_len, "pixel (%d, %d)'s primary ray took %u evaluations traced alone, %u in the frame",
                         x, y, hit.steps, expect_steps ? expect_steps[i] : hit.steps);
                rc = -1;
                break;
            }
            uint32_t k;
            map[i] = replay(&log, tp->eps, &k);
            if (steps)
                steps[i] = k;
        }
    free(log.t);
    free(log.r);
    return rc;
}
