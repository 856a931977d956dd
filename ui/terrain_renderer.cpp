#include "ui/terrain_renderer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

namespace lacet::ui {
namespace {

const char* kTerrainVertex = R"(#version 410 core
layout(location = 0) in vec3 aGrid;  // i, j, 1 on the skirt
uniform mat4 uViewProj;
uniform vec3 uOrigin;       // the leaf's lower-left corner, camera-relative (z: minus the camera's)
uniform float uSize;        // leaf size (m)
uniform float uN;           // grid cells per side
uniform vec4 uElev;         // elevation texture coordinates: xy + f * zw, f in [0, 1]^2 over the leaf
uniform vec2 uElevTexel;    // one elevation sample in texture coordinates
uniform float uElevDelta;   // metres between elevation samples of the tile used
uniform vec4 uApp;          // appearance texture coordinates, likewise
uniform float uMorph;       // K times the leaf size; 0: no morphing
uniform vec2 uMorphBand;    // ViewParams' morphStart, morphWidth (in units of uMorph)
uniform float uViewerHeight;
uniform float uSkirt;
uniform sampler2D uElevTex;
out vec2 vApp;
out vec3 vNormal;
out vec3 vView;
void main() {
    vec2 f = aGrid.xy / uN;
    vec2 xy = uOrigin.xy + f * uSize;
    vec2 tc = uElev.xy + f * uElev.zw;
    vec2 z = texture(uElevTex, tc).rg;
    float h = z.x;
    if (uMorph > 0.0) {
        // The K rule's distance; 1 at twice K times the size, where the parent's level begins.
        float d = sqrt(dot(xy, xy) + uViewerHeight * uViewerHeight);
        h = mix(z.x, z.y, clamp((d / uMorph - uMorphBand.x) / uMorphBand.y, 0.0, 1.0));
    }
    float hx = texture(uElevTex, tc + vec2(uElevTexel.x, 0.0)).r - texture(uElevTex, tc - vec2(uElevTexel.x, 0.0)).r;
    float hy = texture(uElevTex, tc + vec2(0.0, uElevTexel.y)).r - texture(uElevTex, tc - vec2(0.0, uElevTexel.y)).r;
    vNormal = vec3(-hx, -hy, 2.0 * uElevDelta);
    if (aGrid.z > 0.5) h -= uSkirt;
    vec3 p = vec3(xy, h + uOrigin.z);
    vView = -p;
    vApp = uApp.xy + f * uApp.zw;
    gl_Position = uViewProj * vec4(p, 1.0);
}
)";

const char* kTerrainFragment = R"(#version 410 core
in vec2 vApp;
in vec3 vNormal;
in vec3 vView;
uniform sampler2D uAppTex;
uniform vec3 uSun;
uniform int uWater;
out vec4 oColor;
void main() {
    vec4 c = texture(uAppTex, vApp);
    vec3 n = normalize(vNormal);
    vec3 colour = c.rgb * (0.4 + 0.6 * max(dot(n, uSun), 0.0));  // Lambert
    if (uWater != 0 && c.a > 0.0) {
        // Fresnel (Schlick, water n = 1.33) between the water's own colour and the sky.
        vec3 v = normalize(vView);
        float cosT = max(v.z, 0.0);
        float F = 0.02 + 0.98 * pow(1.0 - cosT, 5.0);
        vec3 sky = mix(vec3(0.78, 0.86, 0.95), vec3(0.36, 0.56, 0.86), cosT);
        vec3 r = reflect(-v, vec3(0.0, 0.0, 1.0));
        float spec = pow(max(dot(r, uSun), 0.0), 300.0);
        vec3 water = mix(c.rgb * (0.4 + 0.6 * uSun.z), sky, F) + vec3(spec);
        colour = mix(colour, water, c.a);
    }
    oColor = vec4(colour, 1.0);
}
)";

}  // namespace

TerrainRenderer::TerrainRenderer() : program_("terrain", kTerrainVertex, kTerrainFragment) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenBuffers(1, &ibo_);
}

