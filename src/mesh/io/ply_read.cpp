// sdftrace — the PLY reader (see ply_read.h).
//
// The file is read whole and every step is checked against what is left of
// it, since a header is a claim, not a fact:
// - element counts: before anything is allocated, the counts must fit the
//   body's length at the fewest bytes an element can take (its scalars' and
//   list counts' sizes in binary; a word and a separator per property in
//   ascii). So the vertex array reserved from the header is backed by the
//   file, and no loop runs more often than the file has bytes (an element
//   with no properties takes none, but its count is below the file's length).
// - list lengths: a binary list's items must fit what is left before they
//   are read; an ascii list ends when its words do. A list never reserves
//   room from its count.
// - every value: a read past the end is an error, never a default.
// - indices: each one is checked against the header's vertex count (strips'
//   -1 excepted), so the loader can index the points unchecked; a face with
//   one out of range is left out and counted (PolygonSoup::skippedFaces).
// A header line that is no PLY keyword (a free-text line an old exporter
// wrote without `comment`) is read as a comment, and said in a warning.
#include "io/ply_read.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>

namespace meshsdf
{

namespace
{

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool scalarNamed(const std::string &name, Scalar &type)
{
    static const struct {
        const char *name;
        Scalar type;
    } names[] = {{"char", Scalar::Int8},      {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
                 {"uint8", Scalar::UInt8},    {"short", Scalar::Int16},     {"int16", Scalar::Int16},
                 {"ushort", Scalar::UInt16},  {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
                 {"int32", Scalar::Int32},    {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
                 {"float", Scalar::Float32},  {"float32", Scalar::Float32}, {"double", Scalar::Float64},
                 {"float64", Scalar::Float64}};
    for (const auto &n : names)
        if (name == n.name) {
            type = n.type;
            return true;
        }
    return false;
}

size_t scalarBytes(Scalar type)
{
    switch (type) {
    case Scalar::Int8:
    case Scalar::UInt8:
        return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
        return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
        return 4;
    default:
        return 8;
    }
}

bool isInteger(Scalar type) { return type != Scalar::Float32 && type != Scalar::Float64; }

struct Property {
    std::string name;
    Scalar type = Scalar::Float32; // a list's items
    bool list = false;
    Scalar countType = Scalar::UInt8;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Encoding { Ascii, LittleEndian, BigEndian };

struct Header {
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
    size_t bodyStart = 0;
    size_t freeTextLines = 0;                     // lines that are no keyword, read as comments
    std::pair<size_t, std::string> firstFreeText; // the first of them: its number, its text
};

std::vector<std::string> words(const char *begin, const char *end)
{
    std::vector<std::string> out;
    for (const char *at = begin; at < end;) {
        while (at < end && (*at == ' ' || *at == '\t'))
            ++at;
        const char *start = at;
        while (at < end && *at != ' ' && *at != '\t')
            ++at;
        if (at > start)
            out.emplace_back(start, at);
    }
    return out;
}

bool wholeUnsigned(const std::string &word, uint64_t &value)
{
    const auto [stop, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    return ec == std::errc() && stop == word.data() + word.size();
}

// The header's lines up to end_header; `problem` says what is wrong with it.
bool parseHeader(const std::string &file, Header &header, std::string &problem)
{
    bool sawFormat = false;
    size_t at = 0;
    for (size_t line = 0;; ++line) {
        const size_t newline = file.find('\n', at);
        if (newline == std::string::npos) {
            problem = line == 0 ? "not a PLY file (no 'ply' line)" : "PLY header has no end_header line";
            return false;
        }
        size_t stop = newline;
        if (stop > at && file[stop - 1] == '\r')
            --stop;
        const std::vector<std::string> w = words(file.data() + at, file.data() + stop);
        const size_t begin = at;
        at = newline + 1;
        if (line == 0) {
            if (w.size() != 1 || w[0] != "ply") {
                problem = "not a PLY file (no 'ply' line)";
                return false;
            }
            continue;
        }
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info")
            continue;
        if (w[0] == "end_header" && w.size() == 1) {
            if (!sawFormat) {
                problem = "PLY header has no format line";
                return false;
            }
            header.bodyStart = at;
            return true;
        }
        if (w[0] == "format") {
            const Encoding encodings[] = {Encoding::Ascii, Encoding::LittleEndian, Encoding::BigEndian};
            const char *names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
            const auto known = std::find(std::begin(names), std::end(names), w.size() == 3 ? w[1] : "");
            if (sawFormat || known == std::end(names) || (w[2] != "1.0" && w[2] != "1")) {
                problem = "PLY format line not understood (want 'format ascii|binary_little_endian|"
                          "binary_big_endian 1.0')";
                return false;
            }
            header.encoding = encodings[known - std::begin(names)];
            sawFormat = true;
        } else if (w[0] == "element") {
            Element element;
            if (w.size() != 3 || !wholeUnsigned(w[2], element.count)) {
                problem = "PLY element line not understood (line " + std::to_string(line + 1) + ")";
                return false;
            }
            element.name = w[1];
            header.elements.push_back(element);
        } else if (w[0] == "property") {
            Property p;
            const bool list = w.size() == 5 && w[1] == "list";
            const bool scalar = w.size() == 3 && scalarNamed(w[1], p.type);
            if (header.elements.empty() || !(scalar || (list && scalarNamed(w[2], p.countType) &&
                                                        isInteger(p.countType) && scalarNamed(w[3], p.type)))) {
                problem = "PLY property line not understood (line " + std::to_string(line + 1) + ")";
                return false;
            }
            p.list = list;
            p.name = w.back();
            header.elements.back().properties.push_back(p);
        } else {
            // No keyword: free text an old exporter wrote without `comment`.
            if (header.freeTextLines++ == 0)
                header.firstFreeText = {line + 1, file.substr(begin, std::min<size_t>(stop - begin, 60))};
        }
    }
}

// Reads the body's values one at a time, never past its end.
class Body
{
  public:
    Body(const char *at, const char *end, Encoding encoding) : mAt(at), mEnd(end), mEncoding(encoding) {}

    size_t remaining() const { return size_t(mEnd - mAt); }

    /// The next value as `type`; a float32 value is exact in the double.
    /// False at the end of the body or, in ascii, on a word that is not a
    /// number of that type (problem() says which).
    bool read(Scalar type, double &value)
    {
        if (mEncoding == Encoding::Ascii)
            return readWord(type, value);
        const size_t n = scalarBytes(type);
        if (remaining() < n)
            return fail("ends early");
        unsigned char b[8];
        std::memcpy(b, mAt, n);
        mAt += n;
        if ((mEncoding == Encoding::BigEndian) == (__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__))
            std::reverse(b, b + n);
        value = decode(type, b);
        return true;
    }

    /// Steps over `count` values of `type`.
    bool skip(Scalar type, uint64_t count)
    {
        if (mEncoding != Encoding::Ascii) {
            // Checked before stepping: a claimed list length beyond the file.
            if (count > remaining() / scalarBytes(type))
                return fail("ends early");
            mAt += count * scalarBytes(type);
            return true;
        }
        // Each word takes at least one byte, so this ends within the body.
        for (uint64_t i = 0; i < count; ++i)
            if (!nextWord())
                return fail("ends early");
        return true;
    }

    const char *problem() const { return mProblem; }

  private:
    template <typename T> static double as(const unsigned char *b)
    {
        T v;
        std::memcpy(&v, b, sizeof v);
        return double(v);
    }

    // In Scalar's order.
    static double decode(Scalar type, const unsigned char *b)
    {
        static double (*const as_type[])(const unsigned char *) = {as<int8_t>,  as<uint8_t>,  as<int16_t>, as<uint16_t>,
                                                                   as<int32_t>, as<uint32_t>, as<float>,   as<double>};
        return as_type[int(type)](b);
    }

    bool fail(const char *problem)
    {
        mProblem = problem;
        return false;
    }

    bool nextWord()
    {
        while (mAt < mEnd && std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        mWord = mAt;
        while (mAt < mEnd && !std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        return mAt > mWord;
    }

    // An ascii value: integers as integers; floats correctly rounded to
    // their type (float32 as a float, as OpenMesh's stream reads it), with
    // strtod's spellings (a leading '+', 1e999 as infinity) as the fallback.
    bool readWord(Scalar type, double &value)
    {
        if (!nextWord())
            return fail("ends early");
        const char *first = mWord, *last = mAt;
        if (isInteger(type)) {
            int64_t v;
            const auto [stop, ec] = std::from_chars(first + (*first == '+'), last, v);
            if (ec != std::errc() || stop != last)
                return fail("has a malformed integer");
            value = double(v);
            return true;
        }
        if (type == Scalar::Float32) {
            float v;
            const auto [stop, ec] = std::from_chars(first, last, v);
            if (ec == std::errc() && stop == last) {
                value = v;
                return true;
            }
        } else {
            const auto [stop, ec] = std::from_chars(first, last, value);
            if (ec == std::errc() && stop == last)
                return true;
        }
        const std::string word(first, last);
        char *end = nullptr;
        value = type == Scalar::Float32 ? double(std::strtof(word.c_str(), &end)) : std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0')
            return fail("has a malformed number");
        return true;
    }

    const char *mAt, *mEnd;
    const char *mWord = nullptr;
    Encoding mEncoding;
    const char *mProblem = "";
};

// What an element's properties are to the reader.
enum class Role { Skip, X, Y, Z, Indices };

// The role of each of `element`'s properties; the index list is
// vertex_indices, else vertex_index, for faces and strips.
std::vector<Role> rolesOf(const Element &element)
{
    std::vector<Role> roles(element.properties.size(), Role::Skip);
    const bool faces = element.name == "face" || element.name == "tristrips";
    for (const char *name : {"vertex_indices", "vertex_index"})
        for (size_t i = 0; faces && i < roles.size(); ++i)
            if (element.properties[i].name == name && element.properties[i].list &&
                std::find(roles.begin(), roles.end(), Role::Indices) == roles.end())
                roles[i] = Role::Indices;
    if (element.name == "vertex")
        for (size_t i = 0; i < roles.size(); ++i) {
            const std::string &n = element.properties[i].name;
            if (!element.properties[i].list && (n == "x" || n == "y" || n == "z"))
                roles[i] = n == "x" ? Role::X : n == "y" ? Role::Y : Role::Z;
        }
    return roles;
}

// The fewest body bytes one element takes: see the file's comment.
uint64_t leastBytes(const Element &element, Encoding encoding)
{
    uint64_t bytes = 0;
    for (const Property &p : element.properties)
        bytes += encoding == Encoding::Ascii ? 2 : scalarBytes(p.list ? p.countType : p.type);
    return bytes;
}

// The warning for a header's free-text lines: how many, and the first.
std::string freeTextWarning(const Header &header)
{
    std::string text = header.firstFreeText.second;
    for (char &c : text)
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126)
            c = '?';
    const std::string first = "line " + std::to_string(header.firstFreeText.first) + ", '" + text + "'";
    return header.freeTextLines == 1
               ? "the PLY header's " + first + " is no PLY keyword: read as a comment\n"
               : "the PLY header has " + std::to_string(header.freeTextLines) +
                     " lines that are no PLY keyword (the first: " + first + "): read as comments\n";
}

class PlyReader
{
  public:
    PlyReader(const std::string &path, PolygonSoup &soup, std::string &error) : mPath(path), mSoup(soup), mError(error)
    {
    }

    bool read(const std::string &file)
    {
        Header header;
        std::string problem;
        if (!parseHeader(file, header, problem))
            return fail(problem);
        const Element *vertex = nullptr;
        for (const Element &e : header.elements) {
            if (e.name == "vertex" && vertex)
                return fail("PLY header has two vertex elements");
            if (e.name == "vertex")
                vertex = &e;
        }
        if (!vertex)
            return fail("PLY header has no vertex element");
        if (!fitsBody(header, file.size()))
            return false;
        // Indices are uint32_t with UINT32_MAX kept free for "none".
        if (vertex->count >= std::numeric_limits<uint32_t>::max())
            return fail("PLY file has " + std::to_string(vertex->count) + " vertices, more than mesh2sdf indexes");
        const std::vector<Role> roles = rolesOf(*vertex);
        for (Role r : {Role::X, Role::Y, Role::Z})
            if (std::find(roles.begin(), roles.end(), r) == roles.end())
                return fail("PLY vertex element lacks its x, y or z property");
        mVertices = vertex->count;
        mSoup.points.assign(mVertices, {0.0f, 0.0f, 0.0f}); // backed by the body: fitsBody
        Body body(file.data() + header.bodyStart, file.data() + file.size(), header.encoding);
        for (const Element &e : header.elements)
            if (!readElement(e, body))
                return false;
        if (header.freeTextLines > 0)
            mSoup.warnings += freeTextWarning(header);
        return true;
    }

  private:
    bool fail(const std::string &problem)
    {
        mError = problem + ": " + mPath;
        return false;
    }

    // Every element count against the file: first all of them against its
    // length (what any element takes at least a byte of, as it was checked
    // before this reader), then each at its fewest bytes against the body.
    bool fitsBody(const Header &header, size_t fileBytes)
    {
        double claimed = 0;
        for (const Element &e : header.elements)
            claimed += double(e.count);
        if (claimed > double(fileBytes))
            return fail("mesh header claims " +
                        std::to_string(static_cast<unsigned long long>(std::min(claimed, 1e19))) +
                        " elements, more than the file's " + std::to_string(fileBytes) + " bytes hold");
        const uint64_t body = fileBytes - header.bodyStart + 1; // + 1: the last ascii word needs no separator
        uint64_t need = 0;
        for (const Element &e : header.elements) {
            const uint64_t least = leastBytes(e, header.encoding);
            // Division first: count * least may not fit 64 bits.
            if (least > 0 && (e.count > body / least || need + e.count * least > body))
                return fail("PLY header claims " + std::to_string(e.count) + " " + e.name +
                            " elements, more than the file's " + std::to_string(fileBytes) + " bytes hold");
            need += e.count * least;
        }
        return true;
    }

    bool bodyFailed(const Body &body, const Element &e, uint64_t i)
    {
        return fail(std::string("PLY body ") + body.problem() + " (" + e.name + " " + std::to_string(i) + " of " +
                    std::to_string(e.count) + ")");
    }

    bool readElement(const Element &e, Body &body)
    {
        const std::vector<Role> roles = rolesOf(e);
        const bool strips = e.name == "tristrips";
        const bool faces = strips || e.name == "face";
        if (faces && std::find(roles.begin(), roles.end(), Role::Indices) == roles.end())
            return fail("PLY element " + e.name + " has no vertex_indices list");
        for (size_t k = 0; k < roles.size(); ++k)
            if (roles[k] == Role::Indices && !isInteger(e.properties[k].type))
                return fail("PLY " + e.name + " indices are not integers");
        // The loop runs e.count times: below the file's length (fitsBody).
        for (uint64_t i = 0; i < e.count; ++i)
            for (size_t k = 0; k < roles.size(); ++k) {
                const Property &p = e.properties[k];
                double value, count = 0;
                if (p.list && !body.read(p.countType, count))
                    return bodyFailed(body, e, i);
                if (count < 0)
                    return fail("PLY " + e.name + " " + std::to_string(i) + " has a list of negative length");
                if (roles[k] == Role::Indices) {
                    if (!readIndices(body, p.type, uint64_t(count)))
                        return bodyFailed(body, e, i);
                    if (!(strips ? addStrip(p.type) : addFace()))
                        return false;
                } else if (roles[k] == Role::Skip) {
                    if (!body.skip(p.type, p.list ? uint64_t(count) : 1))
                        return bodyFailed(body, e, i);
                } else {
                    if (!body.read(p.type, value))
                        return bodyFailed(body, e, i);
                    mSoup.points[i][int(roles[k]) - int(Role::X)] = float(value);
                }
            }
        return true;
    }

    // A list's indices into mIndices, as read; the list grows with what is
    // read, never with what its count claims.
    bool readIndices(Body &body, Scalar type, uint64_t count)
    {
        mIndices.clear();
        for (uint64_t j = 0; j < count; ++j) {
            double v;
            if (!body.read(type, v))
                return false;
            mIndices.push_back(v);
        }
        return true;
    }

    bool indexInRange(double v) const { return v >= 0 && v < double(mVertices); }

    // A face with a corner out of range is left out and counted.
    bool addFace()
    {
        mCorners.clear();
        for (double v : mIndices) {
            if (!indexInRange(v)) {
                ++mSoup.skippedFaces;
                return true;
            }
            mCorners.push_back(uint32_t(v));
        }
        mSoup.addPolygon(mCorners.data(), mCorners.size());
        return true;
    }

    // Triangle k of a strip is (s[k], s[k+1], s[k+2]) for even k and
    // (s[k+1], s[k], s[k+2]) for odd k, so that all face one way; -1
    // starts a new strip (in an unsigned 16- or 32-bit list, -1 written in
    // that type: the restart index of graphics APIs). A triangle with a
    // corner repeated joins two runs of a strip (a zero-area stitch): no
    // face of the file, it is left out uncounted; one with a corner out of
    // range is left out and counted.
    bool addStrip(Scalar type)
    {
        const double restart = type == Scalar::UInt32 ? 4294967295.0 : type == Scalar::UInt16 ? 65535.0 : -1;
        double a = 0, b = 0;
        size_t length = 0; // of the current strip
        for (double c : mIndices) {
            if (c == -1 || c == restart) {
                length = 0;
                continue;
            }
            if (length >= 2) {
                const double t[3] = {length % 2 ? b : a, length % 2 ? a : b, c};
                if (!indexInRange(a) || !indexInRange(b) || !indexInRange(c))
                    ++mSoup.skippedFaces;
                else if (a != b && b != c && a != c) {
                    const uint32_t corners[3] = {uint32_t(t[0]), uint32_t(t[1]), uint32_t(t[2])};
                    mSoup.addPolygon(corners, 3);
                }
            }
            a = b;
            b = c;
            ++length;
        }
        return true;
    }

    const std::string &mPath;
    PolygonSoup &mSoup;
    std::string &mError;
    uint64_t mVertices = 0;
    std::vector<double> mIndices;
    std::vector<uint32_t> mCorners;
};

} // namespace

bool readPly(const std::string &path, PolygonSoup &soup, std::string &error)
{
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) {
        error = "cannot open mesh: " + path;
        return false;
    }
    std::string file(size_t(in.tellg()), '\0');
    in.seekg(0);
    if (!in.read(file.data(), std::streamsize(file.size()))) {
        error = "cannot read mesh: " + path;
        return false;
    }
    soup = PolygonSoup{};
    return PlyReader(path, soup, error).read(file);
}

} // namespace meshsdf
