// The house rules on the source tree (label `layout`): no function over 150 lines outside tests (measured with
// universal-ctags, as the before-stop hook does), no source file over 600 lines unless its first comment says why,
// no string comparison with a driver's name outside devices/ (read the driver's capabilities instead). Each rule
// has an allow-list of today's breaches that may only shrink: an entry that no longer occurs fails the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include "../test_paths.hpp"

namespace {

namespace fs = std::filesystem;

// The source tree (read when a test runs, from ctest's environment).
fs::path source_root() { return TRIDEX_SOURCE_DIR; }
const std::vector<std::string> kCodeFolders = {"app", "bench", "compute", "renderer", "haptics", "devices", "core", "gpu"};

std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool is_source(const fs::path& p) {
    const std::string e = p.extension().string();
    return e == ".cpp" || e == ".hpp" || e == ".h" || e == ".cc";
}

// Every source file under `folders` of `root`, as paths relative to root.
std::vector<std::string> sources(const fs::path& root, const std::vector<std::string>& folders) {
    std::vector<std::string> out;
    for (const std::string& f : folders) {
        if (!fs::is_directory(root / f)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root / f))
            if (e.is_regular_file() && is_source(e.path())) out.push_back(fs::relative(e.path(), root).generic_string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

struct LongFunction {
    std::string file, name;
    int lines = 0;
};

// Functions over `limit` lines under `folders` of `root`, from universal-ctags' line and end fields.
std::vector<LongFunction> long_functions(const fs::path& root, const std::vector<std::string>& folders, int limit) {
    std::string cmd = "cd '" + root.string() + "' && ctags -R --languages=C++ --kinds-C++=f --fields=+ne -f -";
    for (const std::string& f : folders)
        if (fs::is_directory(root / f)) cmd += " " + f;
    cmd += " 2>/dev/null";
    std::vector<LongFunction> out;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) {
        ADD_FAILURE() << "cannot run ctags (universal-ctags, scripts/install-deps.sh)";
        return out;
    }
    char buf[4096];
    std::string text;
    while (std::fgets(buf, sizeof buf, pipe)) text += buf;
    const int status = pclose(pipe);
    EXPECT_EQ(status, 0) << "ctags failed: is universal-ctags installed (scripts/install-deps.sh)?";
    std::stringstream ss(text);
    for (std::string line; std::getline(ss, line);) {
        std::vector<std::string> cols;
        std::stringstream ls(line);
        for (std::string c; std::getline(ls, c, '\t');) cols.push_back(c);
        if (cols.size() < 4) continue;
        int begin = 0, end = 0;
        for (std::size_t i = 3; i < cols.size(); ++i) {
            if (cols[i].rfind("line:", 0) == 0) begin = std::stoi(cols[i].substr(5));
            if (cols[i].rfind("end:", 0) == 0) end = std::stoi(cols[i].substr(4));
        }
        if (begin > 0 && end >= begin && end - begin + 1 > limit) out.push_back({cols[1], cols[0], end - begin + 1});
    }
    return out;
}

// Today's functions over 150 lines, each to be split by step; the list may only shrink.
const std::set<std::pair<std::string, std::string>> kLongFunctionsAllowed = {};

TEST(HouseRules, LongFunctionsAreFoundInASyntheticTree) {
    const fs::path root = fs::path(::testing::TempDir()) / "tridex_house_rules_fn";
    fs::remove_all(root);
    fs::create_directories(root / "app");
    std::ofstream out(root / "app" / "x.cpp");
    out << "int short_one() { return 1; }\n\nint long_one(int a) {\n";
    for (int i = 0; i < 160; ++i) out << "    a += " << i << ";\n";
    out << "    return a;\n}\n";
    out.close();
    const std::vector<LongFunction> v = long_functions(root, {"app"}, 150);
    fs::remove_all(root);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_EQ(v[0].name, "long_one");
    EXPECT_EQ(v[0].file, "app/x.cpp");
    EXPECT_GT(v[0].lines, 150);
}

TEST(HouseRules, NoFunctionOver150LinesOutsideTests) {
    std::set<std::pair<std::string, std::string>> seen;
    for (const LongFunction& f : long_functions(source_root(), kCodeFolders, 150)) {
        if (kLongFunctionsAllowed.count({f.file, f.name})) {
            seen.insert({f.file, f.name});
            std::printf("allow-listed: %s: %s (%d lines)\n", f.file.c_str(), f.name.c_str(), f.lines);
            continue;
        }
        ADD_FAILURE() << f.file << ": " << f.name << " is " << f.lines << " lines (over 150: split it by step)";
    }
    for (const auto& a : kLongFunctionsAllowed)
        EXPECT_TRUE(seen.count(a)) << a.first << ": " << a.second
                                   << " is no longer over 150 lines: remove it from tests/layout/test_house_rules.cpp";
}

TEST(HouseRules, NoFileOver600LinesWithoutAReasonInItsFirstComment) {
    std::vector<std::string> folders = kCodeFolders;
    folders.push_back("tests");
    int checked = 0;
    for (const std::string& rel : sources(source_root(), folders)) {
        const std::string text = read(source_root() / rel);
        ++checked;
        if (std::count(text.begin(), text.end(), '\n') <= 600) continue;
        // The first comment: the leading lines that start with "//".
        std::string first;
        std::stringstream ss(text);
        for (std::string line; std::getline(ss, line) && line.rfind("//", 0) == 0;) first += line + "\n";
        EXPECT_NE(first.find("over 600 lines because"), std::string::npos)
            << rel << " is over 600 lines: split it by idea, or say why in its first comment (\"over 600 lines because "
            << "...\")";
    }
    EXPECT_GT(checked, 100);
}

// A driver's name compared as a string: `== "falcon"`, `"mouse" !=`, a "net:" prefix test.
const std::regex kDriverNameCompare(
    R"re((==|!=)\s*"(mouse|spacemouse|falcon|falcon-emulator|flystick|tracked-body|net|simulated|omni|wand|6dof|replay|gamepad)"|"(mouse|spacemouse|falcon|falcon-emulator|flystick|tracked-body|net|simulated|omni|wand|6dof|replay|gamepad)"\s*(==|!=)|(starts_with|rfind)\("net:")re");

int driver_name_compares(const std::string& text) {
    int n = 0;
    std::stringstream ss(text);
    for (std::string line; std::getline(ss, line);)
        if (std::regex_search(line, kDriverNameCompare)) ++n;
    return n;
}

// Places outside devices/ allowed to compare a driver's name (file -> lines that do): none; sessions read the
// driver's capabilities from the registry.
const std::map<std::string, int> kDriverComparesAllowed = {};

TEST(HouseRules, DriverNameComparisonsAreFoundInText) {
    EXPECT_EQ(driver_name_compares("if (driver == \"falcon\") x();\n"), 1);
    EXPECT_EQ(driver_name_compares("bool n = d.rfind(\"net:\", 0) == 0;\nif (\"mouse\" != d) y();\n"), 2);
    EXPECT_EQ(driver_name_compares("const char* name = \"falcon\";  // a name, not a comparison\n"), 0);
}

TEST(HouseRules, NoNewDriverNameComparisonOutsideDevices) {
    std::vector<std::string> folders;
    for (const std::string& f : kCodeFolders)
        if (f != "devices") folders.push_back(f);
    std::map<std::string, int> seen;
    for (const std::string& rel : sources(source_root(), folders)) {
        const int n = driver_name_compares(read(source_root() / rel));
        if (n == 0) continue;
        seen[rel] = n;
        const auto it = kDriverComparesAllowed.find(rel);
        const int allowed = it == kDriverComparesAllowed.end() ? 0 : it->second;
        EXPECT_LE(n, allowed) << rel << " compares a driver's name as a string " << n << " times (allowed " << allowed
                              << "): read the driver's capabilities from the registry (devices/registry/device_registry.hpp)";
    }
    for (const auto& [file, allowed] : kDriverComparesAllowed) {
        EXPECT_EQ(seen[file], allowed) << file << ": fewer driver-name comparisons than allowed (" << allowed
                                       << "): lower its entry in tests/layout/test_house_rules.cpp";
    }
}

// The folders (and sub-folders) whose sources include each other's headers around a loop, each loop as its folders
// sorted and joined by ", ". Found as the strongly connected components of the folder include graph.
std::set<std::string> folder_cycles(const fs::path& root, const std::vector<std::string>& folders) {
    std::map<std::string, std::set<std::string>> edges;
    static const std::regex include_line(R"re(^\s*#\s*include\s*"([^"]+)")re");
    for (const std::string& rel : sources(root, folders)) {
        const std::string from = fs::path(rel).parent_path().generic_string();
        std::stringstream ss(read(root / rel));
        for (std::string line; std::getline(ss, line);) {
            std::smatch m;
            if (!std::regex_search(line, m, include_line)) continue;
            const std::string to = fs::path(m[1].str()).parent_path().generic_string();
            if (!to.empty() && to != from && fs::is_directory(root / to)) edges[from].insert(to);
        }
    }
    // Tarjan's strongly connected components, iterative over the small graph by recursion on a lambda.
    std::map<std::string, int> index, low;
    std::vector<std::string> stack;
    std::set<std::string> on_stack, cycles;
    int next = 0;
    std::function<void(const std::string&)> visit = [&](const std::string& v) {
        index[v] = low[v] = next++;
        stack.push_back(v);
        on_stack.insert(v);
        for (const std::string& w : edges[v]) {
            if (!index.count(w)) {
                visit(w);
                low[v] = std::min(low[v], low[w]);
            } else if (on_stack.count(w)) {
                low[v] = std::min(low[v], index[w]);
            }
        }
        if (low[v] != index[v]) return;
        std::vector<std::string> component;
        for (std::string w; w != v;) {
            w = stack.back();
            stack.pop_back();
            on_stack.erase(w);
            component.push_back(w);
        }
        if (component.size() < 2) return;
        std::sort(component.begin(), component.end());
        std::string joined;
        for (const std::string& c : component) joined += (joined.empty() ? "" : ", ") + c;
        cycles.insert(joined);
    };
    std::vector<std::string> nodes;
    for (const auto& [from, tos] : edges) nodes.push_back(from);
    for (const std::string& v : nodes)
        if (!index.count(v)) visit(v);
    return cycles;
}

// Include loops between folders allowed: none (a loop is broken by moving the shared part below both). Between
// top-level modules the include rule (test_layout.cpp) is one-way too.
const std::set<std::string> kFolderCyclesAllowed = {};

TEST(HouseRules, FolderCyclesAreFoundInASyntheticTree) {
    const fs::path root = fs::path(::testing::TempDir()) / "tridex_house_rules_cycles";
    fs::remove_all(root);
    const auto write = [&](const std::string& rel, const std::string& text) {
        fs::create_directories((root / rel).parent_path());
        std::ofstream(root / rel) << text;
    };
    write("app/a.cpp", "#include \"app/study/b.hpp\"\n");
    write("app/study/b.hpp", "#include \"app/c.hpp\"\n");
    write("app/c.hpp", "#pragma once\n");
    write("app/commands/d.cpp", "#include \"app/c.hpp\"\n");  // one way: no loop
    const std::set<std::string> cycles = folder_cycles(root, {"app"});
    fs::remove_all(root);
    EXPECT_EQ(cycles, (std::set<std::string>{"app, app/study"}));
}

TEST(HouseRules, NoNewIncludeLoopBetweenFolders) {
    const std::set<std::string> cycles = folder_cycles(source_root(), kCodeFolders);
    for (const std::string& c : cycles) {
        EXPECT_TRUE(kFolderCyclesAllowed.count(c))
            << "these folders include each other around a loop: " << c
            << "; move what they share into a folder below both (DESIGN.md: includes point one way)";
    }
    for (const std::string& c : kFolderCyclesAllowed) {
        EXPECT_TRUE(cycles.count(c)) << "the loop " << c
                                     << " is gone or changed: update kFolderCyclesAllowed in tests/layout/test_house_rules.cpp";
    }
}

// app/'s layers (commands -> session -> {scene, menu} -> {input, actions} -> support): each folder of app/ includes only its own layer
// and those below it; a layer's sub-folders (session/run/, commands/demo/, ...) are that layer. The input sources
// (app/input/: the mouse stylus, scripted cursor and keys, DTrack head and wand)
// read devices and the renderer's events, never a scene or the session wiring above them; app/main.cpp, the
// dispatcher, sits on top.
int app_layer(const std::string& rel) {
    static const std::vector<std::pair<std::string, int>> kLayers = {
        {"app/support/", 0}, {"app/actions/", 1}, {"app/input/", 1}, {"app/menu/", 2}, {"app/scene/", 2},
        {"app/session/", 3}, {"app/commands/", 4}};
    if (rel == "app/main.cpp") return 5;
    for (const auto& [prefix, layer] : kLayers)
        if (rel.rfind(prefix, 0) == 0) return layer;
    return -1;
}

TEST(HouseRules, AppLayersAreKnownFolders) {
    EXPECT_EQ(app_layer("app/main.cpp"), 5);
    EXPECT_EQ(app_layer("app/commands/study/study_run.cpp"), 4);
    EXPECT_EQ(app_layer("app/commands/demo/demo_command.cpp"), 4);
    EXPECT_EQ(app_layer("app/session/run/run_session.cpp"), 3);
    EXPECT_EQ(app_layer("app/session/report/session_report.hpp"), 3);
    EXPECT_EQ(app_layer("app/scene/run_scene.hpp"), 2);
    EXPECT_EQ(app_layer("app/demo.cpp"), -1);
    int checked = 0;
    for (const std::string& rel : sources(source_root(), {"app"})) {
        ++checked;
        EXPECT_GE(app_layer(rel), 0) << rel << ": app/ holds main.cpp and the folders commands/, session/, scene/, menu/, "
                                     << "input/, actions/ and support/ only; put the file in the layer it belongs to";
    }
    EXPECT_GT(checked, 50);
}

// app/commands/ holds the command table at its top and a folder per command; app/session/ holds only its folders, one
// per idea (runtime/, record/, view/, report/, run/, batch/, cluster/).
TEST(HouseRules, AppCommandsAndSessionKeepTheirFilesInFolders) {
    const std::set<std::string> kTopOfCommands = {"app/commands/command.cpp", "app/commands/command.hpp"};
    int checked = 0;
    for (const std::string& rel : sources(source_root(), {"app/commands", "app/session"})) {
        ++checked;
        const std::string folder = fs::path(rel).parent_path().generic_string();
        if (folder == "app/commands") {
            EXPECT_TRUE(kTopOfCommands.count(rel)) << rel << ": a command's files go in its folder app/commands/NAME/ "
                                                   << "(NAME.hpp/.cpp its work, NAME_command.cpp its registration)";
        }
        EXPECT_NE(folder, "app/session") << rel << ": a session's part goes in the folder of its idea under "
                                         << "app/session/ (runtime, record, view, report, run, batch, cluster)";
    }
    EXPECT_GT(checked, 50);
}

TEST(HouseRules, AppLayersIncludeDownwardOnly) {
    static const std::regex include_line(R"re(^\s*#\s*include\s*"(app/[^"]+)")re");
    int checked = 0;
    for (const std::string& rel : sources(source_root(), {"app"})) {
        const int from = app_layer(rel);
        ++checked;
        std::stringstream ss(read(source_root() / rel));
        int line_no = 0;
        for (std::string line; std::getline(ss, line);) {
            ++line_no;
            std::smatch m;
            if (!std::regex_search(line, m, include_line)) continue;
            const std::string to = m[1].str();
            const int layer = app_layer(to);
            EXPECT_LE(layer, from) << rel << ":" << line_no << ": includes " << to << ", a layer above it (app/: commands -> "
                                   << "session -> {scene, input} -> support)";
            if (rel.rfind("app/input/", 0) == 0) {
                EXPECT_TRUE(to.rfind("app/input/", 0) == 0 || to.rfind("app/support/", 0) == 0)
                    << rel << ":" << line_no << ": an input source includes " << to;
            }
        }
    }
    EXPECT_GT(checked, 50);
}

}  // namespace
