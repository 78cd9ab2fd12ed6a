// sdftrace — .obj files parsed in parallel (see obj_read.h).
//
// The file is cut into pieces of about kPieceBytes at line ends; each piece
// is parsed on its own into points, corners and face sizes, and the pieces
// are joined in order (prefix sums of their counts), so the soup does not
// depend on how many threads parsed it. What makes a piece's lines
// independent is that a corner index names a point by its place in the
// file: a positive one outright, a negative one relative to the "v" lines
// before it, which a piece counts from its own start and the join offsets
// by the pieces before it.
//
// The soup is the one OpenMesh's reader (openmesh_read.h) makes of a plain
// file, which is what lets this reader stand in for it: a line is trimmed
// of " \t\r\n" and skipped when empty, a comment or led by other white
// space; its first word is the keyword; a "v" line's first three words are
// its point, each parsed to the correctly rounded float (std::from_chars,
// as a stream's >> through strtof), the rest of the line ignored; an "f"
// line's words are corners, the first number of each (before any '/') a
// point index, 1-based, or negative from the end of the points so far;
// every other keyword adds nothing to the soup. Where the two could differ,
// this reader does not decide: a word that is not a whole finite float or
// integer where one is wanted, an index 0 or past the points, a face of
// fewer than three corners or with a corner repeated, a "vt" line OpenMesh
// would refuse, a file with no face, and the file goes to OpenMesh's reader
// whole.
#include "io/obj_read.h"

#include "io/mesh_io.h"
#include "io/openmesh_read.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

