// app/session/record/session_recording.cpp - loop records -> recording file.
#include "app/session/record/session_recording.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/input/mouse_stylus.hpp"
#include "core/error.hpp"

namespace tridex::app {

static_assert(devices::kMaxRecordedWorkpieces == static_cast<int>(haptics::kMaxLoopWorkpieces),
              "a recording holds the workpiece index of any haptic loop");


std::string recorded_tool_problem(const ToolShape& session_tool, const ToolShape& used) {
    if (used.kind != session_tool.kind || !(used.radius_m > 0.0)) return "";
    const double k = std::pow(MouseStylus::kSizeStep, MouseStylus::kMaxSizeSteps) * (1.0 + 1e-9);
    const auto outside = [&](const char* field, double v, double base) -> std::string {
        if (used.kind == ToolKind::kMesh || (v >= base / k && v <= base * k)) return "";
        char buf[200];
        std::snprintf(buf, sizeof buf, "tool.%s = %.9g m is outside what the session's tool takes (%.9g to %.9g m)",
                      field, v, base / k, base * k);
        return buf;
    };
    std::string e = outside("radius_m", used.radius_m, session_tool.radius_m);
    if (e.empty() && used.kind == ToolKind::kFlatEnd) e = outside("length_m", used.length_m, session_tool.length_m);
    return e;
}

devices::RecordedTick to_recorded_tick(const haptics::TickRecord& r, ToolOp op, double prev_t_s, int tool_points) {
    devices::RecordedTick t;
    const double dev_t = r.device.t_s;
    t.t_s = (std::isfinite(dev_t) && dev_t > prev_t_s) ? dev_t : std::nextafter(prev_t_s, INFINITY) + 1e-9;
    t.device = r.device;
    t.wand_centre_m = r.tool_world.position;
    devices::to_axis_angle(r.tool_world.orientation, t.rotation_axis, t.rotation_angle_rad);
    const haptics::PointRecord& top = r.points[0];
    // A single-point tool has no second point: the bottom repeats the top, free.
    const haptics::PointRecord bottom =
        tool_points >= 2 ? r.points[1] : haptics::PointRecord{top.world_m, top.world_m, Vec3(0.0), 0.0, -1};
    t.top_m = top.world_m;
    t.bottom_m = bottom.world_m;
    t.top_contact_m = top.proxy_m;
    t.bottom_contact_m = bottom.proxy_m;
    t.top_deviation_m = top.depth_m;
    t.bottom_deviation_m = bottom.depth_m;
    t.top_force_n = top.force_n;
    t.bottom_force_n = bottom.force_n;
    t.force_n = r.force_n;
    t.torque_nm = r.torque_nm;
    t.top_collision_id = top.collision_id;
    t.bottom_collision_id = bottom.collision_id;
    t.buttons = r.device.buttons;
    const bool has_tool = r.valid_sample && r.tool.radius_m > 0.0;
    // While the pie menu was open the samples carried no operation: recorded so, a replay's tool schedule (below)
    // carries none there either, whatever buttons the device held.
    const ToolOp used = r.menu_open ? ToolOp::kNone : has_tool ? r.op : op;
    t.tool_mode = static_cast<std::uint8_t>(r.modelling_paused ? ToolOp::kNone : used);
    t.valid = r.valid_sample ? 1 : 0;
    t.op = static_cast<std::uint8_t>(used);
    t.workpiece = r.workpiece;
    if (has_tool) {
        t.material = r.material;
        t.tool = r.tool;
        t.tool.mesh_id = 0;
        t.symmetry = r.symmetry;
    }
    return t;
}

std::vector<haptics::ToolChange> tool_schedule(const devices::Recording& rec, const SessionSpec& spec) {
    std::vector<haptics::ToolChange> out;
    haptics::ToolChange now;
    now.op = parse_tool_op(spec.op);
    now.material = static_cast<std::uint8_t>(spec.material);
    now.tool = spec.tool;
    now.symmetry = parse_symmetry(spec.symmetry, "symmetry");
    now.workpiece = -1;  // the first tick that names its workpiece sets it (recordings from version 4)
    for (std::size_t i = 0; i < rec.ticks.size(); ++i) {
        const devices::RecordedTick& t = rec.ticks[i];
        if (t.valid != 1 || !(t.tool.radius_m > 0.0)) continue;
        const std::string bad = recorded_tool_problem(spec.tool, t.tool);
        if (!bad.empty()) throw Error("tick " + std::to_string(i) + ": " + bad);
        haptics::ToolChange c = now;
        c.device_t_s = t.device.t_s;
        c.op = static_cast<ToolOp>(t.op);
        c.material = t.material;
        c.symmetry = t.symmetry;
        if (t.workpiece >= 0) c.workpiece = t.workpiece;
        if (t.tool.kind == spec.tool.kind) {
            c.tool.radius_m = t.tool.radius_m;
            c.tool.length_m = t.tool.length_m;
        }
        if (c.op == now.op && c.material == now.material && c.symmetry == now.symmetry && c.tool.radius_m == now.tool.radius_m &&
            c.tool.length_m == now.tool.length_m && c.workpiece == now.workpiece)
            continue;
        out.push_back(c);
        now = c;
    }
    return out;
}

std::vector<devices::RecordedMark> recorded_marks(std::span<const SculptMark> marks,
                                                  std::span<const std::vector<SculptMark>> more) {
    const auto kind_of = [](SculptRequest r) {
        return r == SculptRequest::kUndo      ? "undo"
               : r == SculptRequest::kRedo    ? "redo"
               : r == SculptRequest::kFiner   ? "finer"
               : r == SculptRequest::kCoarser ? "coarser"
                                              : "end_stroke";
    };
    std::vector<devices::RecordedMark> out;
    out.reserve(marks.size());
    for (const SculptMark& m : marks) out.push_back({m.after_samples, kind_of(m.request), 0});
    for (std::size_t k = 0; k < more.size(); ++k)
        for (const SculptMark& m : more[k])
            out.push_back({m.after_samples, kind_of(m.request), static_cast<std::uint8_t>(k + 1)});
    // One order for all: by samples, then by workpiece (each workpiece's own marks keep their order).
    std::stable_sort(out.begin(), out.end(), [](const devices::RecordedMark& a, const devices::RecordedMark& b) {
        return a.after_samples != b.after_samples ? a.after_samples < b.after_samples : a.workpiece < b.workpiece;
    });
    return out;
}

std::optional<std::vector<SculptMark>> sculpt_marks(const devices::RecordingHeader& header, std::uint8_t workpiece) {
    if (!header.marks) return std::nullopt;
    std::vector<SculptMark> out;
    for (const devices::RecordedMark& m : *header.marks) {
        if (m.workpiece != workpiece) continue;
        const SculptRequest r = m.kind == "undo"      ? SculptRequest::kUndo
                                : m.kind == "redo"    ? SculptRequest::kRedo
                                : m.kind == "finer"   ? SculptRequest::kFiner
                                : m.kind == "coarser" ? SculptRequest::kCoarser
                                                      : SculptRequest::kEndStroke;
        out.push_back({m.after_samples, r});
    }
    return out;
}

devices::Recording session_recording(const SessionSpec& settings, const std::vector<haptics::TickRecord>& records) {
    devices::Recording rec;
    rec.header.device_name = device_profile(settings.device).name;
    rec.header.period_s = settings.period_s;
    rec.header.workspace_mode = settings.workspace_mode;
    rec.header.notes = spec_to_json(settings);
    rec.ticks.reserve(records.size());
    double prev = -INFINITY;
    const ToolOp op = parse_tool_op(settings.op);
    for (const haptics::TickRecord& r : records) {
        rec.ticks.push_back(to_recorded_tick(r, op, prev, settings.points));
        prev = rec.ticks.back().t_s;
    }
    return rec;
}

devices::RecordingHeader recording_header(const SessionSpec& settings, const std::string& notes,
                                          std::span<const SculptMark> marks,
                                          std::span<const std::vector<SculptMark>> more_marks,
                                          std::span<const haptics::PoseChange> poses) {
    devices::RecordingHeader header;
    header.device_name = device_profile(settings.device).name;
    header.period_s = settings.period_s;
    header.workspace_mode = settings.workspace_mode;
    header.notes = notes.empty() ? spec_to_json(settings) : notes;
    header.marks = recorded_marks(marks, more_marks);
    for (const haptics::PoseChange& c : poses) header.poses.push_back({c.tick, c.device_t_s, c.workpiece, c.pose});
    return header;
}

std::vector<haptics::PoseChange> pose_schedule(const devices::RecordingHeader& header, std::size_t workpieces) {
    std::vector<haptics::PoseChange> out;
    for (std::size_t k = 0; k < header.poses.size(); ++k) {
        const devices::RecordedPose& p = header.poses[k];
        if (p.workpiece >= workpieces)
            throw Error("poses[" + std::to_string(k) + "].workpiece = " + std::to_string(p.workpiece) +
                        ", but the session has " + std::to_string(workpieces) + " workpiece" +
                        (workpieces == 1 ? "" : "s"));
        out.push_back({p.tick, p.device_t_s, p.workpiece, p.pose});
    }
    return out;
}

void write_session_recording(const std::string& path, const SessionSpec& settings,
                             const std::vector<haptics::TickRecord>& records, const std::string& notes,
                             std::span<const SculptMark> marks, std::span<const haptics::PoseChange> poses) {
    devices::RecordingWriter writer(path, recording_header(settings, notes, marks, {}, poses));
    double prev = -INFINITY;
    for (const haptics::TickRecord& r : records) {
        const devices::RecordedTick t = to_recorded_tick(r, parse_tool_op(settings.op), prev, settings.points);
        writer.write(t);
        prev = t.t_s;
    }
    writer.close();
}

}  // namespace tridex::app
