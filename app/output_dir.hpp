// app/output_dir.hpp - checking an output folder before a session spends any time on it.
#pragma once

#include <string>

namespace tridex::app {

/// Creates `dir` (and its parents) when missing and proves it writable by creating and removing a small probe
/// file in it. Throws tridex::Error "<flag> <dir>: <reason>" (e.g. "--out /dev/full: not a folder", "--out /ro:
/// cannot write there: Read-only file system") so that a bad output location is refused before the session runs.
void prepare_output_dir(const std::string& dir, const std::string& flag);

/// Checks that a file can be created at `path` (its folder exists or can be made, and a probe file can be written
/// beside it; the file itself is not created). Throws tridex::Error "<flag> <path>: <reason>".
void check_output_file(const std::string& path, const std::string& flag);

}  // namespace tridex::app
