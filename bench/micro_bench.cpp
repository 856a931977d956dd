// Google Benchmark programs for the innermost operations of CLIPANDREFINE.
#include <random>

#include <benchmark/benchmark.h>

#include "model/bezier.h"
#include "model/clip_and_refine.h"

namespace lacet {
namespace {

BezierPiece randomCubic(std::mt19937_64& rng) {
    BezierPiece b;
    b.degree = 3;
    for (auto& p : b.p) p = Vec2(double(rng() % 1000), double(rng() % 1000));
    return b;
}

void BM_TightBounds(benchmark::State& state) {
    std::mt19937_64 rng(1);
    const BezierPiece b = randomCubic(rng);
    for (auto _ : state) benchmark::DoNotOptimize(tightBounds(b));
}
BENCHMARK(BM_TightBounds);

void BM_SplitHalf(benchmark::State& state) {
    std::mt19937_64 rng(2);
    const BezierPiece b = randomCubic(rng);
    for (auto _ : state) benchmark::DoNotOptimize(splitHalf(b));
}
BENCHMARK(BM_SplitHalf);

// Clip and refine one cubic into a quad 1/8 of its size, at a tolerance of `range(0)`/100 texel.
void BM_ClipAndRefineCurve(benchmark::State& state) {
    std::mt19937_64 rng(3);
    ClippedCurve c;
    const BezierPiece b = randomCubic(rng);
    for (int i = 0; i <= 3; ++i) c.vertices.push_back({b.p[i], i == 0 || i == 3});
    const Box quad{{400, 400}, {525, 525}};
    const double tol = double(state.range(0)) / 100.0 * 125.0 / 256.0;
    std::vector<ClippedCurve> out;
    for (auto _ : state) {
        out.clear();
        clipAndRefineCurve(c, 0, quad, 5.0, tol, out);
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_ClipAndRefineCurve)->Arg(400)->Arg(100)->Arg(50)->Arg(12);

void BM_ClipAndRefineArea(benchmark::State& state) {
    ClippedArea a;
    ClippedLoop l;
    l.vertices = {{{-300, -300}}, {{200, -500}, false}, {{900, -300}}, {{900, 900}}, {{300, 600}, false}, {{-300, 900}}, {{-300, -300}}};
    a.loops.push_back(l);
    const Box quad{{400, 400}, {525, 525}};
    std::vector<ClippedArea> out;
    for (auto _ : state) {
        out.clear();
        clipAndRefineArea(a, 0, quad, 5.0, 0.25, out);
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_ClipAndRefineArea);

}  // namespace
}  // namespace lacet
