// sdftrace — the settings of the params structs (sdftrace/mesh.h): the
// tables of the header as rows to list (sdft_mesh_settings), and the two
// things every call does with them, filling the defaults and checking the
// ranges, written once for every setting.
#include "api.h"

#include "parse.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace meshsdf::api
{

namespace
{

#define SDFT_MESH_UNPAREN(...) __VA_ARGS__
#define SDFT_MESH_SETTING_ROW(name, kind, type, values, def, lo, hi, flags, choices, automatic, value, doc)            \
    {#name,     kind,  values, offsetof(Params, name), {SDFT_MESH_UNPAREN def}, lo, hi, flags, choices,                \
     automatic, value, doc},

template <class P> struct Table;
template <> struct Table<sdft_mesh_params> {
    using Params = sdft_mesh_params;
    static constexpr sdft_mesh_setting rows[] = {SDFT_MESH_SETTINGS(SDFT_MESH_SETTING_ROW)};
};
template <> struct Table<sdft_mesh_grid_params> {
    using Params = sdft_mesh_grid_params;
    static constexpr sdft_mesh_setting rows[] = {SDFT_MESH_GRID_SETTINGS(SDFT_MESH_SETTING_ROW)};
};
template <> struct Table<sdft_mesh_sample_params> {
    using Params = sdft_mesh_sample_params;
    static constexpr sdft_mesh_setting rows[] = {SDFT_MESH_SAMPLE_SETTINGS(SDFT_MESH_SETTING_ROW)};
};

#undef SDFT_MESH_SETTING_ROW
#undef SDFT_MESH_UNPAREN

template <class P> Settings rowsOf() { return {Table<P>::rows, sizeof Table<P>::rows / sizeof *Table<P>::rows}; }

// The number of names in a CHOICE row's list.
int choiceCount(const sdft_mesh_setting &s)
{
    const char *name;
    int n = 0;
    while (parse_list_item(s.choices, n, &name))
        ++n;
    return n;
}

bool inRange(const sdft_mesh_setting &s, double v)
{
    return (s.flags & SDFT_MESH_SETTING_AUTO && v == s.def[0]) || parse_in_range(v, s.lo, s.hi, int(s.flags));
}

// "WHAT: NAME must be in RANGE, got VALUE", SDFT_EINVAL.
sdft_error outside(const sdft_mesh_setting &s, const char *what, const std::string &value, char *msg, size_t msg_len)
{
    char range[96];
    parse_range_text(s.lo, s.hi, int(s.flags & (SDFT_MESH_SETTING_OPEN_LO | SDFT_MESH_SETTING_OPEN_HI)),
                     s.kind == SDFT_MESH_SETTING_REAL ? "%g" : "%.0f", range, sizeof range);
    return fail_with(msg, msg_len, SDFT_EINVAL, "%s: %s must be%s, got %s", what, s.name, range, value.c_str());
}

// One row's value in `params` against its range: SDFT_OK, or SDFT_EINVAL
// and one line.
sdft_error checkRow(const sdft_mesh_setting &s, const char *params, const char *what, char *msg, size_t msg_len)
{
    const char *at = params + s.offset;
    switch (s.kind) {
    case SDFT_MESH_SETTING_INT:
    case SDFT_MESH_SETTING_COUNT: {
        int i = 0;
        uint64_t u = 0;
        if (s.kind == SDFT_MESH_SETTING_INT)
            std::memcpy(&i, at, sizeof i);
        else
            std::memcpy(&u, at, sizeof u);
        const double v = s.kind == SDFT_MESH_SETTING_INT ? double(i) : double(u);
        if (inRange(s, v))
            return SDFT_OK;
        return outside(s, what, s.kind == SDFT_MESH_SETTING_INT ? std::to_string(i) : std::to_string(u), msg, msg_len);
    }
    case SDFT_MESH_SETTING_REAL:
        for (int k = 0; k < s.count; ++k) {
            double v;
            std::memcpy(&v, at + k * sizeof v, sizeof v);
            if (std::isfinite(v) && inRange(s, v))
                continue;
            char text[32];
            std::snprintf(text, sizeof text, "%g", v);
            return outside(s, what, text, msg, msg_len);
        }
        return SDFT_OK;
    case SDFT_MESH_SETTING_CHOICE: {
        int v;
        std::memcpy(&v, at, sizeof v);
        if (v >= 0 && v < choiceCount(s))
            return SDFT_OK;
        return fail_with(msg, msg_len, SDFT_EINVAL, "%s: unknown %s %d (%s)", what, s.name, v, s.choices);
    }
    case SDFT_MESH_SETTING_FLAG:
    case SDFT_MESH_SETTING_TEXT:
        break;
    }
    return SDFT_OK;
}

} // namespace

Settings settingsOf(sdft_mesh_settings_of of)
{
    switch (enumValue(of)) {
    case SDFT_MESH_SETTINGS_MESH:
        return rowsOf<sdft_mesh_params>();
    case SDFT_MESH_SETTINGS_GRID:
        return rowsOf<sdft_mesh_grid_params>();
    case SDFT_MESH_SETTINGS_SAMPLES:
        return rowsOf<sdft_mesh_sample_params>();
    }
    return {nullptr, 0};
}

void fillDefaults(sdft_mesh_settings_of of, void *params)
{
    const Settings table = settingsOf(of);
    for (size_t r = 0; r < table.count; ++r) {
        const sdft_mesh_setting &s = table.rows[r];
        char *at = static_cast<char *>(params) + s.offset;
        switch (s.kind) {
        case SDFT_MESH_SETTING_INT:
        case SDFT_MESH_SETTING_FLAG:
        case SDFT_MESH_SETTING_CHOICE: {
            const int v = int(s.def[0]);
            std::memcpy(at, &v, sizeof v);
            break;
        }
        case SDFT_MESH_SETTING_COUNT: {
            const uint64_t v = uint64_t(s.def[0]);
            std::memcpy(at, &v, sizeof v);
            break;
        }
        case SDFT_MESH_SETTING_REAL:
            std::memcpy(at, s.def, sizeof(double) * size_t(s.count));
            break;
        case SDFT_MESH_SETTING_TEXT: {
            const char *none = nullptr;
            std::memcpy(at, &none, sizeof none);
            break;
        }
        }
    }
}

sdft_error checkSettings(sdft_mesh_settings_of of, const void *params, const char *what, char *msg, size_t msg_len)
{
    const Settings table = settingsOf(of);
    for (size_t r = 0; r < table.count; ++r) {
        const sdft_error e = checkRow(table.rows[r], static_cast<const char *>(params), what, msg, msg_len);
        if (e != SDFT_OK)
            return e;
    }
    return SDFT_OK;
}

size_t choiceText(sdft_mesh_settings_of of, const char *setting, int value, const char **name) noexcept
{
    const Settings table = settingsOf(of);
    for (size_t r = 0; r < table.count; ++r) {
        const sdft_mesh_setting &s = table.rows[r];
        if (s.kind == SDFT_MESH_SETTING_CHOICE && std::strcmp(s.name, setting) == 0 && value >= 0)
            return parse_list_item(s.choices, value, name);
    }
    return 0;
}

std::string choiceName(sdft_mesh_settings_of of, const char *setting, int value)
{
    const char *name;
    const size_t n = choiceText(of, setting, value, &name);
    return n ? std::string(name, n) : std::string("?");
}

} // namespace meshsdf::api

extern "C" const sdft_mesh_setting *sdft_mesh_settings(sdft_mesh_settings_of of, size_t *count)
{
    const meshsdf::api::Settings table = meshsdf::api::settingsOf(of);
    if (count)
        *count = table.count;
    return table.rows;
}
