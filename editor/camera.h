#pragma once
// The editor's camera (issue: the 3D editor), with no window: orbit, pan and zoom around a target
// point, and a fly mode down to car view. Positions are doubles in scene metres; the matrices are camera-relative
// (the camera at the origin, world offsets subtracted in double before they become floats), so a
// view 10 km from the scene origin does not jitter.
//
// Angles: yaw 0 looks north (+y), increasing clockwise seen from above; pitch > 0 looks down.

#include <array>
#include <functional>
#include <optional>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace lacet {

struct Ray {
    glm::dvec3 origin, direction;  // direction has unit length
};

// The view volume as six planes (a, b, c, d with a x + b y + c z + d >= 0 inside), camera-relative.
struct Frustum {
    std::array<glm::dvec4, 6> planes;
    // Whether the camera-relative box [lo, hi] may intersect the volume (conservative).
    bool mayIntersect(glm::dvec3 lo, glm::dvec3 hi) const;
};

class Camera {
public:
    glm::dvec3 target{0.0};  // orbit centre (metres)
    double distance = 3000.0;  // from the target (metres)
    double yaw = 0.0, pitch = 0.8;  // radians
    double fovY = 0.9;  // radians
    bool fly = false;
    glm::dvec3 flyPosition{0.0};  // the position in fly mode

    glm::dvec3 position() const { return fly ? flyPosition : target - distance * forward(); }
    glm::dvec3 forward() const;
    glm::dvec3 right() const;
    glm::dvec3 up() const;

    // Near and far planes for a camera `heightAboveGround` metres above the terrain.
    static glm::dvec2 clipRange(double heightAboveGround);
    // Camera-relative view matrix (rotation only) and perspective projection.
    glm::dmat4 view() const;
    glm::dmat4 projection(double aspect, glm::dvec2 clip) const;
    Frustum frustum(double aspect, glm::dvec2 clip) const;

    // The ray through pixel (x, y) of a width x height viewport (y down, as window coordinates).
    Ray ray(double x, double y, int width, int height) const;
    // Window pixel of a world point; empty behind the camera.
    std::optional<glm::dvec2> project(glm::dvec3 world, int width, int height, glm::dvec2 clip) const;
    // World point of a window pixel and its depth-buffer value in [0, 1].
    glm::dvec3 unproject(double x, double y, double depth, int width, int height, glm::dvec2 clip) const;

    // Orbit: turn around the target; pan: move the target in the ground plane by a fraction of
    // the distance; zoom: scale the distance (at least `minDistance`).
    void orbit(double dYaw, double dPitch);
    void pan(double right, double forwardAmount);
    void zoom(double factor, double minDistance = 2.0);
    // Switches between orbit and fly mode keeping the viewpoint.
    void setFly(bool on);
    // Fly mode: move along the view direction, to the right, and up (metres).
    void move(double forwardAmount, double rightAmount, double upAmount);
};

struct Quad;
class Dem;

// The heights a frustum test should span over `dem`: its lowest and highest samples, 50 m wider
// each way (interpolation overshoot). A pass over every sample: compute it once per DEM.
glm::dvec2 frustumHeightRange(const Dem& dem);

// The session's visibility test for a camera (EditSession::frame): a quad is visible when its box,
// from `zRange.x` less half its size (below any skirt a renderer hangs) to `zRange.y`, may
// intersect the view frustum. zRange: the DEM's lowest and highest heights (metres).
std::function<bool(const Quad&)> frustumVisibility(const Camera& camera, double aspect, glm::dvec2 clip, glm::dvec2 zRange);

}  // namespace lacet
