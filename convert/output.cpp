// mesh2sdf — output files (see output.h).
#include "output.h"

#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace mesh2sdf {

bool reserveFile(const std::string& path, PendingFile& file, std::string& error)
{
    struct stat st;
    if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        error = "output is a folder, not a file: " + path;
        return false;
    }
    std::string tmpl = path + ".tmp-XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    const int fd = mkstemp(buf.data());
    if (fd < 0) {
        error = "cannot write " + path + ": " + std::strerror(errno);
        return false;
    }
    close(fd);
    file.path = path;
    file.tmp = buf.data();
    return true;
}

bool commitFile(PendingFile& file, std::string& error)
{
    if (file.tmp.empty())
        return true;
    // mkstemp made the file 0600; give it the usual permissions.
    const mode_t mask = umask(0);
    umask(mask);
    chmod(file.tmp.c_str(), 0666 & ~mask);
    if (std::rename(file.tmp.c_str(), file.path.c_str()) != 0) {
        error = "cannot rename " + file.tmp + " to " + file.path + ": " + std::strerror(errno);
        return false;
    }
    file.tmp.clear();
    return true;
}

void discardFile(PendingFile& file)
{
    if (!file.tmp.empty())
        std::remove(file.tmp.c_str());
    file.tmp.clear();
}

void describeGrid(openvdb::FloatGrid& grid, const std::string& name, const Provenance& how)
{
    grid.setName(name);
    grid.insertMeta("mesh2sdf_source", openvdb::StringMetadata(how.source));
    grid.insertMeta("mesh2sdf_sign", openvdb::StringMetadata(how.sign));
    grid.insertMeta("mesh2sdf_band_voxels", openvdb::DoubleMetadata(how.band));
    grid.insertMeta("mesh2sdf_full", openvdb::BoolMetadata(how.full));
}

bool writeVdb(const openvdb::FloatGrid& grid, const std::string& tmp, std::string& error)
{
    try {
        openvdb::io::File file(tmp);
        openvdb::GridCPtrVec grids{grid.copyGrid()};
        file.write(grids);
        file.close();
    } catch (const std::exception& e) {
        error = "cannot write " + tmp + ": " + e.what();
        return false;
    }
    return true;
}

bool writeNvdb(const openvdb::FloatGrid& grid, bool fp16, const std::string& tmp, std::string& error)
{
    try {
        if (fp16) {
            auto handle = nanovdb::openToNanoVDB<nanovdb::HostBuffer, openvdb::FloatTree, nanovdb::Fp16>(grid);
            nanovdb::io::writeGrid(tmp, handle);
        } else {
            auto handle = nanovdb::openToNanoVDB(grid);
            nanovdb::io::writeGrid(tmp, handle);
        }
    } catch (const std::exception& e) {
        error = "cannot write " + tmp + ": " + e.what();
        return false;
    }
    return true;
}

bool writeNpy(const openvdb::FloatGrid& grid, const BoxGeometry& box, const std::string& tmp, std::string& error)
{
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        error = "cannot write " + tmp + ": " + std::strerror(errno);
        return false;
    }
    // NPY format 1.0: magic, version, little-endian header length, a Python
    // dict literal padded with spaces to a multiple of 64 bytes, newline.
    char dict[256];
    int len = std::snprintf(dict, sizeof dict, "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d, %d), }",
                            box.dims[0], box.dims[1], box.dims[2]);
    std::string header(dict, size_t(len));
    const size_t total = 10 + header.size() + 1;
    header.append((64 - total % 64) % 64, ' ');
    header.push_back('\n');
    const unsigned short hlen = static_cast<unsigned short>(header.size());
    const unsigned char preamble[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0,
                                        static_cast<unsigned char>(hlen & 0xff), static_cast<unsigned char>(hlen >> 8)};
    bool ok = std::fwrite(preamble, 1, 10, f) == 10 && std::fwrite(header.data(), 1, header.size(), f) == header.size();
    openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
    std::vector<float> row(size_t(box.dims[2]));
    for (int i = 0; ok && i < box.dims[0]; ++i)
        for (int j = 0; ok && j < box.dims[1]; ++j) {
            for (int k = 0; k < box.dims[2]; ++k)
                row[size_t(k)] = acc.getValue(openvdb::Coord(i, j, k));
            ok = std::fwrite(row.data(), sizeof(float), row.size(), f) == row.size();
        }
    ok = (std::fclose(f) == 0) && ok;
    if (!ok)
        error = "cannot write " + tmp + ": " + std::strerror(errno);
    return ok;
}

namespace {

std::string jsonString(const std::string& s)
{
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char esc[8];
            std::snprintf(esc, sizeof esc, "\\u%04x", c);
            out += esc;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

} // namespace

bool writeNpyJson(const BoxGeometry& box, const std::string& npyName, const Provenance& how, float background,
                  const std::string& tmp, std::string& error)
{
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) {
        error = "cannot write " + tmp + ": " + std::strerror(errno);
        return false;
    }
    std::fprintf(f,
                 "{\n"
                 "  \"array\": %s,\n"
                 "  \"dtype\": \"float32\",\n"
                 "  \"shape\": [%d, %d, %d],\n"
                 "  \"axis_order\": \"a[i, j, k] is the distance at origin + (i, j, k) * voxel_size (x, y, z); C "
                 "order, k fastest\",\n"
                 "  \"origin\": [%.17g, %.17g, %.17g],\n"
                 "  \"voxel_size\": %.17g,\n"
                 "  \"units\": \"world units of the mesh; negative inside\",\n"
                 "  \"background\": %.9g,\n"
                 "  \"band_voxels\": %.17g,\n"
                 "  \"full\": %s,\n"
                 "  \"sign\": %s,\n"
                 "  \"source_mesh\": %s\n"
                 "}\n",
                 jsonString(npyName).c_str(), box.dims[0], box.dims[1], box.dims[2], box.origin[0], box.origin[1],
                 box.origin[2], box.voxelSize, double(background), how.band, how.full ? "true" : "false",
                 jsonString(how.sign).c_str(), jsonString(how.source).c_str());
    const bool bad = std::ferror(f) != 0;
    const bool ok = (std::fclose(f) == 0) && !bad;
    if (!ok)
        error = "cannot write " + tmp + ": " + std::strerror(errno);
    return ok;
}

std::string sidecarPath(const std::string& npyPath)
{
    const size_t n = npyPath.size();
    if (n > 4 && npyPath.compare(n - 4, 4, ".npy") == 0)
        return npyPath.substr(0, n - 4) + ".json";
    return npyPath + ".json";
}

} // namespace mesh2sdf
