// Synthetic DEM: terrain noise, river beds, valleys. See raster/synthetic_dem.h.

#include "raster/synthetic_dem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#ifdef DEM_DEBUG
#include <cstdio>
#endif

#include <glm/geometric.hpp>

namespace lacet {

namespace {

constexpr double kPaperSide = 100000.0;  // m: the extent that `resolution` refers to

// --- Terrain ---------------------------------------------------------------------------------

constexpr double kBaseAltitude = 300.0;              // m, at the extent border
constexpr double kInlandRise = 400.0;                // m, added away from the border
constexpr double kInlandRange = 12000.0;             // m from the border over which the rise builds up
constexpr int kNoiseOctaves = 6;
constexpr double kNoiseLongestSpacing = 12000.0;     // m between lattice values of the first octave
constexpr double kNoiseAmplitude = 600.0;            // m, lattice values of the first octave in [-a, a]
constexpr double kNoisePersistence = 0.5;            // amplitude ratio of successive octaves (spacing halves)
constexpr double kMinNoiseSpacingCells = 2.0;        // cells: finer octaves would alias, they are left out

// --- Rivers ----------------------------------------------------------------------------------

constexpr double kRiverSampleStep = 0.5;     // cells between river samples
constexpr double kChannelDepth = 2.0;        // m, bed below the lowest terrain under its valley floor
constexpr double kMinBedSlope = 0.0005;      // m/m: beds strictly decrease downstream
constexpr double kMaxBedSlope = 0.05;        // m/m: steeper terrain is cut into
constexpr double kFloodplainMargin = 10.0;   // m, valley floor beyond the river's half width
// Cells: the valley floor reaches at least this far from the river axis, past the Catmull-Rom
// stencil (2 cells on each axis, 2.83 diagonally) of any point of the axis between two samples,
// so that the Dem along the axis interpolates floor values only.
constexpr double kMinFloorCells = 3.25;
constexpr double kValleySlope = 0.35;        // m/m, valley walls from the floor up to the terrain
constexpr int kMaxCorrections = 4;           // passes of step 4
constexpr double kCorrectionRise = 0.2;      // m: a rise along a river beyond this is corrected

constexpr float kInfinity = std::numeric_limits<float>::infinity();

std::uint64_t splitmix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Uniform cubic B-spline weights of lattice values -1, 0, 1, 2 at f in [0, 1].
std::array<double, 4> bspline(double f) {
    const double f2 = f * f, f3 = f2 * f, g = 1.0 - f;
    return {g * g * g / 6.0, (3.0 * f3 - 6.0 * f2 + 4.0) / 6.0, (-3.0 * f3 + 3.0 * f2 + 3.0 * f + 1.0) / 6.0, f3 / 6.0};
}

double smoothstep(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

struct Grid {
    Box extent;
    int w = 0, h = 0;
    Vec2 cell{0.0};

    std::size_t index(int i, int j) const { return std::size_t(j) * std::size_t(w) + std::size_t(i); }
    Vec2 position(int i, int j) const { return extent.min + (Vec2(i, j) + 0.5) * cell; }
};

// Weights and first lattice index of a B-spline lattice of spacing `spacing` (m) over an axis,
// for each of the `n` sample centres of that axis.
struct AxisWeights {
    std::vector<std::size_t> first;
    std::vector<std::array<double, 4>> w;
};

AxisWeights axisWeights(int n, double cell, double spacing) {
    AxisWeights a;
    a.first.resize(std::size_t(n));
    a.w.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) {
        // Lattice value k sits at (k - 1) * spacing from the extent's min, so k >= 0 below.
        const double u = (double(i) + 0.5) * cell / spacing + 1.0;
        const double k = std::floor(u);
        a.first[std::size_t(i)] = std::size_t(k) - 1;
        a.w[std::size_t(i)] = bspline(u - k);
    }
    return a;
}

// Heights (m) of the terrain before any valley: base altitude, inland rise, value noise.
std::vector<float> terrain(const Grid& g, std::uint64_t seed) {
    const auto W = std::size_t(g.w), H = std::size_t(g.h);
    std::vector<double> rx(W), ry(H);
    const Vec2 size = g.extent.size();
    for (std::size_t i = 0; i < W; ++i) {
        const double x = (double(i) + 0.5) * g.cell.x;
        rx[i] = smoothstep(std::min(x, size.x - x) / kInlandRange);
    }
    for (std::size_t j = 0; j < H; ++j) {
        const double y = (double(j) + 0.5) * g.cell.y;
        ry[j] = smoothstep(std::min(y, size.y - y) / kInlandRange);
    }
    std::vector<double> acc(W * H);
    for (std::size_t j = 0; j < H; ++j)
        for (std::size_t i = 0; i < W; ++i) acc[j * W + i] = kBaseAltitude + kInlandRise * rx[i] * ry[j];

    std::vector<double> lattice, rows;
    for (int o = 0; o < kNoiseOctaves; ++o) {
        const double spacing = kNoiseLongestSpacing / double(1 << o);
        if (spacing < kMinNoiseSpacingCells * std::max(g.cell.x, g.cell.y)) break;
        const double amplitude = kNoiseAmplitude * std::pow(kNoisePersistence, double(o));
        const auto nx = std::size_t(std::ceil(size.x / spacing)) + 4, ny = std::size_t(std::ceil(size.y / spacing)) + 4;
        std::mt19937_64 rng(splitmix(seed + 0x9e3779b97f4a7c15ull * std::uint64_t(o + 1)));
        lattice.resize(nx * ny);
        for (double& v : lattice) v = amplitude * (double(rng() >> 11) * 0x1.0p-52 - 1.0);  // [-a, a)
        const AxisWeights ax = axisWeights(g.w, g.cell.x, spacing), ay = axisWeights(g.h, g.cell.y, spacing);
        // Separable: along x on every lattice row, then along y for every grid row.
        rows.resize(ny * W);
        for (std::size_t b = 0; b < ny; ++b)
            for (std::size_t i = 0; i < W; ++i) {
                const double* l = &lattice[b * nx + ax.first[i]];
                const auto& w = ax.w[i];
                rows[b * W + i] = w[0] * l[0] + w[1] * l[1] + w[2] * l[2] + w[3] * l[3];
            }
        for (std::size_t j = 0; j < H; ++j) {
            const auto& w = ay.w[j];
            const double* r = &rows[ay.first[j] * W];
            double* out = &acc[j * W];
            for (std::size_t i = 0; i < W; ++i)
                out[i] += w[0] * r[i] + w[1] * r[W + i] + w[2] * r[2 * W + i] + w[3] * r[3 * W + i];
        }
    }
    std::vector<float> t(W * H);
    for (std::size_t k = 0; k < W * H; ++k) t[k] = float(acc[k]);
    return t;
}

// --- River network ---------------------------------------------------------------------------

struct River {
    std::size_t start = 0, end = 0;  // network node indices
    double floor = 0.0;              // m, half width of the valley floor
    std::vector<Vec2> x;             // samples from start to end
    std::vector<double> ds;          // m, ds[k] = |x[k] - x[k-1]|, ds[0] = 0
    std::vector<double> target;      // m, the highest bed allowed at each sample
    std::vector<double> bed;         // m
};

struct Network {
    std::vector<River> rivers;
    std::vector<std::vector<std::size_t>> in, out;  // per node: curves ending, starting there
    std::vector<std::size_t> order;                 // rivers, upstream before downstream
};

Network riverNetwork(const Scene& scene, const Grid& g) {
    Network net;
    const double step = kRiverSampleStep * std::min(g.cell.x, g.cell.y);
    const double minFloor = kMinFloorCells * std::max(g.cell.x, g.cell.y);
    std::size_t nodes = 0;
    for (const Layer& layer : scene.layers) {
        if (layer.kind != LayerKind::Rivers) continue;
        for (const Curve& c : layer.curves) {
            if (!c.alive || c.vertices.size() < 2 || c.start >= layer.nodes.size() || c.end >= layer.nodes.size())
                continue;
            River r;
            r.start = nodes + c.start;
            r.end = nodes + c.end;
            r.floor = std::max(0.5 * double(c.w) + kFloodplainMargin, minFloor);
            r.x.push_back(c.vertices.front().p);
            forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
                double polygon = 0.0;
                for (int k = 0; k < b.degree; ++k) polygon += glm::distance(b.p[std::size_t(k)], b.p[std::size_t(k + 1)]);
                const auto n = std::max<std::size_t>(1, std::size_t(std::ceil(polygon / step)));
                for (std::size_t k = 1; k <= n; ++k) r.x.push_back(evaluate(b, double(k) / double(n)));
            });
            r.ds.resize(r.x.size(), 0.0);
            for (std::size_t k = 1; k < r.x.size(); ++k) r.ds[k] = glm::distance(r.x[k - 1], r.x[k]);
            net.rivers.push_back(std::move(r));
        }
        nodes += layer.nodes.size();
    }
    net.in.resize(nodes);
    net.out.resize(nodes);
    for (std::size_t c = 0; c < net.rivers.size(); ++c) {
        net.out[net.rivers[c].start].push_back(c);
        net.in[net.rivers[c].end].push_back(c);
    }
    // Kahn's order on curves: a curve comes after every curve ending at its start node. Curves
    // on a cycle are appended last, in index order.
    std::vector<std::size_t> waiting(net.rivers.size());
    std::vector<std::size_t> ready;
    for (std::size_t c = 0; c < net.rivers.size(); ++c)
        if ((waiting[c] = net.in[net.rivers[c].start].size()) == 0) ready.push_back(c);
    std::vector<bool> placed(net.rivers.size(), false);
    for (std::size_t head = 0; head < ready.size(); ++head) {
        const std::size_t c = ready[head];
        net.order.push_back(c);
        placed[c] = true;
        for (std::size_t d : net.out[net.rivers[c].end])
            if (--waiting[d] == 0) ready.push_back(d);
    }
    for (std::size_t c = 0; c < net.rivers.size(); ++c)
        if (!placed[c]) net.order.push_back(c);
    return net;
}