namespace meshsdf
{

namespace
{

constexpr size_t kPieceBytes = size_t(1) << 18;

bool space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// The next word of [at, end) (a run of non-space characters), or an empty
// one at the end.
struct Word {
    const char *begin, *end;
    bool empty() const { return begin == end; }
    bool is(const char *text) const
    {
        const size_t n = std::strlen(text);
        return size_t(end - begin) == n && std::memcmp(begin, text, n) == 0;
    }
};

Word nextWord(const char *&at, const char *end)
{
    while (at < end && space(*at))
        ++at;
    const char *begin = at;
    while (at < end && !space(*at))
        ++at;
    return {begin, at};
}

// The whole word as a finite float.
bool wholeFloat(const Word &w, float &value)
{
    const auto [stopped, ec] = std::from_chars(w.begin, w.end, value);
    return ec == std::errc() && stopped == w.end && !w.empty() && std::isfinite(value);
}

// [begin, end) as a whole integer.
bool wholeInt(const char *begin, const char *end, long long &value)
{
    const auto [stopped, ec] = std::from_chars(begin, end, value);
    return ec == std::errc() && stopped == end && begin != end;
}

// One piece's lines parsed.
struct Piece {
    const char *begin = nullptr, *end = nullptr;
    std::vector<std::array<float, 3>> points;
    std::vector<long long> corners;  // 1-based indices; for relative ones (below), the "v" lines before
                                     // the corner in this piece plus the negative index
    std::vector<size_t> relative;    // which of `corners` are relative to the piece's start
    std::vector<uint32_t> faceSizes; // corners per face
    bool plain = true;
};

// A corner word: the point index, then optionally "/texture" and
// "/normal", each an integer or empty.
bool cornerIndex(const Word &w, long long &index)
{
    const char *slash = std::find(w.begin, w.end, '/');
    if (!wholeInt(w.begin, slash, index) || index == 0)
        return false;
    for (int part = 0; part < 2 && slash != w.end; ++part) {
        const char *from = slash + 1;
        slash = std::find(from, w.end, '/');
        long long ignored;
        if (from != slash && !wholeInt(from, slash, ignored))
            return false;
    }
    return slash == w.end;
}

void parsePiece(Piece &piece)
{
    long long vLines = 0; // "v" lines so far in this piece
    for (const char *line = piece.begin; line < piece.end && piece.plain;) {
        const char *newline = static_cast<const char *>(std::memchr(line, '\n', size_t(piece.end - line)));
        const char *next = newline ? newline + 1 : piece.end, *end = newline ? newline : piece.end;
        auto trimmed = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
        while (line < end && trimmed(*line))
            ++line;
        while (end > line && trimmed(end[-1]))
            --end;
        if (line == end || *line == '#' || space(*line)) {
            line = next;
            continue;
        }
        const char *at = line;
        const Word key = nextWord(at, end);
        if (key.is("v")) {
            std::array<float, 3> p;
            for (int k = 0; k < 3 && piece.plain; ++k)
                piece.plain = wholeFloat(nextWord(at, end), p[k]);
            piece.points.push_back(p);
            ++vLines;
        } else if (key.is("vt")) {
            float uv;
            for (int k = 0; k < 2 && piece.plain; ++k)
                piece.plain = wholeFloat(nextWord(at, end), uv);
        } else if (key.is("f")) {
            uint32_t n = 0;
            for (Word w = nextWord(at, end); !w.empty() && piece.plain; w = nextWord(at, end), ++n) {
                long long index = 0;
                piece.plain = cornerIndex(w, index);
                if (index < 0) {
                    piece.relative.push_back(piece.corners.size());
                    index += vLines;
                }
                piece.corners.push_back(index);
            }
            piece.plain = piece.plain && n >= 3;
            piece.faceSizes.push_back(n);
        }
        line = next;
    }
}

// The whole file, or false.
bool readWhole(const std::string &path, std::vector<char> &text)
{
    std::unique_ptr<FILE, int (*)(FILE *)> f(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!f || std::fseek(f.get(), 0, SEEK_END) != 0)
        return false;
    const long size = std::ftell(f.get());
    if (size < 0 || std::fseek(f.get(), 0, SEEK_SET) != 0)
        return false;
    text.resize(size_t(size));
    return std::fread(text.data(), 1, text.size(), f.get()) == text.size();
}

} // namespace

bool parsePlainObj(const char *text, size_t size, PolygonSoup &soup)
{
    soup = PolygonSoup{};
    std::vector<Piece> pieces;
    const char *begin = text, *end = begin + size;
    for (const char *at = begin; at < end;) {
        const char *cut = end - at > ptrdiff_t(kPieceBytes) ? at + kPieceBytes : end;
        const char *newline = static_cast<const char *>(std::memchr(cut, '\n', size_t(end - cut)));
        cut = cut == end || !newline ? end : newline + 1;
        pieces.emplace_back();
        pieces.back().begin = at;
        pieces.back().end = cut;
        at = cut;
    }
    tbb::parallel_for(size_t(0), pieces.size(), [&](size_t i) { parsePiece(pieces[i]); });
    // Where each piece's points, corners and faces go.
    std::vector<size_t> points(pieces.size() + 1, 0), corners(pieces.size() + 1, 0), faces(pieces.size() + 1, 0);
    for (size_t i = 0; i < pieces.size(); ++i) {
        if (!pieces[i].plain)
            return false;
        points[i + 1] = points[i] + pieces[i].points.size();
        corners[i + 1] = corners[i] + pieces[i].corners.size();
        faces[i + 1] = faces[i] + pieces[i].faceSizes.size();
    }
    if (faces.back() == 0 || points.back() >= UINT32_MAX)
        return false; // no face: OpenMesh's reader says why
    soup.points.resize(points.back());
    soup.corners.resize(corners.back());
    soup.ends.resize(faces.back());
    std::atomic<bool> plain{true};
    tbb::parallel_for(size_t(0), pieces.size(), [&](size_t i) {
        Piece &piece = pieces[i];
        std::copy(piece.points.begin(), piece.points.end(), soup.points.begin() + ptrdiff_t(points[i]));
        for (size_t r : piece.relative) // now 1-based in the file: the points before the piece, and one
            piece.corners[r] += (long long)points[i] + 1;
        const long long count = (long long)points.back();
        uint32_t *out = soup.corners.data() + corners[i];
        for (size_t c = 0; c < piece.corners.size(); ++c) {
            const long long index = piece.corners[c];
            if (index < 1 || index > count) {
                plain = false;
                return;
            }
            out[c] = uint32_t(index - 1);
        }
        size_t at = corners[i];
        for (size_t f = 0; f < piece.faceSizes.size(); ++f) {
            if (!isPolygon(soup.corners.data() + at, piece.faceSizes[f])) {
                plain = false;
                return;
            }
            at += piece.faceSizes[f];
            soup.ends[faces[i] + f] = at;
        }
        piece = Piece{}; // its memory back as soon as it is joined
    });
    if (!plain)
        soup = PolygonSoup{};
    return plain;
}

bool readObj(const std::string &path, PolygonSoup &soup, std::string &error)
{
    std::vector<char> text;
    if (readWhole(path, text) && parsePlainObj(text.data(), text.size(), soup))
        return true;
    soup = PolygonSoup{};
    return readOpenMesh(path, "obj", soup, error);
}

} // namespace meshsdf
