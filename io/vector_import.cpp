#include "io/vector_import.h"

#include <cmath>
#include <memory>

#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

namespace lacet {
namespace {

struct GdalClose {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};

// GDAL's messages go to the report, not to stderr, while this lives (exception-safe).
struct QuietGdal {
    QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
    ~QuietGdal() { CPLPopErrorHandler(); }
    QuietGdal(const QuietGdal&) = delete;
    QuietGdal& operator=(const QuietGdal&) = delete;
};

// Points of a line string as lon/lat, consecutive duplicates removed. Returns false on a
// non-finite coordinate; `duplicates` counts the removed points.
bool points(const OGRSimpleCurve& c, OGRCoordinateTransformation* ct, std::vector<glm::dvec2>& out, std::size_t& duplicates) {
    out.clear();
    const int n = c.getNumPoints();
    std::vector<double> xs(std::size_t(std::max(n, 0))), ys(xs.size());
    for (int i = 0; i < n; ++i) xs[std::size_t(i)] = c.getX(i), ys[std::size_t(i)] = c.getY(i);
    for (std::size_t i = 0; i < xs.size(); ++i)
        if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) return false;
    if (ct && n > 0 && !ct->Transform(std::size_t(n), xs.data(), ys.data())) return false;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        const glm::dvec2 p(xs[i], ys[i]);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || std::abs(p.x) > 180.0 || std::abs(p.y) > 90.0) return false;
        if (!out.empty() && out.back() == p) {
            ++duplicates;
            continue;
        }
        out.push_back(p);
    }
    return true;
}

class Reader {
public:
    Reader(const std::string& path, const FeatureMapping& mapping, VectorData& out, bool osm)
        : path_(path), mapping_(mapping), out_(out), osm_(osm) {}

    void feature(OGRLayer& layer, OGRFeature& f, OGRCoordinateTransformation* ct) {
        ++out_.featuresRead;
        const SourceRef src{path_, layer.GetName(), f.GetFID()};
        if (osm_ && out_.dedupOsmIds && !firstOsmElement(layer, f)) {
            ++out_.duplicateOsmIds;
            problem(src, "duplicate OpenStreetMap element (read before from another file)");
            return;
        }
        std::map<std::string, std::string> attributes;
        for (int i = 0; i < f.GetFieldCount(); ++i) {
            if (!f.IsFieldSetAndNotNull(i)) continue;
            const std::string name = f.GetFieldDefnRef(i)->GetNameRef();
            if (name == "other_tags") parseOtherTags(f.GetFieldAsString(i), attributes);
            else attributes[name] = f.GetFieldAsString(i);
        }
        const OGRGeometry* g = f.GetGeometryRef();
        if (!g) {
            // Attributes alone: not a problem unless a rule would have taken it.
            if (mapping_.match(attributes, GeometryKind::Line) || mapping_.match(attributes, GeometryKind::Area))
                problem(src, "no geometry");
            else ++out_.unmapped;
            return;
        }
        const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
        const bool line = type == wkbLineString || type == wkbMultiLineString;
        const bool area = type == wkbPolygon || type == wkbMultiPolygon;
        if (!line && !area) {
            ++out_.unmapped;
            return;
        }
        auto rule = mapping_.match(attributes, line ? GeometryKind::Line : GeometryKind::Area);
        // A closed way that only an area rule takes is that area's ring: OGR's OSM reader makes
        // closed ways of keys it does not list as polygons (waterway=riverbank) lines.
        OGRPolygon closedWay;
        if (!rule && type == wkbLineString && g->toLineString()->get_IsClosed() && g->toLineString()->getNumPoints() >= 4)
            if ((rule = mapping_.match(attributes, GeometryKind::Area))) {
                auto ring = std::make_unique<OGRLinearRing>();
                ring->addSubLineString(g->toLineString());
                closedWay.addRingDirectly(ring.release());
                g = &closedWay;
            }
        if (!rule) {
            ++out_.unmapped;
            return;
        }
        std::map<std::string, std::string> kept;
        for (const std::string& k : mapping_.keep)
            if (attributes.count(k)) kept[k] = attributes[k];
        const std::size_t before = out_.linesKept + out_.areasKept;
        outOfRange_ = false;
        if (g == &closedWay) areas(*g, wkbPolygon, *rule, kept, src, ct);
        else if (line) lines(*g, type, *rule, attributes, kept, src, ct);
        else areas(*g, type, *rule, kept, src, ct);
        // A feature counts as out of range when nothing of it was kept for that reason.
        auto& counts = rangeCounts[layer.GetName()];
        ++counts.first;
        if (outOfRange_ && out_.linesKept + out_.areasKept == before) ++counts.second;
    }

