// The session's object meshes (§5.3): made with each quad's elevation tile, carried by the draw
// plan once per tile, and remade exactly when the tile is (an edit elsewhere leaves them).
#include "editor/edit_session.h"

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace lacet {
namespace {

constexpr LayerId kRoads = 0, kRivers = 1;
constexpr double kSide = 2048.0;

ElementId addCurve(Scene& s, LayerId l, std::vector<Vertex> v, float w, float wf, std::uint16_t cls, std::uint16_t flags = 0) {
    Layer& L = s.layers[l];
    Curve c;
    c.vertices = std::move(v);
    c.start = L.addNode(c.vertices.front().p);
    c.end = L.addNode(c.vertices.back().p);
    c.w = w, c.wf = wf, c.cls = cls, c.flags = flags;
    return L.addCurve(c);
}

SceneDocument document() {
    SceneDocument d;
    d.scene.extent = {Vec2(0.0), Vec2(kSide)};
    d.scene.layers.resize(2);
    d.scene.layers[kRoads].name = "roads";
    d.scene.layers[kRoads].kind = LayerKind::Roads;
    d.scene.layers[kRivers].name = "rivers";
    d.scene.layers[kRivers].kind = LayerKind::Rivers;
    addCurve(d.scene, kRivers, {{{8.0, 1024.0}}, {{kSide - 8.0, 1024.0}}}, 20.0f, 36.0f, 0);
    // Road 0 crosses the river (a bridge); road 1, an alley, runs far from it.
    addCurve(d.scene, kRoads, {{{1030.0, 700.0}}, {{1000.0, 1000.0}, false}, {{1018.0, 1350.0}}}, 6.0f, 12.0f, 0);
    addCurve(d.scene, kRoads, {{{100.0, 200.0}}, {{900.0, 350.0}, false}, {{1900.0, 260.0}}}, 5.0f, 10.0f, 1);
    const int n = 129;
    std::vector<float> z(std::size_t(n) * std::size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) z[std::size_t(j * n + i)] = float(150.0 + 0.06 * std::abs((j + 0.5) * kSide / n - 1024.0));
    d.dem.emplace(Box{Vec2(0.0), Vec2(kSide)}, n, n, std::move(z));
    return d;
}

// The cached tiles holding a bridge deck / trees.
std::set<QuadKey> tilesWith(const EditSession& s, ObjectKind kind) {
    std::set<QuadKey> out;
    for (const auto& [key, t] : s.tiles())
        for (const ObjectPart& p : t.objects.parts)
            if (p.kind == kind) out.insert(key);
    return out;
}

TEST(EditSessionObjects, MadeWithTheTilesDrawnOnceRemadeWhereAnEditTouched) {
    EditSession s(document());
    const glm::dvec3 viewer(1024.0, 1024.0, 400.0);
    s.frame(viewer, 0.0);
    const std::set<QuadKey> decks = tilesWith(s, ObjectKind::Deck);
    ASSERT_FALSE(decks.empty()) << "no bridge mesh in any tile";
    EXPECT_FALSE(tilesWith(s, ObjectKind::Tree).empty());
    EXPECT_GE(s.objectCounters().bridges, decks.size());
    EXPECT_EQ(s.params().objects.deckThickness, s.params().graph.deckThickness);

    // The plan carries each tile's objects once, on a drawn item of that tile.
    std::set<QuadKey> carried;
    for (const DrawItem& item : s.plan().items) {
        if (!item.objects) continue;
        EXPECT_TRUE(item.drawn());
        EXPECT_EQ(item.objects, &item.tile->objects);
        EXPECT_TRUE(carried.insert(item.tileKey).second);
    }
    EXPECT_FALSE(carried.empty());

    // Moving the alley far from the bridge leaves the bridge's tiles as they were.
    std::map<QuadKey, std::uint64_t> versions;
    for (const QuadKey& k : decks) versions[k] = s.tile(k)->version;
    const std::size_t bridgesBefore = s.objectCounters().bridges;
    s.execute(MoveVertexCmd{kRoads, 1, 1, {900.0, 330.0}});
    for (const QuadKey& k : decks) EXPECT_FALSE(s.tile(k)->dirty);
    s.frame(viewer, 0.0);
    for (const QuadKey& k : decks) {
        ASSERT_NE(s.tile(k), nullptr);
        EXPECT_EQ(s.tile(k)->version, versions[k]);
    }
    EXPECT_EQ(s.objectCounters().bridges, bridgesBefore);

    // Moving the bridged road remakes them.
    s.execute(MoveVertexCmd{kRoads, 0, 1, {1010.0, 1000.0}});
    for (const QuadKey& k : decks) EXPECT_TRUE(s.tile(k)->dirty);
    s.frame(viewer, 0.0);
    EXPECT_GT(s.objectCounters().bridges, bridgesBefore);
    EXPECT_FALSE(tilesWith(s, ObjectKind::Deck).empty());
}

}  // namespace
}  // namespace lacet
