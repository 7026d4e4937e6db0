// haptics/haptic_loop_workpieces.cpp - the haptic loop's workpieces: the contact against each one's snapshot in its
// model frame (and the scene objects beside them), which one the tool carves, and each tick's sample handed to each.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <limits>
#include <thread>

#include "haptics/forces/force_clamp.hpp"
#include "haptics/haptic_loop.hpp"
#include "haptics/realtime.hpp"

namespace tridex::haptics {

HapticLoop::ContactOut HapticLoop::contact(const Pose& tool_world, double dt_s) {
    ContactOut out;
    // Each workpiece's surface is in its model frame: the tool goes there, the wrench comes back; while carving, the
    // contact reads the snapshot with the tool's own sweeps it does not hold yet cut away.
    for (const std::unique_ptr<Piece>& pp : pieces_) {
        Piece& p = *pp;
        const ActiveSurface& surface = p.cuts.apply(p.surface->latest(), *p.cut_surface);
        const MultiPointResult& r = p.contact->update(surface, p.model_from_world * tool_world, dt_s);
        p.result = &r;
        p.touched = r.in_contact > 0;
        out.force_n += p.world_from_model.rotate(r.wrench.force_n);
        out.torque_nm += p.world_from_model.rotate(r.wrench.torque_nm);  // about the tool centre
        out.in_contact += r.in_contact;
    }
    // The proxy and the points shown are the target's, or the first workpiece touched when the target is not.
    const Piece* shown = pieces_[target_].get();
    for (std::size_t i = 0; !shown->touched && i < pieces_.size(); ++i)
        if (pieces_[i]->touched) shown = pieces_[i].get();
    const MultiPointResult& r = *shown->result;
    out.proxy_m = r.points > 0 ? shown->world_from_model.apply(r.point[0].proxy_m) : tool_world.position;
    out.contact = out.in_contact > 0;
    out.hip_inside = r.points > 0 && r.point[0].hip_inside;
    out.points = &r;
    out.points_pose = &shown->world_from_model;
    // The scene objects: each point's penetration of an elastic sphere's undeformed surface or of a reference object's
    // distance field, pushed back by its penalty force (no allocation: fixed-size contacts).
    const auto add = [&](const ElasticContacts& oc, double stiffness_n_per_m) {
        if (oc.count == 0) return;
        const Vec3 f = penetration_force(stiffness_n_per_m, oc, limits_.max_force_n);
        out.force_n += f;
        out.object_force_n += f;
        out.in_contact += oc.count;
        out.contact = true;
    };
    const ToolPoints& points = pieces_[0]->contact->tool_points();
    for (const ElasticSphere& e : cfg_.elastic_objects)
        add(elastic_contacts(e, points, tool_world), e.stiffness_n_per_m);
    for (const ReferenceObject& o : cfg_.reference_objects)
        add(reference_contacts(o, points, tool_world), o.stiffness_n_per_m);
    return out;
}

void HapticLoop::reset_contact() {
    for (const std::unique_ptr<Piece>& p : pieces_) p->contact->reset();
}

bool HapticLoop::choose_workpiece(int index) {
    if (index < -1 || index >= static_cast<int>(pieces_.size())) return false;
    chosen_.store(index, std::memory_order_relaxed);
    return true;
}

std::size_t HapticLoop::pick_target(const Pose& tool_world, bool keep) const {
    if (keep) return target_;
    const int chosen = chosen_.load(std::memory_order_relaxed);
    if (chosen >= 0 && chosen < static_cast<int>(pieces_.size())) return static_cast<std::size_t>(chosen);
    if (pieces_[target_]->touched) return target_;
    for (std::size_t i = 0; i < pieces_.size(); ++i)
        if (pieces_[i]->touched) return i;
    // The workpiece whose lattice box is nearest the tool centre (in its model frame); the target on a tie.
    std::size_t best = target_;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
        const Aabb& b = pieces_[i]->bounds_m;
        if (b.empty()) continue;
        const Vec3 p = pieces_[i]->model_from_world.apply(tool_world.position);
        const double d = glm::length(glm::max(glm::max(b.lo - p, p - b.hi), Vec3(0.0)));
        if (d < best_d || (d == best_d && i == target_)) {
            best = i;
            best_d = d;
        }
    }
    return best;
}

bool HapticLoop::set_workpiece_pose(int index, const Pose& pose) {
    if (index < 0 || static_cast<std::size_t>(index) >= pieces_.size()) return false;
    if (!is_rigid(pose)) return false;
    if (pose_sets_sent_ >= kMaxPoseChanges) return false;
    if (!pose_sets_.try_push(PoseChange{0, 0.0, static_cast<std::uint8_t>(index), pose})) return false;
    ++pose_sets_sent_;
    return true;
}

