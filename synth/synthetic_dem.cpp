// Synthetic DEM: terrain noise, river beds, valleys. See synth/synthetic_dem.h.

#include "synth/synthetic_dem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace lacet {

namespace {

constexpr double kPaperSide = 100000.0;  // m: the extent that `resolution` refers to

// --- Terrain ---------------------------------------------------------------------------------

constexpr double kOutletAltitude = 200.0;        // m, valley lines where rivers leave the network
constexpr double kPlateauAltitude = 1400.0;      // m, terrain far from any river (before noise)
constexpr double kHillslope = 0.12;              // m/m, terrain rising from the valley lines to the ridges
// Valley lines rise upstream by kValleyLineGradient + kValleyLineWidthGradient / w (m/m, w the
// river width in metres, at least kNarrowestRiver): steep for brooks, gentle for wide rivers
// (Flint's law, with the width standing in for the drainage area).
constexpr double kValleyLineGradient = 0.003;
constexpr double kValleyLineWidthGradient = 0.04;  // m
constexpr double kNarrowestRiver = 1.0;            // m
constexpr int kNoiseOctaves = 6;
constexpr double kNoiseLongestSpacing = 8000.0;    // m between lattice values of the first octave
constexpr double kNoiseAmplitude = 250.0;          // m, lattice values of the first octave in [-a, a)
constexpr double kNoisePersistence = 0.5;          // amplitude ratio of successive octaves (spacing halves)
constexpr double kMinNoiseSpacingCells = 2.0;      // cells: finer octaves would alias, they are left out
constexpr double kNoiseFadeDistance = 800.0;       // m from a valley floor over which the noise fades in

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
// m/m: the floors, where they overlap (at confluences), ramp from the lower level to the higher
// at most this steeply instead of stepping; above kMaxBedSlope so that a lone floor is unchanged.
constexpr double kFloorSlope = 0.06;
constexpr double kValleySlope = 0.35;        // m/m, valley walls from the floor up to the terrain

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

// Value noise (m): octaves of cubic B-spline interpolated random lattices, fixed in metres so
// that a coarser Dem shows the same terrain, less its finest octaves.
std::vector<float> noise(const Grid& g, std::uint64_t seed) {
    const auto W = std::size_t(g.w), H = std::size_t(g.h);
    const Vec2 size = g.extent.size();
    // Separable: each octave is interpolated along x on every lattice row first, then every grid
    // row sums the octaves' interpolations along y.
    struct Octave {
        AxisWeights y;
        std::vector<float> rows;  // lattice row b, grid column i at b * W + i
    };
    std::vector<Octave> octaves;
    std::vector<double> lattice;
    for (int o = 0; o < kNoiseOctaves; ++o) {
        const double spacing = kNoiseLongestSpacing / double(1 << o);
        if (spacing < kMinNoiseSpacingCells * std::max(g.cell.x, g.cell.y)) break;
        const double amplitude = kNoiseAmplitude * std::pow(kNoisePersistence, double(o));
        const auto nx = std::size_t(std::ceil(size.x / spacing)) + 4, ny = std::size_t(std::ceil(size.y / spacing)) + 4;
        std::mt19937_64 rng(splitmix(seed + 0x9e3779b97f4a7c15ull * std::uint64_t(o + 1)));
        lattice.resize(nx * ny);
        for (double& v : lattice) v = amplitude * (double(rng() >> 11) * 0x1.0p-52 - 1.0);  // [-a, a)
        const AxisWeights ax = axisWeights(g.w, g.cell.x, spacing);
        Octave& octave = octaves.emplace_back(Octave{axisWeights(g.h, g.cell.y, spacing), std::vector<float>(ny * W)});
        for (std::size_t b = 0; b < ny; ++b)
            for (std::size_t i = 0; i < W; ++i) {
                const double* l = &lattice[b * nx + ax.first[i]];
                const auto& w = ax.w[i];
                octave.rows[b * W + i] = float(w[0] * l[0] + w[1] * l[1] + w[2] * l[2] + w[3] * l[3]);
            }
    }
    std::vector<float> n(W * H, 0.0f);
    for (std::size_t j = 0; j < H; ++j) {
        float* out = &n[j * W];
        for (const Octave& octave : octaves) {
            const auto& w64 = octave.y.w[j];
            const std::array<float, 4> w = {float(w64[0]), float(w64[1]), float(w64[2]), float(w64[3])};
            const float* r = &octave.rows[octave.y.first[j] * W];
            const auto sum = [&](std::size_t i) {
                return out[i] + (w[0] * r[i] + w[1] * r[W + i] + w[2] * r[2 * W + i] + w[3] * r[3 * W + i]);
            };
            // By groups of 4 through a local array, which the compiler turns into vector code.
            std::size_t i = 0;
            for (constexpr std::size_t kGroup = 4; i + kGroup <= W; i += kGroup) {
                std::array<float, kGroup> group;
                for (std::size_t q = 0; q < kGroup; ++q) group[q] = sum(i + q);
                std::copy(group.begin(), group.end(), out + i);
            }
            for (; i < W; ++i) out[i] = sum(i);
        }
    }
    return n;
}

// --- River network ---------------------------------------------------------------------------

struct River {
    std::size_t start = 0, end = 0;  // network node indices
    double width = 0.0;              // m, the curve's w
    double floor = 0.0;              // m, half width of the valley floor
    std::vector<Vec2> x;             // samples from start to end
    std::vector<double> ds;          // m, ds[k] = |x[k] - x[k-1]|, ds[0] = 0
    // The cells of its valley floor (centre within `floor` of a sample), each with its nearest
    // sample, by cell index.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> floorCells;
    std::vector<double> target;      // m, the highest bed allowed at each sample
    std::vector<double> bed;         // m
};

struct Network {
    std::vector<River> rivers;
    std::vector<std::vector<std::size_t>> in, out;  // per node: curves ending, starting there
    std::vector<std::size_t> order;                 // rivers, upstream before downstream
};

// Calls f(cell index, squared distance in m^2) for every grid cell whose centre lies within
// `radius` of p.
template <class F>
void forCellsWithin(const Grid& g, Vec2 p, double radius, F&& f) {
    const Vec2 lo = (p - radius - g.extent.min) / g.cell - 0.5, hi = (p + radius - g.extent.min) / g.cell - 0.5;
    const int i0 = std::max(0, int(std::ceil(lo.x))), i1 = std::min(g.w - 1, int(std::floor(hi.x)));
    const int j0 = std::max(0, int(std::ceil(lo.y))), j1 = std::min(g.h - 1, int(std::floor(hi.y)));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            const Vec2 d = g.position(i, j) - p;
            if (const double d2 = glm::dot(d, d); d2 <= radius * radius) f(g.index(i, j), d2);
        }
}

