// app/session/shared/shared_host.cpp - the host's network thread: joiners in, the ordered stream out.
#include "app/session/shared/shared_host.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace net = devices::net;

/// One joiner, on the network thread.
struct SharedHost::Joiner {
    std::unique_ptr<net::SealedLink> link;
    JoinerReport report;
    bool joined = false;    // its join was taken: it has a site
    bool welcomed = false;  // it has its model and gets the stream (a late joiner waits for its snapshot)
    bool gone = false;
    std::uint64_t sent = 0;  // records of log_ sent to it
    Vec3 colour{1.0};
};

namespace {
double steady_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

SharedHost::SharedHost(SharedHostOptions options, PeerAccept accept) : o_(std::move(options)), accept_(std::move(accept)) {
    if (!(o_.digest_check_s > 0.0)) throw Error("shared session: the digest check interval must be > 0 s");
    if (!accept_) throw Error("shared session: no way to accept joiners");
    site_names_.assign(kMaxSites, std::string());
    site_names_[0] = o_.name;
}

SharedHost::~SharedHost() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

double SharedHost::now_s() const { return steady_s() - started_s_; }

void SharedHost::configure(SculptOptions& options) {
    options.streams.push_back(&stream_);
    options.sculpt_setup.push_back([this](SculptThread& t) {
        t.use_site_intake(intake_);
        t.use_snapshots([this](SculptSnapshot&& s) {  // on the sculpt thread: every record so far is in the model
            const std::uint64_t records = stream_.records();
            std::lock_guard lock(mutex_);
            snapshots_.push_back(Snapshot{std::move(s), records});
        });
        t.observe_refusals([this](const SculptRefusal& r) {
            std::lock_guard lock(mutex_);
            refusals_.push_back(r);
        });
    });
}

void SharedHost::start(const compute::TriDexel& model, std::vector<unsigned char> start_tdx, std::string spec_json,
                       ModelBytes model_bytes) {
    if (thread_.joinable()) throw Error("shared session: the host started twice");
    start_tdx_ = std::move(start_tdx);
    model_bytes_ = std::move(model_bytes);
    start_digest_ = compute::model_digest(model);
    spec_json_ = std::move(spec_json);
    started_s_ = steady_s();
    thread_ = std::thread([this] { run_network(); });
}

void SharedHost::set_own_presence(const SitePresence& p) {
    std::lock_guard lock(mutex_);
    own_presence_ = p;
    own_presence_.site = 0;
}

void SharedHost::finish(const compute::TriDexel& model) {
    final_digest_ = compute::model_digest(model);
    final_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

void SharedHost::run_network() {
    double linger_until = 0.0;
    for (;;) {
        try {
            serve_once();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "tridex: shared session: %s\n", e.what());
        }
        if (stop_.load()) break;
        if (final_.load(std::memory_order_acquire)) {
            if (linger_until == 0.0) {
                send_records();  // the last of the stream
                const EndMessage end{final_digest_, records_sent_, "the host ended the session"};
                for (auto& j : joiners_)
                    if (j->joined && !j->gone) send(*j, encode_end(end), true);  // a late joiner still waiting too
                linger_until = now_s() + o_.linger_s;
            }
            bool all_gone = true;
            for (auto& j : joiners_) all_gone &= j->gone || !j->joined;
            if (all_gone || now_s() >= linger_until) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    for (auto& j : joiners_)
        if (!j->gone) j->link->drop_peer();
    for (int k = 0; k < 50; ++k) {  // let the disconnects go out
        for (auto& j : joiners_) {
            net::LinkEvent ev;
            while (j->link->poll(ev)) {
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }    copy_reports();  // what report() and joiners() give from now on
}

void SharedHost::serve_once() {
    accept_joiners();
    for (auto& j : joiners_)
        if (!j->gone) poll_joiner(*j);
    welcome_late_joiners();
    if (!final_.load(std::memory_order_acquire)) {
        const double t = now_s();
        if (t - last_check_s_ >= o_.digest_check_s) {
            stream_.request_digest();
            last_check_s_ = t;
        }
        send_records();
    }
    send_refusals();
    send_presence();
    if (now_s() - last_reports_s_ >= 0.1) copy_reports();
}

void SharedHost::copy_reports() {
    last_reports_s_ = now_s();
    std::lock_guard lock(mutex_);
    reports_.clear();
    for (auto& j : joiners_) {
        j->report.sealed_refused = j->link->stats().refused();
        if (j->joined) reports_.push_back(j->report);
    }
}

void SharedHost::accept_joiners() {
    while (std::unique_ptr<net::DatagramLink> inner = accept_()) {
        auto j = std::make_unique<Joiner>();
        j->report.where = inner->where();
        j->link = std::make_unique<net::SealedLink>(std::move(inner), o_.key, net::SealRole::kListener);
        joiners_.push_back(std::move(j));
    }
}

void SharedHost::poll_joiner(Joiner& j) {
    net::LinkEvent ev;
    while (!j.gone && j.link->poll(ev)) {
        if (ev.kind == net::LinkEvent::kDisconnected) {
            leave(j, final_.load() ? "after the end" : "its link dropped");
        } else if (ev.kind == net::LinkEvent::kData) {
            j.report.bytes_in += ev.data.size();
            try {
                on_message(j, ev.data);
            } catch (const Error& e) {
                ++j.report.bad_messages;
                send(j, encode_end(EndMessage{0, 0, std::string("the host could not read your message: ") + e.what()}), true);
                leave(j, e.what());
            }
        }
    }
    if (!j.gone && !j.link->handshake_failure().empty()) {
        ++peers_refused_;
        std::fprintf(stderr, "tridex: a peer at %s was refused: %s\n", j.report.where.c_str(),
                     j.link->handshake_failure().c_str());
        leave(j, j.link->handshake_failure());
    }
}

void SharedHost::on_message(Joiner& j, const std::vector<std::uint8_t>& bytes) {
    const std::string from = "joiner " + (j.report.name.empty() ? j.report.where : j.report.name);
    const SharedKind kind = shared_kind(bytes, from);
    if (!j.joined && kind != SharedKind::kJoin) throw Error(from + ": a message before its join");
    switch (kind) {
        case SharedKind::kJoin: return on_join(j, decode_join(bytes, from));
        case SharedKind::kSamples: {
            std::vector<ToolSample> s = decode_samples(bytes, from);
            for (ToolSample& x : s) {
                if (x.tool.kind == ToolKind::kMesh) throw Error(from + ": a mesh tool, which a joiner cannot use");
                x.site = j.report.site;  // the link says who, not the sample
            }
            intake_.push_samples(s);
            j.report.samples += s.size();
            return;
        }
        case SharedKind::kRequest: {
            const SculptRequest r = decode_request(bytes, from);
            ++j.report.requests;
            intake_.push_request(j.report.site, r);
            return;
        }
        case SharedKind::kPresence: {
            PresenceMessage p = decode_presence(bytes, from);
            ++j.report.presence;
            p.site = j.report.site;
            p.name = j.report.name;
            p.colour = j.colour;
            std::lock_guard lock(mutex_);
            for (PresenceMessage& q : presence_)
                if (q.site == p.site) {
                    q = p;
                    return;
                }
            presence_.push_back(p);
            return;
        }
        default: throw Error(from + ": kind " + std::to_string(static_cast<int>(kind)) + " is the host's to send");
    }
}

void SharedHost::on_join(Joiner& j, const JoinMessage& m) {
    if (j.joined) throw Error("joiner " + m.name + ": a second join");
    if (m.protocol != kSharedProtocol)
        throw Error("joiner " + m.name + ": protocol " + std::to_string(m.protocol) + ", the host speaks " +
                    std::to_string(kSharedProtocol));
    // The same person again before their old link timed out (a rejoin after a drop): the old link gives way.
    for (const auto& other : joiners_)
        if (other.get() != &j && other->joined && !other->gone && other->report.name == m.name)
            leave(*other, "rejoined from " + j.report.where);
    const std::uint8_t site = site_for(m.name);
    if (site == 0) throw Error("joiner " + m.name + ": the session holds " + std::to_string(kMaxSites - 1) + " joiners at most");
    j.joined = true;
    j.report.site = site;
    j.report.name = m.name;
    j.report.joined_s = now_s();
    j.colour = m.colour;
    if (!m.from_start && model_bytes_) {
        // The model as it stands: the sculpt thread takes a snapshot where the request falls in the stream.
        intake_.push_snapshot(site);
        std::fprintf(stderr, "tridex: %s joins the shared session from %s (site %d), with the model as it stands\n",
                     m.name.c_str(), j.report.where.c_str(), site);
        return;
    }
    send(j, encode_welcome(WelcomeMessage{site, o_.name, spec_json_, start_tdx_, start_digest_}), true);
    j.welcomed = true;
    send_backlog(j);
    std::fprintf(stderr, "tridex: %s joined the shared session from %s (site %d)\n", m.name.c_str(),
                 j.report.where.c_str(), site);
}

void SharedHost::welcome_late_joiners() {
    std::vector<Snapshot> ready;
    {
        std::lock_guard lock(mutex_);
        ready.swap(snapshots_);
    }
    for (Snapshot& s : ready) {
        Joiner* j = nullptr;
        for (auto& k : joiners_)
            if (k->joined && !k->welcomed && !k->gone && k->report.site == s.snapshot.site) j = k.get();
        if (!j) continue;  // it left while the snapshot was taken
        send_records();    // the log now holds every record the snapshot's model holds
        std::vector<unsigned char> model;
        try {
            model = model_bytes_(s.snapshot.model);
        } catch (const Error& e) {  // an unwritable output folder: the joiner hears why, the session goes on
            send(*j, encode_end(EndMessage{0, 0, std::string("the host could not write its model: ") + e.what()}), true);
            leave(*j, e.what());
            continue;
        }
        WelcomeMessage w{j->report.site, o_.name, spec_json_, std::move(model), compute::model_digest(s.snapshot.model)};
        w.first_record = s.records;
        w.history = std::move(s.snapshot.history);
        w.prevs = std::move(s.snapshot.prevs);
        w.last_closed_serial = s.snapshot.last_closed_serial;
        send(*j, encode_welcome(w), true);
        j->welcomed = true;
        j->sent = s.records;
        j->report.first_record = s.records;
        send_backlog(*j);
        std::fprintf(stderr, "tridex: %s joined the shared session (site %d) at record %llu\n", j->report.name.c_str(),
                     j->report.site, static_cast<unsigned long long>(s.records));
    }
}

std::uint8_t SharedHost::site_for(const std::string& name) {
    for (std::uint8_t s = 1; s < kMaxSites; ++s)
        if (site_names_[s] == name) return s;  // a rejoin keeps its site, and so its strokes
    for (std::uint8_t s = 1; s < kMaxSites; ++s)
        if (site_names_[s].empty()) {
            site_names_[s] = name;
            return s;
        }
    return 0;
}

void SharedHost::leave(Joiner& j, const std::string& why) {
    if (j.gone) return;
    j.gone = true;
    j.report.left_s = now_s();
    if (j.joined) {
        intake_.push_request(j.report.site, SculptRequest::kEndStroke);  // its gesture ended with its link
        std::fprintf(stderr, "tridex: %s left the shared session (%s)\n", j.report.name.c_str(), why.c_str());
        std::lock_guard lock(mutex_);
        for (PresenceMessage& p : presence_)
            if (p.site == j.report.site) p.gone = true;
    }
    j.link->drop_peer();
}

void SharedHost::send(Joiner& j, const std::vector<unsigned char>& bytes, bool reliable) {
    j.link->send(bytes, reliable);
    j.report.bytes_out += bytes.size();
}

void SharedHost::send_backlog(Joiner& j) {
    while (j.sent < log_.size()) {
        const std::size_t n = std::min<std::size_t>(o_.max_records_per_message, log_.size() - j.sent);
        RecordsMessage m;
        m.records = log_.read(j.sent, n);
        send(j, encode_records(m), true);
        j.sent += n;
    }
}

void SharedHost::send_records() {
    compute::ToolStreamBuffer::Taken t = stream_.take();
    if (t.records.empty()) return;
    RecordsMessage m;
    m.check_digest = t.digest;
    m.check_after = t.digest_after;
    if (t.digest) ++checks_;
    m.records = std::move(t.records);
    const std::vector<unsigned char> bytes = encode_records(m);  // once, for every joiner
    for (auto& j : joiners_)
        if (j->welcomed && !j->gone) {
            send_backlog(*j);  // every joiner holds the whole log, so this sends nothing: the new records follow it
            send(*j, bytes, true);
            j->sent += m.records.size();
        }
    log_.append(std::move(m.records));
    records_sent_ = log_.size();
    log_bytes_ = log_.bytes();
}

void SharedHost::send_refusals() {
    std::vector<SculptRefusal> rs;
    {
        std::lock_guard lock(mutex_);
        rs.swap(refusals_);
    }
    for (const SculptRefusal& r : rs) {
        const std::string by = r.by_site < site_names_.size() ? site_names_[r.by_site] : "";
        if (r.site == 0) {
            ++own_refusals_;
            std::fprintf(stderr, "tridex: %s refused: %s has carved since your stroke began\n", sculpt_request_name(r.request),
                         by.c_str());
            continue;
        }
        for (auto& j : joiners_)
            if (j->welcomed && !j->gone && j->report.site == r.site) {
                ++j->report.refusals;
                send(*j, encode_refused(RefusedMessage{r.request, r.by_site, by}), true);
            }
    }
}

void SharedHost::send_presence() {
    const double t = now_s();
    if (t - last_presence_s_ < 0.03) return;
    last_presence_s_ = t;
    std::vector<PresenceMessage> all;
    {
        std::lock_guard lock(mutex_);
        all = presence_;
        all.push_back(own_presence_);
    }
    for (const PresenceMessage& p : all) {
        const std::vector<unsigned char> bytes = encode_presence(p);
        for (auto& j : joiners_)
            if (j->welcomed && !j->gone && j->report.site != p.site) send(*j, bytes, false);
    }
}

std::vector<PresenceMessage> SharedHost::others() const {
    std::lock_guard lock(mutex_);
    return presence_;
}

std::vector<JoinerReport> SharedHost::joiners() const {
    std::lock_guard lock(mutex_);
    return reports_;
}

nlohmann::json SharedHost::report() const {
    std::lock_guard lock(mutex_);
    nlohmann::json js = nlohmann::json::array();
    for (const JoinerReport& r : reports_)
        js.push_back({{"site", r.site}, {"name", r.name}, {"where", r.where}, {"samples", r.samples},
                      {"requests", r.requests}, {"refusals", r.refusals}, {"bad_messages", r.bad_messages},
                      {"bytes_in", r.bytes_in}, {"bytes_out", r.bytes_out}, {"joined_s", r.joined_s},
                      {"left_s", r.left_s}, {"sealed_refused", r.sealed_refused}, {"presence", r.presence},
                      {"first_record", r.first_record}});
    return {{"role", "host"}, {"name", o_.name}, {"joiners", js}, {"records", records_sent_},
            {"stream_log_bytes", log_bytes_}, {"digest_checks", checks_}, {"final_digest", final_digest_}, {"own_refusals", own_refusals_},
            {"site_samples_dropped", intake_.dropped()}, {"peers_refused", peers_refused_}};
}

}  // namespace tridex::app
