// The module include rule of ../shared/DESIGN.md, read from its text, and a checker of `#include` lines
// against it (tests/layout/test_layout.cpp).
//
// What is read from DESIGN.md:
// - the paragraph that starts "Includes point one way:": every backquoted span with arrows is a chain
//   (`app -> {renderer, compute, haptics, devices} -> {gpu, core}`): each module of one link may include
//   each module of the next; arrows point down layers, so a module may also include what those include
//   (transitive closure);
// - in the same paragraph, "`a` and `b` never include `x/` or Vulkan headers": those edges are removed
//   (before and after the closure), and `a`, `b` may not include vulkan/, volk or GLFW headers;
// - in the module table, the folder whose line says "every module shares" (core/) may be included by
//   every module.
// A module includes itself freely. Anything else (an include of another module not allowed above) breaks
// the rule. When DESIGN.md is absent, kFallbackDesign (a copy of those lines) is parsed instead and the
// source says so.
#pragma once

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace tridex::layout {

/// A copy of the rule's lines of ../shared/DESIGN.md, used only when that file is absent.
inline constexpr const char* kFallbackDesign = R"(
core/      vocabulary every module shares: SI units (m, N, s, N*m), Pose, Aabb, Segment,

Includes point one way: `bench -> app -> {renderer, compute, haptics, devices} -> {gpu, core}`,
`{renderer, compute} -> shaders` (embedded SPIR-V); nothing includes `bench/`;
`haptics -> devices -> core`; `haptics` and `devices` never include `gpu/` or Vulkan
headers. The active-surface cache type lives in `core/` (compute writes it, haptics reads it).
)";

struct IncludeRules {
    std::string source;             ///< where the rule came from (DESIGN.md path, or the built-in fallback)
    std::string rule_text;          ///< the paragraph the rule was read from
    std::set<std::string> modules;  ///< modules named by the rule
    std::map<std::string, std::set<std::string>> may;    ///< module -> modules it may include
    std::map<std::string, std::set<std::string>> never;  ///< module -> modules it must never include
    std::set<std::string> no_vulkan;                     ///< modules that may not include Vulkan/GLFW
    std::set<std::string> shared;                        ///< modules every module may include

    bool allows(const std::string& from, const std::string& to) const {
        if (from == to) return true;
        if (auto n = never.find(from); n != never.end() && n->second.count(to)) return false;
        if (shared.count(to)) return true;
        auto m = may.find(from);
        return m != may.end() && m->second.count(to) > 0;
    }
    /// The rule `from` breaks by including `to`, in words.
    std::string why(const std::string& from, const std::string& to) const {
        if (auto n = never.find(from); n != never.end() && n->second.count(to))
            return "`" + from + "` never includes `" + to + "/` (" + source + ")";
        std::string allowed;
        if (auto m = may.find(from); m != may.end())
            for (const auto& a : m->second) allowed += (allowed.empty() ? "" : ", ") + a;
        for (const auto& s : shared)
            if (!may.count(from) || !may.at(from).count(s)) allowed += (allowed.empty() ? "" : ", ") + s;
        return "`" + from + "` may include only {" + allowed + "} (" + rule_text_short() + ", " + source + ")";
    }
    std::string rule_text_short() const {
        std::string s = rule_text.substr(0, rule_text.find('.'));
        std::replace(s.begin(), s.end(), '\n', ' ');
        return s;
    }
};