// Calls f(cell index) for every grid cell whose centre lies within `radius` of p.
template <class F>
void forCellsWithin(const Grid& g, Vec2 p, double radius, F&& f) {
    const Vec2 lo = (p - radius - g.extent.min) / g.cell - 0.5, hi = (p + radius - g.extent.min) / g.cell - 0.5;
    const int i0 = std::max(0, int(std::ceil(lo.x))), i1 = std::min(g.w - 1, int(std::floor(hi.x)));
    const int j0 = std::max(0, int(std::ceil(lo.y))), j1 = std::min(g.h - 1, int(std::floor(hi.y)));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            const Vec2 d = g.position(i, j) - p;
            if (glm::dot(d, d) <= radius * radius) f(g.index(i, j));
        }
}

// The highest bed allowed at each river sample: the lowest terrain under its valley floor, less
// the channel depth (the terrain of the nearest cell when the floor covers no cell centre).
void setTargets(Network& net, const Grid& g, const std::vector<float>& t) {
    for (River& r : net.rivers) {
        r.target.resize(r.x.size());
        for (std::size_t k = 0; k < r.x.size(); ++k) {
            const Vec2 c = glm::floor((r.x[k] - g.extent.min) / g.cell);
            double lowest = t[g.index(std::clamp(int(c.x), 0, g.w - 1), std::clamp(int(c.y), 0, g.h - 1))];
            forCellsWithin(g, r.x[k], r.floor, [&](std::size_t cell) { lowest = std::min(lowest, double(t[cell])); });
            r.target[k] = lowest - kChannelDepth;
        }
    }
}

