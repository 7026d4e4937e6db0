// devices/falcon/falcon_usb_transport.hpp - the Falcon's FTDI bridge over libusb-1.0 (Debian libusb-1.0-0-dev).
#pragma once

#include <cstdint>
#include <string>

#include "devices/falcon/falcon_transport.hpp"

struct libusb_context;
struct libusb_device_handle;
struct libusb_transfer;

namespace tridex::devices::falcon {

/// The real unit. open() finds the `index`-th device with VID:PID 0403:cb48 (or the one at `location`, "bus B
/// port P.Q" as `tridex devices` prints it), opens it, detaches a kernel driver (ftdi_sio) if one is bound and
/// claims interface 0. Control and the firmware load use synchronous transfers; exchange() uses libusb's
/// asynchronous API: the OUT frame and an IN read are submitted together and events are handled until the IN
/// completes or the deadline passes; an IN that misses its deadline stays in flight and its packet is taken by
/// the next exchange, so one exchange per 1 ms tick fits whatever the host's scheduling. Unplug: a transfer
/// that fails with LIBUSB_ERROR_NO_DEVICE (or completes with LIBUSB_TRANSFER_NO_DEVICE), or libusb's hotplug
/// "device left" event where the platform has hotplug (checked with libusb_has_capability), sets unplugged().
/// Events are handled only inside this object's calls, on the caller's thread (no thread of its own).
class FalconUsbTransport : public FalconTransport {
public:
    explicit FalconUsbTransport(std::string location = "", int index = 0);
    ~FalconUsbTransport() override;
    FalconUsbTransport(const FalconUsbTransport&) = delete;
    FalconUsbTransport& operator=(const FalconUsbTransport&) = delete;

    void open() override;
    void close() noexcept override;
    TransferStatus control(const FtdiRequest& request, int timeout_ms) override;
    TransferStatus bulk_out(std::span<const std::uint8_t> data, int timeout_ms, std::size_t& written) override;
    TransferStatus bulk_in(std::span<std::uint8_t> packet, int timeout_ms, std::size_t& got) override;
    TransferStatus exchange(std::span<const std::uint8_t> out, std::span<std::uint8_t> packet, int timeout_us,
                            std::size_t& got) override;
    bool unplugged() const override { return unplugged_; }
    double last_exchange_s() const override { return last_exchange_s_; }
    std::string describe() const override { return where_.empty() ? "USB 0403:cb48" : "USB " + where_; }

    /// Called by the libusb callbacks (public for them; not for users).
    void on_transfer_done(libusb_transfer* t);
    void on_left() { unplugged_ = true; }

private:
    TransferStatus map(int rc);
    void cancel_pending() noexcept;

    std::string location_;
    int index_;
    std::string where_;
    libusb_context* ctx_ = nullptr;
    libusb_device_handle* dev_ = nullptr;
    libusb_transfer* out_ = nullptr;
    libusb_transfer* in_ = nullptr;
    bool out_busy_ = false, in_busy_ = false, in_ready_ = false;
    int in_status_ = 0, in_length_ = 0;
    std::uint8_t out_buf_[kUsbPacketBytes]{};
    std::uint8_t in_buf_[kUsbPacketBytes]{};
    int hotplug_handle_ = 0;
    bool hotplug_ = false;
    bool unplugged_ = false;
    bool claimed_ = false, kernel_detached_ = false;
    double last_exchange_s_ = 0.0;
};

}  // namespace tridex::devices::falcon
