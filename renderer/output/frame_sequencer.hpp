// renderer/output/frame_sequencer.hpp - frame-sequential (active shutter) stereo: which eye each present shows.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>

namespace tridex::renderer {

/// Sequences the eyes of frame-sequential stereo: the display shows present n for the shutter
/// shutter_for_present(n) = n mod 2 (0 = left shutter open on even presents, 1 = right on odd ones), at the
/// display's refresh rate (120 Hz on the PowerWall, i.e. 60 Hz per eye). The image presented is
/// eye_for_present(n): the shutter's own eye, or the other one when swap eyes is on (fixes glasses that open
/// the wrong way round). An emitter hook (on_eye) is told each present's shutter.
///
/// Thread safety: set_swap_eyes() / swap_eyes() may be called from any thread (an input thread toggles it);
/// on_eye() must be set before presenting starts; present() is called by the one presenting thread.
class FrameSequencer {
public:
    /// `refresh_hz`: the display's present rate in Hz (each eye then runs at refresh_hz / 2).
    /// Throws tridex::Error when refresh_hz is not finite or not in (0, 1000].
    explicit FrameSequencer(double refresh_hz = 120.0, bool swap_eyes = false);

    FrameSequencer(const FrameSequencer&) = delete;
    FrameSequencer& operator=(const FrameSequencer&) = delete;

    /// The shutter open during present n: n mod 2 (0 = left, 1 = right).
    int shutter_for_present(std::uint64_t n) const;
    /// The eye whose image present n shows: shutter_for_present(n), flipped when swap_eyes() is on.
    int eye_for_present(std::uint64_t n) const;
    /// Switches eye swapping on or off (takes effect at the next present).
    void set_swap_eyes(bool swap);
    /// True when eyes are swapped.
    bool swap_eyes() const;
    /// Installs the emitter hook, called by present() with (shutter eye 0/1, present index); replaces any earlier one.
    void on_eye(std::function<void(int eye, std::uint64_t present)> hook);

    /// Call once per present, just before queueing it on the vsync'd swapchain: returns the eye whose image
    /// this present must show (eye_for_present of the current index), calls the hook with the shutter eye and
    /// the index, then advances the present counter.
    int present();
    /// Number of present() calls so far (the index the next present() uses).
    std::uint64_t presents() const;

    /// The display's refresh rate, Hz.
    double refresh_hz() const;
    /// The rate each eye is refreshed at, refresh_hz() / 2, Hz.
    double per_eye_hz() const;
    /// The time of present n after present 0, n / refresh_hz(), s.
    double present_time_s(std::uint64_t n) const;
    /// The index of the present on screen at time t_s >= 0 after present 0: floor(t_s * refresh_hz() + 1e-9)
    /// (the 1e-9 makes present_at(present_time_s(n)) == n despite rounding).
    /// Throws tridex::Error when t_s is negative or not finite.
    std::uint64_t present_at(double t_s) const;

private:
    double refresh_hz_;
    std::atomic<bool> swap_eyes_;
    std::uint64_t presents_ = 0;
    std::function<void(int, std::uint64_t)> hook_;
};

}  // namespace tridex::renderer
