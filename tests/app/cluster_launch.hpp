// tests/app/cluster_launch.hpp - a three-rank cluster session of the small wall scene under mpirun on this machine
// (rank 0 the session, ranks 1 and 2 the render ranks of a cluster config in tests/data/cluster), for the cluster and
// chaos tests. The executable and the source tree come from ctest's environment (tests/test_paths.hpp).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include "../test_paths.hpp"

namespace tridex::app::test {

/// tests/data/cluster of the source tree.
inline std::filesystem::path cluster_data() {
    return std::filesystem::path(TRIDEX_SOURCE_DIR) / "tests" / "data" / "cluster";
}

/// How an mpirun ended: its exit code (-1 when killed) and everything the ranks printed.
struct Launch {
    int exit_code = -1;
    std::string log;
};

/// True when mpirun is on the PATH.
inline bool have_mpirun() { return std::system("command -v mpirun > /dev/null 2>&1") == 0; }

/// mpirun -np 3 (at most 300 s) of tests/data/cluster/wall_small_scene.json offscreen with the cluster config
/// `config` (a path), `env` (e.g. "TRIDEX_CLUSTER_FAULT=2:3:kill") before the command; out is emptied first and the
/// ranks' output goes to OUT.log.
inline Launch mpirun3(const std::filesystem::path& out, const std::filesystem::path& config,
                      const std::string& env = "") {
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    const std::string root = geteuid() == 0 ? " --allow-run-as-root" : "";
    const std::filesystem::path log = out.string() + ".log";
    const std::string cmd = env + " timeout 300 mpirun" + root +
                            " --oversubscribe --mca orte_abort_on_non_zero_status 0 -np 3 " + TRIDEX_EXE + " run " +
                            (cluster_data() / "wall_small_scene.json").string() +
                            " --display offscreen --no-items --cluster " + config.string() + " --out " +
                            out.string() + " > " + log.string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    Launch l;
    l.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    l.log.assign(std::istreambuf_iterator<char>(in), {});
    return l;
}

}  // namespace tridex::app::test