// Beds under the targets, decreasing downstream by kMinBedSlope..kMaxBedSlope, one height per
// node. A downstream pass (beds follow the targets and never rise) then an upstream pass (the
// ends of incoming curves meet their node's height, steep drops are spread upstream); both only
// lower beds, and a tree needs one round of each. A node with several outgoing curves may need
// more: rounds repeat until nothing changes, a few at most.
void setBeds(Network& net) {
    constexpr int kMaxRounds = 8;
    const std::size_t nodes = net.in.size();
    std::vector<double> node(nodes, std::numeric_limits<double>::infinity());
    for (River& r : net.rivers) {
        node[r.start] = std::min(node[r.start], r.target[0]);
        r.bed = r.target;
    }
    for (int round = 0; round < kMaxRounds; ++round) {
        bool changed = false;
        const auto lower = [&](double& v, double to) {
            if (to < v) {
                v = to;
                changed = true;
            }
        };
        for (std::size_t c : net.order) {
            River& r = net.rivers[c];
            lower(r.bed[0], node[r.start]);
            for (std::size_t k = 1; k < r.bed.size(); ++k) lower(r.bed[k], r.bed[k - 1] - kMinBedSlope * r.ds[k]);
            lower(node[r.end], r.bed.back());
        }
        for (auto it = net.order.rbegin(); it != net.order.rend(); ++it) {
            River& r = net.rivers[*it];
            lower(r.bed.back(), node[r.end]);
            for (std::size_t k = r.bed.size() - 1; k > 0; --k) lower(r.bed[k - 1], r.bed[k] + kMaxBedSlope * r.ds[k]);
            lower(node[r.start], r.bed[0]);
        }
        if (!changed && round > 0) break;
    }
}

