// sdftrace — OpenMesh's readers (.obj .off .stl .om) into a polygon soup
// (see openmesh_read.h), in a child process, with the text checks OpenMesh
// leaves out.
#include "io/openmesh_read.h"

#include "io/reader_process.h"

// GCC 12 with sanitizers flags OpenMesh's property vectors (VectorT copies
// in PropertyT::push_back) as maybe-uninitialized; a false positive in its
// headers, silenced for this file only.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace meshsdf
{

namespace
{

using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

// OpenMesh's readers parse the file; this importer keeps what they read,
// every vertex and every face as the file gives them. OpenMesh's own
// half-edge mesh cannot hold a face whose edge is already used in the same
// direction (a face flipped against its neighbour, a face used twice): its
// importer gives such a face copies of its vertices, which would split the
// mesh along every flipped face. The faces are recorded here before that,
// on the file's vertex numbers; the half-edge mesh is still built (the
// readers ask it for handles) but never read. Readers that rebuild a mesh
// from stored half-edges (.om with topology) add no face through
// add_face(VHandles): for those the half-edge mesh's faces are read.
class FaceRecorder : public OpenMesh::IO::ImporterT<PolyMesh>
{
  public:
    explicit FaceRecorder(PolyMesh &mesh) : ImporterT<PolyMesh>(mesh), mMesh(mesh) {}

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f &p) override { return note(ImporterT::add_vertex(p)); }
    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d &p) override { return note(ImporterT::add_vertex(p)); }
    OpenMesh::VertexHandle add_vertex() override { return note(ImporterT::add_vertex()); }

    OpenMesh::FaceHandle add_face(const OpenMesh::IO::BaseImporter::VHandles &corners) override
    {
        // The faces ImporterT takes: at least three corners, all valid and
        // distinct (it refuses the others).
        bool valid = corners.size() > 2;
        for (size_t i = 0; valid && i < corners.size(); ++i) {
            valid = mMesh.is_valid_handle(corners[i]) && fileVertex(corners[i]) != kNotFromFile;
            for (size_t j = i + 1; valid && j < corners.size(); ++j)
                valid = corners[i] != corners[j];
        }
        if (valid) {
            for (const auto vh : corners)
                mFaces.corners.push_back(fileVertex(vh));
            mFaces.ends.push_back(mFaces.corners.size());
        }
        return ImporterT::add_face(corners);
    }

    /// The file's vertices, in its order, at their final positions.
    std::vector<std::array<float, 3>> points() const
    {
        std::vector<std::array<float, 3>> out(mFileHandles.size());
        for (size_t v = 0; v < mFileHandles.size(); ++v) {
            const auto &p = mMesh.point(mFileHandles[v]);
            out[v] = {p[0], p[1], p[2]};
        }
        return out;
    }

    /// The file's faces on points()'s numbering; for a reader that added
    /// none through add_face(VHandles), the half-edge mesh's.
    PolygonSoup &faces()
    {
        if (mFaces.ends.empty())
            for (const auto fh : mMesh.faces()) {
                const size_t begin = mFaces.corners.size();
                for (const auto vh : mMesh.fv_range(fh))
                    mFaces.corners.push_back(fileVertex(vh));
                if (std::find(mFaces.corners.begin() + begin, mFaces.corners.end(), kNotFromFile) ==
                    mFaces.corners.end())
                    mFaces.ends.push_back(mFaces.corners.size());
                else
                    mFaces.corners.resize(begin);
            }
        return mFaces;
    }

  private:
    static constexpr uint32_t kNotFromFile = UINT32_MAX;

    uint32_t fileVertex(OpenMesh::VertexHandle vh) const
    {
        return vh.idx() >= 0 && size_t(vh.idx()) < mFileVertex.size() ? mFileVertex[vh.idx()] : kNotFromFile;
    }

    OpenMesh::VertexHandle note(OpenMesh::VertexHandle vh)
    {
        if (size_t(vh.idx()) >= mFileVertex.size())
            mFileVertex.resize(size_t(vh.idx()) + 1, kNotFromFile);
        mFileVertex[vh.idx()] = uint32_t(mFileHandles.size());
        mFileHandles.push_back(vh);
        return vh;
    }

    PolyMesh &mMesh;
    std::vector<OpenMesh::VertexHandle> mFileHandles; // the file's vertices, in order
    std::vector<uint32_t> mFileVertex;                // handle -> file vertex; kNotFromFile: a copy
    PolygonSoup mFaces;                               // corners and ends only
};

