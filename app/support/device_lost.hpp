// app/support/device_lost.hpp - the error a session ends with when its device went away.
#pragma once

#include <string>

#include "core/error.hpp"

namespace tridex::app {

/// The session's device went away in the middle of the session (unplugged, its daemon or device server gone).
/// Thrown after the session's outputs were written; what() names the device, when it was lost and what was kept.
/// The command exits 4 (docs/report.md, "Exit codes").
class DeviceLostError : public Error {
public:
    explicit DeviceLostError(const std::string& message) : Error(message) {}
};

}  // namespace tridex::app
