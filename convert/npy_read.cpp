// mesh2sdf — the strict .npy reader (see npy_read.h). The format
// (numpy.lib.format): the magic "\x93NUMPY", a major and a minor version
// byte, the header's length (2 bytes little-endian in version 1, 4 in 2 and
// 3), the header (a Python dict literal, padded with spaces, ending in a
// newline), then the data. Only the dict literal that NumPy writes is
// accepted: quoted keys without escapes, True or False, a tuple of decimal
// integers.
#include "npy_read.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sys/stat.h>

namespace mesh2sdf
{

namespace
{

// Longest header read (NumPy's own limit for version 1 is 65535 bytes;
// later versions write far less than this in practice).
constexpr uint64_t kMaxHeader = 1 << 20;

struct FileCloser {
    void operator()(FILE *f) const { std::fclose(f); }
};
using File = std::unique_ptr<FILE, FileCloser>;

// The header dict's fields, as found.
struct Header {
    std::string descr;
    bool fortran = false;
    std::vector<uint64_t> shape;
    int seen[3] = {0, 0, 0}; // descr, fortran_order, shape
};

// A cursor over the header text; each read skips the blanks before it and
// fails with a sentence in `error`.
class DictReader
{
  public:
    explicit DictReader(const std::string &text) : mText(text) {}

    bool expect(char c)
    {
        skip();
        if (mAt < mText.size() && mText[mAt] == c) {
            ++mAt;
            return true;
        }
        return fail(std::string("'") + c + "' expected");
    }
    bool peek(char c)
    {
        skip();
        return mAt < mText.size() && mText[mAt] == c;
    }
    // A quoted string without escapes, of printable ASCII only: keys and
    // dtypes are, and an error message quotes it on its one line.
    bool string(std::string &out)
    {
        skip();
        if (mAt >= mText.size() || (mText[mAt] != '\'' && mText[mAt] != '"'))
            return fail("a quoted string expected");
        const char quote = mText[mAt++];
        const size_t end = mText.find(quote, mAt);
        if (end == std::string::npos)
            return fail("unterminated string");
        out = mText.substr(mAt, end - mAt);
        mAt = end + 1;
        if (out.find('\\') != std::string::npos)
            return fail("escapes in a string");
        for (const char c : out)
            if (c < 0x20 || c > 0x7e)
                return fail("a control or non-ASCII byte in a string");
        return true;
    }
    bool boolean(bool &out)
    {
        skip();
        for (const char *word : {"True", "False"}) {
            const size_t n = std::strlen(word);
            if (mText.compare(mAt, n, word) == 0) {
                out = word[0] == 'T';
                mAt += n;
                return true;
            }
        }
        return fail("True or False expected");
    }
    // A decimal integer below 2^62.
    bool integer(uint64_t &out)
    {
        skip();
        out = 0;
        const size_t from = mAt;
        while (mAt < mText.size() && mText[mAt] >= '0' && mText[mAt] <= '9') {
            if (out >= (uint64_t(1) << 62) / 10)
                return fail("a dimension too large");
            out = out * 10 + uint64_t(mText[mAt++] - '0');
        }
        return mAt > from || fail("a dimension expected");
    }
    // Only blanks are left.
    bool atEnd()
    {
        skip();
        return mAt == mText.size() || fail("text after the dict");
    }
    const std::string &error() const { return mError; }
    bool fail(const std::string &what)
    {
        if (mError.empty())
            mError = what + " at byte " + std::to_string(mAt) + " of the header";
        return false;
    }

