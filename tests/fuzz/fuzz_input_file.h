/* sdftrace fuzzing — the harnesses' input as a file: the readers under test
 * take a path. One file per process (and extension), rewritten for each
 * input, in /dev/shm where there is one (no disk traffic). */
#ifndef SDFT_FUZZ_INPUT_FILE_H
#define SDFT_FUZZ_INPUT_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

/* Writes data to a file named for this process with extension ext (".vdb")
 * into path (len bytes); 0 on success. */
static inline int fuzz_input_file(const uint8_t *data, size_t size, const char *ext, char *path, size_t len)
{
    const char *dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    snprintf(path, len, "%s/sdft_fuzz_%ld%s", dir, (long)getpid(), ext);
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    const size_t wrote = size ? fwrite(data, 1, size, f) : 0;
    return (fclose(f) == 0 && wrote == size) ? 0 : -1;
}

#endif
