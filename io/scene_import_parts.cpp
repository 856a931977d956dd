// `lacet import` to a file, and its vectors out of core (io/scene_import.h: importSceneToFile).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <cpl_conv.h>

#include "io/network_builder.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "io/scene_import_internal.h"
#include "io/vector_spill.h"

namespace lacet {
namespace {

static_assert(kMaxVectorPartLevel == VectorSpill::kGridLevel);

void addSummary(LayerSummary& into, const LayerSummary& s) {
    for (const auto& [cls, n] : s.curvesByClass) into.curvesByClass[cls] += n;
    for (const auto& [cls, n] : s.areasByClass) into.areasByClass[cls] += n;
    into.nodes += s.nodes;
    into.junctions += s.junctions;
    into.bridges += s.bridges;
    into.tunnels += s.tunnels;
    into.holes += s.holes;
    into.inputPoints += s.inputPoints;
    into.outputVertices += s.outputVertices;
    into.onCurveVertices += s.onCurveVertices;
    into.maxFitError = std::max(into.maxFitError, s.maxFitError);
}

// A part's network report added to the scene's: counts summed (a border node once per part that
// has it), the largest fit error kept.
void addNetworkReport(NetworkReport& into, NetworkReport&& part) {
    if (into.layers.empty()) {
        into.layers = part.layers;
    } else {
        for (std::size_t l = 0; l < into.layers.size() && l < part.layers.size(); ++l) addSummary(into.layers[l], part.layers[l]);
    }
    into.inputPoints += part.inputPoints;
    into.outputVertices += part.outputVertices;
    into.onCurveVertices += part.onCurveVertices;
    into.maxFitError = std::max(into.maxFitError, part.maxFitError);
    into.chainsMerged += part.chainsMerged;
    into.duplicateLines += part.duplicateLines;
    into.duplicateLineSegments += part.duplicateLineSegments;
    into.duplicateAreas += part.duplicateAreas;
    into.riverAreas += part.riverAreas;
    into.riverAreasWithAxial += part.riverAreasWithAxial;
    into.problems.insert(into.problems.end(), std::make_move_iterator(part.problems.begin()), std::make_move_iterator(part.problems.end()));
}

// The problems past kMaxListedProblems (those read, then the network's) counted by reason instead.
void capProblems(std::vector<FeatureProblem>& problems, std::size_t listed, std::map<std::string, std::size_t>& notListed) {
    const std::size_t room = kMaxListedProblems > listed ? kMaxListedProblems - listed : 0;
    if (problems.size() <= room) return;
    for (std::size_t i = room; i < problems.size(); ++i) ++notListed[problems[i].reason];
    problems.resize(room);
}

std::string mibText(double bytes) {
    std::ostringstream s;
    s.precision(3);
    s << bytes / 1048576.0 << " MiB";
    return s.str();
}

// The level of the parts: the option's, or the coarsest whose densest part fits the budget.
int partLevel(const ImportOptions& o, const VectorSpill& spill, const std::string& out) {
    if (o.vectorPartLevel >= 0) return o.vectorPartLevel;
    const double budget = o.vectorBudgetMiB * 1048576.0;
    for (int level = 0; level <= VectorSpill::kGridLevel; ++level)
        if (double(spill.largestCellBytes(level)) * kVectorMemoryPerSpillByte <= budget) return level;
    const int finest = VectorSpill::kGridLevel;
    throw ImportError(out + ": cannot import within a vector budget of " + mibText(budget) + ": the densest of " +
                      std::to_string(1 << finest) + " x " + std::to_string(1 << finest) + " parts holds " +
                      mibText(double(spill.largestCellBytes(finest))) + " of features (about " +
                      mibText(double(spill.largestCellBytes(finest)) * kVectorMemoryPerSpillByte) +
                      " while it is built); give --vector-budget at least that");
}

void importOutOfCore(const ImportOptions& o, const std::string& out, ImportReport& report, Progress* progress) {
    using namespace import_detail;
    const auto t0 = std::chrono::steady_clock::now();
    ImportStart start;
    startImport(o, report, start);
    const FeatureMapping& mapping = start.mapping;
    VectorSpill spill(uniqueImportTempPath(out, "vectors"), std::clamp(o.vectorBudgetMiB / 8.0, 8.0, 256.0));
    std::vector<FeatureKindsPlan> kinds(mapping.layers.size());
    VectorData data;
    data.maxProblems = kMaxListedProblems;
    data.lineSink = [&](RawLine&& l) {
        start.bounds.grow(l.lonLat);
        FeatureKindsPlan& k = kinds[mapping.rules[l.rule].layer];
        k.lines = true;
        for (const auto& kv : l.kept) k.lineKeys.insert(kv.first);
        spill.add(l);
    };
    data.areaSink = [&](RawArea&& a) {
        for (const auto& ring : a.rings) start.bounds.grow(ring);
        FeatureKindsPlan& k = kinds[mapping.rules[a.rule].layer];
        k.areas = true;
        for (const auto& kv : a.kept) k.areaKeys.insert(kv.first);
        spill.add(a);
    };
    data.firstOsmKey = [&](const std::string& key) { return spill.firstOsmKey(key); };
    {
        // GDAL's OSM reader, held to a bound that does not grow with the extract (a user's own
        // settings of these options win):
        // - its index of the extract's nodes and ways stays in memory up to OSM_MAX_TMPFILE_SIZE
        //   (MB; its own default is 100), on disk beyond: a quarter of the budget;
        // - those files go beside --out, as the spill does (GDAL's default is the working folder);
        //   GDAL unlinks them as soon as they are open, so a killed import leaves none;
        // - a PBF is decoded a block at a time: with more than one thread GDAL's PBF reader holds up
        //   to 150 MB of blocks (50 read, 100 decompressed) to decode them at once.
        const std::string osmIndexMb = std::to_string(int(std::clamp(o.vectorBudgetMiB / 4.0, 1.0, 100.0)));
        const CPLConfigOptionSetter osmIndex("OSM_MAX_TMPFILE_SIZE", osmIndexMb.c_str(), true);
        const std::string outFolder = std::filesystem::absolute(out).parent_path().string();
        const CPLConfigOptionSetter osmTemp("CPL_TMPDIR", outFolder.c_str(), true);
        const CPLConfigOptionSetter pbfThreads("GDAL_NUM_THREADS", "1", true);
        readAllVectors(o, mapping, data, report, progress);
    }

    RemoveFileOnExit lodFile;  // a lod DEM's file: removed after the save, or when a step fails
    SceneDocument head;
    const SceneFrame frame = frameAndDem(o, start, data, report, head, lodFile, progress);
    head.scene.extent = report.extent;
    for (const MappingLayer& ml : mapping.layers) {
        head.scene.layers.emplace_back();
        head.scene.layers.back().name = ml.name;
        head.scene.layers.back().kind = ml.kind;
    }
    progressBegin(progress, "indexing the features", 0, "");
    spill.index([&](glm::dvec2 p) { return frame.forward(p); }, report.extent);
    progressEnd(progress);
    const int level = partLevel(o, spill, out);
    const PartGrid grid{report.extent, 1 << level};
    report.vectorPartLevel = level;
    report.spilledFeatures = spill.features();
    report.spilledBytes = spill.bytes();
    report.densestPartBytes = spill.largestCellBytes(level);

    std::size_t kept = 0, below = 0, checked = 0;
    const int parts = grid.side * grid.side;
    // Features are read by their boxes: a part's box, grown a little so that a point on its edge,
    // whose box the R-tree rounds outward to floats, is read by both parts it touches.
    const double grow = 1e-6 * report.extent.size().x + 1e-3;
    // An ImportError inside the save (the kept count) is the import's refusal, not a failed save.
    std::exception_ptr refusal;
    try {
        // A border node at p is made by p's own part and by parts before it (a segment goes to the lower
    // numbered of its points' parts): p's part is the last to have it.
    const auto lastPartAt = [&](Vec2 p) { return std::size_t(grid.partOf(p)); };
    saveSceneInParts(out, head, kinds, lastPartAt, [&](const std::function<void(ScenePart&&)>& sink) {
            progressBegin(progress, "building the scene by parts", std::size_t(parts), "parts");
            for (int part = 0; part < parts; ++part) {
                VectorData partData;
                spill.read(grid.partBox(part).dilated(grow), partData);
                progressAdvance(progress);
                if (partData.lines.empty() && partData.areas.empty()) continue;
                PartCut cut{grid, part, {}};
                NetworkReport network;
                ScenePart scenePart;
            scenePart.index = std::size_t(part);
                scenePart.scene = buildScene(partData, mapping, frame, report.extent, start.bounds.insideDem, SplineFitParams{o.fitTolerance},
                                             network, &scenePart.attributes, nullptr, &cut);
                for (const auto& nodes : cut.borderNodes) report.borderNodes += nodes.size();
                scenePart.borderNodes = std::move(cut.borderNodes);
                kept += keptElements(scenePart.scene);
                countRiverNodes(scenePart.scene, *head.dem, below, checked);
                capProblems(network.problems, report.problems.size() + report.network.problems.size(), report.problemsNotListed);
            addNetworkReport(report.network, std::move(network));
                ++report.vectorParts;
                sink(std::move(scenePart));
            }
            progressEnd(progress);
            report.problems.insert(report.problems.end(), report.network.problems.begin(), report.network.problems.end());
            try {
                checkKept(o, kept, report);  // before the file is committed: a refused import leaves `out` as it was
            } catch (const ImportError&) {
                refusal = std::current_exception();
                throw;
            }
        });
    } catch (const SceneFileError&) {
        if (refusal) std::rethrow_exception(refusal);
        throw;
    }
    setRiverCheck(report, below, checked);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void importSceneToFile(const ImportOptions& o, const std::string& out, ImportReport& report, Progress* progress) {
    removeStaleImportTempFiles(out);  // what killed imports beside `out` left, whatever they wrote
    if (o.vectorBudgetMiB == 0.0 && o.vectorPartLevel < 0) {
        RemoveFileOnExit lodFile;
        const SceneDocument doc = importScene(o, report, progress);
        if (doc.demLod) lodFile.path = doc.demLod->path();
        saveScene(out, doc);
        return;
    }
    importOutOfCore(o, out, report, progress);
}

}  // namespace lacet
