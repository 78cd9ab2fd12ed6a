// sdftrace — a mesh asked at points: signed distances and winding numbers
// (sdft_mesh_signed_distance, sdft_mesh_winding_number) and training
// samples (sdft_mesh_samples), the converter's own answers (query.h,
// samples.h), in parallel.
#include "api.h"

#include "samples/samples.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

using namespace meshsdf::api;

namespace
{

// Point i of pts, in double.
void pointAt(const sdft_mesh_points &pts, size_t i, double *p)
{
    const ptrdiff_t width = pts.type == SDFT_MESH_FLOAT32 ? 4 : 8;
    const ptrdiff_t row = pts.stride[0] || pts.stride[1] ? pts.stride[0] : 3 * width;
    const ptrdiff_t column = pts.stride[0] || pts.stride[1] ? pts.stride[1] : width;
    const char *at = static_cast<const char *>(pts.data) + ptrdiff_t(i) * row;
    for (int k = 0; k < 3; ++k, at += column) {
        if (pts.type == SDFT_MESH_FLOAT32) {
            float x;
            std::memcpy(&x, at, sizeof x);
            p[k] = x;
        } else {
            std::memcpy(&p[k], at, sizeof p[k]);
        }
    }
}

sdft_error checkPoints(const char *what, const sdft_mesh *m, const sdft_mesh_points *pts, const void *out,
                       const sdft_mesh_query_params *q, char *msg, size_t msg_len)
{
    if (!m || !pts || (!pts->data && pts->count) || !out)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what,
                         !m     ? "m"
                         : !pts ? "pts"
                         : !out ? "the output"
                                : "pts->data");
    if (enumValue(pts->type) != SDFT_MESH_FLOAT32 && enumValue(pts->type) != SDFT_MESH_FLOAT64)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: points must be float32 or float64", what);
    if (q && (q->threads < 0 || q->threads > 1024))
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: threads must be in [0, 1024], not %d", what, q->threads);
    return SDFT_OK;
}

// Distance and winding number at every point, into either (NULL: not
// wanted), in Morton order in the mesh's cube (neighbours in it are near
// in space: the hierarchies' nodes stay in cache, and close points search
// together; each point's answer is the same in any order).
sdft_error evaluate(const char *what, const sdft_mesh *m, const sdft_mesh_points *pts, float *distance, float *winding,
                    const sdft_mesh_query_params *q, char *msg, size_t msg_len)
{
    return guarded(what, msg, msg_len, [&] {
        if (pts->count == 0)
            return SDFT_OK;
        Listened listened(q ? q->progress : nullptr, nullptr, q ? q->progress_user : nullptr);
        meshsdf::Progress &progress = listened.progress;
        return inArena(q && q->threads > 0 ? q->threads : m->threads, [&] {
            const meshsdf::PointQuery &query = m->query();
            std::vector<double> xyz(pts->count * 3);
            tbb::parallel_for(tbb::blocked_range<size_t>(0, pts->count, 4096),
                              [&](const tbb::blocked_range<size_t> &r) {
                                  for (size_t i = r.begin(); i != r.end(); ++i)
                                      pointAt(*pts, i, &xyz[i * 3]);
                              });
            const std::vector<size_t> order = meshsdf::mortonOrder(xyz, m->frame());
            progress.stage("points", 0, 100);
            std::atomic<size_t> evaluated{0};
            tbb::parallel_for(tbb::blocked_range<size_t>(0, pts->count, 256), [&](const tbb::blocked_range<size_t> &r) {
                query.evaluate(xyz.data(), order.data(), r.begin(), r.end(), {distance != nullptr, winding != nullptr},
                               [&](size_t i, double d, double w) {
                                   if (distance)
                                       distance[i] = float(d);
                                   if (winding)
                                       winding[i] = float(w);
                               });
                progress.report(int(100 * (evaluated += r.size()) / pts->count)); // throws when told to stop
            });
            return SDFT_OK;
        });
    });
}

} // namespace

extern "C" {

sdft_mesh_query_params sdft_mesh_query_params_defaults(void) { return sdft_mesh_query_params{}; }

sdft_error sdft_mesh_signed_distance(const sdft_mesh *m, const sdft_mesh_points *pts, float *distance, float *winding,
                                     const sdft_mesh_query_params *q, char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_signed_distance";
    const sdft_error e = checkPoints(what, m, pts, distance, q, msg, msg_len);
    return e != SDFT_OK ? e : evaluate(what, m, pts, distance, winding, q, msg, msg_len);
}

sdft_error sdft_mesh_winding_number(const sdft_mesh *m, const sdft_mesh_points *pts, float *winding,
                                    const sdft_mesh_query_params *q, char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_winding_number";
    const sdft_error e = checkPoints(what, m, pts, winding, q, msg, msg_len);
    return e != SDFT_OK ? e : evaluate(what, m, pts, nullptr, winding, q, msg, msg_len);
}

sdft_mesh_sample_params sdft_mesh_sample_params_defaults(void)
{
    sdft_mesh_sample_params p{};
    fillDefaults(SDFT_MESH_SETTINGS_SAMPLES, &p);
    return p;
}

sdft_error sdft_mesh_samples(const sdft_mesh *m, const sdft_mesh_sample_params *p, float *rows, size_t rows_len,
                             char *msg, size_t msg_len)
{
    const char *what = "sdft_mesh_samples";
    if (!m || !p || !rows)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s is NULL", what, !m ? "m" : !p ? "p" : "rows");
    const sdft_error bad = checkSettings(SDFT_MESH_SETTINGS_SAMPLES, p, what, msg, msg_len);
    if (bad != SDFT_OK)
        return bad;
    if (rows_len / 4 < p->count)
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %llu rows need %llu floats, rows_len is %zu", what,
                         (unsigned long long)p->count, (unsigned long long)p->count * 4, rows_len);
    return guarded(what, msg, msg_len, [&] {
        Listened listened(p->progress, p->stage, p->progress_user);
        meshsdf::Progress &progress = listened.progress;
        return inArena(p->threads > 0 ? p->threads : m->threads, [&] {
            progress.stage("hierarchies", 0, 20);
            const meshsdf::PointQuery &query = m->query();
            progress.stage("samples", 20, 100);
            meshsdf::drawSamples(m->mesh, m->frame(), query, *p, rows, progress);
            progress.report(100);
            return SDFT_OK;
        });
    });
}

} // extern "C"
