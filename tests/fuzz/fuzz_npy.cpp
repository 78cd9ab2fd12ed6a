// sdftrace fuzzing — the strict .npy reader of mesh2sdf's --query points
// (src/common/npy_read.h): the whole input is the .npy file.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_input_file.h"
#include "npy_read.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[256];
    if (fuzz_input_file(data, size, ".npy", path, sizeof path))
        return 0;
    double *xyz = nullptr;
    size_t rows = 0;
    char msg[512];
    npy_read_rows(path, 3, &xyz, &rows, msg, sizeof msg);
    std::free(xyz);
    unlink(path);
    return 0;
}
