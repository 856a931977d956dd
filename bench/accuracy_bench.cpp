#include <algorithm>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

struct Error {
    double maxTexels = 0.0;
    std::size_t pieces = 0;
};

// Hausdorff distance, by dense sampling, between each kept piece (an exact sub-piece of its
// ancestor) and its chord, the segment the producers draw; in texels of the piece's quad.
void measure(const std::vector<Vertex>& v, double texel, Error& e) {
    forEachPiece(v, [&](const BezierPiece& b, std::size_t first) {
        if (v[first].closing) return;
        ++e.pieces;
        double d = 0.0;
        constexpr int kSamples = 64;
        for (int i = 0; i <= kSamples; ++i) {
            const double t = double(i) / kSamples;
            d = std::max(d, distanceToSegment(evaluate(b, t), b.start(), b.end()));
            d = std::max(d, distanceTo(b, b.start() + (b.end() - b.start()) * t, texel * 1e-3));
        }
        e.maxTexels = std::max(e.maxTexels, d / texel);
    });
}

}  // namespace

constexpr int kRepetitions = 7;  // timing runs per tolerance; the median is reported

nlohmann::json benchAccuracy(const std::vector<double>& tolerancesTexels, std::size_t curves, std::uint64_t seed) {
    const Scene s = makeSyntheticScene({seed, curves});
    const Vec2 c = s.extent.center();
    const ViewParams view;
    nlohmann::json rows = nlohmann::json::array();
    for (double tol : tolerancesTexels) {
        RefineParams params;
        params.toleranceTexels = tol;
        std::vector<double> times;
        std::size_t vertices = 0, quads = 0;
        Error err;
        for (int rep = 0; rep < kRepetitions; ++rep) {
            const auto t0 = Clock::now();
            GraphStep qtStep(s);
            Quadtree qt(s, params, &qtStep);
            qt.refineForViewer({c.x, c.y, 10.0}, view);
            times.push_back(msSince(t0));
            if (rep > 0) continue;
            qt.forEachQuad([&](const Quad& q) {
                if (q.layers.empty()) return;
                ++quads;
                const double texel = q.bounds.size().x / double(params.resolution);
                for (const auto& layer : q.layers) {
                    for (const auto& [a, pieces] : layer.curves)
                        for (const auto& p : pieces) {
                            vertices += p.vertices.size();
                            measure(p.vertices, texel, err);
                        }
                    for (const auto& [a, pieces] : layer.areas)
                        for (const auto& p : pieces)
                            for (const auto& l : p.loops) {
                                vertices += l.vertices.size();
                                measure(l.vertices, texel, err);
                            }
                }
            });
        }
        rows.push_back({{"tolerance_texels", tol},
                        {"clip_and_refine_ms", median(times)},
                        {"quads", quads},
                        {"vertices", vertices},
                        {"pieces_measured", err.pieces},
                        {"max_deviation_texels", err.maxTexels}});
    }
    return {{"curves", curves},
            {"resolution_texels", RefineParams{}.resolution},
            {"viewer", "10 m above the scene centre"},
            {"K", view.K},
            {"reference", "dense sampling (65 points per piece, both ways) of the exact Bezier pieces"},
            {"rows", rows}};
}

}  // namespace lacet::bench
