// src/mesh/progress: a long call's stages mapped onto one rising fraction,
// the listener told one call at a time and never a step back, the stages
// named, and a listener's stop thrown out as seam::Cancelled (and said to
// OpenVDB's interrupter).
#include "progress/progress.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <string>
#include <vector>

// Last: cmocka's macros would rename members of the headers above.
#include "mesh_unit.h"

namespace
{

struct Heard {
    std::vector<float> done;
    std::vector<std::string> stages;
    float stopAt = 2; // past 1: never
};

int listen(void *user, float done)
{
    Heard &h = *static_cast<Heard *>(user);
    h.done.push_back(done);
    return done >= h.stopAt;
}

void named(void *user, const char *stage) { static_cast<Heard *>(user)->stages.push_back(stage); }

void stages_map_onto_the_whole(void **)
{
    Heard h;
    meshsdf::Progress p(listen, named, &h);
    p.stage("first", 0, 40);
    p.report(50); // 20% of the whole
    p.report(25); // a step back: not told
    p.stage("second", 40, 100);
    tbb::parallel_for(0, 101, [&](int percent) { p.report(percent); }); // from any thread
    p.done();
    assert_int_equal(h.stages.size(), 2);
    assert_string_equal(h.stages[1].c_str(), "second");
    assert_true(h.done.front() == 0.0f && h.done.back() == 1.0f);
    for (size_t i = 1; i < h.done.size(); ++i)
        assert_true(h.done[i] > h.done[i - 1]);
    assert_true(std::find(h.done.begin(), h.done.end(), 0.2f) != h.done.end());
    assert_false(p.cancelled());
}

void a_stop_is_thrown(void **)
{
    Heard h;
    h.stopAt = 0.3f;
    meshsdf::Progress p(listen, nullptr, &h);
    p.stage("work", 0, 100);
    bool thrown = false;
    try {
        for (int percent = 0; percent <= 100; ++percent)
            p.report(percent);
    } catch (const seam::Cancelled &) {
        thrown = true;
    }
    assert_true(thrown && p.cancelled());
    assert_true(h.done.back() >= 0.3f && h.done.back() < 0.32f);
    assert_true(p.wasInterrupted(50)); // OpenVDB's loops hear it too, without a throw
    // No listener: nothing to tell, nothing to stop.
    meshsdf::Progress quiet(nullptr, nullptr, nullptr);
    quiet.stage("x", 0, 100);
    quiet.report(100);
    assert_false(quiet.wasInterrupted(100));
}

} // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stages_map_onto_the_whole),
        cmocka_unit_test(a_stop_is_thrown),
    };
    return cmocka_run_group_tests_name("mesh_progress", tests, nullptr, nullptr);
}