// Sets r.floorCells. Samples are taken in chunks whose floors fit a small local grid; a cell
// reached from several chunks keeps its nearest sample (the first one on a tie).
void assignFloorCells(River& r, const Grid& g) {
    constexpr std::size_t kChunk = 512;  // samples
    struct Candidate {
        std::uint32_t cell, sample;
        double d2;  // m^2
    };
    std::vector<Candidate> found;
    std::vector<double> best;
    std::vector<std::uint32_t> nearest;
    for (std::size_t first = 0; first < r.x.size(); first += kChunk) {
        const std::size_t last = std::min(r.x.size(), first + kChunk);
        Vec2 lo = r.x[first], hi = r.x[first];
        for (std::size_t k = first; k < last; ++k) {
            lo = glm::min(lo, r.x[k]);
            hi = glm::max(hi, r.x[k]);
        }
        const Vec2 a = (lo - r.floor - g.extent.min) / g.cell - 0.5, b = (hi + r.floor - g.extent.min) / g.cell - 0.5;
        const int i0 = std::max(0, int(std::ceil(a.x))), i1 = std::min(g.w - 1, int(std::floor(b.x)));
        const int j0 = std::max(0, int(std::ceil(a.y))), j1 = std::min(g.h - 1, int(std::floor(b.y)));
        if (i0 > i1 || j0 > j1) continue;
        const auto w = std::size_t(i1 - i0 + 1), h = std::size_t(j1 - j0 + 1);
        best.assign(w * h, std::numeric_limits<double>::infinity());
        nearest.assign(w * h, 0);
        for (std::size_t k = first; k < last; ++k)
            forCellsWithin(g, r.x[k], r.floor, [&](std::size_t cell, double d2) {
                const std::size_t local = (cell / std::size_t(g.w) - std::size_t(j0)) * w + cell % std::size_t(g.w) - std::size_t(i0);
                if (d2 < best[local]) {
                    best[local] = d2;
                    nearest[local] = std::uint32_t(k);
                }
            });
        for (std::size_t j = 0; j < h; ++j)
            for (std::size_t i = 0; i < w; ++i)
                if (const std::size_t local = j * w + i; !std::isinf(best[local]))
                    found.push_back({std::uint32_t(g.index(i0 + int(i), j0 + int(j))), nearest[local], best[local]});
    }
    std::sort(found.begin(), found.end(), [](const Candidate& p, const Candidate& q) {
        return p.cell != q.cell ? p.cell < q.cell : p.d2 != q.d2 ? p.d2 < q.d2 : p.sample < q.sample;
    });
    r.floorCells.clear();
    for (std::size_t n = 0; n < found.size(); ++n)
        if (n == 0 || found[n].cell != found[n - 1].cell) r.floorCells.emplace_back(found[n].cell, found[n].sample);
}

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
            r.width = double(c.w);
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
            assignFloorCells(r, g);
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

