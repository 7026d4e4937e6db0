// The module include rule of ../shared/DESIGN.md ("Includes point one way"), checked on every source file
// of the module folders and their sub-folders (compute/contour/, renderer/stereo/, ...; a file's module is
// its top-level folder): an `#include "module/..."` the rule does not allow fails with file:line and the rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include "../test_paths.hpp"
#include "tests/layout/include_rules.hpp"

namespace tridex::layout {
namespace {

namespace fs = std::filesystem;

// The module folders scanned (DESIGN.md's top-level folders that hold code). bench/, when present, may
// include what app/ may.
const std::vector<std::string> kModuleFolders = {"core",     "gpu",     "devices", "haptics", "compute",
                                                 "renderer", "shaders", "app",     "bench"};

// Current breaks of the rule as written, kept so the test passes until the design or the code changes.
// Each entry: file, included module, why. An entry that no longer occurs fails the test (remove it).
struct Allowed {
    const char* file;
    const char* module;
    const char* why;
};
// None today: `tridex bench` registers itself from bench/ (bench/bench_command.cpp), so app/ includes no bench/ header.
const std::vector<Allowed> kAllowList = {};

IncludeRules rules_for_tree() {
    IncludeRules r = load_rules(TRIDEX_DESIGN_MD);
    // bench/ sits above app/ (`bench -> app -> ...`): it may include app/ and what app/ may. DESIGN.md's
    // module table names bench/ but its include paragraph does not, so that edge is encoded here.
    r.may["bench"] = r.may["app"];
    r.may["bench"].insert("app");
    r.never["bench"] = r.never["app"];
    r.modules.insert("bench");
    // core/ includes nothing but itself and its third-party vocabulary (GLM): no Vulkan, volk or GLFW
    // either (core/CMakeLists.txt: "no Vulkan, no GLFW").
    r.no_vulkan.insert("core");
    return r;
}

bool is_source(const fs::path& p) {
    static const std::set<std::string> ext = {".cpp",  ".hpp",  ".h",    ".cc",   ".inc",
                                              ".glsl", ".comp", ".vert", ".frag", ".geom"};
    return ext.count(p.extension().string()) > 0;
}

std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const std::set<std::string> kModules(kModuleFolders.begin(), kModuleFolders.end());

struct SourceFile {
    fs::path path;
    std::string rel;     ///< relative to the source root, e.g. "compute/contour/contour_dual.cpp"
    std::string module;  ///< its top-level folder, e.g. "compute"
};

/// Every source file under the module folders of `root`, sub-folders included, sorted by path.
std::vector<SourceFile> sources_under(const fs::path& root) {
    std::vector<SourceFile> out;
    for (const auto& module : kModuleFolders) {
        if (!fs::is_directory(root / module)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root / module)) {
            if (!e.is_regular_file() || !is_source(e.path())) continue;
            out.push_back({e.path(), fs::relative(e.path(), root).generic_string(), module});
        }
    }
    std::sort(out.begin(), out.end(), [](const SourceFile& a, const SourceFile& b) { return a.rel < b.rel; });
    return out;
}

/// The rule's violations in every source file under `root` (`files`: how many were read).
std::vector<Violation> check_tree(const IncludeRules& r, const fs::path& root, int& files) {
    std::vector<Violation> out;
    for (const auto& f : sources_under(root)) {
        ++files;
        for (auto& v : check_source(r, f.module, f.rel, read(f.path), kModules)) out.push_back(std::move(v));
    }
    return out;
}

TEST(LayoutRule, ParsedFromTheDesignText) {
    const IncludeRules r = load_rules(TRIDEX_DESIGN_MD);
    std::cout << "include rule from: " << r.source << "\n" << r.rule_text << "\n";
    RecordProperty("rule_source", r.source);
    // The rule as written: app -> {renderer, compute, haptics, devices} -> {gpu, core};
    // haptics -> devices -> core; haptics and devices never include gpu/ or Vulkan headers.
    EXPECT_TRUE(r.allows("app", "renderer"));
    EXPECT_TRUE(r.allows("app", "gpu"));
    EXPECT_TRUE(r.allows("app", "core"));
    EXPECT_TRUE(r.allows("compute", "gpu"));
    EXPECT_TRUE(r.allows("renderer", "gpu"));
    EXPECT_TRUE(r.allows("haptics", "devices"));
    EXPECT_TRUE(r.allows("devices", "core"));
    EXPECT_TRUE(r.allows("gpu", "core"));  // core/ is the vocabulary every module shares
    EXPECT_FALSE(r.allows("core", "gpu"));
    EXPECT_FALSE(r.allows("gpu", "compute"));
    EXPECT_FALSE(r.allows("renderer", "compute"));
    EXPECT_FALSE(r.allows("compute", "app"));
    EXPECT_FALSE(r.allows("devices", "haptics"));
    EXPECT_FALSE(r.allows("haptics", "gpu"));
    EXPECT_FALSE(r.allows("devices", "gpu"));
    EXPECT_TRUE(r.no_vulkan.count("haptics"));
    EXPECT_TRUE(r.no_vulkan.count("devices"));
}

TEST(LayoutRule, FallbackCopyIsUsedOnlyWhenDesignIsAbsentAndSaysSo) {
    const IncludeRules r = load_rules("/nonexistent/DESIGN.md");
    EXPECT_NE(r.source.find("fallback"), std::string::npos) << r.source;
    EXPECT_FALSE(r.allows("haptics", "gpu"));
    EXPECT_TRUE(r.allows("app", "core"));
    EXPECT_THROW(parse_rules("no rule here", "synthetic"), std::runtime_error);
}

TEST(LayoutRule, SyntheticViolatingIncludesAreRejected) {
    const IncludeRules r = rules_for_tree();
    const std::string text =
        "// haptics must not see the GPU\n"
        "#include \"core/units.hpp\"\n"
        "#include \"devices/haptic_device.hpp\"\n"
        "#include \"gpu/context.hpp\"\n"
        "#  include <vulkan/vulkan.h>\n"
        "#include \"app/session/batch/session.hpp\"\n";
    const auto v = check_source(r, "haptics", "haptics/synthetic.cpp", text, kModules);
    ASSERT_EQ(v.size(), 3u);
    EXPECT_EQ(v[0].line, 4);
    EXPECT_EQ(v[0].module, "gpu");
    EXPECT_NE(v[0].rule.find("never"), std::string::npos) << v[0].rule;
    EXPECT_EQ(v[1].line, 5);
    EXPECT_EQ(v[1].module, "vulkan");
    EXPECT_EQ(v[2].line, 6);
    EXPECT_EQ(v[2].module, "app");
    // core includes nothing else; renderer may not include compute as the rule is written.
    EXPECT_EQ(check_source(r, "core", "core/x.hpp", "#include \"gpu/context.hpp\"\n", kModules).size(), 1u);
    EXPECT_EQ(check_source(r, "core", "core/x.hpp", "#include <GLFW/glfw3.h>\n", kModules).size(), 1u);
    EXPECT_EQ(
        check_source(r, "renderer", "renderer/x.cpp", "#include \"compute/model/tridexel.hpp\"\n", kModules).size(),
        1u);
    EXPECT_TRUE(
        check_source(r, "app", "app/x.cpp", "#include \"renderer/a.hpp\"\n#include \"gpu/b.hpp\"\n", kModules).empty());
    // bench/ sits above app/: it may include app/ and below; nothing below includes bench/.
    EXPECT_TRUE(check_source(r, "bench", "bench/x.cpp", "#include \"app/stats.hpp\"\n#include \"compute/a.hpp\"\n",
                             kModules)
                    .empty());
    EXPECT_EQ(check_source(r, "app", "app/x.cpp", "#include \"bench/bench_sculpt.hpp\"\n", kModules).size(), 1u);
    EXPECT_EQ(check_source(r, "compute", "compute/x.cpp", "#include \"bench/bench_sculpt.hpp\"\n", kModules).size(),
              1u);
}

TEST(LayoutRule, FilesInSubFoldersAreCheckedAsTheirModule) {
    const IncludeRules r = rules_for_tree();
    const fs::path root = fs::path(::testing::TempDir()) / "tridex_layout_tree";
    fs::remove_all(root);
    const auto write = [&](const std::string& rel, const std::string& text) {
        fs::create_directories((root / rel).parent_path());
        std::ofstream(root / rel) << text;
    };
    write("core/units.hpp", "#pragma once\n");
    write("compute/runtime/deep/x.cpp", "#include \"core/units.hpp\"\n#include \"app/session/batch/session.hpp\"\n");
    write("renderer/stereo/y.hpp", "#include \"gpu/context.hpp\"\n#include \"compute/model/tridexel.hpp\"\n");
    write("bench/z.cpp", "#include \"app/stats.hpp\"\n");
    write("app/cli/w.cpp", "#include \"bench/z.hpp\"\n");
    write("haptics/loop/v.txt", "#include \"gpu/context.hpp\"\n");  // not a source file: not read
    int files = 0;
    const auto v = check_tree(r, root, files);
    fs::remove_all(root);
    EXPECT_EQ(files, 5);
    ASSERT_EQ(v.size(), 3u);
    EXPECT_EQ(v[0].file, "app/cli/w.cpp");
    EXPECT_EQ(v[0].module, "bench");
    EXPECT_EQ(v[1].file, "compute/runtime/deep/x.cpp");
    EXPECT_EQ(v[1].line, 2);
    EXPECT_EQ(v[1].module, "app");
    EXPECT_EQ(v[2].file, "renderer/stereo/y.hpp");
    EXPECT_EQ(v[2].line, 2);
    EXPECT_EQ(v[2].module, "compute");
}

TEST(LayoutRule, EverySourceFileFollowsTheIncludeRule) {
    const IncludeRules r = rules_for_tree();
    std::cout << "include rule from: " << r.source << "\n";
    const fs::path root = TRIDEX_SOURCE_DIR;
    std::map<std::pair<std::string, std::string>, int> allow_hits;
    for (const auto& a : kAllowList) allow_hits[{a.file, a.module}] = 0;
    int files = 0;
    for (const auto& v : check_tree(r, root, files)) {
        if (auto it = allow_hits.find({v.file, v.module}); it != allow_hits.end()) {
            ++it->second;
            std::cout << "allow-listed: " << v.file << ":" << v.line << ": #include \"" << v.included << "\" breaks "
                      << v.rule << "\n";
            continue;
        }
        ADD_FAILURE() << v.file << ":" << v.line << ": #include \"" << v.included << "\" breaks " << v.rule;
    }
    EXPECT_GT(files, 50) << "scanned too few files under " << root;
    for (const auto& [key, hits] : allow_hits)
        EXPECT_GT(hits, 0) << "allow-list entry " << key.first << " -> " << key.second
                           << " no longer occurs: remove it from tests/layout/test_layout.cpp";
}

// Includes are paths from the source root ("compute/contour/contour_dual.hpp"): one that names a module but no
// file of the tree (say, a path from before a file moved, in a header no target compiles) fails here.
TEST(LayoutRule, EveryModuleIncludeNamesAFileOfTheTree) {
    static const std::regex include_line(R"re(^\s*#\s*include\s*"([^"]+)")re");
    const fs::path root = TRIDEX_SOURCE_DIR;
    for (const auto& f : sources_under(root)) {
        std::stringstream ss(read(f.path));
        int n = 0;
        for (std::string line; std::getline(ss, line);) {
            ++n;
            std::smatch m;
            if (!std::regex_search(line, m, include_line)) continue;
            const std::string path = m[1];
            if (!kModules.count(path.substr(0, path.find('/'))) || path.find('/') == std::string::npos) continue;
            // shaders/<name>.h (SPIR-V) and shaders/spirv_table.inc are made at build time (shaders/CMakeLists.txt).
            const std::string ext = fs::path(path).extension().string();
            if (path.rfind("shaders/", 0) == 0 && (ext == ".h" || ext == ".inc")) continue;
            EXPECT_TRUE(fs::is_regular_file(root / path)) << f.rel << ":" << n << ": #include \"" << path
                                                          << "\" names no file under " << root;
        }
    }
}

}  // namespace
}  // namespace tridex::layout
