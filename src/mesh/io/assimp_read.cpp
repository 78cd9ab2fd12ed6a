// sdftrace — the interchange formats through assimp (see assimp_read.h).
#include "io/assimp_read.h"
#include "io/reader_process.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include <nlohmann/json.hpp>

#include <malloc.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace meshsdf
{

const char *const kAssimpExtensions = "gltf glb fbx dae 3mf";

namespace
{

// A node's accumulated transform, row-major 3x4 (the affine part), in
// double so that a deep hierarchy rounds once, at the vertex.
struct Affine {
    double m[3][4];

    static Affine of(const aiMatrix4x4 &a)
    {
        return {{{a.a1, a.a2, a.a3, a.a4}, {a.b1, a.b2, a.b3, a.b4}, {a.c1, a.c2, a.c3, a.c4}}};
    }

    Affine then(const Affine &local) const // this * local
    {
        Affine r{};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j)
                r.m[i][j] = m[i][0] * local.m[0][j] + m[i][1] * local.m[1][j] + m[i][2] * local.m[2][j] +
                            (j == 3 ? m[i][3] : 0.0);
        return r;
    }

    /// Whether the transform mirrors (a negative determinant): then it
    /// turns every face inside out, and the face's corners are reversed.
    bool mirrors() const
    {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]) <
               0;
    }

    std::array<float, 3> apply(const aiVector3D &p) const
    {
        std::array<float, 3> out;
        for (int i = 0; i < 3; ++i)
            out[i] = float(m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3]);
        return out;
    }
};

std::string extensionOf(const std::string &path)
{
    const size_t dot = path.find_last_of('.');
    return dot == std::string::npos ? "" : path.substr(dot + 1);
}

// assimp's message, on one line.
std::string oneLine(const char *message)
{
    std::string s = message && *message ? message : "unknown error";
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    return s;
}

// Appends `mesh`'s vertices moved by `world` and its polygons (three or
// more corners) on them, their corners reversed where `world` mirrors: a
// mirrored instance keeps its outside out (glTF requires it; so does every
// format whose importer leaves the node transforms to us).
bool addInstance(const aiMesh &mesh, const Affine &world, PolygonSoup &soup, const std::string &path,
                 std::string &error)
{
    const bool mirrored = world.mirrors();
    // A mesh of points or lines only (glTF's POINTS and LINES primitives)
    // adds nothing, not even its vertices.
    if (!(mesh.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)))
        return true;
    const size_t base = soup.points.size();
    // Indices are uint32_t with UINT32_MAX kept free for "none".
    if (mesh.mNumVertices >= std::numeric_limits<uint32_t>::max() - base) {
        error = "mesh has more vertices than mesh2sdf indexes, once its instances are placed: " + path;
        return false;
    }
    if (!mesh.mVertices && mesh.mNumVertices > 0) {
        error = "mesh has a mesh without vertex positions: " + path;
        return false;
    }
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
        soup.points.push_back(world.apply(mesh.mVertices[v]));
    std::vector<uint32_t> corners;
    for (unsigned f = 0; mesh.mFaces && f < mesh.mNumFaces; ++f) {
        const aiFace &face = mesh.mFaces[f];
        if (face.mNumIndices < 3 || !face.mIndices)
            continue; // a point or a line
        corners.clear();
        for (unsigned k = 0; k < face.mNumIndices; ++k) {
            if (face.mIndices[k] >= mesh.mNumVertices) {
                error = "mesh has a face with vertex index " + std::to_string(face.mIndices[k]) + ", outside its " +
                        std::to_string(mesh.mNumVertices) + " vertices: " + path;
                return false;
            }
            corners.push_back(uint32_t(base + face.mIndices[k]));
        }
        if (mirrored)
            std::reverse(corners.begin(), corners.end());
        soup.addPolygon(corners.data(), corners.size());
    }
    return true;
}

