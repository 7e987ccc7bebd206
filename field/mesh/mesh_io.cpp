#include "field/mesh/mesh_io.h"

#include "core/error.h"
#include "core/input_file.h"
#include "field/mesh/mesh_scan.h"

#include <cctype>
#include <filesystem>
#include <limits>

namespace rosy::field {
namespace {

std::string lower(std::string s) {
    for (char &c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// Meshes are read only from regular files: the readers check header counts against
/// the file's size, which a pipe or a device (a link to /dev/zero) does not have.
std::string readWholeFile(const std::string &path) {
    return readInputFile(path, InputFileRules{"mesh file", std::numeric_limits<size_t>::max(), false});
}

} // namespace

Mesh loadMesh(const std::string &path, const LoadOptions &options, LoadReport *report) {
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl")
        throw InputError(FileLoc{path},
                         "unknown mesh format '" + (ext.empty() ? std::string("(none)") : ext) + "'",
                         "use a .obj, .ply, .off or .stl file");
    const std::string file = readWholeFile(path);
    std::string_view text = file;
    // A UTF-8 byte order mark (some Windows editors write one) is not content.
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw InputError(FileLoc{path}, "the file is empty", "export the mesh again");

    detail::PolygonSoup soup;
    if (ext == ".off") detail::readOff(path, text, options, soup);
    else if (ext == ".obj") detail::readObj(path, text, options, soup);
    else if (ext == ".stl") detail::readStl(path, text, options, soup);
    else detail::readPly(path, text, options, soup);
    return repairAndBuild(std::move(soup.positions), soup.polygons, path, options, report);
}

} // namespace rosy::field