namespace detail {

inline std::string trim(std::string s) {
    const auto b = s.find_first_not_of(" \t\n{}");
    const auto e = s.find_last_not_of(" \t\n{}/");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

inline std::vector<std::string> names(const std::string& link) {  // "{a, b}" or "a" -> names
    std::vector<std::string> out;
    std::stringstream ss(trim(link));
    for (std::string n; std::getline(ss, n, ',');)
        if (auto t = trim(n); !t.empty()) out.push_back(t);
    return out;
}

inline std::vector<std::string> backquoted(const std::string& text) {
    std::vector<std::string> out;
    for (std::size_t a = text.find('`'); a != std::string::npos;) {
        const std::size_t b = text.find('`', a + 1);
        if (b == std::string::npos) break;
        out.push_back(text.substr(a + 1, b - a - 1));
        a = text.find('`', b + 1);
    }
    return out;
}

}  // namespace detail

/// Parses the rule out of DESIGN.md's text. Throws std::runtime_error when the paragraph is missing or
/// has no chain (a test must not pass on a rule it could not read).
inline IncludeRules parse_rules(const std::string& design, const std::string& source) {
    IncludeRules r;
    r.source = source;
    const std::size_t start = design.find("Includes point one way:");
    if (start == std::string::npos) throw std::runtime_error(source + ": no \"Includes point one way:\" paragraph");
    std::size_t end = design.find("\n\n", start);
    r.rule_text = design.substr(start, end == std::string::npos ? std::string::npos : end - start);

    // Chains: every backquoted span with an arrow.
    std::map<std::string, std::set<std::string>> edges;
    for (const auto& span : detail::backquoted(r.rule_text)) {
        if (span.find("->") == std::string::npos) continue;
        std::vector<std::vector<std::string>> links;
        for (std::size_t a = 0;;) {
            const std::size_t b = span.find("->", a);
            links.push_back(detail::names(span.substr(a, b == std::string::npos ? std::string::npos : b - a)));
            if (b == std::string::npos) break;
            a = b + 2;
        }
        for (std::size_t i = 0; i < links.size(); ++i)
            for (const auto& from : links[i]) {
                r.modules.insert(from);
                if (i + 1 < links.size())
                    for (const auto& to : links[i + 1]) edges[from].insert(to);
            }
    }
    if (edges.empty()) throw std::runtime_error(source + ": the include paragraph has no `a -> b` chain");

    // "`a` and `b` never include `x/` or Vulkan headers": per sentence, subjects before, objects after.
    std::string clauses = r.rule_text;
    for (std::size_t dot; (dot = clauses.find(". ")) != std::string::npos;) clauses[dot] = ';';
    std::stringstream sentences(clauses);
    for (std::string sentence; std::getline(sentences, sentence, ';');) {
        const std::size_t k = sentence.find("never include");
        if (k == std::string::npos) continue;
        const auto subjects = detail::backquoted(sentence.substr(0, k));
        const std::string rest = sentence.substr(k);
        for (const auto& s : subjects) {
            for (const auto& o : detail::backquoted(rest)) r.never[detail::trim(s)].insert(detail::trim(o));
            if (rest.find("Vulkan") != std::string::npos) r.no_vulkan.insert(detail::trim(s));
        }
    }
    for (const auto& [from, tos] : r.never)
        for (const auto& to : tos) edges[from].erase(to);

    // Arrows point down layers: the closure.
    for (const auto& m : r.modules) {
        std::set<std::string> seen;
        std::vector<std::string> todo(edges[m].begin(), edges[m].end());
        while (!todo.empty()) {
            const std::string n = todo.back();
            todo.pop_back();
            if (!seen.insert(n).second) continue;
            for (const auto& x : edges[n]) todo.push_back(x);
        }
        for (const auto& x : r.never[m]) seen.erase(x);
        seen.erase(m);
        r.may[m] = seen;
    }

    // The module table's "every module shares" folder.
    const std::regex shared_line(R"(^(\w+)/\s+[^\n]*every module shares)");
    std::stringstream lines(design);
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (std::regex_search(line, m, shared_line)) r.shared.insert(m[1]);
    }
    return r;
}

/// Reads the rule from `design_path`, or from kFallbackDesign when that file cannot be opened.
inline IncludeRules load_rules(const std::string& design_path) {
    std::ifstream in(design_path);
    if (!in) return parse_rules(kFallbackDesign, "built-in fallback copy of the rule (" + design_path + " absent)");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_rules(ss.str(), design_path);
}

struct Violation {
    std::string file;      ///< path relative to the source root, e.g. "haptics/loop.cpp"
    int line = 0;          ///< 1-based
    std::string included;  ///< the included path
    std::string module;    ///< the module included ("vulkan" for a Vulkan/GLFW header)
    std::string rule;      ///< the rule broken, in words
};

/// Checks the `#include` lines of one source file of module `module` (file: its path for messages).
/// `modules`: every module folder name (an include "x/..." with x among them is an include of module x).
inline std::vector<Violation> check_source(const IncludeRules& rules, const std::string& module,
                                           const std::string& file, const std::string& text,
                                           const std::set<std::string>& modules) {
    static const std::regex include_line(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
    std::vector<Violation> out;
    std::stringstream ss(text);
    int n = 0;
    for (std::string line; std::getline(ss, line);) {
        ++n;
        std::smatch m;
        if (!std::regex_search(line, m, include_line)) continue;
        const std::string path = m[1];
        const std::string head = path.substr(0, path.find('/'));
        const bool vulkan = path.rfind("vulkan/", 0) == 0 || path.rfind("volk", 0) == 0 || path.rfind("GLFW/", 0) == 0;
        if (vulkan && rules.no_vulkan.count(module))
            out.push_back({file, n, path, "vulkan", "`" + module + "` never includes Vulkan, volk or GLFW headers"});
        if (path.find('/') == std::string::npos || !modules.count(head)) continue;
        if (!rules.allows(module, head)) out.push_back({file, n, path, head, rules.why(module, head)});
    }
    return out;
}

}  // namespace tridex::layout
