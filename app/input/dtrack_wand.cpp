// app/input/dtrack_wand.cpp - DTrack Flystick as the Wand.
#include "app/input/dtrack_wand.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "app/input/dtrack_head.hpp"
#include "core/error.hpp"

namespace tridex::app {

void parse_dtrack_wand_option(const std::string& value, int& port, int& flystick) {
    const std::string_view v(value);
    const std::string usage = " (expected dtrack:PORT[:FLYSTICK], e.g. dtrack:5000:0)";
    if (v.rfind("dtrack:", 0) != 0) throw Error("--wand: '" + value + "' is not dtrack:PORT[:FLYSTICK]" + usage);
    parse_port_and_id(v.substr(7), "--wand", "Flystick id", devices::kDTrackKeptFlysticks, usage, port, flystick);
}

void parse_tracked_tool_address(const devices::DriverInfo& driver, const std::string& address, int& port, int& id) {
    const std::string& name = driver.name;
    const std::string usage = " (expected " + name + "[:PORT[:ID]], e.g. " + name + ":5000:" +
                              std::to_string(std::min(2, driver.caps.target_ids - 1)) + ")";
    if (!address.empty())
        parse_port_and_id(address, "--device", driver.caps.target_kind + " id", driver.caps.target_ids, usage, port, id);
}

DTrackWand::DTrackWand(const DTrackWandSettings& s, std::shared_ptr<devices::DTrackReceiver> shared)
    : settings_(s), receiver_(std::move(shared)), shared_(receiver_ != nullptr) {
    if (s.flystick < 0 || s.flystick >= devices::kDTrackKeptFlysticks)
        throw Error("DTrack wand Flystick " + std::to_string(s.flystick) + ": must be in 0.." +
                    std::to_string(devices::kDTrackKeptFlysticks - 1));
    if (!std::isfinite(s.timeout_s) || !(s.timeout_s > 0.0))
        throw Error("DTrack wand: timeout_s must be finite and > 0 (s)");
    if (!receiver_) receiver_ = std::make_shared<devices::DTrackReceiver>(s.port, s.bind_address);
}

WandSample DTrackWand::sample() {
    const devices::DTrackFlystickSample& f = receiver_->latest().flysticks[static_cast<std::size_t>(settings_.flystick)];
    WandSample w;
    if (!f.seen) {
        why_ = "no sample of this Flystick yet";
    } else if (!f.flystick.body.tracked()) {
        why_ = "not tracked (quality -1)";
    } else if (static_cast<double>(devices::dtrack_clock_ns() - f.receipt_ns) * 1e-9 > settings_.timeout_s) {
        why_ = "stale (no datagram for more than " + std::to_string(settings_.timeout_s) + " s)";
    } else {
        why_ = "tracked";
        w.fresh = true;
        w.pose = settings_.tracker_to_wall * f.flystick.body.pose();
        w.buttons = f.flystick.buttons;
        w.joystick_y = f.flystick.controller_count >= 2 ? f.flystick.controllers[1] : 0.0;
    }
    if (w.fresh) ++frames_tracked_;
    else ++frames_stale_;
    return w;
}

std::string DTrackWand::note() const {
    return "DTrack Flystick " + std::to_string(settings_.flystick) + " on UDP port " + std::to_string(port()) + ": " +
           why_;
}

nlohmann::json DTrackWand::report_json() const {
    return nlohmann::json{{"provider", "dtrack"},
                          {"port", port()},
                          {"flystick", settings_.flystick},
                          {"shared_receiver", shared_},
                          {"frames_tracked", frames_tracked_},
                          {"frames_stale", frames_stale_},
                          {"note", note()}};
}

nlohmann::json wand_report_json(const DTrackWand& wand, const WandNavigator& w, const renderer::SceneNavigation& nav) {
    nlohmann::json j = wand.report_json();
    const Vec3 p = nav.pose().position;
    j["grabs"] = w.grabs();
    j["grabs_dropped"] = w.grabs_dropped();
    j["resets"] = w.resets();
    j["scaled_by"] = w.scaled_by();
    j["final_scale"] = nav.scale();
    j["final_position_m"] = nlohmann::json::array({p.x, p.y, p.z});
    return j;
}

}  // namespace tridex::app
