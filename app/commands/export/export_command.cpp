// app/commands/export/export_command.cpp - `tridex export MODEL OUT`: a saved model or a scene's workpiece as a closed
// mesh.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/export/export.hpp"

namespace tridex::app {
namespace {

CommandAction setup_export(CLI::App& cmd) {
    auto o = std::make_shared<ExportOptions>();
    cmd.add_option("MODEL", o->model,
                   "Saved model (tridex demo/run --save FILE.tdx), or a scene (.json, such as the FILE.scene.json a "
                   "session saves beside its model): its workpiece where the scene places it")
        ->required()
        ->check(CLI::ExistingFile);
    cmd.add_option("OUT", o->out, "Mesh file: .stl (binary), .obj or .ply (binary, material colours)")->required();
    cmd.add_option("--units", o->units, "Units of the written coordinates: m, mm or in (inches)")
        ->capture_default_str()
        ->check(CLI::IsMember({"m", "mm", "in"}));
    cmd.add_option("--frame", o->frame,
                   "world: where the session placed the workpiece; input: the input mesh's own frame and units, so "
                   "the export lines up with the mesh it was carved from")
        ->capture_default_str()
        ->check(CLI::IsMember({"world", "input"}));
    cmd.add_option("--objects", o->objects,
                   "workpiece: the workpiece alone (a scene's further workpieces each in a file beside OUT, "
                   "OUT-wp2.EXT, ...); all: a scene's workpieces and its reference objects in one file (an OBJ object each)")
        ->capture_default_str()
        ->check(CLI::IsMember({"workpiece", "all"}));
    return [o] {
        run_export(*o);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"export", "Contour a saved model (.tdx) or a scene's workpiece and write it as a closed mesh (STL, OBJ or PLY)", 50,
     setup_export}};

}  // namespace
}  // namespace tridex::app
