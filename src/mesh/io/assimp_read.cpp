// sdftrace — the interchange formats through assimp (see assimp_read.h).
#include "io/assimp_read.h"
#include "io/reader_process.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <fstream>
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
// more corners) on them.
bool addInstance(const aiMesh &mesh, const Affine &world, PolygonSoup &soup, const std::string &path,
                 std::string &error)
{
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

// The import itself, run in the child process.
bool importScene(const std::string &path, PolygonSoup &soup, std::string &error)
{
    Assimp::Importer importer;
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
        return false;
    }
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
        error = "cannot read mesh (the scene is incomplete): " + path;
        return false;
    }
    return flattenScene(*scene, soup, path, error);
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
    return readInChildProcess([&path](PolygonSoup &s, std::string &e) { return importScene(path, s, e); }, path, soup,
                              error);
}

} // namespace meshsdf
