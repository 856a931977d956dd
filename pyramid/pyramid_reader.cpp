#include "pyramid/pyramid_reader.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <span>
#include <sstream>
#include <vector>

#include "io/scene_checksum.h"
#include "io/tile_codec.h"
#include "pyramid/pyramid_store.h"
#include "pyramid/pyramid_tiles.h"

namespace lacet {
namespace {

using Clock = std::chrono::steady_clock;
// Extents are written as text by the build; a scene and its pyramid agree far better than this.
constexpr double kExtentTolerance = 1e-6;  // metres

bool sameExtent(const Box& a, const Box& b) {
    return std::abs(a.min.x - b.min.x) <= kExtentTolerance && std::abs(a.min.y - b.min.y) <= kExtentTolerance &&
           std::abs(a.max.x - b.max.x) <= kExtentTolerance && std::abs(a.max.y - b.max.y) <= kExtentTolerance;
}

std::string boxText(const Box& b) {
    std::ostringstream s;
    s.precision(17);
    s << "(" << b.min.x << ", " << b.min.y << ") - (" << b.max.x << ", " << b.max.y << ")";
    return s.str();
}

// One channel plane of a decoded image (`channel` of `channels`), or empty when it is not size^2.
bool plane(const DecodedImage& d, int size, int first, int count, std::vector<std::uint8_t>& out) {
    if (d.width != size || d.height != size || d.channels < first + count) return false;
    const std::size_t n = std::size_t(size) * std::size_t(size);
    if (d.pixels.size() != n * std::size_t(d.channels)) return false;
    out.resize(n * std::size_t(count));
    for (std::size_t p = 0; p < n; ++p)
        for (int c = 0; c < count; ++c) out[p * std::size_t(count) + std::size_t(c)] = d.pixels[p * std::size_t(d.channels) + std::size_t(first + c)];
    return true;
}

}  // namespace

struct PyramidReader::Impl {
    std::unique_ptr<PyramidStore> store;
    PyramidInfo info;
    std::mutex mutex;  // the connection, one statement at a time
    std::atomic<std::size_t> read{0}, corrupt{0}, missing{0}, unreadable{0};
    std::atomic<std::uint64_t> readNs{0}, decodeNs{0};
};

namespace {
PyramidError otherState(const std::string& path) {
    return PyramidError(path + ": the pyramid was made from another state of the scene (edited or imported since): run lacet "
                               "pyramid update on the scene");
}
}  // namespace

PyramidReader::PyramidReader(const std::string& path, const SceneDocument& doc)
    : PyramidReader(path, doc.scene.extent, doc.georeference.valid ? doc.georeference.crsWkt : std::string()) {
    // A pyramid made from a scene file of format 1 records that form of its checksum
    // (io/scene_checksum.h); the same document either way.
    const std::string& recorded = impl_->info.sceneChecksum;
    if (!recorded.empty() && recorded != sceneChecksumText(doc) && recorded != sceneChecksumText(doc, 1)) throw otherState(path);
}

PyramidReader::PyramidReader(const std::string& path, const Box& extent, const std::string& crsWkt, const std::string& sceneChecksum)
    : PyramidReader(path, extent, crsWkt) {
    // Tiles of another state of the scene (edited without updating the pyramid, imported again)
    // would show what is no longer there.
    if (!impl_->info.sceneChecksum.empty() && impl_->info.sceneChecksum != sceneChecksum) throw otherState(path);
}

PyramidReader::PyramidReader(const std::string& path, const Box& extent, const std::string& crsWkt) : impl_(std::make_unique<Impl>()) {
    std::optional<PyramidInfo> info;
    try {
        impl_->store = std::make_unique<PyramidStore>(path, PyramidStore::Mode::ReadOnly);
        info = impl_->store->info();
    } catch (const PyramidError&) {
        throw;
    } catch (const std::exception& e) {
        throw PyramidError(path + ": cannot open the pyramid: " + e.what());
    }
    if (!info) throw PyramidError(path + ": holds no pyramid (no lacet_pyramid table)");
    if (!info->complete) throw PyramidError(path + ": the pyramid is incomplete (an interrupted build?); run lacet pyramid build again");
    if (!info->appearance) throw PyramidError(path + ": the pyramid holds no appearance tiles");
    if (!sameExtent(info->extent, extent))
        throw PyramidError(path + ": the pyramid was made for the extent " + boxText(info->extent) + ", the scene's is " + boxText(extent));
    if (info->crsWkt != crsWkt)
        throw PyramidError(path + ": the pyramid was made for another CRS than the scene's" +
                           (info->crsWkt.empty() ? std::string(" (it has none)") : crsWkt.empty() ? std::string(" (the scene has none)") : std::string()));
    if (info->tileSize <= 0 || info->tileSize > kMaxTileSide || info->minLevel < 0 || info->maxLevel < info->minLevel)
        throw PyramidError(path + ": the pyramid's tile size or levels are out of range");
    impl_->info = *info;
}

PyramidReader::~PyramidReader() = default;

const std::string& PyramidReader::path() const { return impl_->store->path(); }
int PyramidReader::minLevel() const { return impl_->info.minLevel; }
int PyramidReader::maxLevel() const { return impl_->info.maxLevel; }
int PyramidReader::vectorLevel() const { return impl_->info.vectorLevel; }
int PyramidReader::tileSize() const { return impl_->info.tileSize; }
const std::string& PyramidReader::encoding() const { return impl_->info.encoding; }
const std::string& PyramidReader::sceneChecksum() const { return impl_->info.sceneChecksum; }

bool PyramidReader::serves(int level) const {
    const PyramidInfo& i = impl_->info;
    return level >= i.minLevel && level <= i.maxLevel && level < i.vectorLevel;
}

std::optional<AppearanceTile> PyramidReader::appearance(const Quad& q, int border) {
    if (!serves(q.level)) return std::nullopt;
    Impl& m = *impl_;
    const PyramidKey key{q.level, q.tx, q.ty};
    std::optional<std::vector<std::uint8_t>> rgbBytes, waterBytes;
    const auto t0 = Clock::now();
    try {
        const std::lock_guard<std::mutex> lock(m.mutex);
        rgbBytes = m.store->tile(kAppearanceTable, key);
        if (rgbBytes) waterBytes = m.store->tile(kWaterTable, key);
    } catch (const std::exception&) {
        ++m.unreadable;
        return std::nullopt;
    }
    const auto t1 = Clock::now();
    m.readNs += std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    if (!rgbBytes) {
        ++m.missing;
        return std::nullopt;
    }
    PyramidImage image;
    image.size = m.info.tileSize;
    bool ok = false;
    try {
        const DecodedImage rgb = decodeImage(*rgbBytes);
        ok = plane(rgb, image.size, 0, 3, image.rgb);
        if (ok && waterBytes) {
            const DecodedImage water = decodeImage(*waterBytes);
            ok = plane(water, image.size, 0, 1, image.water);  // grey (or grey + alpha): the first channel
        } else if (ok) {
            image.water.assign(std::size_t(image.size) * std::size_t(image.size), 0);  // no tile: no water
        }
    } catch (const TileDecodeError&) {
        ok = false;
    }
    m.decodeNs += std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t1).count());
    if (!ok) {
        ++m.corrupt;
        return std::nullopt;
    }
    ++m.read;
    return appearanceTile(image, q.bounds, border);
}

PyramidReadStats PyramidReader::stats() const {
    PyramidReadStats s;
    s.read = impl_->read;
    s.corrupt = impl_->corrupt;
    s.missing = impl_->missing;
    s.unreadable = impl_->unreadable;
    s.readMs = double(impl_->readNs.load()) * 1e-6;
    s.decodeMs = double(impl_->decodeNs.load()) * 1e-6;
    return s;
}

}  // namespace lacet
