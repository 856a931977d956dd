#pragma once
// What the command-line tests share: a file's bytes, a word quoted for sh, and root without the
// capabilities that let it ignore file permissions.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace lacet::test {

// The bytes of a regular file (at most `maxBytes`); empty for anything else.
inline std::string readFile(const std::filesystem::path& path, std::size_t maxBytes = std::string::npos) {
    if (!std::filesystem::is_regular_file(path)) return {};
    std::ifstream in(path, std::ios::binary);
    std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return s.substr(0, maxBytes);
}

// `s` as one sh word.
inline std::string quoted(const std::string& s) {
    std::string q = "'";
    for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Root without the capabilities that let it ignore file permissions (util-linux's setpriv), so that
// a read-only directory is read-only to it too.
inline constexpr const char* kWithoutRootsOverride = "setpriv --bounding-set -dac_override,-dac_read_search";

}  // namespace lacet::test
