// app/commands/demo/demo.cpp - `tridex demo`: wires the three threads of DESIGN.md around one scripted stroke.
#include "app/commands/demo/demo.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <tuple>

#include "app/support/assets.hpp"
#include "app/support/output_dir.hpp"
#include "app/session/batch/session.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/scene/session_memory.hpp"
#include "app/scene/session_spec.hpp"
#include "app/scene/stroke.hpp"
#include "app/scene/tool_mesh.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "app/support/device_lost.hpp"
#include "core/error.hpp"
#include "core/symmetry.hpp"
#include "core/format.hpp"
#include "devices/device_profiles.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// World frame (DESIGN.md): metres, y up, the PowerWall screen in the z = 0 plane facing +z. The
// workpiece floats 0.3 m in front of the wall, within the designer's reach (head pose: session.cpp).
const Vec3 kWorkpieceCentre{0.0, 0.0, 0.3};

}  // namespace


namespace {

// The drivers whose hand a demo can drive: every one a person does not move.
bool demo_can_drive(const devices::DriverInfo& d) { return !devices::person_moves_hand(d.caps.input); }

// --device for the demo: a profile of the simulated hand, a driver a script can drive, or NAME:ADDRESS.
devices::DeviceChoice choose_demo_device(const std::string& text) {
    const devices::DeviceRegistry& registry = devices::builtin_registry();
    try {
        return registry.choose(text, "--device", demo_can_drive);
    } catch (const Error& e) {
        const devices::DriverInfo* d = registry.find(text.substr(0, text.find(':')));
        if (d && !demo_can_drive(*d))
            throw Error("--device " + text + ": a person moves this device; the demo plays a scripted stroke (use `tridex "
                        "run --device " + text + "`)");
        throw;
    }
}

// The drivers that load a firmware file.
std::vector<std::string> firmware_drivers() {
    std::vector<std::string> names;
    for (const devices::DriverInfo& d : devices::builtin_registry().drivers())
        if (d.available && d.caps.takes_firmware) names.push_back(d.name);
    return names;
}

// Everything a demo session is made of before its threads start.
struct DemoPlan {
    SessionSpec s;
    std::optional<Workpiece> wp;
    std::optional<StrokePlan> plan;
    haptics::HapticLoopConfig cfg;
    devices::DeviceInputs inputs;
    std::unique_ptr<devices::HapticDevice> net_device;  // --device net:HOST:PORT, connected before the slow work
};

// Checks the options, loads the workpiece and plans the stroke; connect_net: connect to a device server when the
// device is net:HOST:PORT (its profile decides the workspace mapping); chosen: the driver and profile to use instead
// of o.device (a device server's).
DemoPlan plan_demo(const DemoOptions& o, bool connect_net, const devices::DeviceChoice* chosen = nullptr) {
    if (!(o.seconds >= 0.5 && o.seconds <= 600.0))
        throw Error("--seconds: must be between 0.5 and 600, got " + format_number(o.seconds));
    if (!(o.tool_radius_m >= 0.0005 && o.tool_radius_m <= 0.25 * o.stock_m))
        throw Error("--tool-radius-mm: must be between 0.5 mm and a quarter of the stock (" +
                    format_number(250.0 * o.stock_m) + " mm), got " + format_number(o.tool_radius_m * 1e3));
    if (!(o.static_friction >= 0.0 && o.static_friction <= 10.0))
        throw Error("--static-friction: must be between 0 and 10, got " + format_number(o.static_friction));
    if (!(o.dynamic_friction >= 0.0 && o.dynamic_friction <= o.static_friction))
        throw Error("--dynamic-friction: must be between 0 and --static-friction (" + format_number(o.static_friction) +
                    "), got " + format_number(o.dynamic_friction));
    if (!o.workpiece.empty() && !o.mesh.empty()) throw Error("--workpiece, --mesh: choose one");
    DemoPlan d;
    SessionSpec& s = d.s;
    if (!o.workpiece.empty()) s.model_path = fs::absolute(o.workpiece).lexically_normal().string();
    else s.mesh_path = fs::absolute(o.mesh.empty() ? default_mesh_path() : o.mesh).lexically_normal().string();
    s.resolution = o.resolution;
    s.stock_m = o.stock_m;
    s.history_budget_bytes = static_cast<std::size_t>(o.history_mib * 1048576.0);
    s.keep_islands = o.keep_islands;
    s.workpiece_centre_m = kWorkpieceCentre;
    s.tool = ToolShape{parse_tool_kind(o.tool, "--tool"), o.tool_radius_m, 0.0, 0};
    double press_reach_m = o.tool_radius_m;  // from the tool origin to its lowest point along the press direction (+z)
    if (s.tool.kind == ToolKind::kMesh) {
        if (o.tool_mesh.empty()) throw Error("--tool mesh: needs --tool-mesh FILE (a closed mesh)");
        if (!(o.tool_size_m >= 0.001 && o.tool_size_m <= 0.25 * o.stock_m))
            throw Error("--tool-size-mm: must be between 1 mm and a quarter of the stock (" +
                        format_number(250.0 * o.stock_m) + " mm), got " + format_number(o.tool_size_m * 1e3));
        set_tool_mesh(s, o.tool_mesh, o.tool_size_m, "--tool-mesh");
        press_reach_m = tool_mesh_reach_m(load_tool_mesh(s.tool_mesh_path, s.tool_size_m), 2);
    } else if (!o.tool_mesh.empty()) {
        throw Error("--tool-mesh: only with --tool mesh");
    }
    if (s.tool.kind == ToolKind::kFlatEnd) {
        if (!(o.tool_length_m >= 0.0005 && o.tool_length_m <= o.stock_m))
            throw Error("--tool-length-mm: must be between 0.5 mm and the stock (" + format_number(1e3 * o.stock_m) +
                        " mm), got " + format_number(o.tool_length_m * 1e3));
        s.tool.length_m = o.tool_length_m;
    }
    s.points = o.points;
    // The demo's hand plays a scripted stroke: a driver a person moves (the mouse, a 3D mouse, a tracked tool) has no
    // place here (`tridex run`).
    const devices::DeviceChoice choice = chosen ? *chosen : choose_demo_device(o.device);
    const devices::DriverCapabilities& caps = devices::builtin_registry().info(choice.driver).caps;
    s.device_driver = choice.driver;
    s.device = choice.profile.empty() ? DemoOptions{}.device : choice.profile;
    const bool remote = caps.input == devices::InputKind::kRemote;
    if (o.haptic_rendering != "distributed" && !remote)
        throw Error("--haptic-rendering " + o.haptic_rendering + ": only with --device net:HOST:PORT (a device server)");
    if ((!o.key_file.empty() || !o.passphrase_env.empty()) && !caps.seals_link)
        throw Error(std::string(o.key_file.empty() ? "--passphrase-env" : "--key-file") +
                    ": only with --device net:HOST:PORT (a device server whose link is sealed)");
    s.device_key_file = o.key_file;
    s.device_passphrase_env = o.passphrase_env;
    if (remote) {
        s.device_serial = choice.address;
        s.haptic_rendering = o.haptic_rendering;
        s.device = "omni";
        if (connect_net) {
            devices::DeviceInputs in;
            in.period_s = s.period_s;
            d.net_device = make_device(s, in);
            s.device = devices::profile_name_of(d.net_device->profile().name);
            if (s.device.empty())
                throw Error("--device " + o.device + ": the device server serves '" + d.net_device->profile().name +
                            "', whose workspace tridex does not know (omni, wand, 6dof, falcon)");
        }
    }
    if (!o.falcon_firmware.empty() && !caps.takes_firmware)
        throw Error("--falcon-firmware: only with --device " + devices::join_or(firmware_drivers()));
    s.device_firmware = o.falcon_firmware;
    s.workspace_mode = o.workspace;
    s.static_friction = o.static_friction;
    s.dynamic_friction = o.dynamic_friction;
    s.cutting = o.cutting;
    s.op = o.op;
    s.material = o.material;
    s.symmetry = to_string(parse_symmetry(o.symmetry, "--symmetry"));
    const devices::DeviceProfile profile = device_profile(s.device);  // checks --device before the slow work
    // Hardware: "none plugged in", at once, before the slow work.
    if (caps.input == devices::InputKind::kHardware) (void)make_device(s, devices::DeviceInputs{});

    // 1. Workpiece: load, place in the world, scan-convert into the tri-dexel model (or restore a saved model).
    check_session_memory_up_front(s, SessionKind::kBatch);  // a lattice too fine is refused before its scan conversion
    d.wp.emplace(prepare_session_workpiece(s));
    Workpiece& wp = *d.wp;  // checksums of the mesh or model for a replay
    check_session_memory_of(wp.model, wp.resolution, SessionKind::kBatch);  // before its contour, the session's largest part

    // 2. The stroke, the device workspace centred on it, and the simulated device that follows it.
    StrokeParams sp;
    sp.duration_s = o.seconds;
    sp.tool_radius_m = press_reach_m;
    sp.workspace_scale = s.workspace_scale;
    d.plan.emplace(plan_stroke(wp.model, sp));
    const StrokePlan& plan = *d.plan;
    // The device's home (its workspace centre) sits on the stroke's centre.
    const Vec3 home = devices::home_position_m(profile);
    s.device_origin_m = plan.centre_m - s.workspace_scale * home;
    d.cfg = loop_config(s, 0);  // checks the spec before the device is made
    const haptics::HapticLoopConfig& cfg = d.cfg;
    std::vector<Vec3> device_path;
    for (const Vec3& off : plan.device_offsets_m(s.workspace_scale)) device_path.push_back(home + off);
    d.inputs.period_s = cfg.period_s;
    d.inputs.hand_path.emplace(plan.t_s, device_path);
    d.inputs.haptic_rendering = s.haptic_rendering;
    return d;
}

}  // namespace

