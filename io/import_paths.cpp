#include "io/import_paths.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include <cpl_vsi.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/scene_file.h"

namespace lacet {
namespace {

struct FileId {
    dev_t dev = 0;
    ino_t ino = 0;
    friend bool operator==(const FileId&, const FileId&) = default;
};

bool isVirtual(const std::string& path) { return path.rfind("/vsi", 0) == 0; }

// The real file a GDAL virtual path lives in: the longest prefix after its /vsizip/ (or other
// /vsi...) part that is a regular file (/vsizip//data/a.zip/inner.shp -> /data/a.zip); empty when
// there is none.
std::string containerOf(const std::string& path) {
    const std::size_t start = path.find('/', 1);
    if (start == std::string::npos) return {};
    std::string rest = path.substr(start + 1);
    if (!rest.empty() && rest.front() == '{') {  // /vsizip/{/data/a.zip}/inner
        const std::size_t close = rest.find('}');
        rest = rest.substr(1, close == std::string::npos ? std::string::npos : close - 1);
    }
    for (std::size_t slash = rest.size(); slash != std::string::npos && slash > 0; slash = rest.rfind('/', slash - 1)) {
        const std::string candidate = rest.substr(0, slash);
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode)) return candidate;
    }
    return {};
}

// The identity of the file behind `path` (its container for a virtual path), if it exists.
bool fileId(const std::string& path, FileId& id) {
    const std::string real = isVirtual(path) ? containerOf(path) : path;
    struct stat st {};
    if (real.empty() || ::stat(real.c_str(), &st) != 0) return false;
    id = {st.st_dev, st.st_ino};
    return true;
}

void checkInput(const std::string& what, const std::string& path) {
    if (path.empty()) throw ImportPathError(what + ": an empty path");
    if (isVirtual(path)) {
        VSIStatBufL st;
        if (VSIStatL(path.c_str(), &st) != 0) throw ImportPathError(path + ": cannot open the " + what + ": No such file or directory");
        return;
    }
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw ImportPathError(path + ": cannot open the " + what + ": " + std::strerror(errno));
    if (::access(path.c_str(), R_OK) != 0) throw ImportPathError(path + ": cannot read the " + what + ": " + std::strerror(errno));
}

}  // namespace

void checkImportPaths(const ImportPaths& p) {
    std::vector<std::pair<std::string, std::string>> inputs;  // (kind, path)
    for (const std::string& d : p.dems) inputs.push_back({"DEM", d});
    for (const std::string& v : p.vectors) inputs.push_back({"vector file", v});
    if (!p.mapping.empty()) inputs.push_back({"mapping file", p.mapping});
    for (const auto& [kind, path] : inputs) checkInput(kind, path);

    // The same vector file twice would import everything twice (DEM files: io/dem_import.h).
    for (std::size_t i = 0; i < p.vectors.size(); ++i)
        for (std::size_t j = 0; j < i; ++j) {
            FileId a, b;
            const bool same = p.vectors[i] == p.vectors[j] ||
                              (!isVirtual(p.vectors[i]) && !isVirtual(p.vectors[j]) && fileId(p.vectors[i], a) && fileId(p.vectors[j], b) &&
                               a == b);
            if (same) throw ImportPathError(p.vectors[i] + ": given twice to --vectors (also as " + p.vectors[j] + ")");
        }

    if (p.out.empty()) throw ImportPathError("no output scene file given");
    const std::filesystem::path out(p.out);
    const std::filesystem::path dir = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw ImportPathError(p.out + ": the output's directory " + dir.string() + " does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw ImportPathError(p.out + ": cannot write in " + dir.string() + ": " + std::strerror(errno));
    // The save writes `out`.tmp first and removes a stale one: it must be ours too.
    const std::string tmp = p.out + ".tmp";
    if (::stat(tmp.c_str(), &st) == 0 && !isStaleSaveTemporary(tmp))
        throw ImportPathError(tmp + ": exists and is not a Lacet scene's temporary file: the save would remove it (move it away)");
    // A scene written into a directory of DEM tiles would be read as a tile by the next import.
    for (const std::string& d : p.dems) {
        struct stat ds {};
        if (!isVirtual(d) && ::stat(d.c_str(), &ds) == 0 && S_ISDIR(ds.st_mode) &&
            std::filesystem::weakly_canonical(dir) == std::filesystem::weakly_canonical(d))
            throw ImportPathError(p.out + ": is inside the DEM directory " + d + " (its DEM would be read as a tile next time)");
    }
    if (::stat(p.out.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) throw ImportPathError(p.out + ": is a directory, not a scene file");
        const FileId outId{st.st_dev, st.st_ino};
        for (const auto& [kind, path] : inputs) {
            FileId id;
            if (fileId(path, id) && id == outId)
                throw ImportPathError(p.out + ": is an input (the " + kind + " " + path + "): an input is never an output");
        }
        if (!p.force && !isLacetScene(p.out))
            throw ImportPathError(p.out + ": exists and is not a Lacet scene: refusing to overwrite it (--force replaces it)");
    }
}

}  // namespace lacet
