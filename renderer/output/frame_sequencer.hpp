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
/// A missed present (a frame that came late, so the display showed the previous image for one refresh more while
/// the emitter kept toggling the shutters on every refresh) would leave every later image on the wrong eye if
/// eyes simply alternated per present. So the sequencer follows the display's refresh count: present() shows the
/// eye of the shutter open at the refresh the present is expected on (the one after the previous present's), and
/// presented() / presented_at_refresh() tell it when a present was actually shown (from present timing or a
/// display frame counter); a present shown k refreshes after the previous one counts k - 1 missed refreshes and
/// moves the expected refresh on, so the eye order is right again from the next present. Without those calls
/// the refresh count advances by one per present (shutter_for_present(n) = n mod 2).
///
/// Thread safety: set_swap_eyes() / swap_eyes() may be called from any thread (an input thread toggles it);
/// on_eye() must be set before presenting starts; present() and presented*() are called by the one presenting
/// thread.
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

    /// The shutter open at the refresh the next present is expected on (0 = left, 1 = right): n mod 2 for present
    /// n while no present was missed.
    int next_shutter() const;
    /// The eye whose image the next present must show: next_shutter(), flipped when swap_eyes() is on.
    int next_eye() const;
    /// Call once per present, just before queueing it on the vsync'd swapchain: returns the eye whose image
    /// this present must show (next_eye()), calls the hook with the shutter eye and the present index, then
    /// advances the present counter and expects the next present one refresh later.
    int present();
    /// After the last present() was shown: `t_s` is when (s, any monotonic clock; e.g. the time the present
    /// call returned under vsync). The display's refresh then is round((t_s - t_first) * refresh_hz) after the
    /// first present timed (t_first); when that is later than the refresh the present was expected on, the
    /// difference is counted as missed refreshes and the refresh count (and so the next eye) moves on by it.
    /// Earlier (a present queued ahead) changes nothing. An estimate: timing jitter of half a refresh reads as
    /// a miss. Non-finite or decreasing times are ignored (returns false); returns true otherwise.
    bool presented(double t_s);
    /// After the last present() was shown, from a display frame counter: `refresh` is the display's refresh
    /// number (any origin, increasing by one per refresh). As presented(), counting refresh - previous - 1
    /// missed refreshes. A counter that does not increase is ignored (returns false).
    bool presented_at_refresh(std::uint64_t refresh);
    /// Refreshes missed so far (presented() / presented_at_refresh()).
    std::uint64_t missed_refreshes() const { return missed_; }
    /// Presents shown late (at least one refresh missed before them).
    std::uint64_t late_presents() const { return late_; }
    /// The shutter each of the last presents showed, in order, up to the last 64 (0 = left, 1 = right;
    /// oldest first): for tests and the report.
    std::uint64_t shown_shutters() const { return history_; }
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
    std::uint64_t next_refresh_ = 0;  // refresh (since the first present) the next present is expected on
    std::uint64_t last_refresh_ = 0;  // the refresh the last present was expected on
    double last_t_s_ = 0.0;           // presented(): when the previous present was shown
    double first_t_s_ = 0.0;          // presented(): when the first timed present was shown
    std::uint64_t first_refresh_ = 0; // ... and its refresh
    bool have_t_ = false;
    std::uint64_t last_counter_ = 0;  // presented_at_refresh(): the previous counter
    bool have_counter_ = false;
    std::uint64_t missed_ = 0, late_ = 0;
    std::uint64_t history_ = 0;       // shutter bits of the last presents, newest in bit 0
    // A present shown `extra` refreshes later than expected: counts it and moves the refresh count on.
    void shown_late(std::uint64_t extra);
};

}  // namespace tridex::renderer