devices::DeviceInputs demo_device_inputs(const DemoOptions& o, const devices::DeviceChoice& device) {
    if (devices::builtin_registry().info(device.driver).caps.input != devices::InputKind::kScripted)
        throw Error("--device " + device.driver + ": its hand is not scripted; only a scripted hand plays the stroke");
    return plan_demo(o, false, &device).inputs;
}

void run_demo(const DemoOptions& o) {
    const auto t_start = Clock::now();
    check_image_size(o.width, o.height);
    prepare_output_dir(o.out, "--out");
    if (!o.record.empty()) check_output_file(o.record, "--record");
    if (!o.save.empty()) check_output_file(o.save, "--save");
    const std::string journal = o.no_journal ? "" : o.journal.empty() ? (fs::path(o.out) / "session.tdj").string() : o.journal;
    if (!o.journal.empty() && o.no_journal) throw Error("--journal, --no-journal: choose one");
    if (!o.journal.empty()) check_output_file(o.journal, "--journal");
    {
        std::vector<NamedFile> outputs;
        for (const char* name : kSessionOutputFiles)
            outputs.push_back({std::string("--out's ") + name, (fs::path(o.out) / name).string()});
        outputs.push_back({"--record", o.record});
        outputs.push_back({"--save", o.save});
        outputs.push_back({o.journal.empty() ? "the journal (--out's session.tdj)" : "--journal", journal});
        check_distinct_files(outputs, {{"--workpiece", o.workpiece}, {"--mesh", o.mesh}, {"--tool-mesh", o.tool_mesh}});
    }
    if (!(o.checkpoint_s >= 0.0 && o.checkpoint_s <= 86400.0))
        throw Error("--checkpoint-s: must be between 0 (none) and 86400, got " + format_number(o.checkpoint_s));
    if (!(o.history_mib >= 1.0 && o.history_mib <= 1048576.0))
        throw Error("--history-mib: must be between 1 and 1048576, got " + format_number(o.history_mib));
    DemoPlan d = plan_demo(o, true);
    const SessionSpec& s = d.s;
    const haptics::HapticLoopConfig& cfg = d.cfg;
    const StrokePlan& plan = *d.plan;
    Workpiece wp = std::move(*d.wp);
    std::unique_ptr<devices::HapticDevice> device = d.net_device ? std::move(d.net_device) : make_device(s, d.inputs);

    // 3. The haptic loop and the sculpt thread. The session lasts the stroke's length in device time
    // (one simulated step per tick), so an overloaded machine that skips deadlines still plays the whole
    // stroke; wall time is only a safety net.
    const std::size_t ticks = static_cast<std::size_t>(std::llround(o.seconds / cfg.period_s));
    const Vec3 start = plan.world_m.front();
    SculptOptions sculpt{o.cpu, o.validate, o.cpu_contour, o.gpu_contour, journal};
    sculpt.gpu_clay = o.gpu_clay;
    sculpt.gpu = o.gpu;
    sculpt.checkpoint_s = o.checkpoint_s;
    // A clay session reports how far the surface moved: keep the model as it was.
    std::optional<compute::TriDexel> before;
    if (compute::is_clay_op(parse_tool_op(s.op))) before = wp.model;
    SessionRun run = run_session(s, std::move(wp), std::move(device), ticks, static_cast<std::size_t>(o.seconds * 1500.0) + 1000,
                                 3.0 * o.seconds + 10.0, start, sculpt);
    if (before) {
        const compute::TriDexel& after = run.runtime->workpiece().model;
        run.deformation_max_displacement_m =
            compute::clay_max_displacement_cells(*before, after) * after.lattice.cell_m;
    }
    // 4. Images, mesh, per-tick haptics and the report; then the recording and the model. Each is written on its own:
    // one that fails (a disk that filled) is said at once and costs none of the others.
    OutputWrites writes;
    write_session_outputs(OutputOptions{o.out, o.width, o.height, o.validate, o.ao}, run, t_start, writes);
    if (!o.record.empty())
        writes.attempt(o.record, [&] { write_session_recording(o.record, s, run.records, "", run.sculpt.marks,
                                                                run.runtime->pose_changes()); });
    if (!o.save.empty()) writes.attempt(o.save, [&] { save_session_model(o.save, run.runtime->workpiece(), s); });
    if (run.device_lost_at_s) {
        std::string kept;
        for (const std::string& f : writes.written()) kept += (kept.empty() ? "" : ", ") + f;
        if (!journal.empty()) kept += (kept.empty() ? "the journal " : ", the journal ") + journal;
        throw DeviceLostError("--device " + o.device + ": the " + run.runtime->profile().name + " was lost " +
                              format_number(*run.device_lost_at_s) +
                              " s into the session; the session ended there and kept its work: " +
                              (kept.empty() ? std::string("nothing could be written") : kept));
    }
    writes.finish(o.out);
}

}  // namespace tridex::app
