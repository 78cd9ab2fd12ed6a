// sdftrace fuzzing — mesh2sdf's reader of --query points (convert/npy_read's
// readNpyPoints): the whole input is the .npy file.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input_file.h"
#include "npy_read.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[256];
    if (fuzz_input_file(data, size, ".npy", path, sizeof path))
        return 0;
    std::vector<double> xyz;
    std::string error;
    mesh2sdf::readNpyPoints(path, xyz, error);
    unlink(path);
    return 0;
}
