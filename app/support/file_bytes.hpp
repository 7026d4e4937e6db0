// app/support/file_bytes.hpp - a whole file's bytes read or written at once (a model handed to another machine).
#pragma once

#include <span>
#include <string>
#include <vector>

namespace tridex::app {

/// The bytes of the file at `path`. Throws tridex::Error "<path>: cannot be read" when it cannot be opened or read.
std::vector<unsigned char> read_file_bytes(const std::string& path);

/// Writes `bytes` to `path` (replaced atomically: core/atomic_file.hpp). Throws tridex::Error "<path>: ..." naming
/// what failed (a missing folder, a full disk).
void write_file_bytes(const std::string& path, std::span<const unsigned char> bytes);

}  // namespace tridex::app
