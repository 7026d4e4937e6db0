// tests/chaos/chaos_env.hpp - the long forms of the fault tests: a count or length from the environment.
#pragma once

#include <cstdlib>

namespace tridex::app::test {

/// The positive number in environment variable `name`, or `fallback` when it is unset, not a number or not > 0.
inline double chaos_env(const char* name, double fallback) {
    const char* v = std::getenv(name);
    const double x = v ? std::atof(v) : 0.0;
    return x > 0.0 ? x : fallback;
}

}  // namespace tridex::app::test
