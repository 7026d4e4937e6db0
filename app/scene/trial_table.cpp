// app/scene/trial_table.cpp - reading and writing the per-trial CSV table.
#include "app/scene/trial_table.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return {};
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
    std::vector<std::string> out;
    std::string field;
    std::istringstream in(line);
    while (std::getline(in, field, ',')) out.push_back(trim(field));
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& column, const std::string& what) {
    throw Error(path + ":" + std::to_string(line) + ": field '" + column + "': " + what);
}

double parse_measure(const std::string& text, const std::string& path, std::size_t line, const std::string& column) {
    if (text.empty()) fail(path, line, column, "empty");
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE) fail(path, line, column, "not a number: '" + text + "'");
    if (!std::isfinite(v)) fail(path, line, column, "not finite: '" + text + "'");
    if (v < 0.0) fail(path, line, column, "negative: " + text);
    return v;
}

int parse_trial(const std::string& text, const std::string& path, std::size_t line) {
    if (text.empty() || text.size() > 6 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
        fail(path, line, "trial", "not a positive integer: '" + text + "'");
    const int v = std::atoi(text.c_str());
    if (v < 1) fail(path, line, "trial", "not a positive integer: '" + text + "'");
    return v;
}

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

}  // namespace

const std::vector<std::string>& trial_csv_columns() {
    static const std::vector<std::string> cols{"participant", "group", "trial", "time_s", "deviation_m",
                                               "deviation_top_m", "deviation_bottom_m", "max_deviation_m"};
    return cols;
}

bool valid_participant_id(const std::string& id) {
    return !id.empty() && id.size() <= 64 && std::all_of(id.begin(), id.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    });
}

std::vector<TrialRow> read_trial_csv(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot read");
    std::string text;
    std::size_t line_no = 0;
    std::map<std::string, std::size_t> col;  // column name -> index
    std::size_t header_fields = 0;
    std::vector<std::string> header_names;
    while (std::getline(in, text)) {
        ++line_no;
        if (trim(text).empty()) continue;
        const std::vector<std::string> names = split_fields(text);
        for (std::size_t i = 0; i < names.size(); ++i) {
            if (names[i].empty()) fail(path, line_no, "column " + std::to_string(i + 1), "empty column name");
            if (col.count(names[i])) fail(path, line_no, names[i], "column named twice");
            col[names[i]] = i;
        }
        header_fields = names.size();
        header_names = names;
        break;
    }
    if (header_fields == 0) throw Error(path + ": empty file; expected a header row naming the columns");
    const std::size_t header_line = line_no;
    for (const char* required : {"participant", "group", "trial", "time_s", "deviation_m"})
        if (!col.count(required)) fail(path, header_line, required, "missing column");

    std::vector<TrialRow> rows;
    std::map<std::string, std::string> group_of;              // participant -> group
    std::map<std::pair<std::string, int>, std::size_t> seen;  // (participant, trial) -> line
    while (std::getline(in, text)) {
        ++line_no;
        if (trim(text).empty()) continue;
        const std::vector<std::string> f = split_fields(text);
        if (f.size() != header_fields)
            fail(path, line_no, f.size() < header_fields ? header_names[f.size()] : "(extra)",
                 (f.size() < header_fields ? "missing: " : "too many fields: ") + std::to_string(f.size()) +
                     " fields, the header has " + std::to_string(header_fields));
        TrialRow r;
        r.participant = f[col["participant"]];
        if (!valid_participant_id(r.participant))
            fail(path, line_no, "participant", "'" + r.participant + "' is not an ID (1..64 of A-Z a-z 0-9 _ -)");
        r.group = f[col["group"]];
        const auto& groups = study_groups();
        if (std::find(groups.begin(), groups.end(), r.group) == groups.end())
            fail(path, line_no, "group", "unknown group '" + r.group + "' (haptic or visual)");
        r.trial = parse_trial(f[col["trial"]], path, line_no);
        r.time_s = parse_measure(f[col["time_s"]], path, line_no, "time_s");
        r.deviation_m = parse_measure(f[col["deviation_m"]], path, line_no, "deviation_m");
        for (const auto& [name, field] : {std::pair<const char*, double TrialRow::*>{"deviation_top_m", &TrialRow::deviation_top_m},
                                          {"deviation_bottom_m", &TrialRow::deviation_bottom_m},
                                          {"max_deviation_m", &TrialRow::max_deviation_m}})
            if (auto it = col.find(name); it != col.end()) r.*field = parse_measure(f[it->second], path, line_no, name);
        if (auto g = group_of.find(r.participant); g != group_of.end() && g->second != r.group)
            fail(path, line_no, "group", "participant '" + r.participant + "' is in group '" + g->second + "' above");
        group_of[r.participant] = r.group;
        if (auto s = seen.find({r.participant, r.trial}); s != seen.end())
            fail(path, line_no, "trial", "participant '" + r.participant + "' trial " + std::to_string(r.trial) +
                                             " repeats line " + std::to_string(s->second));
        seen[{r.participant, r.trial}] = line_no;
        rows.push_back(std::move(r));
    }
    for (const std::string& g : study_groups()) {
        const auto n = std::count_if(rows.begin(), rows.end(), [&](const TrialRow& r) { return r.group == g; });
        if (n < 2)
            throw Error(path + ":" + std::to_string(line_no) + ": field 'group': group '" + g + "' has " +
                        std::to_string(n) + " trial" + (n == 1 ? "" : "s") + "; need at least two per group");
    }
    return rows;
}

void write_trial_csv(const std::string& path, const std::vector<TrialRow>& rows) {
    std::string out;
    const auto& cols = trial_csv_columns();
    for (std::size_t i = 0; i < cols.size(); ++i) out += (i ? "," : "") + cols[i];
    out += "\n";
    for (const TrialRow& r : rows)
        out += r.participant + "," + r.group + "," + std::to_string(r.trial) + "," + number(r.time_s) + "," +
               number(r.deviation_m) + "," + number(r.deviation_top_m) + "," + number(r.deviation_bottom_m) + "," +
               number(r.max_deviation_m) + "\n";
    write_file_atomically(path, out);
}

}  // namespace tridex::app::study
