/* src/common/atomic_file.h: files written together, all or none. A set
 * whose one target cannot be reserved leaves nothing; a committed set's
 * targets all hold what was written, with the umask's mode; an aborted
 * one leaves the old files as they were and no temporary file. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_file.h"
#include "testutil.h"

/* A fresh folder of this run's own (a run stopped half way leaves its
 * temporaries in its own folder, not in the next run's). */
static char dir[512];

static const char *in_dir(char *buf, size_t len, const char *name)
{
    const int n = snprintf(buf, len, "%s/%s", dir, name);
    assert_true(n > 0 && (size_t)n < len);
    return buf;
}

static void assert_holds(const char *path, const char *text)
{
    char *got = tu_slurp(path);
    assert_non_null(got);
    assert_string_equal(got, text);
    free(got);
}

static void all_or_none(void **state)
{
    (void)state;
    char a[512], b[512], c[512], msg[256];
    in_dir(a, sizeof a, "set_a.txt");
    in_dir(b, sizeof b, "set_b.txt");
    in_dir(c, sizeof c, "no/such/folder/c.txt");
    tu_assert_write_text(a, "old a");
    unlink(b);
    atomic_file files[3];

    /* One target cannot be reserved: none is, and nothing is left. */
    const char *bad[3] = {a, b, c};
    assert_int_equal(atomic_files_begin(files, bad, 3, msg, sizeof msg), SDFT_EIO);
    assert_non_null(strstr(msg, "c.txt"));
    assert_int_equal(tu_temporaries(dir, "set_a.txt"), 0);
    assert_int_equal(tu_temporaries(dir, "set_b.txt"), 0);

    /* Aborted after writing: the old files as they were. */
    const char *good[2] = {a, b};
    assert_int_equal(atomic_files_begin(files, good, 2, msg, sizeof msg), SDFT_OK);
    tu_assert_write_text(files[0].tmp_path, "new a");
    tu_assert_write_text(files[1].tmp_path, "new b");
    atomic_files_abort(files, 2);
    assert_holds(a, "old a");
    assert_false(tu_file_exists(b));
    assert_int_equal(tu_temporaries(dir, "set_a.txt"), 0);

    /* Committed: both, with the umask's mode. */
    assert_int_equal(atomic_files_begin(files, good, 2, msg, sizeof msg), SDFT_OK);
    tu_assert_write_text(files[0].tmp_path, "new a");
    tu_assert_write_text(files[1].tmp_path, "new b");
    assert_int_equal(atomic_files_commit(files, 2, msg, sizeof msg), SDFT_OK);
    assert_holds(a, "new a");
    assert_holds(b, "new b");
    assert_int_equal(tu_file_mode(b), (int)atomic_file_mode());
    assert_int_equal(tu_temporaries(dir, "set_b.txt"), 0);
    atomic_files_abort(files, 2); /* after a commit: nothing to do */
    assert_holds(a, "new a");
}

/* A device among the targets is written in place, the others renamed. */
static void a_device_in_the_set(void **state)
{
    (void)state;
    char a[512], msg[256];
    in_dir(a, sizeof a, "set_dev.txt");
    const char *paths[2] = {"/dev/null", a};
    atomic_file files[2];
    assert_int_equal(atomic_files_begin(files, paths, 2, msg, sizeof msg), SDFT_OK);
    assert_string_equal(files[0].tmp_path, "/dev/null");
    assert_int_equal(write(files[0].fd, "x", 1), 1);
    tu_assert_write_text(files[1].tmp_path, "beside the device");
    assert_int_equal(atomic_files_commit(files, 2, msg, sizeof msg), SDFT_OK);
    assert_holds(a, "beside the device");
    struct stat st;
    assert_int_equal(stat("/dev/null", &st), 0);
    assert_true(S_ISCHR(st.st_mode));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(all_or_none),
        cmocka_unit_test(a_device_in_the_set),
    };
    snprintf(dir, sizeof dir, "%s/atomic_set-XXXXXX", SDFT_TEST_TMP);
    if (!mkdtemp(dir))
        return 1;
    const int failed = cmocka_run_group_tests_name("atomic_file", tests, NULL, NULL);
    if (!failed)
        tu_run(NULL, 0, "rm -rf '%s'", dir);
    return failed;
}
