// app/session/cluster/mpi_transport.cpp - ClusterTransport over Open MPI: non-blocking sends, probed receives, every
// wait polled against its deadline (an MPI collective cannot time out, nor say which rank is missing).
#include "app/session/cluster/cluster_transport.hpp"

#include <cstdlib>
#include <list>
#include <thread>

#include <mpi.h>

#include "core/error.hpp"

namespace tridex::app {

namespace {

constexpr int kTag = 7;  // every cluster message
// Poll interval of a receive or flush while nothing is there.
constexpr std::chrono::microseconds kPoll{100};

std::string mpi_error(int code) {
    char text[MPI_MAX_ERROR_STRING];
    int n = 0;
    MPI_Error_string(code, text, &n);
    return std::string(text, static_cast<std::size_t>(n));
}

class MpiTransport final : public ClusterTransport {
public:
    MpiTransport() {
        int inited = 0;
        MPI_Initialized(&inited);
        if (!inited) {
            int provided = 0;
            if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
                throw Error("cluster: MPI did not start (MPI_Init_thread)");
            owns_ = true;
        }
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);  // a dead peer is an error here, not an abort
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        char version[MPI_MAX_LIBRARY_VERSION_STRING];
        int n = 0;
        MPI_Get_library_version(version, &n);
        name_ = std::string(version, static_cast<std::size_t>(n));
        if (const auto nl = name_.find_first_of(",\n"); nl != std::string::npos) name_.resize(nl);
    }
    ~MpiTransport() override {
        if (!owns_) return;
        if (flush(Clock::now() + std::chrono::seconds(2))) MPI_Finalize();
        // Sends still pending (a peer gone): finalising could wait for it forever; the process ends without it.
    }

    int rank() const override { return rank_; }
    int size() const override { return size_; }

    void send(int to, std::vector<unsigned char> bytes) override {
        if (to < 0 || to >= size_ || to == rank_) throw Error("cluster: no rank " + std::to_string(to) + " to send to");
        reap();
        pending_.push_back({std::move(bytes), MPI_REQUEST_NULL});
        Pending& p = pending_.back();
        const int rc = MPI_Isend(p.bytes.data(), static_cast<int>(p.bytes.size()), MPI_BYTE, to, kTag, MPI_COMM_WORLD,
                                 &p.request);
        if (rc != MPI_SUCCESS) {
            pending_.pop_back();
            throw Error("cluster: sending to rank " + std::to_string(to) + " failed: " + mpi_error(rc));
        }
    }

    std::optional<std::vector<unsigned char>> receive(int from, Clock::time_point deadline) override {
        for (;;) {
            reap();
            int ready = 0;
            MPI_Status st;
            const int rc = MPI_Iprobe(from, kTag, MPI_COMM_WORLD, &ready, &st);
            if (rc != MPI_SUCCESS) throw Error("cluster: waiting for rank " + std::to_string(from) + " failed: " + mpi_error(rc));
            if (ready) {
                int count = 0;
                MPI_Get_count(&st, MPI_BYTE, &count);
                std::vector<unsigned char> bytes(static_cast<std::size_t>(count));
                const int rr = MPI_Recv(bytes.data(), count, MPI_BYTE, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                if (rr != MPI_SUCCESS) throw Error("cluster: receiving from rank " + std::to_string(from) + " failed: " + mpi_error(rr));
                return bytes;
            }
            if (Clock::now() >= deadline) return std::nullopt;
            std::this_thread::sleep_for(kPoll);
        }
    }

    bool flush(Clock::time_point deadline) override {
        for (;;) {
            reap();
            if (pending_.empty()) return true;
            if (Clock::now() >= deadline) return false;
            std::this_thread::sleep_for(kPoll);
        }
    }

    [[noreturn]] void abort_all(int code) override {
        MPI_Abort(MPI_COMM_WORLD, code);
        std::_Exit(code);  // MPI_Abort does not return; should it, the process still ends
    }

    std::string name() const override { return name_; }

private:
    struct Pending {
        std::vector<unsigned char> bytes;
        MPI_Request request;
    };
    // Drops the sends that completed.
    void reap() {
        for (auto it = pending_.begin(); it != pending_.end();) {
            int done = 0;
            MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
            it = done ? pending_.erase(it) : std::next(it);
        }
    }

    int rank_ = 0, size_ = 1;
    bool owns_ = false;
    std::string name_;
    std::list<Pending> pending_;  // a list: the buffers and requests must not move while MPI holds them
};

}  // namespace

bool cluster_supported() { return true; }

std::unique_ptr<ClusterTransport> make_mpi_transport() { return std::make_unique<MpiTransport>(); }

}  // namespace tridex::app
