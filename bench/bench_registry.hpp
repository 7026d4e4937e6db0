// bench/bench_registry.hpp - the benchmarks of `tridex bench`: each registers itself (a flag --NAME, its own
// options, how it runs) from its own source file; bench/bench_command.cpp turns the list into the command.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace tridex::bench {

/// The options every benchmark shares (`tridex bench --out DIR --mesh FILE`).
struct BenchCommon {
    std::string out = "out/bench";  ///< output folder for the JSON tables and plots
    std::string mesh;               ///< workpiece mesh; empty = the bundled bunny (benchmarks that load one)
};

/// Runs one benchmark with the shared options; throws tridex::Error on a bad option.
using BenchRun = std::function<void(const BenchCommon&)>;

/// One benchmark of `tridex bench`.
struct Benchmark {
    std::string name;     ///< `tridex bench --NAME` selects it (lower case)
    std::string summary;  ///< help text of --NAME: what it measures
    int rank = 100;       ///< benchmarks chosen together run in rank order, lowest first
    /// Declares the benchmark's own options on the `bench` command (named --NAME-..., help starting "With
    /// --NAME:") and returns how to run it; the options must stay alive until then (keep them in a shared_ptr).
    std::function<BenchRun(CLI::App& bench)> setup;
};

/// Adds a benchmark; throws std::logic_error when its name is empty or taken, or setup is empty.
void register_benchmark(Benchmark benchmark);

/// Every registered benchmark, in rank order (then by name).
std::vector<Benchmark> registered_benchmarks();

/// Registers a benchmark during static initialisation: `static const BenchmarkRegistration reg{{...}};` at the end
/// of the benchmark's source file.
struct BenchmarkRegistration {
    explicit BenchmarkRegistration(Benchmark benchmark);
};

}  // namespace tridex::bench