// Every node's meshes, depth first from the root, each node's transform
// accumulated from the root down.
bool flattenScene(const aiScene &scene, PolygonSoup &soup, const std::string &path, std::string &error)
{
    // A bound on the depth: the walk's stack holds at most kMaxDepth
    // unvisited siblings' parents, and a malformed hierarchy cannot make it
    // loop for ever.
    constexpr size_t kMaxDepth = 1024;
    struct Visit {
        const aiNode *node;
        Affine world;
        size_t depth;
    };
    std::vector<Visit> stack{{scene.mRootNode, Affine::of(scene.mRootNode->mTransformation), 0}};
    while (!stack.empty()) {
        const Visit visit = stack.back();
        stack.pop_back();
        if (visit.depth > kMaxDepth) {
            error = "mesh's node hierarchy is deeper than " + std::to_string(kMaxDepth) + " levels: " + path;
            return false;
        }
        const aiNode &node = *visit.node;
        for (unsigned i = 0; node.mMeshes && i < node.mNumMeshes; ++i) {
            if (node.mMeshes[i] >= scene.mNumMeshes || !scene.mMeshes[node.mMeshes[i]]) {
                error = "mesh has a node naming a mesh it does not have: " + path;
                return false;
            }
            if (!addInstance(*scene.mMeshes[node.mMeshes[i]], visit.world, soup, path, error))
                return false;
        }
        // Children pushed last first, so that they are visited in order.
        for (unsigned c = node.mNumChildren; node.mChildren && c-- > 0;)
            if (node.mChildren[c])
                stack.push_back({node.mChildren[c], visit.world.then(Affine::of(node.mChildren[c]->mTransformation)),
                                 visit.depth + 1});
    }
    return true;
}

// The format's name, for messages.
std::string formatName(const std::string &path)
{
    std::string ext = extensionOf(path);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == "gltf" ? "glTF" : ext == "glb" ? "GLB" : ext == "dae" ? "Collada" : ext == "fbx" ? "FBX" : "3MF";
}

// The JSON of a .gltf file, or of a .glb file's first chunk (read alone:
// the binary chunk after it may be most of the file); "" if there is none.
std::string gltfJson(const std::string &path)
{
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in.tellg();
    char header[20];
    if (!in.seekg(0) || !in.read(header, sizeof header) || std::memcmp(header, "glTF", 4) != 0) {
        in.clear();
        in.seekg(0);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    uint32_t length = 0, type = 0;
    std::memcpy(&length, header + 12, 4);
    std::memcpy(&type, header + 16, 4);
    if (type != 0x4E4F534Au || std::streamoff(length) > size - 20)
        return "";
    std::string json(length, '\0');
    return in.read(&json[0], length) ? json : "";
}

// The faces glTF primitives declare that assimp's importer left out: it
// drops a triangle with an index out of range, with a warning that says
// no count. Each triangle primitive's faces as its accessor's count
// declares them (TRIANGLES: count / 3; STRIP and FAN: count - 2), less
// the faces of the scene's mesh made of it (the importer makes one mesh
// per primitive, in the file's order). 0 where the file is not glTF 2 or
// the meshes do not match the primitives one to one.
size_t gltfFacesLeftOut(const std::string &path, const aiScene &scene)
{
    const nlohmann::json doc = nlohmann::json::parse(gltfJson(path), nullptr, false);
    if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors") ||
        !doc["accessors"].is_array())
        return 0;
    const nlohmann::json &accessors = doc["accessors"];
    // The faces of each primitive, or -1 for one that makes no faces.
    std::vector<int64_t> declared;
    for (const auto &mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            return 0;
        for (const auto &prim : mesh["primitives"]) {
            if (!prim.is_object())
                return 0;
            const int64_t mode = prim.value("mode", int64_t(4));
            int64_t accessor = -1;
            if (prim.contains("indices") && prim["indices"].is_number_integer())
                accessor = prim["indices"].get<int64_t>();
            else if (prim.contains("attributes") && prim["attributes"].is_object() &&
                     prim["attributes"].contains("POSITION") && prim["attributes"]["POSITION"].is_number_integer())
                accessor = prim["attributes"]["POSITION"].get<int64_t>();
            if (accessor < 0 || size_t(accessor) >= accessors.size() || !accessors[size_t(accessor)].is_object())
                return 0;
            const int64_t count = accessors[size_t(accessor)].value("count", int64_t(0));
            declared.push_back(mode == 4 ? count / 3 : (mode == 5 || mode == 6) ? std::max<int64_t>(count - 2, 0) : -1);
        }
    }
    if (declared.size() != scene.mNumMeshes)
        return 0;
    size_t leftOut = 0;
    for (size_t i = 0; i < declared.size(); ++i)
        if (declared[i] > 0 && scene.mMeshes[i] && int64_t(scene.mMeshes[i]->mNumFaces) < declared[i])
            leftOut += size_t(declared[i] - int64_t(scene.mMeshes[i]->mNumFaces));
    return leftOut;
}

