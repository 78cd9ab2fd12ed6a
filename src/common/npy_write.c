/* sdftrace common — an .npy header (see npy_write.h). */
#include "npy_write.h"

#include <string.h>

int npy_write_header(FILE *f, const char *shape)
{
    char header[512];
    int n = snprintf(header, sizeof header, "{'descr': '<f4', 'fortran_order': False, 'shape': %s, }", shape);
    if (n < 0 || (size_t)n + 64 >= sizeof header)
        return -1;
    const size_t total = 10 + (size_t)n + 1; /* preamble, dict, newline */
    const size_t pad = (64 - total % 64) % 64;
    memset(header + n, ' ', pad);
    header[(size_t)n + pad] = '\n';
    const size_t len = (size_t)n + pad + 1;
    const unsigned char preamble[10] = {
        0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, (unsigned char)(len & 0xff), (unsigned char)(len >> 8)};
    return fwrite(preamble, 1, 10, f) == 10 && fwrite(header, 1, len, f) == len ? 0 : -1;
}
