#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace lacet {
namespace {

std::string systemError(const std::string& what) { return what + ": " + std::strerror(errno); }

// Removes `p` if it exists; throws if it exists and cannot be removed (e.g. a directory).
void removeStale(const std::string& p) {
    if (::unlink(p.c_str()) != 0 && errno != ENOENT)
        throw std::runtime_error(systemError("cannot remove the stale temporary file " + p));
}

void fsyncOrThrow(const std::string& p) {
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(systemError("cannot open " + p + " to flush it"));
    if (::fsync(fd) != 0) {
        const std::string reason = systemError("cannot flush " + p);
        ::close(fd);
        throw std::runtime_error(reason);
    }
    ::close(fd);
}

// Best effort: the rename is durable once the directory is flushed; failing that changes nothing
// about the file's contents, so errors are ignored.
void fsyncDirectoryOf(const std::string& p) {
    std::string dir = std::filesystem::path(p).parent_path().string();
    if (dir.empty()) dir.push_back('.');
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

void replaceFileAtomically(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
    const std::string tmp = path + ".tmp";
    bool tmpIsOurs = false;
    try {
        // A crashed save may have left the temporary file and its journal: a journal left next to a
        // new file would be "rolled back" into it.
        for (const char* suffix : {"", "-journal", "-wal", "-shm"}) removeStale(tmp + suffix);
        tmpIsOurs = true;
        write(tmp);
        fsyncOrThrow(tmp);
        if (std::rename(tmp.c_str(), path.c_str()) != 0)
            throw std::runtime_error(systemError("cannot rename " + tmp + " to it"));
        tmpIsOurs = false;
        fsyncDirectoryOf(path);
    } catch (...) {
        if (tmpIsOurs) {
            ::unlink(tmp.c_str());
            ::unlink((tmp + "-journal").c_str());
        }
        throw;
    }
}

}  // namespace lacet