// `word` as a number, the way strtod reads it: true, with *value, when
// strtod takes the whole word. std::from_chars first (several times
// faster, the same correctly rounded value for the decimal numbers it
// takes), strtod for what it does not take whole (a leading '+', hex).
bool wholeNumber(const std::string &word, double *value)
{
    const char *first = word.data(), *last = first + word.size();
    const auto [stopped, ec] = std::from_chars(first, last, *value);
    if (ec == std::errc() && stopped == last)
        return true;
    char *end = nullptr;
    *value = std::strtod(word.c_str(), &end);
    return end != word.c_str() && *end == '\0';
}

// True if `word` is a whole number that is not finite ("nan", "inf", 1e999).
bool nonFiniteNumber(const std::string &word)
{
    double v;
    return wholeNumber(word, &v) && !std::isfinite(v);
}

// The words of one line (runs of characters that are not white space, as
// a stream's >> reads them), one at a time into a reused string.
class LineWords
{
  public:
    LineWords(const char *begin, const char *end) : mAt(begin), mEnd(end) {}
    bool next(std::string &word)
    {
        while (mAt < mEnd && std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        if (mAt == mEnd)
            return false;
        const char *start = mAt;
        while (mAt < mEnd && !std::isspace(static_cast<unsigned char>(*mAt)))
            ++mAt;
        word.assign(start, mAt);
        return true;
    }

  private:
    const char *mAt, *mEnd;
};

// Faces a file declares, when it says: kUnknown otherwise.
constexpr size_t kUnknown = SIZE_MAX;

// OpenMesh's text readers do not report a coordinate they cannot parse
// ("nan", "inf", 1e999): the OBJ reader drops the vertex line, shifting
// every later index, the OFF reader stops and finds no faces, the STL
// reader goes on with a wrong vertex. So the coordinates of text files are
// checked here first: OBJ "v" lines, every number after OFF's keyword line,
// and STL "vertex" lines (PLY's reader is our own and checks its numbers).
// Binary formats carry NaN and Inf through and are caught after reading.
// Nor do they report a face they leave out (an OBJ corner out of range):
// the faces an OBJ or ascii STL declares ("f" lines, "facet" lines) are
// counted on the way into `declared`, so that those left out can be.
// Each line's words are scanned in place (a string stream per line cost
// more than the reading).
bool checkTextCoordinates(const std::string &path, const std::string &ext, size_t &declared, std::string &error)
{
    if (ext != "obj" && ext != "off" && ext != "stl")
        return true;
    if (ext != "off")
        declared = 0;
    std::ifstream in(path);
    std::string text, word; // a line at a time: a binary file is left after its header
    bool data = false;      // OFF: past the header
    for (size_t number = 1; std::getline(in, text); ++number) {
        const char *line = text.data(), *end = line + text.size();
        if (ext == "off") { // comments run from '#' to the end of the line
            const char *hash = static_cast<const char *>(std::memchr(line, '#', text.size()));
            if (hash)
                end = hash;
        }
        LineWords words(line, end);
        int check = 0; // words to check on this line; -1: all
        if (ext == "obj") {
            const bool blank = end - line >= 2 && (line[1] == ' ' || line[1] == '\t');
            declared += blank && line[0] == 'f';
            if (!blank || line[0] != 'v')
                continue;
            words.next(word); // "v"
            for (int k = 0; k < 3; ++k) {
                if (!words.next(word)) {
                    error = "mesh has a malformed coordinate (line " + std::to_string(number) + "): " + path;
                    return false;
                }
                double v;
                if (!wholeNumber(word, &v) || !std::isfinite(v)) {
                    error =
                        "mesh has a non-finite or malformed coordinate (line " + std::to_string(number) + "): " + path;
                    return false;
                }
            }
            continue;
        } else if (ext == "off") {
            if (!data) { // the keyword line: OFF, COFF, NOFF ...; binary OFF is checked after reading
                if (!words.next(word))
                    continue;
                if (word.find("OFF") == std::string::npos || text.find("BINARY") != std::string::npos)
                    return true;
                data = true;
            }
            check = -1;
        } else { // stl
            if (!words.next(word))
                continue;
            declared += word == "facet";
            if (word != "vertex")
                continue;
            check = 3;
        }
        for (int k = 0; (check < 0 || k < check) && words.next(word); ++k)
            if (nonFiniteNumber(word)) {
                error = "mesh has a non-finite coordinate (line " + std::to_string(number) + "): " + path;
                return false;
            }
    }
    return true;
}

// The element counts of an OFF header, checked against the file's length
// before OpenMesh reserves room for them: its reader allocates what a header
// claims (2^40 vertices: killed for memory, or std::bad_alloc). Every
// element takes at least one byte of the file, in any encoding. (PLY's
// reader checks its own header the same way, and more closely.)
bool checkHeaderCounts(const std::string &path, const std::string &ext, size_t &declared, std::string &error)
{
    if (ext != "off")
        return true;
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const double length = double(in.tellg());
    in.seekg(0);
    std::string line, word;
    double claimed = 0;
    // The keyword line (OFF, COFF, NOFF, ... or "OFF nv nf ne"), comments,
    // then the counts: the first line with three numbers.
    for (int n = 0; n < 10000 && std::getline(in, line); ++n) {
        const size_t hash = line.find('#');
        LineWords words(line.data(), line.data() + (hash == std::string::npos ? line.size() : hash));
        double v, f;
        if (words.next(word) && word.find("OFF") != std::string::npos && !words.next(word))
            continue;
        if (word == "BINARY")
            return true; // its counts are binary: OpenMesh's reader checks them
        if (wholeNumber(word, &v) && words.next(word) && wholeNumber(word, &f)) {
            claimed = v + f;
            if (f >= 0 && f == std::floor(f) && f < 1e18)
                declared = size_t(f);
            break;
        }
    }
    if (claimed > length) {
        error = "mesh header claims " + std::to_string(static_cast<unsigned long long>(std::min(claimed, 1e19))) +
                " elements, more than the file's " + std::to_string(static_cast<long long>(length)) +
                " bytes hold: " + path;
        return false;
    }
    return true;
}

// The facets a binary STL declares, as OpenMesh's reader tells the two
// kinds apart (a file of exactly 84 + 50 n bytes, n the count after the
// 80-byte header, is binary), or kUnknown for an ascii one.
size_t binaryStlFacets(const std::string &path)
{
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const uint64_t length = uint64_t(in.tellg());
    unsigned char count[4];
    if (length < 84 || !in.seekg(80) || !in.read(reinterpret_cast<char *>(count), 4))
        return kUnknown;
    const uint64_t n =
        uint64_t(count[0]) | uint64_t(count[1]) << 8 | uint64_t(count[2]) << 16 | uint64_t(count[3]) << 24;
    return length == 84 + 50 * n ? size_t(n) : kUnknown;
}

// The names readers go by in errors.
std::string readerName(const std::string &ext)
{
    std::string upper = ext;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    return "OpenMesh's " + upper + " reader";
}

} // namespace

