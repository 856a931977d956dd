#include "raster/appearance_ground.h"

#include <algorithm>
#include <cstring>

#include <glm/geometric.hpp>

namespace lacet::appearance {

void drawGround(Canvas& canvas, const AppearanceTile& t, const Dem& dem, int cells) {
    const double cell = t.bounds.size().x / double(cells);
    // Nodes -1 .. cells + 1 cover the border texels (border * delta < one cell).
    const int nodes = cells + 3;
    std::vector<glm::vec3> grid(std::size_t(nodes) * std::size_t(nodes));
    for (int j = 0; j < nodes; ++j)
        for (int i = 0; i < nodes; ++i) {
            const Vec2 p = t.bounds.min + Vec2(double(i - 1), double(j - 1)) * cell;
            Vec2 gradient;
            const double z = dem.sampleAndGradient(p, gradient);
            // Beyond the DEM the heights only continue its border: shown as no data.
            grid[std::size_t(j) * std::size_t(nodes) + std::size_t(i)] =
                dem.extent().contains(p) ? groundColour(z, glm::length(gradient)) : kNoDataGround;
        }
    const int side = canvas.side();
    std::vector<int> i0(std::size_t(side), 0);
    std::vector<float> fx(std::size_t(side), 0.0f);
    for (int x = 0; x < side; ++x) {
        const double g = std::clamp((canvas.world(x, 0).x - t.bounds.min.x) / cell + 1.0, 0.0, double(nodes - 1) - 1e-9);
        i0[std::size_t(x)] = int(g);
        fx[std::size_t(x)] = float(g - std::floor(g));
    }
    // Runs of texels between the same two nodes along x (i0 does not decrease).
    struct Run {
        std::size_t node;
        int begin, end;
    };
    std::vector<Run> runs;
    for (int x = 0; x < side; ++x)
        if (runs.empty() || runs.back().node != std::size_t(i0[std::size_t(x)])) runs.push_back({std::size_t(i0[std::size_t(x)]), x, x + 1});
        else runs.back().end = x + 1;
    Scratch& s = canvas.scratch();
    std::vector<glm::vec3> row(static_cast<std::size_t>(nodes));
    for (int y = 0; y < side; ++y) {
        const double g = std::clamp((canvas.world(0, y).y - t.bounds.min.y) / cell + 1.0, 0.0, double(nodes - 1) - 1e-9);
        const int j0 = int(g);
        const float fy = float(g - std::floor(g));
        // The row of nodes at this y first, then along x: bilinear, one lerp per texel.
        const glm::vec3* r0 = &grid[std::size_t(j0) * std::size_t(nodes)];
        const glm::vec3* r1 = r0 + nodes;
        for (int i = 0; i < nodes; ++i) row[std::size_t(i)] = r0[i] + (r1[i] - r0[i]) * fy;
        Rgbm* out = &s.colour[std::size_t(y) * std::size_t(side)];
        for (const Run& run : runs) {
            const glm::vec3 a = row[run.node], d = row[run.node + 1] - row[run.node];
            const Float4 a4{a.r, a.g, a.b, 0.0f}, d4{d.r, d.g, d.b, 0.0f};  // the three channels at once
            for (int x = run.begin; x < run.end; ++x) {
                const Float4 c = a4 + d4 * fx[std::size_t(x)];
                std::memcpy(&out[x], &c, sizeof c);
            }
        }
    }
}

}  // namespace lacet::appearance