// The highest bed allowed at each river sample: the lowest terrain of the floor cells it is the
// nearest sample of, and of its own cell, less the channel depth.
void setTargets(Network& net, const Grid& g, const std::vector<float>& t) {
    for (River& r : net.rivers) {
        r.target.resize(r.x.size());
        for (std::size_t k = 0; k < r.x.size(); ++k) {
            const Vec2 c = glm::floor((r.x[k] - g.extent.min) / g.cell);
            r.target[k] = t[g.index(std::clamp(int(c.x), 0, g.w - 1), std::clamp(int(c.y), 0, g.h - 1))];
        }
        for (const auto& [cell, k] : r.floorCells) r.target[k] = std::min(r.target[k], double(t[cell]));
        for (double& z : r.target) z -= kChannelDepth;
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

// Fills v with a field that is, on the valley floor of each river c, the value `value(c, k)` of
// its nearest sample k (so that it is level across the river), the lowest of them where
// floors overlap, and +infinity elsewhere.
template <class F>
void floors(std::vector<float>& v, const Network& net, const Grid& g, F&& value) {
    v.assign(std::size_t(g.w) * std::size_t(g.h), kInfinity);
    for (std::size_t c = 0; c < net.rivers.size(); ++c)
        for (const auto& [cell, k] : net.rivers[c].floorCells) v[cell] = std::min(v[cell], float(value(c, k)));
}

// v(c) = min over cells c' of v(c') + slope * |c - c'|, the distance measured by a two-pass
// 5 x 5 chamfer propagation (within 2% of Euclidean). Linear in the number of cells. With
// `withinFinite`, cells at +infinity stay there and pass nothing on: the cones spread only
// through the finite cells.
void propagateCones(std::vector<float>& v, const Grid& g, double slope, bool withinFinite) {
    constexpr std::size_t kMargin = 2;  // cells of +infinity around the rows before, for the mask
    const auto W = std::size_t(g.w), H = std::size_t(g.h);
    const double cx = g.cell.x, cy = g.cell.y;
    const auto rise = [&](double metres) { return float(slope * metres); };
    const float side = rise(cx), up = rise(cy), diagonal = rise(std::hypot(cx, cy)),
                knightX = rise(std::hypot(2.0 * cx, cy)), knightY = rise(std::hypot(cx, 2.0 * cy));
    // A row is relaxed from the two rows before it in the scan (above in the forward scan,
    // below in the backward one; the mask is symmetric across the column), then by a running
    // minimum along the row (rightwards forward, leftwards backward).
    std::vector<float> before1(W + 2 * kMargin), before2(W + 2 * kMargin), relaxed(W);
    const auto scan = [&](bool forward) {
        std::fill(before1.begin(), before1.end(), kInfinity);
        std::fill(before2.begin(), before2.end(), kInfinity);
        for (std::size_t n = 0; n < H; ++n) {
            float* row = &v[(forward ? n : H - 1 - n) * W];
            const float* a = before1.data() + kMargin;
            const float* b = before2.data() + kMargin;
            float* out = relaxed.data();
            const auto relax = [&](std::size_t i) {
                const float m = std::min(std::min(row[i], a[i] + up), std::min(a[i - 1], a[i + 1]) + diagonal);
                return std::min(m, std::min(std::min(a[i - 2], a[i + 2]) + knightX, std::min(b[i - 1], b[i + 1]) + knightY));
            };
            // By groups of 4 through a local array, which the compiler turns into vector code.
            std::size_t i = 0;
            for (constexpr std::size_t kGroup = 4; i + kGroup <= W; i += kGroup) {
                std::array<float, kGroup> group;
                for (std::size_t q = 0; q < kGroup; ++q) group[q] = relax(i + q);
                std::copy(group.begin(), group.end(), out + i);
            }
            for (; i < W; ++i) out[i] = relax(i);
            if (withinFinite)
                for (i = 0; i < W; ++i)
                    if (std::isinf(row[i])) out[i] = kInfinity;
            float run = kInfinity;
            const auto step = [&](std::size_t k) {
                run = withinFinite && std::isinf(out[k]) ? kInfinity : std::min(out[k], run + side);
                row[k] = run;
            };
            if (forward)
                for (i = 0; i < W; ++i) step(i);
            else
                for (i = W; i-- > 0;) step(i);
            std::swap(before1, before2);
            std::copy_n(row, W, before1.data() + kMargin);
        }
    };
    scan(true);
    scan(false);
}

// Valley lines: heights rising upstream from kOutletAltitude at the network's outlets (nodes no
// curve leaves), by the Flint-like gradient of each curve's width. They shape the terrain only;
// the beds are made later from the terrain. One upstream walk; a node left by several curves
// takes the lowest of their heights.
std::vector<std::vector<double>> valleyLines(const Network& net) {
    std::vector<double> node(net.in.size(), std::numeric_limits<double>::infinity());
    std::vector<std::vector<double>> lines(net.rivers.size());
    for (auto it = net.order.rbegin(); it != net.order.rend(); ++it) {
        const River& r = net.rivers[*it];
        std::vector<double>& z = lines[*it];
        z.resize(r.x.size());
        const double end = node[r.end];
        z.back() = std::isinf(end) ? kOutletAltitude : end;  // an outlet, or a curve on a cycle
        const double gradient = kValleyLineGradient + kValleyLineWidthGradient / std::max(r.width, kNarrowestRiver);
        for (std::size_t k = z.size() - 1; k > 0; --k) z[k - 1] = z[k] + gradient * r.ds[k];
        node[r.start] = std::min(node[r.start], z.front());
    }
    return lines;
}

// The terrain before the valleys are cut: hillsides rising at kHillslope from the valley lines
// up to a plateau, and noise that fades in away from the valley floors.
std::vector<float> terrain(const Network& net, const Grid& g, std::uint64_t seed) {
    const std::vector<std::vector<double>> lines = valleyLines(net);
    std::vector<float> t, distance;
    floors(t, net, g, [&](std::size_t c, std::size_t k) { return lines[c][k]; });
    propagateCones(t, g, kHillslope, false);
    floors(distance, net, g, [](std::size_t, std::size_t) { return 0.0; });
    propagateCones(distance, g, 1.0, false);
    const std::vector<float> n = noise(g, seed);
    for (std::size_t k = 0; k < t.size(); ++k)
        t[k] = float(std::min(double(t[k]), kPlateauAltitude) + smoothstep(double(distance[k]) / kNoiseFadeDistance) * n[k]);
    return t;
}

}  // namespace

Dem makeSyntheticDem(const Scene& scene, const SyntheticDemParams& params) {
    const Vec2 size = scene.extent.size();
    if (params.resolution < 1)
        throw std::invalid_argument("makeSyntheticDem: resolution must be >= 1, got " + std::to_string(params.resolution));
    if (!(size.x > 0.0 && size.y > 0.0))
        throw std::invalid_argument("makeSyntheticDem: the scene extent is empty");
    const double w = std::max(2.0, std::round(double(params.resolution) * size.x / kPaperSide)),
                 h = std::max(2.0, std::round(double(params.resolution) * size.y / kPaperSide));
    if (w * h > double(std::numeric_limits<std::uint32_t>::max()))
        throw std::invalid_argument("makeSyntheticDem: " + std::to_string(std::llround(w)) + " x " +
                                    std::to_string(std::llround(h)) + " samples are 2^32 or more");
    Grid g;
    g.extent = scene.extent;
    g.w = int(w);
    g.h = int(h);
    g.cell = size / Vec2(g.w, g.h);

    Network net = riverNetwork(scene, g);
    const std::vector<float> t = terrain(net, g, params.seed);
    setTargets(net, g, t);
    setBeds(net);
    // Valleys: floors at the beds, walls rising at kValleySlope from them until they meet the
    // terrain. A wall does not cut into another river's floor, so that the Dem along a river
    // interpolates its floor only.
    std::vector<float> levels;
    floors(levels, net, g, [&](std::size_t c, std::size_t k) { return net.rivers[c].bed[k]; });
    propagateCones(levels, g, kFloorSlope, true);
    std::vector<float> z = levels;
    propagateCones(z, g, kValleySlope, false);
    for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::isinf(levels[k]) ? std::min(z[k], t[k]) : levels[k];
    return Dem(g.extent, g.w, g.h, std::move(z));
}

}  // namespace lacet