bool readOpenMesh(const std::string &path, const std::string &ext, PolygonSoup &soup, std::string &error)
{
    size_t textFaces = kUnknown, offFaces = kUnknown;
    if (!checkTextCoordinates(path, ext, textFaces, error) || !checkHeaderCounts(path, ext, offFaces, error))
        return false;
    const size_t binaryFacets = ext == "stl" ? binaryStlFacets(path) : kUnknown;
    const size_t declared = ext == "obj"   ? textFaces
                            : ext == "off" ? offFaces
                            : ext == "stl" ? (binaryFacets != kUnknown ? binaryFacets : textFaces)
                                           : kUnknown;
    const auto read = [&path, &ext](PolygonSoup &s, std::string &e) {
        // OpenMesh reports complex edges and parse problems on its own
        // streams; the health line says what matters, once.
        omerr().disable();
        omlog().disable();
        omout().disable();
        PolyMesh poly;
        FaceRecorder recorder(poly);
        OpenMesh::IO::Options options;
        if (!OpenMesh::IO::IOManager().read(path, recorder, options)) {
            e = "cannot read mesh (not a valid " + ext + " file?): " + path;
            return false;
        }
        PolygonSoup &faces = recorder.faces();
        s.points = recorder.points();
        s.corners = std::move(faces.corners);
        s.ends = std::move(faces.ends);
        return true;
    };
    if (!readInChildProcess(read, path, readerName(ext), soup, error))
        return false;
    // What the file declares and OpenMesh did not hand over: an STL facet
    // only ever for corners at one position (its reader joins vertices by
    // position), a zero-area facet; an OBJ or OFF face for a corner out of
    // range, fewer than three corners or a corner repeated.
    if (declared != kUnknown && declared > soup.ends.size())
        (ext == "stl" ? soup.degenerateFaces : soup.skippedFaces) += declared - soup.ends.size();
    return true;
}

} // namespace meshsdf
