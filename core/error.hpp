// core/error.hpp - the one exception type for user-caused failures (bad files, bad options).
#pragma once

#include <stdexcept>
#include <string>

namespace tridex {

/// A failure the user can fix (bad input file, impossible option, missing device).
/// what() is one line that names the file, line or field at fault. Programming errors
/// ("cannot happen") abort instead.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace tridex
