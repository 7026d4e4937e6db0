// devices/falcon/falcon_usb_transport.cpp - libusb-1.0: open by VID:PID, claim, control, bulk, async exchange, hotplug.
#include "devices/falcon/falcon_usb_transport.hpp"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "core/error.hpp"

namespace tridex::devices::falcon {

namespace {

using Clock = std::chrono::steady_clock;

void LIBUSB_CALL transfer_cb(libusb_transfer* t) {
    static_cast<FalconUsbTransport*>(t->user_data)->on_transfer_done(t);
}

int LIBUSB_CALL hotplug_cb(libusb_context*, libusb_device*, libusb_hotplug_event, void* user) {
    static_cast<FalconUsbTransport*>(user)->on_left();
    return 0;  // stay registered
}

std::string location_of(libusb_device* d) {
    std::string where = "bus " + std::to_string(libusb_get_bus_number(d)) + " port ";
    std::uint8_t ports[8];
    const int depth = libusb_get_port_numbers(d, ports, 8);
    for (int k = 0; k < depth; ++k) where += (k ? "." : "") + std::to_string(ports[k]);
    if (depth <= 0) where += "root";
    return where;
}

const char* kUdevHint =
    "; for access without root install the udev rule of README.md (SUBSYSTEM==\"usb\", ATTRS{idVendor}==\"0403\", "
    "ATTRS{idProduct}==\"cb48\", MODE=\"0660\", GROUP=\"plugdev\") and replug";

}  // namespace

FalconUsbTransport::FalconUsbTransport(std::string location, int index)
    : location_(std::move(location)), index_(index) {}

FalconUsbTransport::~FalconUsbTransport() { close(); }

void FalconUsbTransport::open() {
    close();
    unplugged_ = false;
    if (const int rc = libusb_init(&ctx_); rc != 0) {
        ctx_ = nullptr;
        throw Error(std::string("Novint Falcon: libusb_init failed: ") + libusb_strerror(rc));
    }
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx_, &list);
    libusb_device* found = nullptr;
    int seen = 0;
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor d{};
        if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
        if (d.idVendor != kVendorId || d.idProduct != kProductId) continue;
        const std::string where = location_of(list[i]);
        if (location_.empty() ? seen++ == index_ : where == location_) {
            found = list[i];
            where_ = where;
            break;
        }
    }
    int rc = found ? libusb_open(found, &dev_) : LIBUSB_ERROR_NOT_FOUND;
    if (n >= 0) libusb_free_device_list(list, 1);
    if (!found) {
        close();
        throw Error("Novint Falcon: none is plugged in (no USB device 0403:cb48" +
                    (location_.empty() ? std::string() : " at " + location_) + "); `tridex devices` lists what is");
    }
    if (rc != 0) {
        dev_ = nullptr;
        close();
        throw Error(std::string("Novint Falcon: cannot open it (") + libusb_strerror(rc) + ")" +
                    (rc == LIBUSB_ERROR_ACCESS ? kUdevHint : ""));
    }
    if (libusb_kernel_driver_active(dev_, 0) == 1 && libusb_detach_kernel_driver(dev_, 0) == 0) kernel_detached_ = true;
    if ((rc = libusb_claim_interface(dev_, 0)) != 0) {
        close();
        throw Error(std::string("Novint Falcon: cannot claim its interface (") + libusb_strerror(rc) +
                    "): another program is using it" + (rc == LIBUSB_ERROR_ACCESS ? kUdevHint : ""));
    }
    claimed_ = true;
    out_ = libusb_alloc_transfer(0);
    in_ = libusb_alloc_transfer(0);
    if (!out_ || !in_) {
        close();
        throw Error("Novint Falcon: libusb_alloc_transfer failed");
    }
    if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
        hotplug_ = libusb_hotplug_register_callback(ctx_, LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT, LIBUSB_HOTPLUG_NO_FLAGS,
                                                    kVendorId, kProductId, LIBUSB_HOTPLUG_MATCH_ANY, hotplug_cb, this,
                                                    &hotplug_handle_) == LIBUSB_SUCCESS;
    }
}

void FalconUsbTransport::cancel_pending() noexcept {
    if (!ctx_) return;
    if (out_busy_) libusb_cancel_transfer(out_);
    if (in_busy_) libusb_cancel_transfer(in_);
    // Wait (bounded) for the cancellations to complete: a transfer must not be freed while in flight.
    const auto deadline = Clock::now() + std::chrono::milliseconds(500);
    while ((out_busy_ || in_busy_) && Clock::now() < deadline) {
        timeval tv{0, 10000};
        libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    }
}

void FalconUsbTransport::close() noexcept {
    cancel_pending();
    if (hotplug_ && ctx_) libusb_hotplug_deregister_callback(ctx_, hotplug_handle_);
    hotplug_ = false;
    if (!out_busy_ && out_) libusb_free_transfer(out_);
    if (!in_busy_ && in_) libusb_free_transfer(in_);
    out_ = in_ = nullptr;
    out_busy_ = in_busy_ = in_ready_ = false;
    if (dev_) {
        if (claimed_) libusb_release_interface(dev_, 0);
        if (kernel_detached_) libusb_attach_kernel_driver(dev_, 0);
        libusb_close(dev_);
    }
    claimed_ = kernel_detached_ = false;
    dev_ = nullptr;
    if (ctx_) libusb_exit(ctx_);
    ctx_ = nullptr;
}

