#include "io/vector_spill.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "io/le_bytes.h"
#include "io/sqlite_db.h"

namespace lacet {
namespace {

constexpr const char* kSpillSchema = R"sql(
PRAGMA journal_mode = OFF;
PRAGMA synchronous = OFF;
CREATE TABLE feature (
  id INTEGER PRIMARY KEY, area INTEGER NOT NULL, rule INTEGER NOT NULL, flags INTEGER NOT NULL,
  multi INTEGER NOT NULL, file INTEGER NOT NULL, layer TEXT NOT NULL, fid INTEGER NOT NULL,
  kept BLOB NOT NULL, geometry BLOB NOT NULL);
CREATE VIRTUAL TABLE feature_box USING rtree(id, min_x, max_x, min_y, max_y);
CREATE TABLE osm_key (key TEXT PRIMARY KEY) WITHOUT ROWID;
)sql";

void putPoints(ByteWriter& w, const std::vector<glm::dvec2>& pts) {
    w.u32(std::uint32_t(pts.size()));
    for (const glm::dvec2& p : pts) {
        w.f64(p.x);
        w.f64(p.y);
    }
}

// What putPoints wrote (the spill is this program's own file: a short blob is a logic error).
std::vector<glm::dvec2> getPoints(ByteReader& r) {
    std::uint32_t n = 0;
    if (!r.u32(n) || r.remaining() < std::size_t(n) * 16) throw std::logic_error("VectorSpill: a short geometry");
    std::vector<glm::dvec2> pts(n);
    for (glm::dvec2& p : pts) r.f64(p.x), r.f64(p.y);
    return pts;
}

std::vector<std::uint8_t> keptBlob(const std::map<std::string, std::string>& kept) {
    std::vector<std::uint8_t> out;
    for (const auto& [k, v] : kept) {
        out.insert(out.end(), k.begin(), k.end());
        out.push_back(0);
        out.insert(out.end(), v.begin(), v.end());
        out.push_back(0);
    }
    return out;
}

std::map<std::string, std::string> keptOf(std::span<const std::uint8_t> blob) {
    std::map<std::string, std::string> kept;
    std::vector<std::string> parts(1);
    for (std::uint8_t b : blob) {
        if (b == 0) parts.emplace_back();
        else parts.back().push_back(char(b));
    }
    for (std::size_t i = 0; i + 1 < parts.size(); i += 2) kept.emplace(parts[i], parts[i + 1]);
    return kept;
}

}  // namespace

VectorSpill::VectorSpill(std::string path, double cacheMiB) : path_(std::move(path)) {
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) throw VectorImportError(path_ + ": cannot create the import's spill file: " + std::strerror(errno));
    ::close(fd);
    try {
        db_ = std::make_unique<SqliteDb>(path_, SqliteDb::Mode::ReadWrite);
        db_->exec(kSpillSchema);
        db_->exec("PRAGMA cache_size = -" + std::to_string(std::max<long long>(1024, static_cast<long long>(cacheMiB * 1024.0))));
        db_->exec("BEGIN");
        insert_ = db_->prepareKept(
            "INSERT INTO feature (area, rule, flags, multi, file, layer, fid, kept, geometry) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
        osm_ = db_->prepareKept("INSERT OR IGNORE INTO osm_key (key) VALUES (?)");
    } catch (const SqliteError& e) {
        insert_.reset();
        osm_.reset();
        db_.reset();
        std::error_code ec;
        std::filesystem::remove(path_, ec);
        throw VectorImportError(path_ + ": cannot write the import's spill file: " + e.what());
    }
}

VectorSpill::~VectorSpill() {
    insert_.reset();
    osm_.reset();
    db_.reset();
    std::error_code ec;
    std::filesystem::remove(path_, ec);
}

void VectorSpill::insert(bool area, std::size_t rule, std::uint16_t flags, bool multi, const SourceRef& source,
                         const std::map<std::string, std::string>& kept, const std::vector<std::uint8_t>& geometry) {
    auto file = std::find(files_.begin(), files_.end(), source.file);
    if (file == files_.end()) file = files_.insert(files_.end(), source.file);
    const std::vector<std::uint8_t> keptBytes = keptBlob(kept);
    SqliteStatement& s = *insert_;
    s.bind(1, std::int64_t(area));
    s.bind(2, std::int64_t(rule));
    s.bind(3, std::int64_t(flags));
    s.bind(4, std::int64_t(multi));
    s.bind(5, std::int64_t(file - files_.begin()));
    s.bindText(6, source.layer);
    s.bind(7, source.fid);
    s.bindBlob(8, keptBytes);
    s.bindBlob(9, geometry);
    try {
        s.step();
    } catch (const SqliteError& e) {
        throw VectorImportError(path_ + ": cannot write the import's spill file: " + e.what());
    }
    s.reset();
    ++features_;
    bytes_ += keptBytes.size() + geometry.size();
}

void VectorSpill::add(const RawLine& line) {
    ByteWriter w;
    putPoints(w, line.lonLat);
    const auto b = w.bytes();
    insert(false, line.rule, line.flags, line.inMulti, line.source, line.kept, {b.begin(), b.end()});
}

void VectorSpill::add(const RawArea& area) {
    ByteWriter w;
    w.u32(std::uint32_t(area.rings.size()));
    for (const auto& ring : area.rings) putPoints(w, ring);
    const auto b = w.bytes();
    insert(true, area.rule, 0, false, area.source, area.kept, {b.begin(), b.end()});
}

