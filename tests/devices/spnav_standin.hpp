// tests/devices/spnav_standin.hpp - a stand-in spacenavd: an AF_UNIX stream listener whose thread accepts one client,
// then sends events as the daemon does (8 native int32 per packet, as spacenavd's send_uevent in src/proto_unix.c
// writes them to a protocol-v0 client: FreeSpacenav/spacenavd at bac572a).
#pragma once

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <future>
#include <string>
#include <thread>

namespace tridex::devices::test {

/// One listening socket at a fresh path under /tmp; accept_async() serves the first client on a thread.
class SpnavStandIn {
public:
    SpnavStandIn() {
        char dir[] = "/tmp/tridex-spnav-XXXXXX";
        dir_ = ::mkdtemp(dir) ? dir : "/tmp";
        path_ = dir_ + "/spnav.sock";
        listen_fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
        ::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
        ::listen(listen_fd_, 4);
        std::promise<int> accepted;
        client_ = accepted.get_future();
        server_ = std::thread([this, p = std::move(accepted)]() mutable { p.set_value(::accept(listen_fd_, nullptr, nullptr)); });
    }
    ~SpnavStandIn() {
        close_client();
        ::shutdown(listen_fd_, SHUT_RDWR);  // wakes accept() when no client came
        if (server_.joinable()) server_.join();
        if (client_.valid())
            if (const int f = client_.get(); f >= 0) ::close(f);
        ::close(listen_fd_);
        ::unlink(path_.c_str());
        ::rmdir(dir_.c_str());
    }
    SpnavStandIn(const SpnavStandIn&) = delete;
    SpnavStandIn& operator=(const SpnavStandIn&) = delete;

    /// The socket path a client connects to.
    const std::string& path() const { return path_; }
    /// Waits for the client the server thread accepted (call after the device opened).
    void wait_client() {
        if (fd_ < 0) fd_ = client_.get();
        if (server_.joinable()) server_.join();
    }
    /// Sends raw bytes to the client.
    void send_bytes(const void* data, std::size_t n) { (void)::send(fd_, data, n, MSG_NOSIGNAL); }
    /// Sends one 8-word packet.
    void send_packet(const std::array<std::int32_t, 8>& w) { send_bytes(w.data(), sizeof w); }
    /// A motion event: translation x, y, z and rotation rx, ry, rz, device counts.
    void motion(int x, int y, int z, int rx, int ry, int rz) { send_packet({0, x, y, z, rx, ry, rz, 8}); }
    /// A button press (or release) of button `b`: type 1 (2), the button number, then 1 (0) for pressed.
    void button(int b, bool press) { send_packet({press ? 1 : 2, b, press ? 1 : 0, 0, 0, 0, 0, 0}); }
    /// The daemon goes away: closes the client connection.
    void close_client() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }

private:
    std::string dir_, path_;
    int listen_fd_ = -1;
    int fd_ = -1;
    std::future<int> client_;
    std::thread server_;
};

}  // namespace tridex::devices::test
