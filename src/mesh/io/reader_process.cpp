// sdftrace — a reader in a child process (see reader_process.h).
//
// The child writes one answer: a byte (1 soup, 0 error, 2 out of memory),
// then for a soup the three counts and arrays (points, corners, ends), the
// two counts of faces left out and the warnings' length and text, for an
// error its length and text. The parent takes nothing on trust: every
// count is checked against the bytes that came back before it is used.
#include "io/reader_process.h"

#include "isolated_read.h"

#include <cstring>
#include <new>

namespace meshsdf
{

namespace
{

struct ChildWork {
    const SoupReader *read;
};

template <typename T> bool writeArray(int fd, const T *data, uint64_t n)
{
    return !isolated_write_all(fd, &n, sizeof n) && !isolated_write_all(fd, data, n * sizeof(T));
}

// The child's side: runs the reader and writes its answer.
int answer(void *ctx, int fd)
{
    const SoupReader &read = *static_cast<ChildWork *>(ctx)->read;
    PolygonSoup soup;
    std::string error;
    unsigned char tag;
    try {
        tag = read(soup, error) ? 1 : 0;
    } catch (const std::bad_alloc &) {
        tag = 2;
    }
    if (isolated_write_all(fd, &tag, 1))
        return 1;
    if (tag == 1) {
        const std::vector<uint64_t> ends(soup.ends.begin(), soup.ends.end());
        const uint64_t skipped[2] = {soup.skippedFaces, soup.degenerateFaces};
        return writeArray(fd, soup.points.data(), soup.points.size()) &&
                       writeArray(fd, soup.corners.data(), soup.corners.size()) &&
                       writeArray(fd, ends.data(), ends.size()) && writeArray(fd, skipped, 2) &&
                       writeArray(fd, soup.warnings.data(), soup.warnings.size())
                   ? 0
                   : 1;
    }
    return tag == 0 && !writeArray(fd, error.data(), error.size());
}

// The answer's bytes, taken in order; false once a count asks for more
// than is left.
class AnswerReader
{
  public:
    AnswerReader(const char *data, size_t size) : mAt(data), mLeft(size) {}

    bool bytes(void *to, size_t n)
    {
        if (n > mLeft)
            return false;
        if (n)
            std::memcpy(to, mAt, n);
        mAt += n, mLeft -= n;
        return true;
    }

    template <typename T> bool array(std::vector<T> &v)
    {
        uint64_t n;
        if (!bytes(&n, sizeof n) || n > mLeft / sizeof(T))
            return false;
        v.resize(size_t(n));
        return bytes(v.data(), size_t(n) * sizeof(T));
    }

    bool done() const { return mLeft == 0; }

  private:
    const char *mAt;
    size_t mLeft;
};

} // namespace

bool readInChildProcess(const SoupReader &read, const std::string &path, const std::string &reader, PolygonSoup &soup,
                        std::string &error)
{
    ChildWork work{&read};
    char *data = nullptr, why[128];
    size_t size = 0;
    if (isolated_read(path.c_str(), answer, &work, &data, &size, why, sizeof why) != 0) {
        // A reader that crashes or never ends is at fault whatever the file
        // holds: a valid file can do it too (assimp 5.2 on some 3MF).
        const bool crashed = std::strncmp(why, "signal", 6) == 0;
        error = "cannot read mesh (" + reader + (crashed ? " crashed on it: " : " failed on it: ") + why +
                "; the file may be valid): " + path;
        return false;
    }
    AnswerReader in(data, size);
    unsigned char tag = 3;
    std::vector<char> text, warnings;
    std::vector<uint64_t> ends, skipped;
    soup = PolygonSoup{};
    const bool answered =
        in.bytes(&tag, 1) && (tag == 1 ? in.array(soup.points) && in.array(soup.corners) && in.array(ends) &&
                                             in.array(skipped) && skipped.size() == 2 && in.array(warnings) && in.done()
                              : tag == 0 ? in.array(text) && in.done()
                                         : tag == 2 && in.done());
    std::free(data);
    if (answered && tag == 1) {
        // The loader takes corners within the points and ends in order on
        // trust (polygon_soup.h): the child's answer is held to it here.
        bool consistent = true;
        for (size_t f = 0; f < ends.size() && consistent; ++f)
            consistent = ends[f] <= soup.corners.size() && (f == 0 || ends[f] >= ends[f - 1]);
        for (size_t c = 0; c < soup.corners.size() && consistent; ++c)
            consistent = soup.corners[c] < soup.points.size();
        if (consistent) {
            soup.ends.assign(ends.begin(), ends.end());
            soup.skippedFaces = size_t(skipped[0]);
            soup.degenerateFaces = size_t(skipped[1]);
            soup.warnings.assign(warnings.begin(), warnings.end());
            return true;
        }
    }
    soup = PolygonSoup{};
    if (answered && tag == 1)
        error = "cannot read mesh (the reader process's answer is inconsistent): " + path;
    else if (answered && tag == 0)
        error.assign(text.begin(), text.end());
    else if (answered)
        error = "mesh is larger than memory allows: " + path;
    else
        error = "cannot read mesh (the reader process's answer is inconsistent): " + path;
    return false;
}

} // namespace meshsdf
