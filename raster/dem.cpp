#include "raster/dem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace lacet {

namespace {

// Catmull-Rom weights of the samples at -1, 0, 1, 2 for a position t in [0, 1] between samples
// 0 and 1, and their derivatives with respect to t.
std::array<double, 4> catmullRom(double t) {
    const double t2 = t * t, t3 = t2 * t;
    return {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
            0.5 * (t3 - t2)};
}

std::array<double, 4> catmullRomDerivative(double t) {
    const double t2 = t * t;
    return {0.5 * (-3.0 * t2 + 4.0 * t - 1.0), 0.5 * (9.0 * t2 - 10.0 * t), 0.5 * (-9.0 * t2 + 8.0 * t + 1.0),
            0.5 * (3.0 * t2 - 2.0 * t)};
}

bool hasNaN(Vec2 p) { return std::isnan(p.x) || std::isnan(p.y); }

}  // namespace

Dem::Dem(const Box& extent, int width, int height, std::vector<float> heights)
    : extent_(extent), width_(width), height_(height), heights_(std::move(heights)) {
    if (!(extent.max.x > extent.min.x && extent.max.y > extent.min.y) || !std::isfinite(extent.min.x) ||
        !std::isfinite(extent.min.y) || !std::isfinite(extent.max.x) || !std::isfinite(extent.max.y))
        throw std::invalid_argument("Dem: the extent must be finite with max > min on both axes");
    if (width < 1 || height < 1)
        throw std::invalid_argument("Dem: width and height must be >= 1, got " + std::to_string(width) + " x " +
                                    std::to_string(height));
    if (heights_.size() != std::size_t(width) * std::size_t(height))
        throw std::invalid_argument("Dem: " + std::to_string(width) + " x " + std::to_string(height) + " grid needs " +
                                    std::to_string(std::size_t(width) * std::size_t(height)) + " heights, got " +
                                    std::to_string(heights_.size()));
    const auto bad = std::find_if(heights_.begin(), heights_.end(), [](float h) { return !std::isfinite(h); });
    if (bad != heights_.end()) {
        const auto k = std::size_t(bad - heights_.begin());
        throw std::invalid_argument("Dem: height at cell (" + std::to_string(k % std::size_t(width)) + ", " +
                                    std::to_string(k / std::size_t(width)) + ") is " +
                                    (std::isnan(*bad) ? "NaN" : "infinite") + "; fill voids before making a Dem");
    }
    cell_ = extent.size() / Vec2(width, height);
}

Vec2 Dem::samplePosition(int i, int j) const {
    return extent_.min + (Vec2(i, j) + 0.5) * cell_;
}

float Dem::at(int i, int j) const {
    i = std::clamp(i, 0, width_ - 1);
    j = std::clamp(j, 0, height_ - 1);
    return heights_[std::size_t(j) * std::size_t(width_) + std::size_t(i)];
}

// The 4 x 4 samples around a position and the position inside the central cell.
struct Dem::Stencil {
    std::array<std::array<double, 4>, 4> v;  // v[row][column]
    double tx, ty;                           // in [0, 1] between the samples 1 and 2 of the stencil
};

Dem::Stencil Dem::stencil(Vec2 p) const {
    const Vec2 q = glm::clamp(p, extent_.min, extent_.max);
    // Continuous sample coordinates: sample (i, j) at (i, j); the extent spans [-0.5, n - 0.5].
    const double x = std::clamp((q.x - extent_.min.x) / cell_.x - 0.5, -0.5, double(width_) - 0.5);
    const double y = std::clamp((q.y - extent_.min.y) / cell_.y - 0.5, -0.5, double(height_) - 0.5);
    const double fx = std::floor(x), fy = std::floor(y);
    const int i0 = int(fx) - 1, j0 = int(fy) - 1;
    Stencil s;
    s.tx = x - fx;
    s.ty = y - fy;
    if (i0 >= 0 && j0 >= 0 && i0 + 3 < width_ && j0 + 3 < height_) {
        for (int r = 0; r < 4; ++r) {
            const float* row = &heights_[std::size_t(j0 + r) * std::size_t(width_) + std::size_t(i0)];
            for (int c = 0; c < 4; ++c) s.v[std::size_t(r)][std::size_t(c)] = row[c];
        }
        return s;
    }
    // Near the border: the grid continued by linear extrapolation of its two outermost rows and
    // columns (bilinear in the corners), so that linear height fields stay exact.
    const auto extrapolated = [](int k, int n, auto value) {
        if (k >= 0 && k < n) return value(k);
        if (n == 1) return value(0);
        if (k < 0) return value(0) + double(k) * (value(1) - value(0));
        return value(n - 1) + double(k - n + 1) * (value(n - 1) - value(n - 2));
    };
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            s.v[std::size_t(r)][std::size_t(c)] = extrapolated(j0 + r, height_, [&](int j) {
                return extrapolated(i0 + c, width_, [&](int i) { return double(at(i, j)); });
            });
    return s;
}

double Dem::sample(Vec2 p) const {
    if (hasNaN(p)) return std::numeric_limits<double>::quiet_NaN();
    const Stencil s = stencil(p);
    const auto wx = catmullRom(s.tx), wy = catmullRom(s.ty);
    double h = 0.0;
    for (std::size_t r = 0; r < 4; ++r)
        h += wy[r] * (wx[0] * s.v[r][0] + wx[1] * s.v[r][1] + wx[2] * s.v[r][2] + wx[3] * s.v[r][3]);
    return h;
}

Vec2 Dem::gradient(Vec2 p) const {
    Vec2 g;
    sampleAndGradient(p, g);
    return g;
}

double Dem::sampleAndGradient(Vec2 p, Vec2& gradient) const {
    if (hasNaN(p)) {
        gradient = Vec2(std::numeric_limits<double>::quiet_NaN());
        return std::numeric_limits<double>::quiet_NaN();
    }
    const Stencil s = stencil(p);
    const auto wx = catmullRom(s.tx), wy = catmullRom(s.ty);
    const auto dx = catmullRomDerivative(s.tx), dy = catmullRomDerivative(s.ty);
    double h = 0.0;
    Vec2 g(0.0);
    for (std::size_t r = 0; r < 4; ++r) {
        const auto& v = s.v[r];
        const double across = wx[0] * v[0] + wx[1] * v[1] + wx[2] * v[2] + wx[3] * v[3];
        h += wy[r] * across;
        g.x += wy[r] * (dx[0] * v[0] + dx[1] * v[1] + dx[2] * v[2] + dx[3] * v[3]);
        g.y += dy[r] * across;
    }
    g /= cell_;
    if (p.x < extent_.min.x || p.x > extent_.max.x) g.x = 0.0;
    if (p.y < extent_.min.y || p.y > extent_.max.y) g.y = 0.0;
    gradient = g;
    return h;
}

}  // namespace lacet
