#pragma once
// The features of an import held on disk while it runs out of core (`lacet import --vector-budget`,
// io/scene_import.h): io/vector_import.h's reader writes each kept feature here as it reads it, in
// lon/lat, so that the extract is never in memory whole; once the scene's frame is known, index()
// gives every feature its box in scene metres in an R-tree and counts the bytes stored over a grid,
// which chooses the parts; read() then gives the features of one part's box.
//
// The file is a temporary SQLite database of the caller's choosing (beside the output), created
// new, written without a journal and removed by the destructor (also after an exception): it
// holds nothing a user keeps.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/vector_import.h"
#include "model/types.h"

namespace lacet {

class SqliteDb;
class SqliteStatement;

class VectorSpill {
public:
    // Creates `path`, which must not exist (VectorImportError naming it otherwise, or when it cannot
    // be created); SQLite's page cache is held to `cacheMiB`.
    VectorSpill(std::string path, double cacheMiB);
    ~VectorSpill();
    VectorSpill(const VectorSpill&) = delete;
    VectorSpill& operator=(const VectorSpill&) = delete;

    const std::string& path() const { return path_; }
    void add(const RawLine& line);
    void add(const RawArea& area);
    // Whether this OSM element's key (VectorData::firstOsmKey) is seen for the first time.
    bool firstOsmKey(const std::string& key);

    // After the last add(): each feature's box in scene metres (its points through `project`) into
    // the R-tree, and the bytes stored over the grids of 2^level cells a side of `square`.
    static constexpr int kGridLevel = 8;
    void index(const std::function<Vec2(glm::dvec2)>& project, const Box& square);
    // The most bytes of features whose boxes meet one cell of the grid of 2^level cells a side
    // (level <= kGridLevel): what a part's build reads at most, a feature counting in every part
    // its box meets.
    std::uint64_t largestCellBytes(int level) const;
    // Appends the features whose boxes meet `box` (scene metres), in the order they were added.
    void read(const Box& box, VectorData& out);

    std::uint64_t features() const { return features_; }
    std::uint64_t bytes() const { return bytes_; }  // of the features' geometry and attributes

private:
    template <class F>
    auto named(const char* what, F&& f) -> decltype(f());
    void indexRows(const std::function<Vec2(glm::dvec2)>& project, const Box& square);
    void readRows(const Box& box, VectorData& out);
    void insert(bool area, std::size_t rule, std::uint16_t flags, bool multi, const SourceRef& source,
                const std::map<std::string, std::string>& kept, const std::vector<std::uint8_t>& geometry);
    std::string path_;
    std::unique_ptr<SqliteDb> db_;
    std::unique_ptr<SqliteStatement> insert_, osm_;
    std::vector<std::string> files_;
    std::uint64_t features_ = 0, bytes_ = 0;
    // Per level 0..kGridLevel, row-major: the bytes of the features whose boxes meet each cell.
    std::vector<std::vector<std::uint64_t>> cells_;
};

}  // namespace lacet
