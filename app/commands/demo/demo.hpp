// app/commands/demo/demo.hpp - `tridex demo`: the main job end to end (load, scan-convert, carve under a 1 kHz
// haptic loop with a simulated device, contour, render both eyes, write the outputs).
#pragma once

#include "app/support/assets.hpp"

#include <string>

#include "devices/registry/device_registry.hpp"

namespace tridex::app {

/// Options of `tridex demo` (command-line units converted to SI here).
struct DemoOptions {
    std::string mesh;              ///< workpiece mesh file (OFF, OBJ, PLY, STL); empty = the bundled bunny
    int resolution = 256;          ///< lattice cells along the workpiece's longest side
    double seconds = 4.0;          ///< length of the scripted stroke, s
    std::string out = "out/demo";  ///< output folder (created)
    int width = 1280;              ///< per-eye image width, px
    int height = 960;              ///< per-eye image height, px
    double stock_m = 0.3;          ///< the workpiece is scaled so its longest side is this, m
    double tool_radius_m = 0.008;  ///< tool radius (ball or flat-end mill), m
    std::string tool = "ball";     ///< tool shape: ball | flat_end | mesh (core/tool_shape.hpp)
    double tool_length_m = 0.02;   ///< flat_end: cylinder length along the tool axis, m
    std::string tool_mesh;         ///< mesh: the tool's closed mesh file (app/scene/tool_mesh.hpp places its tip on the HIP)
    double tool_size_m = 0.012;    ///< mesh: longest side of the tool mesh's bounding box after scaling, m
    bool validate = false;         ///< enable VK_LAYER_KHRONOS_validation (also on with TRIDEX_VALIDATION=1)
    int points = 1;                ///< contact points: 1 ball HIP, 2 wand top/bottom, 3..64 interaction mesh
    /// simulated device profile: omni | wand | 6dof; or a Falcon: falcon (a real one over USB) | falcon-emulator
    std::string device = "omni";
    /// --device net:HOST:PORT: where the contact loop runs, distributed (this session) or local (the device server)
    std::string haptic_rendering = "distributed";
    std::string falcon_firmware;  ///< --falcon-firmware: the Falcon firmware file from the user's own installation
    /// --device net:HOST:PORT: the key sealing the link, as the device server's (--key-file FILE, or
    /// --passphrase-env VAR naming the environment variable holding the passphrase); both "" = not authenticated.
    std::string key_file;
    std::string passphrase_env;  ///< see key_file
    std::string workspace = "peng_moving";  ///< workspace technique: peng_moving | scaling | clutching | bubble
    double static_friction = 0.2;  ///< Coulomb friction on the proxy (static >= dynamic >= 0)
    double dynamic_friction = 0.15;
    bool cutting = true;           ///< cutting reaction force while carving
    std::string record;            ///< when set, the session is recorded to this file (TRDXREC)
    std::string save;              ///< when set, the final model is saved to this file (.tdx)
    std::string workpiece;         ///< when set, the session starts from this saved model (.tdx) instead of a mesh
    /// The session journal (compute/journal/journal_format.hpp; `tridex recover` rebuilds the model from it);
    /// "" = <out>/session.tdj.
    std::string journal;
    bool no_journal = false;       ///< --no-journal: write no journal
    double checkpoint_s = 120.0;   ///< wall time between checkpoint models next to the journal, s (0 = none)
    double history_mib = 256.0;    ///< the undo history's memory budget, MiB
    bool cpu = false;              ///< --cpu: sculpt on the CPU pool whatever the Vulkan device (default: decide_backend)
    bool gpu = false;              ///< --gpu: sculpt on the GPU compute path whatever the device's type
    bool keep_islands = false;     ///< --keep-islands: keep the specks a cut leaves floating (SessionSpec::keep_islands)
    bool cpu_contour = false;      ///< --cpu-contour: contour on the CPU even when sculpting on the GPU
    bool gpu_contour = false;      ///< --gpu-contour: contour on the GPU even on a CPU Vulkan device (lavapipe)
    bool gpu_clay = false;         ///< --gpu-clay: clay on the GPU kernel even on a CPU Vulkan device (lavapipe)
    std::string op = "subtract";   ///< what the tool does: subtract | union | paint | push | smooth | pull
    int material = 1;              ///< palette id (1..7) that union adds and paint sets
    std::string symmetry = "off";  ///< sculpting symmetry (core/symmetry.hpp spelling: off, x, xz, radial:6:z, ...)
    bool ao = true;                ///< --ao on|off: ambient occlusion in the images (cuts darker, edges brighter)
};

/// Runs the demo and writes left.png, right.png, sbs.png, sculpted.ply, haptics.csv and report.json
/// into options.out (and, while it runs, the session journal, unless no_journal; the session recording to options.record and the final model to options.save when set). Prints a short summary on stdout. Throws tridex::Error on bad input (a mesh that
/// cannot be loaded or is not closed, an impossible resolution, no Vulkan device).
void run_demo(const DemoOptions& options);

/// What the demo's simulated hand does (its path in the device frame, its buttons, the period) for options o: the
/// workpiece is loaded and the stroke planned as run_demo() does, so a device server whose simulated device gets
/// these inputs plays the stroke a `tridex demo --device net:HOST:PORT` session with the same options expects.
/// `device` is the served driver and profile (o.device is not read). Throws tridex::Error as run_demo() does on bad
/// options, and for a driver whose hand is not scripted (a remote one, hardware, a person's).
devices::DeviceInputs demo_device_inputs(const DemoOptions& o, const devices::DeviceChoice& device);


}  // namespace tridex::app
