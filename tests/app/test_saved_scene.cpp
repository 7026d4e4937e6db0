// The scene of a saved session: the saved model as its workpiece, its reference objects with their turns, no scripts,
// other paths made absolute; read back, it places every reference where the session had it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "cube_off.hpp"
#include "app/scene/reference_objects.hpp"
#include "app/scene/saved_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(SavedScene, HoldsTheModelAndEveryReferenceAndReadsBackToTheSamePlaces) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-saved-scene";
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::write_cube_off(dir / "cube.off");
    const json refs = json::parse(R"([{"name": "a", "mesh": "cube.off", "size_m": 0.05, "position_m": [0.1, 0, 0],
                                       "axis": [1, 2, 3], "angle_deg": -250, "colour": [0.1, 0.2, 0.3, 0.5]},
                                      {"name": "b", "mesh": "cube.off", "grid_cell_m": 0.002}])");
    SessionSpec spec;
    spec.references = references_from_scene_json(refs, "scene.json", dir.string());
    const json scene = json::parse(R"({"workpiece": {"mesh": "bunny.off", "resolution": 64}, "stroke": {"duration_s": 2},
                                       "keys": [], "tool": {"shape": "mesh", "mesh": "tools/spatula.off"},
                                       "display": "desktop"})");
    const std::string model = (dir / "out" / "carved.tdx").string();
    EXPECT_EQ(saved_scene_path(model), (dir / "out" / "carved.scene.json").string());
    const json saved = saved_scene_json(scene, dir.string(), model, spec);
    EXPECT_EQ(saved["workpiece"], json({{"model", "carved.tdx"}}));
    EXPECT_EQ(saved["stroke"], "none");
    EXPECT_FALSE(saved.contains("keys"));
    EXPECT_EQ(saved["display"], "desktop");
    EXPECT_EQ(saved["tool"]["mesh"], (dir / "tools" / "spatula.off").lexically_normal().string());
    ASSERT_EQ(saved["references"].size(), 2u);
    const std::vector<ReferenceSpec> back = references_from_scene_json(saved["references"], "saved", "/nowhere");
    ASSERT_EQ(back.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const ReferenceSpec &a = spec.references[i], &b = back[i];
        EXPECT_EQ(b.name, a.name);
        EXPECT_EQ(b.mesh_path, a.mesh_path);
        EXPECT_EQ(b.mesh_crc32, a.mesh_crc32);
        EXPECT_EQ(b.size_m, a.size_m);
        EXPECT_EQ(b.position_m, a.position_m);
        EXPECT_EQ(b.grid_cell_m, a.grid_cell_m);
        EXPECT_EQ(b.colour, a.colour);
        EXPECT_EQ(b.alpha, a.alpha);
        // The same turn (a quaternion and its negative are one turn).
        EXPECT_NEAR(std::abs(glm::dot(b.orientation, a.orientation)), 1.0, 1e-12) << i;
    }
}

}  // namespace
}  // namespace tridex::app
