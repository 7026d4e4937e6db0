// app/session/cluster/cluster_root.cpp - rank 0: the stream replicated frame by frame, the swap barrier, the checks.
#include "app/session/cluster/cluster_root.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <thread>

#include "app/support/file_bytes.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

namespace {

using Clock = std::chrono::steady_clock;

double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }


}  // namespace

// ---- ClusterRoot ---------------------------------------------------------------------------------------------

// A snapshot's model written as .tdx and read back as bytes, on a thread of its own (a big model takes a while).
struct ClusterRoot::Saving {
    std::uint64_t asks = 0, first_record = 0;
    std::vector<unsigned char> history;
    std::vector<ToolSample> prevs;
    std::uint64_t last_closed_serial = 0, digest = 0;
    std::future<std::vector<unsigned char>> tdx;
};

ClusterRoot::ClusterRoot(ClusterTransport& transport, const ClusterConfig& config, std::string out)
    : transport_(transport), config_(config), out_(std::move(out)) {
    const int want = static_cast<int>(config.ranks.size()) + 1;
    if (transport.size() != want)
        throw Error(config.source + ": names " + std::to_string(config.ranks.size()) + " render ranks, so the session needs " +
                    std::to_string(want) + " ranks (mpirun -np " + std::to_string(want) + "); it has " +
                    std::to_string(transport.size()));
    stats_.ranks = want;
    last_present_s_.assign(config.ranks.size(), 0.0);
    seats_.resize(config.ranks.size());
    if (transport.open_membership()) return;
    if (const char* v = std::getenv("OMPI_MCA_orte_abort_on_non_zero_status"); !v || std::string(v) != "0")
        std::fprintf(stderr, "tridex: cluster: mpirun ends every rank when one exits with an error, so a failing render rank "
                             "would take this session's unsaved work with it; launch with "
                             "--mca orte_abort_on_non_zero_status 0 (docs/cluster.md)\n");
}

ClusterRoot::~ClusterRoot() {
    if (saving_ && saving_->tdx.valid()) saving_->tdx.wait();
}

void ClusterRoot::configure(SculptOptions& options) {
    options.streams.push_back(&stream_);
    if (!transport_.open_membership()) return;
    options.sculpt_setup.push_back([this](SculptThread& t) {
        sculpt_ = &t;
        t.use_snapshot_asks([this](SculptSnapshot&& s) {  // on the sculpt thread: every record so far is in the model
            const std::uint64_t first = stream_.records();
            std::lock_guard lock(snapshot_mutex_);
            snapshot_ = std::move(s);
            snapshot_first_ = first;
        });
    });
}

void ClusterRoot::starting(SessionRuntime& runtime) {
    HelloMessage h;
    h.spec_json = spec_to_json(runtime.spec());
    h.initial_digest = compute::model_digest(runtime.workpiece().model);
    if (!runtime.spec().model_path.empty()) h.model_tdx = read_file_bytes(runtime.spec().model_path);
    spec_json_ = h.spec_json;
    to_world_ = runtime.workpiece().to_world;
    palette_ = runtime.spec().palette;
    if (transport_.open_membership()) return start_open(h);
    const std::vector<unsigned char> bytes = encode_hello(h);
    for (int r = 1; r < transport_.size(); ++r) transport_.send(r, bytes);
    // The session starts when every viewport is ready to draw it: nothing sculpted goes unseen on the wall.
    const auto deadline = deadline_after(config_.start_timeout_s);
    for (int r = 1; r < transport_.size(); ++r) {
        const std::optional<RankAnswer> a = answer_from(r, deadline, config_.start_timeout_s, "the hello", 0);
        if (a && a->frame != kHelloAnswerFrame)
            fail("render rank " + std::to_string(r) + " answered the hello with frame " + std::to_string(a->frame));
        if (!stats_.failure.empty()) throw Error(stats_.failure);
    }
}