  private:
    void skip()
    {
        while (mAt < mText.size() && (mText[mAt] == ' ' || mText[mAt] == '\t' || mText[mAt] == '\n'))
            ++mAt;
    }
    const std::string &mText;
    size_t mAt = 0;
    std::string mError;
};

// shape: '(' [int {',' int} [',']] ')'
bool readShape(DictReader &in, std::vector<uint64_t> &shape)
{
    if (!in.expect('('))
        return false;
    while (!in.peek(')')) {
        uint64_t n;
        if (!in.integer(n))
            return false;
        shape.push_back(n);
        if (shape.size() > 32)
            return in.fail("more than 32 axes");
        if (!in.peek(')') && !in.expect(','))
            return false;
    }
    return in.expect(')');
}

bool readItem(DictReader &in, Header &h, std::string &error)
{
    std::string key;
    if (!in.string(key) || !in.expect(':'))
        return false;
    static const char *const keys[] = {"descr", "fortran_order", "shape"};
    int which = -1;
    for (int i = 0; i < 3; ++i)
        if (key == keys[i])
            which = i;
    if (which < 0) {
        error = "unexpected key '" + key + "' in the header";
        return false;
    }
    if (h.seen[which]++) {
        error = "key '" + key + "' twice in the header";
        return false;
    }
    if (which == 0)
        return in.string(h.descr);
    if (which == 1)
        return in.boolean(h.fortran);
    return readShape(in, h.shape);
}

// The dict: '{' item {',' item} [','] '}', every key once.
bool parseHeader(const std::string &text, Header &h, std::string &error)
{
    DictReader in(text);
    bool ok = in.expect('{');
    while (ok && !in.peek('}')) {
        ok = readItem(in, h, error);
        if (ok && !in.peek('}'))
            ok = in.expect(',');
    }
    ok = ok && in.expect('}') && in.atEnd();
    if (!ok && error.empty())
        error = "malformed header: " + in.error();
    if (ok && !(h.seen[0] && h.seen[1] && h.seen[2])) {
        error = "the header lacks 'descr', 'fortran_order' or 'shape'";
        ok = false;
    }
    return ok;
}

// Bytes per value of a little-endian float32 or float64 descr; 0 for any other.
size_t itemSize(const std::string &descr)
{
    if (descr.size() != 3 || std::strchr("<|=", descr[0]) == nullptr || descr[1] != 'f')
        return 0;
    if (descr[0] == '=' && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__)
        return 0;
    return descr[2] == '4' ? 4 : descr[2] == '8' ? 8 : 0;
}

// The preamble and header of an open file of `size` bytes; `offset` is where the data begins.
bool readPreamble(FILE *f, uint64_t size, Header &h, uint64_t &offset, std::string &error)
{
    unsigned char pre[12];
    if (size < 10 || std::fread(pre, 1, 10, f) != 10 || std::memcmp(pre, "\x93NUMPY", 6) != 0) {
        error = "not a NumPy .npy file (no \\x93NUMPY magic)";
        return false;
    }
    const int major = pre[6], minor = pre[7];
    if (major < 1 || major > 3 || minor != 0) {
        error = "unsupported .npy format version " + std::to_string(major) + "." + std::to_string(minor);
        return false;
    }
    uint64_t length = pre[8] | uint64_t(pre[9]) << 8;
    offset = 10;
    if (major >= 2) {
        if (size < 12 || std::fread(pre + 10, 1, 2, f) != 2) {
            error = "truncated in its preamble";
            return false;
        }
        length |= uint64_t(pre[10]) << 16 | uint64_t(pre[11]) << 24;
        offset = 12;
    }
    if (length > kMaxHeader || length > size - offset) {
        error = "its header length (" + std::to_string(length) + " bytes) runs past the file's end";
        return false;
    }
    std::string text(size_t(length), '\0');
    if (std::fread(&text[0], 1, text.size(), f) != text.size()) {
        error = "cannot read its header";
        return false;
    }
    offset += length;
    if (text.empty() || text.back() != '\n') {
        error = "its header does not end in a newline";
        return false;
    }
    for (char c : text)
        if (static_cast<unsigned char>(c) < 0x20 ? c != '\n' && c != '\t' : static_cast<unsigned char>(c) > 0x7e) {
            error = "its header is not plain text";
            return false;
        }
    return parseHeader(text, h, error);
}

std::string shapeText(const std::vector<uint64_t> &shape)
{
    std::string s = "(";
    for (size_t i = 0; i < shape.size(); ++i)
        s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

// Fills `values` from the data: `count` rows of `columns`, `item` bytes per value.
bool readValues(FILE *f, const Header &h, size_t item, uint64_t count, size_t columns, std::vector<double> &values,
                std::string &error)
{
    std::vector<unsigned char> raw(size_t(count) * columns * item);
    if (std::fread(raw.data(), 1, raw.size(), f) != raw.size()) {
        error = "cannot read its data";
        return false;
    }
    values.resize(size_t(count) * columns);
    for (uint64_t i = 0; i < count; ++i)
        for (size_t k = 0; k < columns; ++k) {
            // C order: row by row; Fortran order: column by column.
            const size_t at = h.fortran ? k * count + i : size_t(i) * columns + k;
            double v;
            if (item == 4) {
                float x;
                std::memcpy(&x, &raw[at * 4], 4);
                v = x;
            } else {
                std::memcpy(&v, &raw[at * 8], 8);
            }
            if (!std::isfinite(v)) {
                error = "row " + std::to_string(i) + " has a value that is not finite";
                return false;
            }
            values[size_t(i) * columns + k] = v;
        }
    return true;
}

} // namespace

bool readNpyRows(const std::string &path, size_t columns, std::vector<double> &values, std::string &error)
{
    struct stat st;
    if (stat(path.c_str(), &st) != 0) {
        error = "cannot read points " + path + ": " + std::strerror(errno);
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        error = "cannot read points " + path + ": not a regular file";
        return false;
    }
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) {
        error = "cannot read points " + path + ": " + std::strerror(errno);
        return false;
    }
    const uint64_t size = uint64_t(st.st_size);
    Header h;
    uint64_t offset = 0;
    std::string why;
    if (!readPreamble(f.get(), size, h, offset, why)) {
        error = "points " + path + ": " + why;
        return false;
    }
    const size_t item = itemSize(h.descr);
    if (item == 0) {
        error = "points " + path + ": dtype '" + h.descr + "' is not float32 or float64 ('<f4' or '<f8')";
        return false;
    }
    if (h.shape.size() != 2 || h.shape[1] != columns || h.shape[0] == 0) {
        error = "points " + path + ": shape " + shapeText(h.shape) + " is not (N, " + std::to_string(columns) +
                ") with N >= 1";
        return false;
    }
    const uint64_t count = h.shape[0], data = size - offset, row = columns * item;
    // count < 2^62: count * row could wrap; compare by division first.
    if (count > data / row || count * row != data) {
        error = "points " + path + ": the shape " + shapeText(h.shape) + " needs " +
                (count > data / row ? "more than " + std::to_string(data) : std::to_string(count * row)) +
                " bytes of data, the file has " + std::to_string(data);
        return false;
    }
    if (!readValues(f.get(), h, item, count, columns, values, why)) {
        error = "points " + path + ": " + why;
        return false;
    }
    return true;
}

} // namespace mesh2sdf