TransferStatus FalconUsbTransport::map(int rc) {
    switch (rc) {
        case LIBUSB_SUCCESS: return TransferStatus::kOk;
        case LIBUSB_ERROR_TIMEOUT: return TransferStatus::kTimeout;
        case LIBUSB_ERROR_NO_DEVICE: unplugged_ = true; return TransferStatus::kNoDevice;
        default: return TransferStatus::kError;
    }
}

TransferStatus FalconUsbTransport::control(const FtdiRequest& r, int timeout_ms) {
    if (!dev_) return TransferStatus::kError;
    const int rc = libusb_control_transfer(dev_, r.request_type, r.request, r.value, r.index, nullptr, 0,
                                           static_cast<unsigned>(timeout_ms));
    return map(rc < 0 ? rc : 0);
}

TransferStatus FalconUsbTransport::bulk_out(std::span<const std::uint8_t> data, int timeout_ms, std::size_t& written) {
    written = 0;
    if (!dev_) return TransferStatus::kError;
    int n = 0;
    const int rc = libusb_bulk_transfer(dev_, kEndpointOut, const_cast<std::uint8_t*>(data.data()),
                                        static_cast<int>(data.size()), &n, static_cast<unsigned>(timeout_ms));
    written = static_cast<std::size_t>(std::max(0, n));
    return map(rc);
}

TransferStatus FalconUsbTransport::bulk_in(std::span<std::uint8_t> packet, int timeout_ms, std::size_t& got) {
    got = 0;
    if (!dev_) return TransferStatus::kError;
    int n = 0;
    const int rc = libusb_bulk_transfer(dev_, kEndpointIn, packet.data(),
                                        static_cast<int>(std::min(packet.size(), kUsbPacketBytes)), &n,
                                        static_cast<unsigned>(timeout_ms));
    got = static_cast<std::size_t>(std::max(0, n));
    return map(rc);
}

void FalconUsbTransport::on_transfer_done(libusb_transfer* t) {
    if (t->status == LIBUSB_TRANSFER_NO_DEVICE) unplugged_ = true;
    if (t == out_) {
        out_busy_ = false;
    } else if (t == in_) {
        in_busy_ = false;
        in_ready_ = true;
        in_status_ = t->status;
        in_length_ = t->actual_length;
    }
}

TransferStatus FalconUsbTransport::exchange(std::span<const std::uint8_t> out, std::span<std::uint8_t> packet,
                                            int timeout_us, std::size_t& got) {
    const auto t0 = Clock::now();
    got = 0;
    if (!dev_ || unplugged_) return unplugged_ ? TransferStatus::kNoDevice : TransferStatus::kError;
    // The OUT frame: skipped when the previous one is still in flight (the device is behind; the newer command
    // goes out next tick).
    if (!out_busy_) {
        const std::size_t n = std::min(out.size(), sizeof out_buf_);
        std::memcpy(out_buf_, out.data(), n);
        libusb_fill_bulk_transfer(out_, dev_, kEndpointOut, out_buf_, static_cast<int>(n), transfer_cb, this, 100);
        const int rc = libusb_submit_transfer(out_);
        if (rc != 0) return map(rc);
        out_busy_ = true;
    }
    // The IN read stays in flight across exchanges until it completes.
    if (!in_busy_ && !in_ready_) {
        libusb_fill_bulk_transfer(in_, dev_, kEndpointIn, in_buf_, static_cast<int>(kUsbPacketBytes), transfer_cb, this,
                                  0);
        const int rc = libusb_submit_transfer(in_);
        if (rc != 0) return map(rc);
        in_busy_ = true;
    }
    const auto deadline = t0 + std::chrono::microseconds(std::max(0, timeout_us));
    while (!in_ready_ && !unplugged_) {
        const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now()).count();
        if (left <= 0) break;
        timeval tv{0, static_cast<suseconds_t>(left)};
        const int rc = libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
        if (rc == LIBUSB_ERROR_NO_DEVICE)
            unplugged_ = true;
        else if (rc != 0 && rc != LIBUSB_ERROR_INTERRUPTED)
            break;
    }
    last_exchange_s_ = std::chrono::duration<double>(Clock::now() - t0).count();
    if (unplugged_) return TransferStatus::kNoDevice;
    if (!in_ready_) return TransferStatus::kTimeout;
    in_ready_ = false;
    if (in_status_ != LIBUSB_TRANSFER_COMPLETED) return TransferStatus::kError;
    got = std::min(static_cast<std::size_t>(std::max(0, in_length_)), packet.size());
    std::memcpy(packet.data(), in_buf_, got);
    return TransferStatus::kOk;
}

}  // namespace tridex::devices::falcon