// One import of `path`: the scene, or null with one line in `error`.
const aiScene *importOnce(Assimp::Importer &importer, const std::string &path, std::string &error)
{
    // The coordinates as the file stores them, as for every other format:
    // Collada's up axis is not applied (its unit is: assimp 5.2 cannot be
    // told otherwise).
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    // Only the structure is checked (indices within their mesh, a root
    // node): no step that joins, splits or triangulates, so the file's
    // vertices and polygons stay as they are.
    const aiScene *scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
    if (!scene) {
        // assimp's format check parses the file, so a malformed file is
        // "no suitable reader"; and it catches its own std::bad_alloc, which
        // its Collada reader throws on a list shorter than its count: say
        // what each means here.
        const std::string why = oneLine(importer.GetErrorString());
        error = "cannot read mesh (" +
                (why.rfind("No suitable reader", 0) == 0 ? "not a valid " + extensionOf(path) + " file"
                 : why == "std::bad_alloc" ? "a count the file's data does not hold, or more than memory allows"
                                           : why) +
                "): " + path;
        return nullptr;
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
        error = "cannot read mesh (the scene is incomplete): " + path;
        return nullptr;
    }
    return scene;
}

// glibc fills memory it hands out with the complement of this byte, and
// memory it takes back with the byte itself (mallopt's M_PERTURB): a read
// of memory nobody wrote sees it. Another allocator ignores it.
void fillFreshMemory(int byte)
{
#ifdef M_PERTURB
    mallopt(M_PERTURB, byte);
#else
    (void)byte;
#endif
}

// The import itself, run in the child process: twice, the first scene kept
// while the second is read (so that the two imports' arrays lie apart),
// fresh and freed memory filled with another byte each time. An importer
// that reads past the file's data (assimp 5.2's Collada reader, for an
// accessor longer than its array) or memory it never wrote then reads
// other bytes each time, and the two scenes differ: the file is refused,
// not turned into a grid of whatever memory held (loadMesh also refuses
// coordinates such bytes make, subnormal or absurdly large ones).
bool importScene(const std::string &path, PolygonSoup &soup, std::string &error)
{
    Assimp::Importer first, second;
    fillFreshMemory(0xA5);
    const aiScene *scene = importOnce(first, path, error);
    if (!scene || !flattenScene(*scene, soup, path, error))
        return false;
    PolygonSoup again;
    fillFreshMemory(0x3C);
    const aiScene *rescene = importOnce(second, path, error);
    if (!rescene || !flattenScene(*rescene, again, path, error))
        return false;
    if (again.points != soup.points || again.corners != soup.corners || again.ends != soup.ends) {
        error = "cannot read mesh (the " + formatName(path) +
                " importer read it twice into two different scenes: it reads past the file's data): " + path;
        return false;
    }
    const std::string ext = formatName(path);
    if (ext == "glTF" || ext == "GLB")
        soup.skippedFaces += gltfFacesLeftOut(path, *scene);
    return true;
}

} // namespace

bool isAssimpExtension(const std::string &ext)
{
    std::istringstream names(kAssimpExtensions);
    std::string name;
    while (names >> name)
        if (ext == name)
            return true;
    return false;
}

bool readAssimp(const std::string &path, PolygonSoup &soup, std::string &error)
{
    // assimp 5.2 aborts on some malformed files (its asserts are on in
    // Debian's build: a 3MF whose zip CRC is wrong), crashes on others and
    // loops on some Collada, or allocates without end: it reads in a child
    // process, within the time and memory isolated_read.h allows.
    const std::string reader = "the " + formatName(path) + " importer (assimp " + std::to_string(aiGetVersionMajor()) +
                               "." + std::to_string(aiGetVersionMinor()) + "." + std::to_string(aiGetVersionPatch()) +
                               ")";
    return readInChildProcess([&path](PolygonSoup &s, std::string &e) { return importScene(path, s, e); }, path, reader,
                              soup, error);
}

} // namespace meshsdf
