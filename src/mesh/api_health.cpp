// sdftrace — a mesh's health report in words and as JSON
// (sdft_mesh_health_text, sdft_mesh_health_json): the one text and the one
// JSON of it, which mesh2sdf prints and its batches report.
#include "api.h"

#include <cstdarg>
#include <cstdio>

namespace
{

// printf onto the end of what `out` holds so far, *at characters of it;
// past out_len only counted, as snprintf counts.
void append(char *out, size_t out_len, size_t *at, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
void append(char *out, size_t out_len, size_t *at, const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    const int n =
        std::vsnprintf(out && *at < out_len ? out + *at : nullptr, out && *at < out_len ? out_len - *at : 0, fmt, args);
    va_end(args);
    *at += n > 0 ? size_t(n) : 0;
}

using ull = unsigned long long;

} // namespace

extern "C" {

size_t sdft_mesh_health_text(const sdft_mesh_health *h, char *out, size_t out_len)
{
    size_t at = 0;
    if (out && out_len)
        out[0] = '\0';
    if (!h)
        return 0;
    append(out, out_len, &at,
           "%llu vertices, %llu faces (%llu triangles), %llu boundary edges, %llu non-manifold edges, %llu "
           "degenerate faces skipped",
           ull(h->vertices), ull(h->faces), ull(h->triangles), ull(h->boundary_edges), ull(h->non_manifold_edges),
           ull(h->degenerate_faces));
    if (h->skipped_faces)
        append(out, out_len, &at, ", %llu faces left out (unreadable)", ull(h->skipped_faces));
    if (h->oriented) {
        append(out, out_len, &at,
               "; %llu vertices welded, %llu duplicate faces dropped, %llu patches, %llu faces reoriented, %llu "
               "patches turned outward",
               ull(h->welded_vertices), ull(h->duplicate_faces), ull(h->patches), ull(h->reoriented_faces),
               ull(h->outward_patches));
        if (h->cavity_patches)
            append(out, out_len, &at, ", %llu inward patches kept as cavity walls", ull(h->cavity_patches));
        if (h->evidence_patches)
            append(out, out_len, &at, ", %llu open patches turned by the rest's winding number",
                   ull(h->evidence_patches));
        if (h->ambiguous_patches)
            append(out, out_len, &at, ", %llu open patches with no clear outside", ull(h->ambiguous_patches));
        if (h->ambiguous_patches && h->ambiguous_area > 0)
            append(out, out_len, &at, " (%.3g%% of the area)", 100 * h->ambiguous_area);
        if (h->non_orientable_patches)
            append(out, out_len, &at, ", %llu non-orientable patches", ull(h->non_orientable_patches));
    }
    return at;
}

size_t sdft_mesh_health_json(const sdft_mesh_health *h, char *out, size_t out_len)
{
    size_t at = 0;
    if (out && out_len)
        out[0] = '\0';
    if (!h)
        return 0;
    const char *orient; // the orient setting's name for what was done
    const int n = int(meshsdf::api::choiceText(SDFT_MESH_SETTINGS_MESH, "orient", h->oriented ? 1 : 0, &orient));
    append(out, out_len, &at,
           "\"vertices\": %llu, \"faces\": %llu, \"triangles\": %llu, \"degenerate_faces\": %llu, "
           "\"boundary_edges\": %llu, \"non_manifold_edges\": %llu, \"skipped_faces\": %llu, \"orient\": \"%.*s\"",
           ull(h->vertices), ull(h->faces), ull(h->triangles), ull(h->degenerate_faces), ull(h->boundary_edges),
           ull(h->non_manifold_edges), ull(h->skipped_faces), n, orient);
    if (h->oriented)
        append(out, out_len, &at,
               ", \"welded_vertices\": %llu, \"duplicate_faces\": %llu, \"patches\": %llu, \"reoriented_faces\": "
               "%llu, \"outward_patches\": %llu, \"cavity_patches\": %llu, \"ambiguous_patches\": %llu, "
               "\"non_orientable_patches\": %llu",
               ull(h->welded_vertices), ull(h->duplicate_faces), ull(h->patches), ull(h->reoriented_faces),
               ull(h->outward_patches), ull(h->cavity_patches), ull(h->ambiguous_patches),
               ull(h->non_orientable_patches));
    if (h->oriented)
        append(out, out_len, &at, ", \"evidence_patches\": %llu, \"ambiguous_area\": %.6g", ull(h->evidence_patches),
               h->ambiguous_area);
    return at;
}

} // extern "C"
