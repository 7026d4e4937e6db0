// bench/bench_command.cpp - `tridex bench`: the registered benchmarks as one command of the command table.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <deque>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "app/commands/command.hpp"
#include "bench/bench_registry.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

std::vector<Benchmark>& table() {
    static std::vector<Benchmark> benchmarks;
    return benchmarks;
}

// What `tridex bench` parses into: the shared options, and per benchmark whether it was chosen and how it runs.
struct BenchCli {
    BenchCommon common;
    std::deque<bool> chosen;  // deque: CLI11 keeps pointers to the flags
    std::deque<std::string> values;           // per benchmark: the value of --NAME VALUE (value_name set)
    std::vector<const CLI::Option*> valued;   // per benchmark: its --NAME VALUE option, or nullptr for a flag
    std::vector<BenchRun> runs;
    std::vector<std::string> names;
};

app::CommandAction setup_bench(CLI::App& cmd) {
    auto o = std::make_shared<BenchCli>();
    for (const Benchmark& b : registered_benchmarks()) {
        o->chosen.push_back(false);
        o->values.emplace_back();
        o->names.push_back(b.name);
        if (b.value_name.empty()) {
            cmd.add_flag("--" + b.name, o->chosen.back(), b.summary);
            o->valued.push_back(nullptr);
        } else {
            o->valued.push_back(cmd.add_option("--" + b.name, o->values.back(), b.summary)->type_name(b.value_name));
        }
        o->runs.push_back(b.setup(cmd));
    }
    cmd.add_option("--out", o->common.out, "Output folder")->capture_default_str();
    cmd.add_option("--mesh", o->common.mesh, "Workpiece mesh; default: the bundled bunny")->check(CLI::ExistingFile);
    return [o]() -> int {
        for (std::size_t i = 0; i < o->valued.size(); ++i)
            if (o->valued[i] && o->valued[i]->count() > 0) o->chosen[i] = true;
        if (std::none_of(o->chosen.begin(), o->chosen.end(), [](bool c) { return c; })) {
            std::string flags;
            for (std::size_t i = 0; i < o->names.size(); ++i)
                flags += (i == 0 ? "--" : i + 1 == o->names.size() ? " and/or --" : ", --") + o->names[i];
            throw Error("bench: choose what to measure: " + flags);
        }
        for (std::size_t i = 0; i < o->runs.size(); ++i)
            if (o->chosen[i]) {
                BenchCommon common = o->common;
                common.value = o->values[i];
                o->runs[i](common);
            }
        return 0;
    };
}

const app::CommandRegistration kRegistration{
    {"bench", "Benchmarks that print tables and write JSON (numbers, not pass/fail)", 90, setup_bench}};

}  // namespace

void register_benchmark(Benchmark benchmark) {
    if (benchmark.name.empty() || !benchmark.setup)
        throw std::logic_error("register_benchmark: a benchmark needs a name and a setup");
    for (const Benchmark& b : table())
        if (b.name == benchmark.name) throw std::logic_error("register_benchmark: '" + benchmark.name + "' registered twice");
    table().push_back(std::move(benchmark));
}

std::vector<Benchmark> registered_benchmarks() {
    std::vector<Benchmark> benchmarks = table();
    std::stable_sort(benchmarks.begin(), benchmarks.end(), [](const Benchmark& a, const Benchmark& b) {
        return a.rank != b.rank ? a.rank < b.rank : a.name < b.name;
    });
    return benchmarks;
}

BenchmarkRegistration::BenchmarkRegistration(Benchmark benchmark) { register_benchmark(std::move(benchmark)); }

}  // namespace tridex::bench