// SQLite's errors (a full disk, an I/O error) name the spill file.
template <class F>
auto VectorSpill::named(const char* what, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const SqliteError& e) {
        throw VectorImportError(path_ + ": cannot " + what + " the import's spill file: " + e.what());
    }
}

bool VectorSpill::firstOsmKey(const std::string& key) {
    return named("write", [&] {
        osm_->bindText(1, key);
        osm_->step();
        osm_->reset();
        return db_->queryInteger("SELECT changes()") == 1;
    });
}

void VectorSpill::index(const std::function<Vec2(glm::dvec2)>& project, const Box& square) {
    named("index", [&] { indexRows(project, square); });
}

void VectorSpill::indexRows(const std::function<Vec2(glm::dvec2)>& project, const Box& square) {
    cells_.clear();
    for (int level = 0; level <= kGridLevel; ++level) cells_.emplace_back(std::size_t(1) << (2 * level), 0);
    auto rows = db_->prepare("SELECT id, area, geometry, length(kept) FROM feature ORDER BY id");
    auto box = db_->prepare("INSERT INTO feature_box (id, min_x, max_x, min_y, max_y) VALUES (?, ?, ?, ?, ?)");
    // Clamped as a double first: a feature far outside the scene must not overflow the int.
    const auto cellOf = [&](double v, double lo, double size, int side) {
        const double f = std::floor((v - lo) / size * side);
        return std::isfinite(f) ? int(std::clamp(f, 0.0, double(side - 1))) : 0;
    };
    while (rows.step()) {
        const std::span<const std::uint8_t> blob = rows.blob(2);
        ByteReader r(blob);
        Box b{Vec2(1e300), Vec2(-1e300)};
        const auto grow = [&](const std::vector<glm::dvec2>& pts) {
            for (const glm::dvec2& p : pts) {
                const Vec2 q = project(p);
                b = {glm::min(b.min, q), glm::max(b.max, q)};
            }
        };
        if (rows.integer(1) != 0) {
            std::uint32_t rings = 0;
            r.u32(rings);
            for (std::uint32_t k = 0; k < rings; ++k) grow(getPoints(r));
        } else {
            grow(getPoints(r));
        }
        if (!(b.min.x <= b.max.x)) continue;  // no point (cannot happen: the reader keeps none such)
        box.bind(1, rows.integer(0));
        box.bind(2, b.min.x);
        box.bind(3, b.max.x);
        box.bind(4, b.min.y);
        box.bind(5, b.max.y);
        box.step();
        box.reset();
        const std::uint64_t bytes = std::uint64_t(blob.size()) + std::uint64_t(rows.integer(3));
        for (int level = 0; level <= kGridLevel; ++level) {
            const int side = 1 << level;
            const int x0 = cellOf(b.min.x, square.min.x, square.size().x, side), x1 = cellOf(b.max.x, square.min.x, square.size().x, side);
            const int y0 = cellOf(b.min.y, square.min.y, square.size().y, side), y1 = cellOf(b.max.y, square.min.y, square.size().y, side);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) cells_[std::size_t(level)][std::size_t(y) * std::size_t(side) + std::size_t(x)] += bytes;
        }
    }
    db_->exec("COMMIT");
}

std::uint64_t VectorSpill::largestCellBytes(int level) const {
    if (cells_.empty() || level < 0 || level > kGridLevel) throw std::logic_error("VectorSpill::largestCellBytes: no index or a bad level");
    const auto& cells = cells_[std::size_t(level)];
    return *std::max_element(cells.begin(), cells.end());
}

void VectorSpill::read(const Box& box, VectorData& out) {
    named("read", [&] { readRows(box, out); });
}

void VectorSpill::readRows(const Box& box, VectorData& out) {
    auto s = db_->prepare(
        "SELECT f.area, f.rule, f.flags, f.multi, f.file, f.layer, f.fid, f.kept, f.geometry FROM feature_box b "
        "JOIN feature f ON f.id = b.id WHERE b.max_x >= ? AND b.min_x <= ? AND b.max_y >= ? AND b.min_y <= ? ORDER BY f.id");
    s.bind(1, box.min.x);
    s.bind(2, box.max.x);
    s.bind(3, box.min.y);
    s.bind(4, box.max.y);
    while (s.step()) {
        const SourceRef source{files_.at(std::size_t(s.integer(4))), s.text(5), s.integer(6)};
        ByteReader r(s.blob(8));
        if (s.integer(0) != 0) {
            RawArea a;
            a.rule = std::size_t(s.integer(1));
            a.kept = keptOf(s.blob(7));
            a.source = source;
            std::uint32_t rings = 0;
            r.u32(rings);
            for (std::uint32_t k = 0; k < rings; ++k) a.rings.push_back(getPoints(r));
            out.areas.push_back(std::move(a));
        } else {
            RawLine l;
            l.rule = std::size_t(s.integer(1));
            l.flags = std::uint16_t(s.integer(2));
            l.inMulti = s.integer(3) != 0;
            l.kept = keptOf(s.blob(7));
            l.source = source;
            l.lonLat = getPoints(r);
            out.lines.push_back(std::move(l));
        }
    }
}

}  // namespace lacet