void ClusterRoot::start_open(const HelloMessage& hello) {
    // The ranks that connect within start_timeout_s start with the session; the rest join it when they come.
    const auto deadline = deadline_after(config_.start_timeout_s);
    const std::vector<unsigned char> bytes = encode_hello(hello);
    for (RankSeat& s : seats_) s.seat = Seat::kAbsent;
    std::size_t in = 0;
    while (in < seats_.size() && ClusterTransport::Clock::now() < deadline) {
        for (const int r : transport_.arrivals()) {
            RankSeat& s = seat(r);
            if (s.seat != Seat::kAbsent) continue;
            transport_.send(r, bytes);
            s.seat = Seat::kStarting;
            ++in;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const auto answered_by = deadline_after(config_.start_timeout_s);  // each loads the workpiece meanwhile
    for (int r = 1; r < transport_.size(); ++r) {
        RankSeat& s = seat(r);
        if (s.seat == Seat::kAbsent) {
            std::fprintf(stderr, "tridex: cluster: render rank %d has not connected within %s s: the wall starts "
                                 "without it, and it joins when it comes\n", r, format_number(config_.start_timeout_s).c_str());
            continue;
        }
        const std::optional<RankAnswer> a = answer_from(r, answered_by, config_.start_timeout_s, "the hello", 0);
        if (!a) continue;  // let go
        if (a->frame != kHelloAnswerFrame) {
            lost(r, 0, "it answered the hello with frame " + std::to_string(a->frame));
            continue;
        }
        s.seat = Seat::kLive;
    }
}

void ClusterRoot::admit(std::uint64_t frame) {
    // New processes: each waits for a snapshot taken after it came.
    for (const int r : transport_.arrivals()) {
        RankSeat& s = seat(r);
        s = RankSeat{};
        s.seat = Seat::kWaiting;
        s.arrived_s = now_s();
        s.ask = sculpt_ ? sculpt_->ask_snapshot() : 0;
        if (!sculpt_) lost(r, frame, "this session takes no late render ranks (no sculpt thread to take a snapshot)");
    }
    // A process that left while it waited or loaded frees its seat.
    for (int r = 1; r < transport_.size(); ++r) {
        RankSeat& s = seat(r);
        if ((s.seat == Seat::kWaiting || s.seat == Seat::kStarting) && !transport_.present(r))
            lost(r, frame, "it left while it joined");
    }
    // A snapshot taken: saved as .tdx on a thread of its own.
    if (!saving_) {
        std::optional<SculptSnapshot> snap;
        std::uint64_t first = 0;
        {
            std::lock_guard lock(snapshot_mutex_);
            snap.swap(snapshot_);
            first = snapshot_first_;
        }
        if (snap) {
            saving_ = std::make_unique<Saving>();
            saving_->asks = snap->asks;
            saving_->first_record = first;
            saving_->history = std::move(snap->history);
            saving_->prevs = std::move(snap->prevs);
            saving_->last_closed_serial = snap->last_closed_serial;
            saving_->digest = compute::model_digest(snap->model);
            const std::string path = (std::filesystem::path(out_) / "cluster_late_join.tdx").string();
            saving_->tdx = std::async(std::launch::async, [path, model = std::move(snap->model), to_world = to_world_,
                                                           json = spec_json_, palette = palette_] {
                compute::save_tdx(path, model, to_world, json, 3, palette);
                return read_file_bytes(path);
            });
        }
    }
    if (saving_ && saving_->tdx.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        std::vector<unsigned char> tdx;
        try {
            tdx = saving_->tdx.get();
        } catch (const std::exception& e) {
            const std::string why = std::string("its model could not be saved: ") + e.what();
            for (int r = 1; r < transport_.size(); ++r)
                if (seat(r).seat == Seat::kWaiting && seat(r).ask <= saving_->asks)
                    lost(r, frame, why);
        }
        if (!tdx.empty()) send_late_hellos(std::move(tdx), frame);
        saving_.reset();
    }
    // Ranks loading their model: their answer, when it came, puts them in step from this frame on.
    for (int r = 1; r < transport_.size(); ++r) {
        RankSeat& s = seat(r);
        if (s.seat != Seat::kStarting) continue;
        std::optional<RankAnswer> a;
        try {
            const auto got = transport_.receive(r, ClusterTransport::Clock::now());
            if (got) a = decode_answer(*got, "render rank " + std::to_string(r));
        } catch (const Error& e) {
            lost(r, frame, e.what());
            continue;
        }
        if (!a) {
            if (now_s() - s.hello_s > config_.start_timeout_s)
                lost(r, frame, "it did not answer the hello within " + format_number(config_.start_timeout_s) + " s");
            continue;
        }
        if (!a->error.empty()) {
            lost(r, frame, "it failed at the hello: " + a->error);
            continue;
        }
        if (a->frame != kHelloAnswerFrame) {
            lost(r, frame, "it answered the hello with frame " + std::to_string(a->frame));
            continue;
        }
        s.seat = Seat::kLive;
        ClusterStats::Event e;
        e.frame = frame;
        e.rank = r;
        e.joined = true;
        e.first_record = s.first_record;
        e.join_s = now_s() - s.arrived_s;
        e.model_bytes = s.model_bytes;
        stats_.events.push_back(e);
        std::fprintf(stderr, "tridex: cluster: render rank %d joined the wall at frame %llu (the model as it stood at "
                             "record %llu, %.1f s after it connected)\n",
                     r, static_cast<unsigned long long>(frame), static_cast<unsigned long long>(s.first_record), e.join_s);
    }
}

void ClusterRoot::send_late_hellos(std::vector<unsigned char> tdx, std::uint64_t frame) {
    HelloMessage h;
    h.spec_json = spec_json_;
    h.initial_digest = saving_->digest;
    h.model_tdx = std::move(tdx);
    h.first_record = saving_->first_record;
    h.history = std::move(saving_->history);
    h.prevs = std::move(saving_->prevs);
    h.last_closed_serial = saving_->last_closed_serial;
    std::optional<std::vector<unsigned char>> bytes;
    for (int r = 1; r < transport_.size(); ++r) {
        RankSeat& s = seat(r);
        if (s.seat != Seat::kWaiting || s.ask > saving_->asks) continue;  // it came after this snapshot was taken
        if (!bytes) bytes = encode_hello(h);
        // What it holds from the snapshot on: the records kept since it asked, from the snapshot's on.
        std::erase_if(s.pending, [&](const compute::JournalRecord& x) { return x.index < h.first_record; });
        try {
            transport_.send(r, *bytes);
        } catch (const Error& e) {
            lost(r, frame, e.what());
            continue;
        }
        s.seat = Seat::kStarting;
        s.first_record = h.first_record;
        s.model_bytes = static_cast<double>(bytes->size());
        s.hello_s = now_s();
    }
}

FrameMessage ClusterRoot::message_of(const FrameShown& shown, compute::ToolStreamBuffer::Taken taken) const {
    FrameMessage m;
    m.frame = shown.frame;
    m.head = shown.head;
    if (shown.nav) {
        m.nav_pose = shown.nav->pose();
        m.nav_scale = shown.nav->scale();
    }
    m.eye_separation_m = shown.eye_separation_m;
    m.show_tool = shown.show_tool;
    m.tool_m = shown.tool_m;
    m.tool_orientation = shown.tool_orientation;
    m.tool = shown.tool;
    m.ao = std::clamp(shown.ao, 0.0, 1.0);
    m.workpiece_pose = shown.workpiece_pose;
    if (shown.menu) m.menu = *shown.menu;
    m.others = shown.others;
    m.records = std::move(taken.records);
    m.check_digest = taken.digest;
    m.check_after = taken.digest_after;
    m.newest_sample_made_s = taken.newest_made_s;
    return m;
}

void ClusterRoot::fail(const std::string& why) {
    if (stats_.failure.empty()) stats_.failure = "cluster: " + why;
}

void ClusterRoot::lost(int r, std::uint64_t frame, const std::string& why) {
    const std::string who = "render rank " + std::to_string(r);
    if (!transport_.open_membership()) return fail(why.starts_with(who) ? why : who + " " + why);
    RankSeat& s = seat(r);
    const bool was_in = s.seat != Seat::kAbsent;
    s = RankSeat{};
    s.seat = Seat::kAbsent;
    last_present_s_[static_cast<std::size_t>(r - 1)] = 0.0;
    try {  // a process still there hears why before its link is dropped
        if (transport_.present(r)) transport_.send(r, encode_let_go("at frame " + std::to_string(frame) + ": " + why));
    } catch (const Error&) {  // it is gone: nothing to tell
    }
    transport_.release(r);
    if (!was_in) return;
    ClusterStats::Event e;
    e.frame = frame;
    e.rank = r;
    e.why = why;
    stats_.events.push_back(e);
    const std::string reason = why.starts_with(who + " ") ? why.substr(who.size() + 1) : why;
    std::fprintf(stderr, "tridex: cluster: render rank %d let go at frame %llu: %s; its viewports stay dark until a "
                         "process takes its place (tridex run ... --cluster-connect HOST:PORT --rank %d)\n",
                 r, static_cast<unsigned long long>(frame), reason.c_str(), r);
}

std::optional<RankAnswer> ClusterRoot::answer_from(int r, Clock::time_point deadline, double timeout_s,
                                                   const std::string& waiting_for, std::uint64_t frame) {
    try {
        const auto got = transport_.receive(r, deadline);
        if (!got) {
            lost(r, frame, "did not answer " + waiting_for + " within " + format_number(timeout_s) +
                               " s (it died, hangs or its machine is unreachable)");
            return std::nullopt;
        }
        RankAnswer a = decode_answer(*got, "render rank " + std::to_string(r));
        if (!a.error.empty()) {
            lost(r, frame, "failed at " + waiting_for + ": " + a.error);
            return std::nullopt;
        }
        return a;
    } catch (const Error& e) {
        lost(r, frame, e.what());
        return std::nullopt;
    }
}

void ClusterRoot::exchange(FrameMessage m, bool first) {
    const std::size_t samples = [&] {
        std::size_t n = 0;
        for (const compute::JournalRecord& r : m.records) n += r.samples.size();
        return n;
    }();
    stats_.records += m.records.size();
    stats_.samples += samples;
    const bool checked = m.check_digest.has_value();
    const std::uint64_t frame = m.frame;
    const double newest = m.newest_sample_made_s;
    m.sent_s = now_s();
    const std::vector<unsigned char> bytes = encode_frame(m);
    stats_.frame_bytes.push_back(static_cast<double>(bytes.size()));
    ++stats_.frames;
    const auto t0 = Clock::now();
    const auto live = [&](int r) { return seat(r).seat == Seat::kLive; };
    for (int r = 1; r < transport_.size(); ++r) {
        if (live(r)) {
            RankSeat& s = seat(r);
            try {
                if (s.pending.empty()) {
                    transport_.send(r, bytes);
                } else {  // it just joined: every record since its snapshot, then this frame's
                    FrameMessage mine = m;
                    mine.records = std::move(s.pending);
                    mine.records.insert(mine.records.end(), m.records.begin(), m.records.end());
                    mine.check_after = m.check_after + static_cast<std::uint32_t>(mine.records.size() - m.records.size());
                    s.pending.clear();
                    transport_.send(r, encode_frame(mine));
                }
            } catch (const Error& e) {
                lost(r, frame, e.what());
                if (!stats_.failure.empty()) return;
            }
        } else if (seat(r).seat != Seat::kAbsent) {  // joining: kept for it
            std::vector<compute::JournalRecord>& p = seat(r).pending;
            p.insert(p.end(), m.records.begin(), m.records.end());
        }
    }
    const double timeout = first ? config_.start_timeout_s : config_.timeout_s;
    const auto deadline = deadline_after(timeout);
    double earliest = 0.0, latest = 0.0;
    for (int r = 1; r < transport_.size(); ++r) {
        if (!live(r)) continue;
        const std::optional<RankAnswer> a = answer_from(r, deadline, timeout, "frame " + std::to_string(frame), frame);
        if (!a) {
            if (!stats_.failure.empty()) return;
            continue;
        }
        if (a->frame != frame) {
            lost(r, frame, "answered frame " + std::to_string(a->frame) + " to frame " + std::to_string(frame));
        } else if (a->digest_mismatch) {
            lost(r, frame, "holds another model than rank 0 at frame " + std::to_string(frame) + " (digest " +
                               compute::digest_hex(a->digest) + ", rank 0's " + compute::digest_hex(m.check_digest.value_or(0)) +
                               "): the replicas diverged; the wall would show a model that is not the one being sculpted");
        } else if (a->previous_present_s > 0.0) {
            earliest = earliest == 0.0 ? a->previous_present_s : std::min(earliest, a->previous_present_s);
            latest = std::max(latest, a->previous_present_s);
            last_present_s_[static_cast<std::size_t>(r - 1)] = a->previous_present_s;
        }
        if (!stats_.failure.empty()) return;
    }
    stats_.ready_wait_ms.add(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (latest > 0.0) stats_.swap_spread_ms.add(1e3 * (latest - earliest));
    if (checked) ++stats_.checks;
    const std::vector<unsigned char> go = encode_go(frame);
    for (int r = 1; r < transport_.size(); ++r) {
        if (!live(r)) continue;
        try {
            transport_.send(r, go);
        } catch (const Error& e) {
            lost(r, frame, e.what());
            if (!stats_.failure.empty()) return;
        }
    }
    // The present of this frame is reported with the next answer: keep its newest sample until then.
    if (prev_newest_s_ > 0.0)
        for (double p : last_present_s_)
            if (p > prev_newest_s_) stats_.sample_to_present_ms.add(1e3 * (p - prev_newest_s_));
    prev_newest_s_ = newest;
}

void ClusterRoot::before_present(const FrameShown& shown) {
    if (!stats_.failure.empty()) return;
    if (transport_.open_membership()) admit(shown.frame);
    if (shown.frame % static_cast<std::uint64_t>(config_.check_every_frames) == 0) stream_.request_digest();
    exchange(message_of(shown, stream_.take()), shown.frame == 0);
}

void ClusterRoot::stopped(SessionRuntime& runtime, const FrameShown& last) {
    if (!stats_.failure.empty()) return;
    // The threads have stopped: the model is final, and read here. Every record left goes out with its digest.
    compute::ToolStreamBuffer::Taken taken = stream_.take();
    taken.digest = compute::model_digest(runtime.workpiece().model);
    taken.digest_after = static_cast<std::uint32_t>(taken.records.size());
    FrameMessage m = message_of(last, std::move(taken));
    m.last = true;
    exchange(std::move(m), last.frame == 0);
    if (!stats_.failure.empty()) return;
    const auto deadline = deadline_after(config_.timeout_s);
    for (int r = 1; r < transport_.size(); ++r) {
        RankSeat& s = seat(r);
        if (s.seat == Seat::kWaiting || s.seat == Seat::kStarting) {  // still joining: it has nothing to finish
            lost(r, last.frame, "the session ended while it joined");
            continue;
        }
        if (s.seat != Seat::kLive) continue;
        const std::optional<RankAnswer> a = answer_from(r, deadline, config_.timeout_s, "the end (its report)", last.frame);
        if (!a) {
            if (!stats_.failure.empty()) return;
            continue;
        }
        if (a->previous_present_s > 0.0 && prev_newest_s_ > 0.0 && a->previous_present_s > prev_newest_s_)
            stats_.sample_to_present_ms.add(1e3 * (a->previous_present_s - prev_newest_s_));
        stats_.rank_reports.push_back(a->report_json);
    }
    (void)transport_.flush(deadline);
}

nlohmann::json ClusterRoot::report() const {
    nlohmann::json ranks = nlohmann::json::array();
    for (const std::string& text : stats_.rank_reports) {
        try {
            ranks.push_back(nlohmann::json::parse(text));
        } catch (const nlohmann::json::exception&) {
            ranks.push_back(nullptr);
        }
    }
    nlohmann::json events = nlohmann::json::array();
    for (const ClusterStats::Event& e : stats_.events) {
        nlohmann::json j = {{"frame", e.frame}, {"rank", e.rank}, {"what", e.joined ? "joined" : "let go"}};
        if (e.joined) {
            j["first_record"] = e.first_record;
            j["join_s"] = e.join_s;
            j["hello_bytes"] = e.model_bytes;
        } else {
            j["why"] = e.why;
        }
        events.push_back(j);
    }
    double bytes_total = 0.0;
    for (double b : stats_.frame_bytes) bytes_total += b;
    return {{"transport", transport_.name()},
            {"config", config_.source},
            {"ranks", stats_.ranks},
            {"frames", stats_.frames},
            {"records", stats_.records},
            {"samples", stats_.samples},
            {"checks", stats_.checks},
            {"frame_bytes", summary_report_json(stats_.frame_bytes)},
            {"frame_bytes_mean", stats_.frames ? bytes_total / static_cast<double>(stats_.frames) : 0.0},
            {"ready_wait_ms", summary_report_json(stats_.ready_wait_ms)},
            {"sample_to_present_ms", summary_report_json(stats_.sample_to_present_ms)},
            {"swap_spread_ms", summary_report_json(stats_.swap_spread_ms)},
            {"failure", stats_.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(stats_.failure)},
            {"open_membership", transport_.open_membership()},
            {"events", events},
            {"render_ranks", ranks}};
}

}  // namespace tridex::app