    void problem(const SourceRef& src, std::string reason, bool skipped = true) {
        if (out_.problems.size() >= out_.maxProblems) ++out_.problemsNotListed[reason];
        else out_.problems.push_back({src, std::move(reason), skipped});
    }

    // Per layer: mapped features with a geometry, and those of them of which nothing was kept
    // because a coordinate was out of lon/lat range.
    std::map<std::string, std::pair<std::size_t, std::size_t>> rangeCounts;

private:
    // Whether this OSM element (layer and osm_id or osm_way_id) is seen for the first time.
    bool firstOsmElement(OGRLayer& layer, OGRFeature& f) {
        for (const char* field : {"osm_id", "osm_way_id"}) {
            const int i = f.GetFieldIndex(field);
            if (i >= 0 && f.IsFieldSetAndNotNull(i)) {
                std::string key = std::string(layer.GetName()) + ":" + field + ":" + f.GetFieldAsString(i);
                return out_.firstOsmKey ? out_.firstOsmKey(key) : out_.osmIds.insert(std::move(key)).second;
            }
        }
        return true;
    }

    void lines(const OGRGeometry& g, OGRwkbGeometryType type, std::size_t rule, const std::map<std::string, std::string>& attributes,
               const std::map<std::string, std::string>& kept, const SourceRef& src, OGRCoordinateTransformation* ct) {
        std::vector<const OGRLineString*> parts;
        if (type == wkbLineString) parts.push_back(g.toLineString());
        else
            for (const OGRLineString* l : *g.toMultiLineString()) parts.push_back(l);
        for (const OGRLineString* part : parts) {
            RawLine l;
            l.rule = rule;
            l.source = src;
            l.kept = kept;
            l.inMulti = type == wkbMultiLineString;
            std::size_t duplicates = 0;
            if (!points(*part, ct, l.lonLat, duplicates)) {
                problem(src, "non-finite or out-of-range coordinate");
                outOfRange_ = true;
                continue;
            }
            if (l.lonLat.size() < 2) {
                problem(src, "zero-length way (fewer than 2 distinct points)");
                continue;
            }
            if (duplicates > 0) problem(src, "duplicate consecutive points (removed)", false);
            const auto is = [&](const char* k, const char* v) {
                const auto it = attributes.find(k);
                return it != attributes.end() && it->second == v;
            };
            if (is("bridge", "yes") || is("bridge", "viaduct")) l.flags |= kBridge;
            if (is("tunnel", "yes")) l.flags |= kTunnel;
            // A ring mapped as such (OSM junction=roundabout): kept as it is, never merged with
            // the roads that meet it (chains merge only curves of the same flags).
            if (is("junction", "roundabout")) l.flags |= kRoundabout;
            ++out_.linesKept;
            if (out_.lineSink) out_.lineSink(std::move(l));
            else out_.lines.push_back(std::move(l));
        }
    }

    void areas(const OGRGeometry& g, OGRwkbGeometryType type, std::size_t rule, const std::map<std::string, std::string>& kept,
               const SourceRef& src, OGRCoordinateTransformation* ct) {
        std::vector<const OGRPolygon*> polygons;
        if (type == wkbPolygon) polygons.push_back(g.toPolygon());
        else
            for (const OGRPolygon* p : *g.toMultiPolygon()) polygons.push_back(p);
        for (const OGRPolygon* polygon : polygons) {
            RawArea a;
            a.rule = rule;
            a.source = src;
            a.kept = kept;
            bool ok = true;
            std::size_t duplicates = 0;
            for (int r = -1; ok && r < polygon->getNumInteriorRings(); ++r) {
                const OGRLinearRing* ring = r < 0 ? polygon->getExteriorRing() : polygon->getInteriorRing(r);
                if (!ring || ring->getNumPoints() == 0) {
                    problem(src, "empty ring");
                    ok = false;
                    break;
                }
                if (ring->getX(0) != ring->getX(ring->getNumPoints() - 1) || ring->getY(0) != ring->getY(ring->getNumPoints() - 1)) {
                    problem(src, "unclosed ring");
                    ok = false;
                    break;
                }
                std::vector<glm::dvec2> pts;
                if (!points(*ring, ct, pts, duplicates)) {
                    problem(src, "non-finite or out-of-range coordinate");
                    outOfRange_ = true;
                    ok = false;
                    break;
                }
                if (pts.size() < 4) {
                    problem(src, "degenerate ring (fewer than 3 distinct points)");
                    ok = false;
                    break;
                }
                a.rings.push_back(std::move(pts));
            }
            if (!ok) continue;
            if (OGRGeometryFactory::haveGEOS()) {
                CPLPushErrorHandler(CPLQuietErrorHandler);
                const bool valid = polygon->IsValid();
                CPLPopErrorHandler();
                if (!valid) {
                    problem(src, "self-intersecting or invalid polygon");
                    continue;
                }
            }
            if (duplicates > 0) problem(src, "duplicate consecutive points (removed)", false);
            ++out_.areasKept;
            if (out_.areaSink) out_.areaSink(std::move(a));
            else out_.areas.push_back(std::move(a));
        }
    }

