// devices/falcon/falcon_transport.hpp - what the Falcon driver needs from the wire: FTDI control requests, bulk
// transfers with timeouts, one tick's exchange, and an unplug signal. The libusb-1.0 implementation is
// falcon_usb_transport.hpp; the emulator (falcon_emulator.hpp) implements the same interface in memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "devices/falcon/falcon_protocol.hpp"

namespace tridex::devices::falcon {

/// Outcome of one transfer.
enum class TransferStatus : std::uint8_t {
    kOk = 0,        ///< done (a bulk IN may still have carried only the modem bytes)
    kTimeout = 1,   ///< nothing (or not everything) within the timeout: a stall
    kNoDevice = 2,  ///< the device is gone (LIBUSB_ERROR_NO_DEVICE, a hotplug "left" event)
    kError = 3,     ///< any other transport error (pipe, overflow, I/O)
};

/// "ok", "timeout", "no_device" or "error".
const char* to_string(TransferStatus s);

/// The wire under a Falcon driver. Not thread-safe: one thread drives it (the driver's lifecycle calls, then the
/// haptic loop). Implementations never allocate in exchange().
class FalconTransport {
public:
    virtual ~FalconTransport() = default;

    /// Connects and claims the bridge. Throws tridex::Error naming the device and what the user can do (not
    /// plugged in, no permission: the udev rule).
    virtual void open() = 0;
    /// Releases the device. Never throws.
    virtual void close() noexcept = 0;

    /// One FTDI vendor control request (no data stage).
    virtual TransferStatus control(const FtdiRequest& request, int timeout_ms) = 0;
    /// Writes `data` to the bulk OUT endpoint; `written` gets the bytes sent.
    virtual TransferStatus bulk_out(std::span<const std::uint8_t> data, int timeout_ms, std::size_t& written) = 0;
    /// Reads one bulk IN packet (up to 64 bytes: the 2 modem bytes, then data) into `packet`; `got` gets its length.
    virtual TransferStatus bulk_in(std::span<std::uint8_t> packet, int timeout_ms, std::size_t& got) = 0;

    /// One tick: sends `out` (a command frame) and returns the IN packet that arrived within timeout_us (modem
    /// bytes and data, in `packet`, length `got`; 0 with kTimeout when none did). The USB transport keeps its
    /// transfers in flight asynchronously, so an exchange that misses its deadline is collected by the next one.
    virtual TransferStatus exchange(std::span<const std::uint8_t> out, std::span<std::uint8_t> packet, int timeout_us,
                                    std::size_t& got) = 0;

    /// True once the device was seen to leave (hotplug event or a kNoDevice transfer). Sticky until open().
    virtual bool unplugged() const = 0;
    /// Wall time of the last exchange() (submit to IN completion or deadline), s.
    virtual double last_exchange_s() const = 0;
    /// Which unit, for messages ("USB bus 1 port 2", "emulator").
    virtual std::string describe() const = 0;
};

}  // namespace tridex::devices::falcon