// Valley heights: the floor of every river sample at its bed, and walls rising at kValleySlope
// from the floors, by a two-pass 5 x 5 chamfer propagation (distances within 2% of Euclidean).
// Cells that no valley reaches stay +infinity.
std::vector<float> valleys(const Network& net, const Grid& g) {
    std::vector<float> v(std::size_t(g.w) * std::size_t(g.h), kInfinity);
    for (const River& r : net.rivers)
        for (std::size_t k = 0; k < r.x.size(); ++k) {
            const auto b = float(r.bed[k]);
            forCellsWithin(g, r.x[k], r.floor, [&](std::size_t cell) { v[cell] = std::min(v[cell], b); });
        }
    const double cx = g.cell.x, cy = g.cell.y;
    const auto rise = [](double metres) { return float(kValleySlope * metres); };
    struct Step {
        int di, dj;
        float dz;
    };
    // The neighbours visited before a cell in a row-major forward scan; the backward scan uses
    // their opposites.
    const std::array<Step, 8> steps = {{{-1, 0, rise(cx)},
                                        {0, -1, rise(cy)},
                                        {-1, -1, rise(std::hypot(cx, cy))},
                                        {1, -1, rise(std::hypot(cx, cy))},
                                        {-2, -1, rise(std::hypot(2.0 * cx, cy))},
                                        {2, -1, rise(std::hypot(2.0 * cx, cy))},
                                        {-1, -2, rise(std::hypot(cx, 2.0 * cy))},
                                        {1, -2, rise(std::hypot(cx, 2.0 * cy))}}};
    const auto relax = [&](int i, int j, int sign) {
        float& here = v[g.index(i, j)];
        for (const Step& s : steps) {
            const int ni = i + sign * s.di, nj = j + sign * s.dj;
            if (ni < 0 || nj < 0 || ni >= g.w || nj >= g.h) continue;
            here = std::min(here, v[g.index(ni, nj)] + s.dz);
        }
    };
    for (int j = 0; j < g.h; ++j)
        for (int i = 0; i < g.w; ++i) relax(i, j, 1);
    for (int j = g.h - 1; j >= 0; --j)
        for (int i = g.w - 1; i >= 0; --i) relax(i, j, -1);
    return v;
}

// Heights along every river, walked downstream from its sources; where the Dem rises by more
// than kCorrectionRise above the lowest height upstream, that sample's target is lowered to it.
// Returns whether a target was lowered.
bool lowerTargetsWhereRising(Network& net, const Dem& dem) {
    std::vector<double> lowest(net.in.size(), std::numeric_limits<double>::infinity());
    bool lowered = false;
    for (std::size_t c : net.order) {
        River& r = net.rivers[c];
        double m = lowest[r.start];
        for (std::size_t k = 0; k < r.x.size(); ++k) {
            const double z = dem.sample(r.x[k]);
            if (z > m + kCorrectionRise && m < r.target[k]) {
                r.target[k] = m;
                lowered = true;
            }
            m = std::min(m, z);
        }
        lowest[r.end] = std::min(lowest[r.end], m);
    }
    return lowered;
}

}  // namespace

Dem makeSyntheticDem(const Scene& scene, const SyntheticDemParams& params) {
    const Vec2 size = scene.extent.size();
    if (params.resolution < 1)
        throw std::invalid_argument("makeSyntheticDem: resolution must be >= 1, got " + std::to_string(params.resolution));
    if (!(size.x > 0.0 && size.y > 0.0))
        throw std::invalid_argument("makeSyntheticDem: the scene extent is empty");
    Grid g;
    g.extent = scene.extent;
    g.w = std::max(2, int(std::lround(double(params.resolution) * size.x / kPaperSide)));
    g.h = std::max(2, int(std::lround(double(params.resolution) * size.y / kPaperSide)));
    g.cell = size / Vec2(g.w, g.h);

    const std::vector<float> t = terrain(g, params.seed);
    Network net = riverNetwork(scene, g);
    setTargets(net, g, t);
    std::vector<float> z;
    for (int pass = 0;; ++pass) {
        setBeds(net);
        z = valleys(net, g);
        for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::min(z[k], t[k]);
#ifdef DEM_DEBUG
        fprintf(stderr, "pass %d\n", pass);
#endif
        if (pass == kMaxCorrections || net.rivers.empty() || !lowerTargetsWhereRising(net, Dem(g.extent, g.w, g.h, z)))
            break;
    }
    return Dem(g.extent, g.w, g.h, std::move(z));
}

}  // namespace lacet
