// The independent fit check (io/fit_check.h): it passes an import that kept its promise, and fails
// (never passes vacuously) a scene whose curve was moved off its source, a layer whose sources are
// missing, and a check of a file it could not read.
#include "io/fit_check.h"

#include <gtest/gtest.h>

#include "io/scene_import.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

struct Imported {
    SceneDocument doc;
    VectorData sources;
};

Imported importGood(const std::filesystem::path& dir) {
    ImportOptions o;
    o.dem = {test::writeFixtureDem(dir)};
    o.vectors = {test::vectorData("good.geojson")};
    ImportReport r;
    Imported out{importScene(o, r), {}};
    readVectors(o.vectors[0], defaultMapping(), out.sources);
    return out;
}

TEST(FitCheck, PassesTheImportAndFailsACurveMovedOffItsSource) {
    const auto dir = test::scratchDir("fitcheck");
    Imported in = importGood(dir);
    FitCheckReport ok = checkFit(in.doc, in.sources, defaultMapping(), {});
    EXPECT_TRUE(ok.passed());
    for (const FitCheckLayer& l : ok.layers) {
        EXPECT_LE(l.curveToSourceUpper, 0.5 + 0.01) << l.name;
        EXPECT_LE(l.sourceToCurveUpper, 0.5 + 0.01) << l.name;
    }
    // One road vertex moved 3 m north: both directions see it (the curve strays, its source
    // stretch is left), within the measure's precision.
    Curve& c = in.doc.scene.layers[0].curves[0];
    c.vertices[c.vertices.size() / 2].p.y += 3.0;
    const FitCheckReport moved = checkFit(in.doc, in.sources, defaultMapping(), {});
    EXPECT_FALSE(moved.passed());
    EXPECT_EQ(moved.layers[0].curvesOver, 1u);
    EXPECT_GT(moved.layers[0].curveToSourceLower, 0.5);
    ASSERT_FALSE(moved.layers[0].worstCurves.empty());
    EXPECT_EQ(moved.layers[0].worstCurves[0].what, "curve 0");
    std::filesystem::remove_all(dir);
}

TEST(FitCheck, CurvesWithoutSourcesFailRatherThanMeasureNothing) {
    const auto dir = test::scratchDir("fitcheck_empty");
    const Imported in = importGood(dir);
    const FitCheckReport none = checkFit(in.doc, VectorData{}, defaultMapping(), {});
    EXPECT_FALSE(none.passed());
    EXPECT_GT(none.layers[0].curvesOver, 0u);  // roads with no source at all
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
