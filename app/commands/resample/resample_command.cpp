// app/commands/resample/resample_command.cpp - `tridex resample MODEL --resolution N --out NEW`: a saved model at
// another resolution.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/resample/resample.hpp"

namespace tridex::app {
namespace {

CommandAction setup_resample(CLI::App& cmd) {
    auto o = std::make_shared<ResampleOptions>();
    cmd.add_option("MODEL", o->model, "Saved model (tridex demo/run --save FILE.tdx)")->required();
    cmd.add_option("--resolution", o->resolution,
                   "New resolution: cells along the model's longest axis (8 to 4096), over the same box")
        ->required();
    cmd.add_option("--out", o->out, "The re-sampled model file to write (.tdx)")->required();
    return [o] {
        run_resample(*o);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"resample", "Re-sample a saved model (.tdx) onto a finer or coarser lattice, its materials kept", 55,
     setup_resample}};

}  // namespace
}  // namespace tridex::app
