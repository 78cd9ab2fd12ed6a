// mesh2sdf — a reader in a child process (see reader_process.h).
//
// The child writes one answer and exits: a byte (1 soup, 0 error), then for
// a soup the three counts and arrays (points, corners, ends), for an error
// its length and text. The parent reads it against a deadline; an answer
// cut short (the child died) is never taken for a soup.
#include "reader_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <new>

namespace mesh2sdf
{

namespace
{

bool writeAll(int fd, const void *data, size_t n)
{
    const char *at = static_cast<const char *>(data);
    while (n > 0) {
        const ssize_t wrote = write(fd, at, n);
        if (wrote < 0 && errno == EINTR)
            continue;
        if (wrote <= 0)
            return false;
        at += wrote;
        n -= size_t(wrote);
    }
    return true;
}

template <typename T> bool writeArray(int fd, const std::vector<T> &v)
{
    const uint64_t n = v.size();
    return writeAll(fd, &n, sizeof n) && writeAll(fd, v.data(), n * sizeof(T));
}

// The child's side: runs the reader and writes its answer.
[[noreturn]] void answer(int fd, const SoupReader &read)
{
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0)
        dup2(null, STDERR_FILENO); // assimp's own messages (and asserts) would be more lines
    PolygonSoup soup;
    std::string error;
    bool ok;
    try {
        ok = read(soup, error);
    } catch (const std::bad_alloc &) {
        ok = false;
        error = "out of memory";
    }
    const unsigned char tag = ok ? 1 : 0;
    // A failed write leaves the parent an answer cut short, which it reports.
    if (ok)
        (void)(writeAll(fd, &tag, 1) && writeArray(fd, soup.points) && writeArray(fd, soup.corners) &&
               writeArray(fd, soup.ends));
    else
        (void)(writeAll(fd, &tag, 1) && writeArray(fd, std::vector<char>(error.begin(), error.end())));
    _exit(0);
}

// Reads exactly n bytes before `deadline`; false on an early end or the
// deadline (`late` says which).
class AnswerReader
{
  public:
    AnswerReader(int fd, std::chrono::steady_clock::time_point deadline) : mFd(fd), mDeadline(deadline) {}

    bool bytes(void *data, size_t n)
    {
        char *at = static_cast<char *>(data);
        while (n > 0) {
            const auto left =
                std::chrono::duration_cast<std::chrono::milliseconds>(mDeadline - std::chrono::steady_clock::now());
            pollfd p{mFd, POLLIN, 0};
            const int ready = left.count() > 0 ? poll(&p, 1, int(std::min<long long>(left.count(), 1000000))) : 0;
            if (ready < 0 && errno == EINTR)
                continue;
            if (ready == 0) {
                late = std::chrono::steady_clock::now() >= mDeadline;
                if (late)
                    return false;
                continue;
            }
            const ssize_t got = ready > 0 ? read(mFd, at, n) : -1;
            if (got < 0 && errno == EINTR)
                continue;
            if (got <= 0)
                return false;
            at += got;
            n -= size_t(got);
        }
        return true;
    }

    template <typename T> bool array(std::vector<T> &v)
    {
        uint64_t n;
        if (!bytes(&n, sizeof n))
            return false;
        // Grown as the bytes arrive, so that a count cut short or wrong
        // never reserves more than came through the pipe.
        constexpr size_t kChunk = (1 << 20) / sizeof(T) + 1;
        for (uint64_t done = 0; done < n;) {
            const size_t take = size_t(std::min<uint64_t>(n - done, kChunk));
            v.resize(size_t(done) + take);
            if (!bytes(v.data() + done, take * sizeof(T)))
                return false;
            done += take;
        }
        return true;
    }

    bool late = false;

  private:
    int mFd;
    std::chrono::steady_clock::time_point mDeadline;
};

} // namespace

bool readInChildProcess(const SoupReader &read, double seconds, const std::string &path, PolygonSoup &soup,
                        std::string &error)
{
    int fds[2];
    if (pipe(fds) != 0) {
        error = "cannot start the reader (pipe: " + std::string(std::strerror(errno)) + "): " + path;
        return false;
    }
    const pid_t child = fork();
    if (child < 0) {
        error = "cannot start the reader (fork: " + std::string(std::strerror(errno)) + "): " + path;
        close(fds[0]);
        close(fds[1]);
        return false;
    }
    if (child == 0) {
        close(fds[0]);
        answer(fds[1], read);
    }
    close(fds[1]);
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<long long>(seconds * 1000));
    AnswerReader in(fds[0], deadline);
    unsigned char tag = 2;
    std::vector<char> text;
    soup = PolygonSoup{};
    const bool answered =
        in.bytes(&tag, 1) &&
        (tag == 1 ? in.array(soup.points) && in.array(soup.corners) && in.array(soup.ends) : in.array(text));
    close(fds[0]);
    if (!answered)
        kill(child, SIGKILL);
    int status = 0;
    while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    if (answered && tag == 1)
        return true;
    if (answered) {
        error.assign(text.begin(), text.end());
        return false;
    }
    soup = PolygonSoup{};
    if (in.late)
        error = "cannot read mesh (the reader took longer than " + std::to_string(static_cast<long long>(seconds)) +
                " s, and was stopped): " + path;
    else if (WIFSIGNALED(status))
        error =
            "cannot read mesh (the reader crashed on it: " + std::string(strsignal(WTERMSIG(status))) + "): " + path;
    else
        error = "cannot read mesh (the reader ended without an answer): " + path;
    return false;
}

} // namespace mesh2sdf
