// `tridex replay` trusts nothing a recording says: settings out of range are refused naming the field, even in a
// recording whose checksum is valid, and a workpiece mesh that changed since the recording is refused instead of
// being replayed into a different model.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands/demo/demo.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/session/batch/session.hpp"
#include "core/error.hpp"
#include "devices/recording.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string refusal(const std::string& recording, const fs::path& out) {
    OutputOptions o;
    o.out = out.string();
    o.width = 32;
    o.height = 32;
    try {
        run_replay(recording, o, SculptOptions{true, false, false, false, ""});
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(ReplayTrust, RefusesOutOfRangeSettingsAndAChangedMesh) {
    const fs::path dir = test::temp_dir("replay_trust");
    const char* assets = std::getenv("TRIDEX_ASSETS");
    const fs::path mesh = dir / "bunny.off";
    fs::copy_file(fs::path(assets ? assets : "assets") / "bunny.off", mesh);

    DemoOptions d;
    d.mesh = mesh.string();
    d.resolution = 32;
    d.seconds = 0.5;
    d.width = d.height = 32;
    d.out = (dir / "demo").string();
    d.record = (dir / "demo.trdx").string();
    d.cpu = true;
    run_demo(d);
    EXPECT_EQ(refusal(d.record, dir / "ok"), "");  // the untouched recording replays

    // Settings a demo would refuse, in a recording with a valid checksum (rewritten by the writer).
    const devices::Recording rec = devices::read_recording(d.record);
    auto tampered = [&](const char* field, const nlohmann::json& value) {
        devices::Recording r = rec;
        nlohmann::json notes = nlohmann::json::parse(r.header.notes);
        if (std::string(field) == "tool.radius_m")
            notes["tool"]["radius_m"] = value;
        else
            notes[field] = value;
        r.header.notes = notes.dump();
        const std::string path = (dir / "tampered.trdx").string();
        devices::write_recording(path, r);
        return refusal(path, dir / "bad");
    };
    const std::string radius = tampered("tool.radius_m", 10.0);
    EXPECT_NE(radius.find("settings field 'tool.radius_m'"), std::string::npos) << radius;
    const std::string stock = tampered("stock_m", 1e308);
    EXPECT_NE(stock.find("settings field 'stock_m'"), std::string::npos) << stock;
    const std::string res = tampered("resolution", 100000);
    EXPECT_NE(res.find("settings field 'resolution'"), std::string::npos) << res;
    const std::string period = tampered("period_s", 0.0);
    EXPECT_NE(period.find("settings field 'period_s'"), std::string::npos) << period;

    // A tick whose tool no session of these settings takes (only the mouse's [ ] keys resize it, 1.25^6 at most),
    // and one whose material is past the palette: refused naming the file and the tick.
    auto tampered_tick = [&](void (*spoil)(devices::RecordedTick&)) {
        devices::Recording r = rec;
        for (devices::RecordedTick& t : r.ticks)
            if (t.valid == 1 && t.tool.radius_m > 0.0) {
                spoil(t);
                break;
            }
        const std::string path = (dir / "tampered_tick.trdx").string();
        devices::write_recording(path, r);
        return refusal(path, dir / "bad");
    };
    const std::string huge = tampered_tick([](devices::RecordedTick& t) { t.tool.radius_m = 5.0; });
    EXPECT_NE(huge.find("tampered_tick.trdx: tick "), std::string::npos) << huge;
    EXPECT_NE(huge.find("tool.radius_m = 5 m is outside what the session's tool takes"), std::string::npos) << huge;
    const std::string resized = tampered_tick([](devices::RecordedTick& t) { t.tool.radius_m *= 3.8; });
    EXPECT_EQ(resized, "");  // within what the [ ] keys reach: replays
    // A material past the palette: the tick check that reading runs refuses it (the writer runs the same check).
    devices::Recording bad_material = rec;
    bad_material.ticks.front().material = 250;
    try {
        devices::write_recording((dir / "material.trdx").string(), bad_material);
        ADD_FAILURE() << "a tick with material 250 was written";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tick 0: material = 250 is not a material id (0..7)"), std::string::npos)
            << e.what();
    }

    // The same mesh file with one byte more: refused, the recording named.
    std::ofstream(mesh, std::ios::app) << "\n";
    const std::string changed = refusal(d.record, dir / "changed");
    EXPECT_NE(changed.find("changed since the recording"), std::string::npos) << changed;
    EXPECT_NE(changed.find(d.record), std::string::npos) << changed;
}

}  // namespace
}  // namespace tridex::app
