// compute/history/undo_history.cpp - before-image undo and redo per stroke.
#include "compute/history/undo_history.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

bool same_ray(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].enter != b[i].enter || a[i].exit != b[i].exit || a[i].enter_material != b[i].enter_material ||
            a[i].exit_material != b[i].exit_material)
            return false;
    }
    return true;
}

// Lattice node index range [lo, hi] along `axis` covering world [a, b] (m), clamped to the lattice; empty when lo > hi.
void node_range(const Lattice& l, int axis, double a, double b, int& lo, int& hi) {
    const double ga = (a - l.origin_m[axis]) / l.cell_m, gb = (b - l.origin_m[axis]) / l.cell_m;
    const double last = static_cast<double>(l.nodes(axis) - 1);
    lo = static_cast<int>(std::clamp(std::floor(ga), 0.0, last + 1.0));
    hi = static_cast<int>(std::clamp(std::ceil(gb), -1.0, last));
}

}  // namespace

UndoHistory::UndoHistory(const Lattice& lattice, std::size_t budget_bytes, std::uint64_t last_serial)
    : lattice_(lattice), budget_(budget_bytes), serial_(last_serial) {
    if (budget_bytes == 0) throw Error("undo history: the budget must be > 0 bytes");
    for (int a = 0; a < 3; ++a) {
        const std::size_t rays = static_cast<std::size_t>(lattice.nodes((a + 1) % 3)) * static_cast<std::size_t>(lattice.nodes((a + 2) % 3));
        copied_[a].assign(rays, 0u);
    }
    counts_.budget_bytes = budget_;
}

std::size_t UndoHistory::image_bytes(const RayImage& r) {
    return sizeof(RayImage) + r.intervals.capacity() * sizeof(Interval);
}

void UndoHistory::trim(std::size_t extra) {
    while (bytes_ + extra > budget_ && !undo_.empty()) {
        bytes_ -= undo_.front().bytes;
        undo_.pop_front();
        ++counts_.dropped_steps;
    }
    while (bytes_ + extra > budget_ && !redo_.empty()) {
        bytes_ -= redo_.front().bytes;
        redo_.pop_front();
        ++counts_.dropped_steps;
    }
}

void UndoHistory::capture(const TriDexel& model, std::span<const Sweep> batch) {
    for (const Sweep& s : batch) {
        if (s.op == ToolOp::kNone) continue;
        if (!open_) {
            open_ = true;
            oversize_ = false;
            open_step_ = Step{};
            if (++stamp_ == 0) {  // wrapped: forget every old stamp
                for (auto& c : copied_) std::fill(c.begin(), c.end(), 0u);
                stamp_ = 1;
            }
        }
        // A clay sweep (push, smooth, pull, grab) may change rays beyond its tool: the box of its radius of influence.
        const Aabb box = is_clay_op(s.op) ? clay_bounds(lattice_, s) : sweep_bounds(s).inflated(lattice_.cell_m);
        if (!is_finite(box.lo) || !is_finite(box.hi)) continue;
        open_step_.box_m.add(box.lo);
        open_step_.box_m.add(box.hi);
        if (oversize_) continue;
        for (int a = 0; a < 3; ++a) {
            const int ua = (a + 1) % 3, va = (a + 2) % 3;
            int u0, u1, v0, v1;
            node_range(lattice_, ua, box.lo[ua], box.hi[ua], u0, u1);
            node_range(lattice_, va, box.lo[va], box.hi[va], v0, v1);
            const RaySet& set = model.sets[a];
            for (int v = v0; v <= v1 && !oversize_; ++v)
                for (int u = u0; u <= u1 && !oversize_; ++u)
                    copy_ray(model, a, static_cast<std::size_t>(u) + static_cast<std::size_t>(set.nu) * static_cast<std::size_t>(v));
            if (oversize_) break;
        }
    }
}

void UndoHistory::copy_ray(const TriDexel& model, int a, std::size_t i) {
    if (copied_[a][i] == stamp_) return;
    copied_[a][i] = stamp_;
    RayImage img{static_cast<std::uint8_t>(a), static_cast<std::uint32_t>(i), model.sets[a].rays[i]};
    const std::size_t b = image_bytes(img);
    if (bytes_ + b > budget_) trim(b);
    if (bytes_ + b > budget_) {  // the open stroke alone outgrew the budget: stop keeping it
        bytes_ -= open_step_.bytes;
        open_step_.rays = {};
        open_step_.bytes = 0;
        oversize_ = true;
        return;
    }
    open_step_.bytes += b;
    bytes_ += b;
    open_step_.rays.push_back(std::move(img));
}