TerrainRenderer::~TerrainRenderer() {
    reset();
    glDeleteBuffers(1, &ibo_);
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void TerrainRenderer::reset() {
    for (auto& [key, t] : gpu_) {
        glDeleteTextures(1, &t.elevation);
        glDeleteTextures(1, &t.appearance);
    }
    gpu_.clear();
}

void TerrainRenderer::buildGrid(int n) {
    // (n + 1)^2 top vertices, then the 4n skirt vertices below the border ring.
    std::vector<float> v;
    auto vertex = [&](int i, int j, int skirt) { v.insert(v.end(), {float(i), float(j), float(skirt)}); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) vertex(i, j, 0);
    auto top = [&](int i, int j) { return GLuint(j * (n + 1) + i); };
    std::vector<GLuint> idx;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            idx.insert(idx.end(), {top(i, j), top(i + 1, j), top(i + 1, j + 1)});
            idx.insert(idx.end(), {top(i, j), top(i + 1, j + 1), top(i, j + 1)});
        }
    // The border ring, counter-clockwise, and a skirt vertex under each of its vertices.
    std::vector<std::pair<int, int>> ring;
    for (int i = 0; i < n; ++i) ring.push_back({i, 0});
    for (int j = 0; j < n; ++j) ring.push_back({n, j});
    for (int i = n; i > 0; --i) ring.push_back({i, n});
    for (int j = n; j > 0; --j) ring.push_back({0, j});
    const GLuint first = GLuint((n + 1) * (n + 1));
    for (const auto& [i, j] : ring) vertex(i, j, 1);
    const GLuint m = GLuint(ring.size());
    for (GLuint k = 0; k < m; ++k) {
        const GLuint a = top(ring[k].first, ring[k].second), b = top(ring[(k + 1) % m].first, ring[(k + 1) % m].second);
        const GLuint sa = first + k, sb = first + (k + 1) % m;
        idx.insert(idx.end(), {a, sa, sb, a, sb, b});
    }
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * sizeof(GLuint)), idx.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindVertexArray(0);
    indexCount_ = GLsizei(idx.size());
    gridN_ = n;
}

const TerrainRenderer::GpuTile* TerrainRenderer::upload(const QuadKey& key, const CachedTile& tile) {
    GpuTile& g = gpu_[key];
    g.lastFrame = frame_;
    if (g.elevation && g.version == tile.version) return &g;
    if (!g.elevation) {
        glGenTextures(1, &g.elevation);
        glGenTextures(1, &g.appearance);
    }
    g.version = tile.version;
    ++stats_.uploads;
    const ElevationTile& e = tile.elevation;
    std::vector<float> rg(e.zm.size() * 2);
    g.zmin = 1e30f, g.zmax = -1e30f;
    for (std::size_t k = 0; k < e.zm.size(); ++k) {
        rg[2 * k] = e.zm[k], rg[2 * k + 1] = e.zc[k];
        g.zmin = std::min({g.zmin, e.zm[k], e.zc[k]});
        g.zmax = std::max({g.zmax, e.zm[k], e.zc[k]});
    }
    glBindTexture(GL_TEXTURE_2D, g.elevation);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RG32F, e.stride, e.stride, 0, GL_RG, GL_FLOAT, rg.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    const AppearanceTile& a = tile.appearance;
    const std::vector<std::uint8_t> texels = tile.texels();
    g.water = false;
    for (std::size_t k = 3; k < texels.size() && !g.water; k += 4) g.water = texels[k] > 0;
    glBindTexture(GL_TEXTURE_2D, g.appearance);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, a.stride, a.stride, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return &g;
}