    std::string path_;
    const FeatureMapping& mapping_;
    VectorData& out_;
    bool osm_;
    bool outOfRange_ = false;  // a part of the current feature was refused for its coordinates
};

}  // namespace

void readVectors(const std::string& path, const FeatureMapping& mapping, VectorData& out) {
    GDALAllRegister();
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::unique_ptr<GDALDataset, GdalClose> ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    CPLPopErrorHandler();
    if (!ds) {
        const std::string why = CPLGetLastErrorMsg();
        throw VectorImportError(path + ": cannot open as vector data" + (why.empty() ? std::string() : " (" + why + ")"));
    }
    Reader reader(path, mapping, out, std::string(ds->GetDriverName()) == "OSM");
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    struct DestroyCt {
        void operator()(OGRCoordinateTransformation* ct) const { OGRCoordinateTransformation::DestroyCT(ct); }
    };
    std::map<OGRLayer*, std::unique_ptr<OGRCoordinateTransformation, DestroyCt>> transforms;
    std::map<OGRLayer*, bool> unknownCrs;
    const std::size_t before = out.featuresRead;
    // Dataset-level iteration: the order OGR's OSM driver needs, and layer by layer elsewhere.
    ds->ResetReading();
    const QuietGdal quiet;
    bool readError = false;
    std::string err;
    for (;;) {
        OGRLayer* layer = nullptr;
        CPLErrorReset();  // so that an error seen below is the driver's, not one of a feature's checks
        OGRFeatureUniquePtr f(ds->GetNextFeature(&layer, nullptr, nullptr, nullptr));
        if (CPLGetLastErrorType() >= CE_Failure && !readError) {
            readError = true;
            err = CPLGetLastErrorMsg();
        }
        if (!f || !layer) break;
        if (!transforms.count(layer)) {
            const OGRSpatialReference* srs = layer->GetSpatialRef();
            unknownCrs[layer] = srs == nullptr;
            transforms[layer] = nullptr;
            if (srs) {
                OGRSpatialReference source(*srs);
                source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
                if (!(source.IsGeographic() && source.IsSame(&wgs84))) {
                    transforms[layer].reset(OGRCreateCoordinateTransformation(&source, &wgs84));
                    if (!transforms[layer]) {
                        unknownCrs[layer] = true;
                        out.fileErrors.push_back(path + " layer '" + layer->GetName() + "': no transformation from its CRS to WGS84");
                    }
                }
            } else {
                out.fileErrors.push_back(path + " layer '" + layer->GetName() +
                                         "': no coordinate reference system (a Shapefile without its .prj?)");
            }
        }
        if (unknownCrs[layer]) {
            ++out.featuresRead;
            continue;
        }
        reader.feature(*layer, *f, transforms[layer].get());
    }
    if (readError) out.fileErrors.push_back(path + ": read error (" + err + "): the file is truncated or malformed, or the parser refused it (an XML entity expansion, say)");
    else if (out.featuresRead == before) out.fileErrors.push_back(path + ": no features (an empty file, or empty layers)");
    for (const auto& [layer, counts] : reader.rangeCounts)
        if (counts.first > 0 && counts.second == counts.first)
            out.fileErrors.push_back(path + " layer '" + layer + "': every coordinate (" + std::to_string(counts.first) +
                                     " features) is outside longitude/latitude ranges: projected data whose CRS the file does not "
                                     "declare? (GeoJSON is WGS84 unless a \"crs\" member says otherwise)");
}

}  // namespace lacet