bool UndoHistory::capture_rays(const TriDexel& model, std::span<const RayImage> rays, const Aabb& box_m) {
    if (!open_) return false;
    for (const RayImage& r : rays)
        if (r.axis > 2 || r.index >= model.sets[r.axis].rays.size())
            throw Error("undo history: ray image outside the model (axis " + std::to_string(r.axis) + ", ray " +
                        std::to_string(r.index) + ")");
    if (!box_m.empty()) {
        open_step_.box_m.add(box_m.lo);
        open_step_.box_m.add(box_m.hi);
    }
    for (const RayImage& r : rays) {
        if (oversize_) break;
        copy_ray(model, r.axis, r.index);
    }
    return true;
}

std::uint64_t UndoHistory::end_stroke(const TriDexel& model) {
    if (!open_) return 0;
    open_ = false;
    const std::uint64_t serial = ++serial_;
    Step step = std::move(open_step_);
    open_step_ = Step{};
    bytes_ -= step.bytes;
    if (oversize_) {
        oversize_ = false;
        ++counts_.oversize_strokes;
        // The model changed in a way no step records: older steps can no longer be restored over it.
        counts_.dropped_steps += undo_.size() + redo_.size();
        for (const Step& s : undo_) bytes_ -= s.bytes;
        for (const Step& s : redo_) bytes_ -= s.bytes;
        undo_.clear();
        redo_.clear();
        return serial;
    }
    // Keep only the rays the stroke changed.
    std::size_t kept = 0;
    step.bytes = 0;
    for (RayImage& r : step.rays) {
        if (same_ray(r.intervals, model.sets[r.axis].rays[r.index])) continue;
        if (&step.rays[kept] != &r) step.rays[kept] = std::move(r);
        step.bytes += image_bytes(step.rays[kept]);
        ++kept;
    }
    step.rays.resize(kept);
    if (kept == 0) return serial;
    step.rays.shrink_to_fit();
    step.serial = serial;
    step.bytes += sizeof(Step);
    for (const Step& s : redo_) bytes_ -= s.bytes;
    redo_.clear();
    trim(step.bytes);
    bytes_ += step.bytes;  // kept even when alone over the budget: it fitted while it was captured
    undo_.push_back(std::move(step));
    ++counts_.strokes;
    return serial;
}

UndoHistory::Change UndoHistory::swap_in(Step& step, const TriDexel& model, const RayWriter& write) {
    // The rays' current images become the step's (for the opposite operation); the stored ones are written.
    std::vector<RayImage> out;
    out.reserve(step.rays.size());
    std::size_t bytes = sizeof(Step);
    for (RayImage& r : step.rays) {
        RayImage now{r.axis, r.index, model.sets[r.axis].rays[r.index]};
        bytes += image_bytes(now);
        out.push_back(std::exchange(r, std::move(now)));
    }
    write(out, step.box_m);
    bytes_ = bytes_ - step.bytes + bytes;
    step.bytes = bytes;
    return Change{step.serial, out.size(), step.box_m};
}

void UndoHistory::drop_redo() {
    for (const Step& s : redo_) bytes_ -= s.bytes;
    redo_.clear();
}

UndoHistory::Change UndoHistory::undo(const TriDexel& model, const RayWriter& write) {
    end_stroke(model);
    if (undo_.empty()) return {};
    Step step = std::move(undo_.back());
    undo_.pop_back();
    const Change c = swap_in(step, model, write);
    redo_.push_back(std::move(step));
    ++counts_.undos;
    return c;
}

UndoHistory::Change UndoHistory::redo(const TriDexel& model, const RayWriter& write) {
    end_stroke(model);
    if (redo_.empty()) return {};
    Step step = std::move(redo_.back());
    redo_.pop_back();
    const Change c = swap_in(step, model, write);
    undo_.push_back(std::move(step));
    ++counts_.redos;
    return c;
}

bool UndoHistory::swap_open_images(TriDexel& model) {
    if (!open_ || oversize_) return false;
    for (RayImage& r : open_step_.rays) model.sets[r.axis].rays[r.index].swap(r.intervals);
    return true;
}

HistoryStats UndoHistory::stats() const {
    HistoryStats s = counts_;
    s.budget_bytes = budget_;
    s.bytes = bytes_;
    s.undo_steps = undo_.size();
    s.redo_steps = redo_.size();
    return s;
}

}  // namespace tridex::compute
