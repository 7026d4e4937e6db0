// app/session/shared/shared_join.cpp - the joiner's network thread: the host's stream in, its own tool out.
#include "app/session/shared/shared_join.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "app/support/file_bytes.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace net = devices::net;

namespace {
double steady_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

SharedJoin::SharedJoin(SharedJoinOptions options, std::unique_ptr<net::DatagramLink> link, const net::SessionKey& key)
    : o_(std::move(options)) {
    if (!link) throw Error("--join: no link to the host");
    host_ = link->where();
    link_ = std::make_unique<net::SealedLink>(std::move(link), key, net::SealRole::kJoiner);
}

SharedJoin::~SharedJoin() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

SharedJoin::Joined SharedJoin::join() {
    const double deadline = steady_s() + o_.join_timeout_s;
    bool sent = false;
    while (!welcomed_) {
        net::LinkEvent ev;
        while (link_->poll(ev)) {
            if (ev.kind == net::LinkEvent::kConnected && !sent) {
                link_->send(encode_join(JoinMessage{kSharedProtocol, o_.name, o_.colour, o_.from_start}), true);
                sent = true;
            } else if (ev.kind == net::LinkEvent::kData) {
                on_message(ev.data);
            }
        }
        {
            std::lock_guard lock(mutex_);
            if (!failure_.empty()) throw Error("--join " + host_ + ": " + failure_);
            if (end_heard_) throw Error("--join " + host_ + ": the host turned the join away: " + end_.reason);
        }
        if (!link_->handshake_failure().empty())
            throw Error("--join " + host_ + ": " + link_->handshake_failure() + " (does the host use the same key?)");
        if (steady_s() > deadline)
            throw Error("--join " + host_ + ": " +
                        (link_->reached() ? std::string("the host answered but sent no welcome")
                                          : std::string("no host answered")) +
                        " within " + std::to_string(static_cast<int>(o_.join_timeout_s)) + " s");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    Joined j;
    j.welcome = welcome_;
    j.start_path = (std::filesystem::path(o_.out) / "shared_start.tdx").string();
    std::filesystem::create_directories(o_.out);
    write_file_bytes(j.start_path, welcome_.model_tdx);
    welcome_.model_tdx.clear();
    welcome_.model_tdx.shrink_to_fit();
    // From now on the link is served on its own thread, so that it stays alive (and the stream keeps arriving into
    // the intake) while the session loads the model and opens its display.
    thread_ = std::thread([this] { run_network(); });
    return j;
}

void SharedJoin::configure(SculptOptions& options) {
    if (!welcomed_) throw Error("--join: the session was not joined");
    options.sculpt_setup.push_back([this](SculptThread& t) {
        FollowerOutlet out;
        out.samples = [this](std::span<const ToolSample> s) {
            std::lock_guard lock(mutex_);
            outbox_.insert(outbox_.end(), s.begin(), s.end());
        };
        out.request = [this](SculptRequest r) {
            std::lock_guard lock(mutex_);
            requests_out_.push_back(r);
        };
        out.mismatch = [this](const std::string& what) { fail(what); };
        std::optional<FollowStart> from;
        if (!welcome_.history.empty())  // joined late: the host's strokes so far, to follow its undos of them
            from = FollowStart{std::move(welcome_.history), std::move(welcome_.prevs), welcome_.last_closed_serial};
        t.follow_host(intake_, welcome_.site, std::move(out), std::move(from));
    });
}

void SharedJoin::set_own_presence(const SitePresence& p) {
    std::lock_guard lock(mutex_);
    own_presence_ = p;
    own_presence_.site = welcome_.site;
}

void SharedJoin::finish(const compute::TriDexel& model) {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    std::lock_guard lock(mutex_);
    final_digest_ = compute::model_digest(model);
    digest_match_ = end_heard_ && end_.digest == final_digest_;
    if (end_heard_ && !digest_match_ && failure_.empty())
        failure_ = "the model here differs from the host's at the end of the session";
}

void SharedJoin::fail(const std::string& why) {
    std::lock_guard lock(mutex_);
    if (failure_.empty()) failure_ = why;
}

std::string SharedJoin::failure() const {
    std::lock_guard lock(mutex_);
    return failure_;
}

std::string SharedJoin::ended() const {
    std::lock_guard lock(mutex_);
    return ended_;
}

std::vector<PresenceMessage> SharedJoin::others() const {
    std::lock_guard lock(mutex_);
    return others_;
}

void SharedJoin::run_network() {
    while (!stop_.load()) {
        if (!poll_once()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    // The last samples and requests the sculpt thread handed over, then goodbye (the host keeps what it applied).
    poll_once();
    link_->drop_peer();
}

bool SharedJoin::poll_once() {
    net::LinkEvent ev;
    while (link_->poll(ev)) {
        if (ev.kind == net::LinkEvent::kDisconnected) {
            std::lock_guard lock(mutex_);
            if (!end_heard_ && failure_.empty())
                failure_ = "the host at " + host_ + " went away (its link dropped); the model as it stood here is kept";
            return false;
        }
        if (ev.kind != net::LinkEvent::kData) continue;
        try {
            on_message(ev.data);
        } catch (const Error& e) {
            fail(e.what());
            return false;
        }
    }
    std::vector<ToolSample> samples;
    std::vector<SculptRequest> requests;
    PresenceMessage me;
    {
        std::lock_guard lock(mutex_);
        samples.swap(outbox_);
        requests.swap(requests_out_);
        me = own_presence_;
    }
    if (!samples.empty()) {
        const std::vector<unsigned char> b = encode_samples(samples);
        link_->send(b, true);
        std::lock_guard lock(mutex_);
        samples_out_ += samples.size();
        bytes_out_ += b.size();
    }
    for (const SculptRequest r : requests) {
        link_->send(encode_request(r), true);
        std::lock_guard lock(mutex_);
        ++requests_sent_;
    }
    const double t = steady_s();
    if (t - last_presence_s_ >= 0.03 && me.site != 0) {
        last_presence_s_ = t;
        link_->send(encode_presence(me), false);
    }
    return true;
}

void SharedJoin::push_records(const RecordsMessage& m) {
    for (std::size_t i = 0; i < m.records.size(); ++i) {
        if (m.check_digest && i == m.check_after) intake_.push_host_check(*m.check_digest);
        intake_.push_host_record(m.records[i]);
    }
    if (m.check_digest && m.check_after == m.records.size()) intake_.push_host_check(*m.check_digest);
    std::lock_guard lock(mutex_);
    records_in_ += m.records.size();
    checks_ += m.check_digest ? 1 : 0;
}

void SharedJoin::on_message(const std::vector<std::uint8_t>& bytes) {
    const std::string from = "the host " + host_;
    {
        std::lock_guard lock(mutex_);
        bytes_in_ += bytes.size();
    }
    switch (shared_kind(bytes, from)) {
        case SharedKind::kWelcome:
            if (welcomed_) throw Error(from + ": a second welcome");
            welcome_ = decode_welcome(bytes, from);
            welcomed_ = true;
            return;
        case SharedKind::kRecords:
        case SharedKind::kRecordsPacked:
            if (!welcomed_) throw Error(from + ": records before the welcome");
            return push_records(decode_records(bytes, from));
        case SharedKind::kRefused: {
            const RefusedMessage m = decode_refused(bytes, from);
            std::fprintf(stderr, "tridex: %s refused: %s has carved since your stroke began\n", sculpt_request_name(m.request),
                         m.by_name.c_str());
            std::lock_guard lock(mutex_);
            ++refusals_;
            return;
        }
        case SharedKind::kPresence: {
            const PresenceMessage p = decode_presence(bytes, from);
            std::lock_guard lock(mutex_);
            for (PresenceMessage& q : others_)
                if (q.site == p.site) {
                    q = p;
                    return;
                }
            others_.push_back(p);
            return;
        }
        case SharedKind::kEnd: {
            const EndMessage m = decode_end(bytes, from);
            std::lock_guard lock(mutex_);
            end_ = m;
            end_heard_ = true;
            ended_ = m.reason.empty() ? "the host ended the session" : m.reason;
            return;
        }
        default: throw Error(from + ": a message only a joiner sends");
    }
}

nlohmann::json SharedJoin::report() const {
    std::lock_guard lock(mutex_);
    return {{"role", "joiner"}, {"name", o_.name}, {"site", welcome_.site}, {"host", host_},
            {"host_name", welcome_.host_name}, {"records", records_in_}, {"samples_sent", samples_out_},
            {"requests_sent", requests_sent_}, {"refusals", refusals_}, {"digest_checks", checks_},
            {"bytes_in", bytes_in_}, {"bytes_out", bytes_out_}, {"final_digest", final_digest_},
            {"host_final_digest", end_.digest}, {"host_ended", end_heard_}, {"digest_match", digest_match_},
            {"sealed_refused", link_->stats().refused()}, {"first_record", welcome_.first_record}};
}

}  // namespace tridex::app
