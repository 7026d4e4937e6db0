// tests/app/error_of.hpp - the message of the error a call throws, for tests that check what a refusal says.
#pragma once

#include <string>

#include "core/error.hpp"

namespace tridex::app::test {

/// The message of the tridex::Error `f` throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace tridex::app::test
