// saveSceneStreamed (io/scene_file.h): a scene written a layer part at a time is the file saveScene
// writes for the whole scene, row for row, and a bad part leaves the previous file.
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// Every table and schema entry of the file, rows in order of their first column; gpkg_contents
// without its last_change time.
std::string dumpFile(const std::string& path) {
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    std::string out;
    std::vector<std::string> tables;
    {
        auto s = db.prepare("SELECT type, name, coalesce(sql, '') FROM sqlite_master WHERE name NOT LIKE 'sqlite_%' ORDER BY type, name");
        while (s.step()) {
            out += s.text(0) + " " + s.text(1) + ": " + s.text(2) + "\n";
            if (s.text(0) == "table") tables.push_back(s.text(1));
        }
    }
    for (const std::string& table : tables) {
        const bool contents = table == "gpkg_contents";
        const std::string columns =
            contents ? "table_name, data_type, identifier, description, min_x, min_y, max_x, max_y, srs_id" : "*";
        auto n = db.prepare("SELECT count(*) FROM pragma_table_info(?)");
        n.bindText(1, table);
        n.step();
        const int count = contents ? 9 : int(n.integer(0));
        auto s = db.prepare("SELECT " + columns + " FROM \"" + table + "\" ORDER BY 1");
        out += "== " + table + "\n";
        while (s.step()) {
            for (int c = 0; c < count; ++c) {
                if (s.type(c) == SQLITE_BLOB) {
                    const auto blob = s.blob(c);
                    out += "blob:" + std::string(blob.begin(), blob.end());
                } else {
                    out += s.text(c);
                }
                out += "|";
            }
            out += "\n";
        }
    }
    return out;
}

struct Synthetic {
    SceneDocument whole;  // makeSyntheticScene
    SceneDocument head;   // the same without its fields
};

Synthetic synthetic(std::uint64_t seed, std::size_t curves) {
    Synthetic s;
    s.whole.scene = makeSyntheticScene({seed, curves});
    s.head.scene = SyntheticSceneParts({seed, curves}).takeScene();
    return s;
}

TEST(SceneStreamedSave, EqualsTheSaveOfTheWholeSceneRowForRow) {
    const fs::path dir = test::scratchDir("streamed");
    for (const std::uint64_t seed : {1u, 5u})
        for (const std::size_t partCurves : {std::size_t(1), std::size_t(300), std::size_t(100000)}) {
            SCOPED_TRACE("seed " + std::to_string(seed) + ", parts of " + std::to_string(partCurves) + " curves");
            const Synthetic s = synthetic(seed, 4000);
            const std::string whole = (dir / "whole.gpkg").string(), streamed = (dir / "streamed.gpkg").string();
            saveScene(whole, s.whole);
            std::size_t parts = 0;
            SyntheticSceneParts gen({seed, 4000});
            saveSceneStreamed(streamed, s.head, kFieldsLayer, [&](const std::function<void(Layer&&)>& sink) {
                gen.fields([&](Layer&& part) {
                    ++parts;
                    sink(std::move(part));
                }, partCurves);
            });
            EXPECT_GT(parts, partCurves < 1000 ? 5u : 0u);
            const std::string a = dumpFile(whole), b = dumpFile(streamed);
            EXPECT_GT(a.size(), 100000u);
            EXPECT_TRUE(a == b) << "the streamed file's tables differ from saveScene's";
            const SceneDocument back = loadScene(streamed);  // checksum checked
            EXPECT_EQ(sceneChecksumText(back), sceneChecksumText(s.whole));
            EXPECT_EQ(back.scene.layers[kFieldsLayer].curves.size(), s.whole.scene.layers[kFieldsLayer].curves.size());
        }
}

TEST(SceneStreamedSave, HeadElementsOfTheStreamedLayerComeFirst) {
    // Half the fields in the head, the rest streamed: the file holds the whole layer, in id order.
    const fs::path dir = test::scratchDir("streamed");
    Synthetic s = synthetic(2, 3000);
    std::vector<Layer> parts;
    SyntheticSceneParts({2, 3000}).fields([&](Layer&& part) { parts.push_back(std::move(part)); }, 200);
    ASSERT_GT(parts.size(), 4u);
    for (std::size_t i = 0; i < parts.size() / 2; ++i) appendLayerPart(s.head.scene.layers[kFieldsLayer], std::move(parts[i]));
    const std::string path = (dir / "half.gpkg").string();
    saveSceneStreamed(path, s.head, kFieldsLayer, [&](const std::function<void(Layer&&)>& sink) {
        for (std::size_t i = parts.size() / 2; i < parts.size(); ++i) sink(std::move(parts[i]));
    });
    saveScene((dir / "whole.gpkg").string(), s.whole);
    EXPECT_TRUE(dumpFile(path) == dumpFile((dir / "whole.gpkg").string()));
}

TEST(SceneStreamedSave, ABadPartOrAFailingProducerLeavesThePreviousFile) {
    const fs::path dir = test::scratchDir("streamed");
    const Synthetic s = synthetic(3, 2000);
    const std::string path = (dir / "scene.gpkg").string();
    saveScene(path, s.whole);
    const std::string before = dumpFile(path);
    const auto refused = [&](const std::function<void(const std::function<void(Layer&&)>&)>& produce, const std::string& reason) {
        try {
            saveSceneStreamed(path, s.head, kFieldsLayer, produce);
            ADD_FAILURE() << "saved; expected '" << reason << "'";
        } catch (const SceneFileError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path), std::string::npos) << what;
            EXPECT_NE(what.find(reason), std::string::npos) << what;
        }
        EXPECT_TRUE(dumpFile(path) == before) << reason;
        EXPECT_FALSE(fs::exists(path + ".tmp")) << reason;
    };
    const auto partsWith = [&](const std::function<void(std::size_t, Layer&)>& spoil) {
        return [spoil](const std::function<void(Layer&&)>& sink) {
            std::size_t i = 0;
            SyntheticSceneParts({3, 2000}).fields([&](Layer&& part) {
                spoil(i++, part);
                sink(std::move(part));
            }, 100);
        };
    };
    // A curve of the second part ending at a node the part does not hold.
    refused(partsWith([](std::size_t i, Layer& p) {
                if (i == 1) p.curves.front().end = ElementId(p.nodes.size() + 3);
            }),
            "part 1 of layer 3 is invalid");
    // A NaN position.
    refused(partsWith([](std::size_t i, Layer& p) {
                if (i == 2) p.nodes.front().p.x = std::nan("");
            }),
            "part 2 of layer 3 is invalid");
    // A loose curve (bordering no area) where the plan has no table of lines.
    refused(partsWith([](std::size_t i, Layer& p) {
                if (i != 0) return;
                Curve c = p.curves.front();
                c.areas.clear();
                p.addCurve(std::move(c));
            }),
            "feature tables were planned without them");
    refused([](const std::function<void(Layer&&)>&) { throw std::runtime_error("the source went away"); },
            "the source went away");
    // A layer that does not exist.
    try {
        saveSceneStreamed(path, s.head, LayerId(9), [](const std::function<void(Layer&&)>&) {});
        ADD_FAILURE() << "saved into layer 9";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find("layer 9 does not exist"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(dumpFile(path) == before);
}

}  // namespace
}  // namespace lacet
