#include "editor/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "model/quadtree.h"
#include "raster/dem.h"

namespace lacet {

bool Frustum::mayIntersect(glm::dvec3 lo, glm::dvec3 hi) const {
    for (const glm::dvec4& p : planes) {
        // The box corner farthest along the plane's normal.
        const glm::dvec3 c(p.x >= 0.0 ? hi.x : lo.x, p.y >= 0.0 ? hi.y : lo.y, p.z >= 0.0 ? hi.z : lo.z);
        if (p.x * c.x + p.y * c.y + p.z * c.z + p.w < 0.0) return false;
    }
    return true;
}

glm::dvec3 Camera::forward() const {
    return {std::cos(pitch) * std::sin(yaw), std::cos(pitch) * std::cos(yaw), -std::sin(pitch)};
}

glm::dvec3 Camera::right() const { return {std::cos(yaw), -std::sin(yaw), 0.0}; }

glm::dvec3 Camera::up() const { return glm::cross(right(), forward()); }

glm::dvec2 Camera::clipRange(double heightAboveGround) {
    const double n = std::clamp(0.3 * heightAboveGround, 0.2, 500.0);
    return {n, std::max(4.0e5, 1.0e4 * n)};
}

glm::dmat4 Camera::view() const { return glm::lookAt(glm::dvec3(0.0), forward(), up()); }

glm::dmat4 Camera::projection(double aspect, glm::dvec2 clip) const {
    return glm::perspective(fovY, aspect, clip.x, clip.y);
}

Frustum Camera::frustum(double aspect, glm::dvec2 clip) const {
    // Gribb-Hartmann: the planes are sums and differences of the rows of the matrix.
    const glm::dmat4 m = projection(aspect, clip) * view();
    auto row = [&](int i) { return glm::dvec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
    Frustum f;
    f.planes = {row(3) + row(0), row(3) - row(0), row(3) + row(1), row(3) - row(1), row(3) + row(2), row(3) - row(2)};
    return f;
}

Ray Camera::ray(double x, double y, int width, int height) const {
    const double ndcX = 2.0 * (x + 0.5) / double(width) - 1.0;
    const double ndcY = 1.0 - 2.0 * (y + 0.5) / double(height);
    const double t = std::tan(0.5 * fovY);
    const double aspect = double(width) / double(height);
    const glm::dvec3 d = forward() + right() * (ndcX * t * aspect) + up() * (ndcY * t);
    return {position(), glm::normalize(d)};
}

std::optional<glm::dvec2> Camera::project(glm::dvec3 world, int width, int height, glm::dvec2 clip) const {
    const glm::dvec4 c = projection(double(width) / double(height), clip) * view() * glm::dvec4(world - position(), 1.0);
    if (c.w <= 1e-9) return std::nullopt;
    const double x = c.x / c.w, y = c.y / c.w;
    return glm::dvec2((x + 1.0) * 0.5 * double(width) - 0.5, (1.0 - y) * 0.5 * double(height) - 0.5);
}

glm::dvec3 Camera::unproject(double x, double y, double depth, int width, int height, glm::dvec2 clip) const {
    const glm::dmat4 inv = glm::inverse(projection(double(width) / double(height), clip) * view());
    const glm::dvec4 ndc(2.0 * (x + 0.5) / double(width) - 1.0, 1.0 - 2.0 * (y + 0.5) / double(height), 2.0 * depth - 1.0, 1.0);
    const glm::dvec4 p = inv * ndc;
    return position() + glm::dvec3(p) / p.w;
}

void Camera::orbit(double dYaw, double dPitch) {
    yaw = std::remainder(yaw + dYaw, 2.0 * M_PI);
    pitch = std::clamp(pitch + dPitch, fly ? -1.5 : 0.05, 1.5);
}

void Camera::pan(double rightAmount, double forwardAmount) {
    const glm::dvec3 f(std::sin(yaw), std::cos(yaw), 0.0);
    const glm::dvec3 delta = (right() * rightAmount + f * forwardAmount) * distance;
    if (fly) flyPosition += delta;
    else target += delta;
}

void Camera::zoom(double factor, double minDistance) {
    if (fly) {
        flyPosition += forward() * distance * (1.0 - factor);
        return;
    }
    distance = std::clamp(distance * factor, minDistance, 5.0e5);
}

void Camera::setFly(bool on) {
    if (on == fly) return;
    if (on) {
        flyPosition = position();
    } else {
        target = flyPosition + distance * forward();
    }
    fly = on;
}

void Camera::move(double forwardAmount, double rightAmount, double upAmount) {
    flyPosition += forward() * forwardAmount + right() * rightAmount + glm::dvec3(0.0, 0.0, upAmount);
}

glm::dvec2 frustumHeightRange(const Dem& dem) {
    const auto [lo, hi] = std::minmax_element(dem.heights().begin(), dem.heights().end());
    return {double(*lo) - 50.0, double(*hi) + 50.0};
}

std::function<bool(const Quad&)> frustumVisibility(const Camera& camera, double aspect, glm::dvec2 clip, glm::dvec2 zRange) {
    const Frustum f = camera.frustum(aspect, clip);
    const glm::dvec3 eye = camera.position();
    return [f, eye, zRange](const Quad& q) {
        const double skirt = 0.5 * q.bounds.size().x;
        return f.mayIntersect({q.bounds.min.x - eye.x, q.bounds.min.y - eye.y, zRange.x - skirt - eye.z},
                              {q.bounds.max.x - eye.x, q.bounds.max.y - eye.y, zRange.y - eye.z});
    };
}

}  // namespace lacet