void TerrainRenderer::draw(const EditSession& session, const TerrainView& view) {
    stats_ = {};
    ++frame_;
    const Camera& cam = *view.camera;
    const glm::dvec3 eye = cam.position();
    const double aspect = double(view.width) / double(view.height);
    const Frustum frustum = cam.frustum(aspect, view.clip);
    const glm::dmat4 viewProj = cam.projection(aspect, view.clip) * cam.view();
    const DrawPlan& plan = session.plan();
    const int n = plan.gridCells;
    if (n > 0 && n != gridN_) buildGrid(n);  // an empty plan (no frame yet) draws nothing

    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(glm::mat4(viewProj)));
    glUniform1f(program_.uniform("uN"), float(n));
    glUniform1f(program_.uniform("uViewerHeight"), float(view.heightAboveGround));
    const ViewParams& vp = session.params().view;
    glUniform2f(program_.uniform("uMorphBand"), float(vp.morphStart), float(vp.morphWidth));
    glUniform3fv(program_.uniform("uSun"), 1, glm::value_ptr(glm::normalize(sun)));
    glUniform1i(program_.uniform("uElevTex"), 0);
    glUniform1i(program_.uniform("uAppTex"), 1);
    glBindVertexArray(vao_);
    glEnable(GL_DEPTH_TEST);
    glPolygonMode(GL_FRONT_AND_BACK, wireframe ? GL_LINE : GL_FILL);

    // The session's plan: every leaf with the tile that stands for it (editor/draw_plan.h).
    stats_.culled = plan.culled;
    stats_.missing = plan.missing;
    for (const DrawItem& item : plan.items) {
        if (!item.drawn()) continue;
        const GpuTile* g = upload(item.tileKey, *item.tile);
        const double size = item.bounds.size().x;
        // The box the leaf's surface and skirt fill, from its tile's heights: what is outside the
        // frustum is not sent to the GPU (it would not change a pixel).
        const glm::dvec3 lo(item.bounds.min.x - eye.x, item.bounds.min.y - eye.y, double(g->zmin) - item.skirt - eye.z);
        const glm::dvec3 hi(item.bounds.max.x - eye.x, item.bounds.max.y - eye.y, double(g->zmax) - eye.z);
        if (!frustum.mayIntersect(lo, hi)) {
            ++stats_.culled;
            continue;
        }
        ++stats_.drawn;
        stats_.fallback += !item.ownTile();
        const ElevationTile& e = item.tile->elevation;
        const AppearanceTile& a = item.tile->appearance;
        const glm::dvec2 eo = (item.bounds.min - e.bounds.min) / e.delta;
        const double es = size / e.delta, st = double(e.stride);
        glUniform4f(program_.uniform("uElev"), float((e.border + 0.5 + eo.x) / st), float((e.border + 0.5 + eo.y) / st),
                    float(es / st), float(es / st));
        glUniform2f(program_.uniform("uElevTexel"), float(1.0 / st), float(1.0 / st));
        glUniform1f(program_.uniform("uElevDelta"), float(e.delta));
        const glm::dvec2 ao = (item.bounds.min - a.bounds.min) / a.delta;
        const double as = size / a.delta, ast = double(a.stride);
        glUniform4f(program_.uniform("uApp"), float((a.border + ao.x) / ast), float((a.border + ao.y) / ast), float(as / ast),
                    float(as / ast));
        glUniform3f(program_.uniform("uOrigin"), float(lo.x), float(lo.y), float(-eye.z));
        glUniform1f(program_.uniform("uSize"), float(size));
        // A leaf drawn with its own tile geomorphs towards its parent's heights (the K rule);
        // with an ancestor's it shows that surface as it is.
        glUniform1f(program_.uniform("uMorph"), item.ownTile() ? float(vp.K * size) : 0.0f);
        glUniform1f(program_.uniform("uSkirt"), float(item.skirt));
        glUniform1i(program_.uniform("uWater"), g->water ? 1 : 0);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, g->elevation);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, g->appearance);
        glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0);

    // Release the GPU copies of tiles the session dropped and of tiles not drawn for a while.
    for (auto it = gpu_.begin(); it != gpu_.end();) {
        if (!session.tile(it->first) || frame_ - it->second.lastFrame > 600) {
            glDeleteTextures(1, &it->second.elevation);
            glDeleteTextures(1, &it->second.appearance);
            it = gpu_.erase(it);
        } else {
            ++it;
        }
    }
    stats_.gpuTiles = gpu_.size();
}

}  // namespace lacet::ui