void HapticLoop::apply_pose_changes(double device_t_s) {
    if (placing_) return;  // the hand holds a workpiece: a set waits in the ring until it lets go
    const std::uint64_t tick = ticks_.load(std::memory_order_relaxed);  // this tick's index (finish() counts it)
    PoseChange c;
    if (pose_sets_.try_pop(c)) {
        c.tick = tick;
        c.device_t_s = device_t_s;
        take_pose(c);
    }
    const std::vector<PoseChange>& sched = cfg_.pose_schedule;
    for (; next_pose_change_ < sched.size() && sched[next_pose_change_].tick <= tick; ++next_pose_change_) {
        c = sched[next_pose_change_];
        c.tick = tick;
        c.device_t_s = device_t_s;
        take_pose(c);
    }
}

void HapticLoop::take_pose(const PoseChange& c) {
    if (c.workpiece >= pieces_.size()) return;  // a replay checks its schedule against the workpieces first
    Piece& p = *pieces_[c.workpiece];
    p.world_from_model = c.pose;
    p.model_from_world = c.pose.inverse();
    p.carve_gap = true;  // no sweep from the old frame's sample to the new one's
    reset_contact();     // the proxy starts over where the tool is
    target_held_ = false;
    if (pose_changes_.size() < pose_changes_.capacity()) pose_changes_.push_back(c);
    pose_taken_.fetch_add(1, std::memory_order_acq_rel);
}

void HapticLoop::push_sample(const devices::DeviceState& state, const Pose& tool_world, const ContactOut& c, bool hold,
                             bool gap, TickRecord& rec) {
    const std::uint16_t op = op_.load(std::memory_order_relaxed);
    const ToolOp chosen = static_cast<ToolOp>(op & 0xffu);
    rec.op = chosen;
    rec.material = static_cast<std::uint8_t>(op >> 8);
    rec.symmetry = symmetry_from_bits(symmetry_.load(std::memory_order_relaxed));
    rec.tool = tool_;
    rec.workpiece = static_cast<std::uint8_t>(target_);
    const double made_s = static_cast<double>(monotonic_ns()) * 1e-9;  // std::chrono::steady_clock's time on Linux
    // A free-running loop (a replay) stays at most kFreeRunLead samples ahead of each sculpt thread, as a paced loop
    // that the sculpt threads keep up with does: every sample reaches them, and the surfaces the contact reads are as
    // recent as in the session.
    const auto behind = [&] {
        for (const std::unique_ptr<Piece>& p : pieces_)
            if (p->samples->size() >= kFreeRunLead) return true;
        return false;
    };
    while (cfg_.free_run && behind() && !stop_requested_.load(std::memory_order_acquire))
        std::this_thread::sleep_for(std::chrono::microseconds(50));
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
        Piece& p = *pieces_[i];
        ToolSample sample;
        sample.t_s = state.t_s;
        sample.made_s = made_s;
        // Each workpiece's sculpt thread carves it in its model frame.
        const Pose tool_model = p.model_from_world * tool_world;
        sample.position = tool_model.position;
        {
            Vec3 offset(0.0);
            if (p.result) offset = p.result->point[0].proxy_m - p.result->point[0].world_m;
            else if (i == 0) offset = p.model_from_world.rotate(c.proxy_m - tool_world.position);
            sample.surface_m = is_finite(offset) ? sample.position + offset : sample.position;
        }
        sample.orientation = tool_model.orientation;
        sample.tool = tool_;
        // kPlace moves the pose, never the material: its samples carve nothing. Only the target is carved.
        sample.op = hold || p.carve_gap || chosen == ToolOp::kPlace || i != target_ ? ToolOp::kNone : chosen;
        sample.material = rec.material;
        sample.symmetry = rec.symmetry;
        sample.buttons = state.buttons;
        const bool pushed = p.samples->try_push(sample);
        if (!pushed) dropped_.fetch_add(1, std::memory_order_relaxed);
        if (pushed && p.tap && !p.tap->try_push(SequencedSample{p.pushed, sample}))
            tap_dropped_.fetch_add(1, std::memory_order_relaxed);
        p.cuts.note(sample, pushed);
        if (pushed) ++p.pushed;
        if (i == 0 && pushed && p.pushed == cfg_.fault_kill_at_sample) ::kill(::getpid(), SIGKILL);
        // The sculpt thread sweeps from the last sample it got: after a non-carving sample it never got (a pause, a
        // jump, an open menu), the next sample must not carve either, or its sweep would bridge the whole stretch.
        p.carve_gap = !pushed && sample.op == ToolOp::kNone;
        // A stroke carving the target where the tool touches it, or a placement, keeps it the target.
        if (i == target_) target_held_ = placing_ || (sample.op != ToolOp::kNone && p.touched);
    }
    carve_gap_ = gap;
}

}  // namespace tridex::haptics
