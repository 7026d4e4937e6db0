// tests/test_paths.hpp - where the tests find the `tridex` executable, the source tree, its assets and the shared
// data: read from the environment that ctest gives every test (TRIDEX_TEST_ENV in tests/CMakeLists.txt), so that
// no absolute path is compiled into a test and its object is the same in every checkout (ccache shares it).
#pragma once

#include <cstdio>
#include <cstdlib>

namespace tridex::test {

/// The value of the environment variable `name` (a path). Ends the program with exit code 2 and a message naming
/// the variable when it is unset or empty: the test was run outside ctest, which sets it.
inline const char* env_path(const char* name) {
    const char* v = std::getenv(name);
    if (v == nullptr || *v == '\0') {
        std::fprintf(stderr,
                     "test: the environment variable %s is not set; run the test through ctest (ctest -R NAME), which "
                     "sets it (tests/CMakeLists.txt, TRIDEX_TEST_ENV)\n",
                     name);
        std::exit(2);
    }
    return v;
}

}  // namespace tridex::test

/// The `tridex` executable of the build tree the test belongs to.
#define TRIDEX_EXE ::tridex::test::env_path("TRIDEX_EXE")
/// The source tree's root.
#define TRIDEX_SOURCE_DIR ::tridex::test::env_path("TRIDEX_SOURCE_DIR")
/// The source tree's assets/ folder.
#define TRIDEX_ASSETS_DIR ::tridex::test::env_path("TRIDEX_ASSETS")
/// The shared test data folder (../shared/data beside the checkout, or -DTRIDEX_SHARED_DATA).
#define TRIDEX_SHARED_DATA_DIR ::tridex::test::env_path("TRIDEX_SHARED_DATA")
/// DESIGN.md beside the checkout (../shared/DESIGN.md).
#define TRIDEX_DESIGN_MD ::tridex::test::env_path("TRIDEX_DESIGN_MD")
