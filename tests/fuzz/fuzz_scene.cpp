// tests/fuzz/fuzz_scene.cpp - libFuzzer target: load_run_scene on a scene file (JSON, every field checked; the
// display block through display_config_from_json). A refusal may name the file a scene refers to (a study scene
// beside it) instead of the scene itself: it must name a file in the scene's folder.
#include <cstdint>
#include <filesystem>

#include "app/scene/run_scene.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of a scene file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = tridex::fuzz::input_file("fuzz_scene.json", data, size);
    const std::string folder = std::filesystem::path(path).parent_path().string();
    tridex::fuzz::expect_clean(folder, [&] { tridex::app::load_run_scene(path); });
    return 0;
}
