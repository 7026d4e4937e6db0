// app/support/json_file.hpp - writing the reports and benchmark results as JSON files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace tridex::app {

/// Writes `j` to `path` (2-space indented, trailing newline), creating the parent folder. Throws
/// tridex::Error "<path>: cannot open for writing" / "<path>: write failed".
void write_json_file(const std::string& path, const nlohmann::json& j);

/// Reads a scene file `path` as JSON. Throws tridex::Error "<path>: is a folder; name a scene file (JSON)",
/// "<path>: cannot read the scene file", "<path>: not valid JSON: parse error at line L, column C: syntax error
/// while parsing object - unexpected string literal; expected '}'" (nlohmann's reason: the line, the column and what
/// was expected there) or "<path>: not valid JSON: number overflow at line L, column C, field 'workpiece.stock_m':
/// '1e400' is beyond a double's range ..." (core/text/json_refusal.hpp).
nlohmann::json read_scene_json(const std::string& path);

}  // namespace tridex::app
