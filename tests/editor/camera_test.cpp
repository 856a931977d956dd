// The editor's camera: projection, unprojection and rays agree; the frustum keeps what is in view
// and culls what is behind; orbit and fly mode keep the viewpoint; camera-relative matrices stay
// exact 10 km and more from the origin.
#include "editor/camera.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace lacet {
namespace {

Camera someCamera(glm::dvec3 target) {
    Camera c;
    c.target = target;
    c.distance = 350.0;
    c.yaw = 0.7;
    c.pitch = 0.5;
    return c;
}

TEST(Camera, ProjectUnprojectAndRayAgreeFarFromTheOrigin) {
    const int w = 1280, h = 800;
    for (const glm::dvec3 target : {glm::dvec3(0.0), glm::dvec3(12500.0, -48000.0, 2100.0), glm::dvec3(1.0e6, 2.0e6, 300.0)}) {
        const Camera cam = someCamera(target);
        const glm::dvec2 clip = Camera::clipRange(150.0);
        const glm::dvec3 p = target + glm::dvec3(31.0, -17.0, 4.0);
        const auto px = cam.project(p, w, h, clip);
        ASSERT_TRUE(px);
        // The ray through that pixel passes within a millimetre of the point.
        const Ray r = cam.ray(px->x, px->y, w, h);
        const glm::dvec3 v = p - r.origin;
        EXPECT_LT(glm::length(v - r.direction * glm::dot(v, r.direction)), 1e-3);
        // Its depth unprojects to the point.
        const glm::dmat4 m = cam.projection(double(w) / h, clip) * cam.view();
        const glm::dvec4 c = m * glm::dvec4(p - cam.position(), 1.0);
        const double depth = 0.5 * (c.z / c.w) + 0.5;
        EXPECT_LT(glm::length(cam.unproject(px->x, px->y, depth, w, h, clip) - p), 1e-3);
        // The target is at the centre of the view.
        const auto centre = cam.project(target, w, h, clip);
        ASSERT_TRUE(centre);
        EXPECT_NEAR(centre->x, w / 2.0 - 0.5, 1e-6);
        EXPECT_NEAR(centre->y, h / 2.0 - 0.5, 1e-6);
    }
}

TEST(Camera, TheFrustumKeepsWhatIsInViewAndCullsWhatIsBehind) {
    const Camera cam = someCamera({5000.0, 5000.0, 1000.0});
    const Frustum f = cam.frustum(1.6, Camera::clipRange(100.0));
    const glm::dvec3 ahead = cam.forward() * 200.0, behind = -cam.forward() * 200.0;
    EXPECT_TRUE(f.mayIntersect(ahead - 1.0, ahead + 1.0));
    EXPECT_FALSE(f.mayIntersect(behind - 1.0, behind + 1.0));
    // A box straddling the view direction is kept even when its corners are all outside.
    EXPECT_TRUE(f.mayIntersect(ahead - 1000.0, ahead + 1000.0));
    EXPECT_FALSE(f.mayIntersect(cam.right() * 5000.0 + ahead - 1.0, cam.right() * 5000.0 + ahead + 1.0));
}

TEST(Camera, FlyModeAndOrbitKeepTheViewpoint) {
    Camera cam = someCamera({100.0, 200.0, 50.0});
    const glm::dvec3 eye = cam.position();
    cam.setFly(true);
    EXPECT_LT(glm::length(cam.position() - eye), 1e-9);
    cam.move(10.0, 0.0, 0.0);
    EXPECT_NEAR(glm::length(cam.position() - eye), 10.0, 1e-9);
    cam.setFly(false);
    EXPECT_NEAR(glm::length(cam.position() - cam.target), cam.distance, 1e-9);
    const glm::dvec3 target = cam.target;
    cam.orbit(0.3, 0.2);
    EXPECT_LT(glm::length(cam.target - target), 1e-12);
    EXPECT_NEAR(glm::length(cam.position() - cam.target), cam.distance, 1e-9);
    cam.zoom(1e-9);
    EXPECT_GE(cam.distance, 2.0);  // never through the target
}

}  // namespace
}  // namespace lacet
