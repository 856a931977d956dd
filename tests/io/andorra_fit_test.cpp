// The import's fit promise on real data (issue 12, DESIGN.md invariant 6): every curve and area
// border of the Andorra scene lies within the fit tolerance of its OpenStreetMap source and every
// source within it of the curves, measured both ways and densely by the independent check
// (io/fit_check.h), and the import's report states the same. Data © OpenStreetMap contributors
// (ODbL), SRTM: NASA/USGS, read in place from ../shared/data/andorra/.
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>

#include "io/fit_check.h"
#include "io/scene_import.h"

namespace lacet {
namespace {

const std::string kData = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra";

class AndorraFit : public testing::TestWithParam<double> {};

TEST_P(AndorraFit, EveryCurveAndSourceStaysWithinTheTolerance) {
#ifdef LACET_SANITIZED
    GTEST_SKIP() << "the whole of Andorra takes minutes under the sanitizers; the Release suite runs it, and the "
                    "sanitized suite runs the same code on the fixtures and the random polylines (SplineFit.*)";
#endif
    const std::string pbf = kData + "/andorra-2021-04-14.osm.pbf", hgt = kData + "/N42E001.hgt.zip";
    if (!std::filesystem::exists(pbf) || !std::filesystem::exists(hgt)) GTEST_SKIP() << "no Andorra data in " << kData;
    const double tolerance = GetParam();
    ImportOptions o;
    o.dem = {"/vsizip/" + hgt + "/N42E001.hgt"};
    o.vectors = {pbf};
    o.fitTolerance = tolerance;
    ImportReport r;
    const SceneDocument doc = importScene(o, r);
    for (const LayerSummary& l : r.network.layers) {
        EXPECT_LE(l.maxFitError, tolerance) << l.name;
        EXPECT_GT(l.maxFitError, 0.0) << l.name;
    }

    VectorData sources;
    const FeatureMapping mapping = defaultMapping();
    readVectors(pbf, mapping, sources);
    FitCheckParams p;
    p.tolerance = tolerance;
    const FitCheckReport check = checkFit(doc, sources, mapping, p);
    ASSERT_EQ(check.layers.size(), 5u);
    for (const FitCheckLayer& l : check.layers) {
        SCOPED_TRACE(l.name);
        EXPECT_GT(l.curves, 0u);
        EXPECT_EQ(l.curvesOver, 0u);
        EXPECT_EQ(l.sourcesOver, 0u);
        // Upper bounds, within the measure's precision of the true distance.
        EXPECT_LE(l.curveToSourceUpper, tolerance + p.precision);
        EXPECT_LE(l.sourceToCurveUpper, tolerance + p.precision);
        std::cout << "[ figures  ] tolerance " << tolerance << " m, " << l.name << ": " << l.curves << " curves, "
                  << l.onCurveVertices << " on-curve of " << l.vertices << " vertices; curve to source <= " << l.curveToSourceUpper
                  << " m, source to curve <= " << l.sourceToCurveUpper << " m\n";
    }
    EXPECT_TRUE(check.passed());
}

INSTANTIATE_TEST_SUITE_P(Tolerances, AndorraFit, testing::Values(0.5, 5.0));

}  // namespace
}  // namespace lacet
