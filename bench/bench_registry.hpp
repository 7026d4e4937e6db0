// bench/bench_registry.hpp - the benchmarks of `tridex bench`: each registers itself (a flag --NAME, its own
// options, how it runs) from its own source file; bench/bench_command.cpp turns the list into the command.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace tridex::bench {

/// The options every benchmark shares (`tridex bench --out DIR --mesh FILE`).
struct BenchCommon {
    std::string out = "out/bench";  ///< output folder for the JSON tables and plots
    std::string mesh;               ///< workpiece mesh; empty = the bundled bunny (benchmarks that load one)
    /// The text given to --NAME for a benchmark that takes a value (Benchmark::value_name), e.g. "10" of
    /// `--soak 10`; empty for the others.
    std::string value;
};

/// Runs one benchmark with the shared options; throws tridex::Error on a bad option.
using BenchRun = std::function<void(const BenchCommon&)>;

/// One benchmark of `tridex bench`.
struct Benchmark {
    Benchmark() = default;
    /// A benchmark of these fields (see each); `value_name` empty: --NAME is a flag.
    Benchmark(std::string name_, std::string summary_, int rank_, std::function<BenchRun(CLI::App& bench)> setup_,
              std::string value_name_ = "")
        : name(std::move(name_)), summary(std::move(summary_)), rank(rank_), setup(std::move(setup_)),
          value_name(std::move(value_name_)) {}
    std::string name;     ///< `tridex bench --NAME` selects it (lower case)
    std::string summary;  ///< help text of --NAME: what it measures
    int rank = 100;       ///< benchmarks chosen together run in rank order, lowest first
    /// Declares the benchmark's own options on the `bench` command (named --NAME-..., help starting "With
    /// --NAME:") and returns how to run it; the options must stay alive until then (keep them in a shared_ptr).
    std::function<BenchRun(CLI::App& bench)> setup;
    /// Non-empty: --NAME takes a value named so in the help (`--soak MINUTES`), handed to the run as
    /// BenchCommon::value; empty: --NAME is a flag.
    std::string value_name;
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
