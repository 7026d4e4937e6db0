// devices/net/sealed_link.cpp - the sealed link: the per-connection handshake, sealing and opening datagrams, the
// replay window. Every primitive is libsodium's (crypto_kdf, crypto_auth, crypto_generichash, crypto_secretbox).
#include "devices/net/sealed_link.hpp"

#include <sodium.h>

#include <atomic>
#include <cstring>
#include <limits>

#include "core/error.hpp"

namespace tridex::devices::net {

namespace {

constexpr std::uint8_t kReliable = 0;    // channel byte of a reliable data datagram
constexpr std::uint8_t kUnreliable = 1;  // channel byte of an unreliable data datagram
constexpr std::uint8_t kHello = 2;       // channel byte of a hello
constexpr std::uint8_t kConfirm = 3;     // channel byte of a key confirmation (sealed, empty)
constexpr char kKdfContext[crypto_kdf_CONTEXTBYTES + 1] = "tdxseal1";
constexpr std::size_t kNonceBytes = 32;                // a hello's random nonce
constexpr std::size_t kHelloSigned = 3 + kNonceBytes;  // version, channel, role, nonce
constexpr int kWindow = 64;                            // accepted counters remembered per channel

static_assert(SealedLink::kMacBytes == crypto_secretbox_MACBYTES);
static_assert(crypto_secretbox_NONCEBYTES == 24 && crypto_secretbox_KEYBYTES == 32);
static_assert(crypto_auth_BYTES == 32 && crypto_auth_KEYBYTES == 32);
static_assert(SealedLink::kHelloBytes == kHelloSigned + crypto_auth_BYTES);

std::uint64_t load_le64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

void store_le64(std::uint8_t* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

void bump(std::atomic<std::uint64_t>& c) { c.fetch_add(1, std::memory_order_relaxed); }

}  // namespace

struct SealedLink::Counters {
    std::atomic<std::uint64_t> accepted{0}, forged{0}, replayed{0}, out_of_order{0}, truncated{0}, bad_version{0},
        hello_refused{0}, early{0}, send_dropped{0};
};

SealedLink::SealedLink(std::unique_ptr<DatagramLink> inner, const SessionKey& key, SealRole role)
    : inner_(std::move(inner)), role_(role), counters_(std::make_unique<Counters>()) {
    if (!inner_) throw Error("sealed link: no inner link given");
    if (sodium_init() < 0) throw Error("sealed link: libsodium could not initialise (sodium_init failed)");
    // Two subkeys of the long-term key (crypto_kdf: keyed BLAKE2b), so the hellos' MAC and the connection-key
    // derivation never use one key for two primitives.
    crypto_kdf_derive_from_key(hello_key_, sizeof hello_key_, 1, kKdfContext, key.data());
    crypto_kdf_derive_from_key(derive_key_, sizeof derive_key_, 2, kKdfContext, key.data());
}

SealedLink::~SealedLink() {
    sodium_memzero(hello_key_, sizeof hello_key_);
    sodium_memzero(derive_key_, sizeof derive_key_);
    sodium_memzero(conn_key_, sizeof conn_key_);
    sodium_memzero(own_nonce_, sizeof own_nonce_);
    sodium_memzero(peer_nonce_, sizeof peer_nonce_);
}

SealStats SealedLink::stats() const {
    const Counters& c = *counters_;
    const auto r = [](const std::atomic<std::uint64_t>& a) { return a.load(std::memory_order_relaxed); };
    SealStats s;
    s.accepted = r(c.accepted);
    s.forged = r(c.forged);
    s.replayed = r(c.replayed);
    s.out_of_order = r(c.out_of_order);
    s.truncated = r(c.truncated);
    s.bad_version = r(c.bad_version);
    s.hello_refused = r(c.hello_refused);
    s.early = r(c.early);
    s.send_dropped = r(c.send_dropped);
    return s;
}

std::uint8_t SealedLink::peer_role() const { return role_ == SealRole::kListener ? 1 : 0; }

bool SealedLink::connected() const { return confirmed_ && inner_->connected(); }

std::string SealedLink::handshake_failure() const { return confirmed_ ? std::string() : failure_; }

void SealedLink::fail(const char* why) {
    failure_ = why;
    // The peer cannot complete this handshake: a listener frees itself for the next one.
    inner_->drop_peer();
    end_connection();
}

void SealedLink::nonce_of(const std::uint8_t* header, std::uint8_t sender_role, std::uint8_t* nonce) const {
    // [sender's role][version][channel][counter, 8 bytes LE][13 zero bytes]: injective in the header, so a changed
    // header byte opens with another nonce and fails the MAC; the role byte keeps the two directions apart.
    std::memset(nonce, 0, crypto_secretbox_NONCEBYTES);
    nonce[0] = sender_role;
    std::memcpy(nonce + 1, header, kHeaderBytes);
}

void SealedLink::end_connection() {
    sodium_memzero(conn_key_, sizeof conn_key_);
    sodium_memzero(own_nonce_, sizeof own_nonce_);
    sodium_memzero(peer_nonce_, sizeof peer_nonce_);
    started_ = established_ = confirmed_ = false;
    send_counter_[0] = send_counter_[1] = send_counter_[2] = send_counter_[3] = 0;
    recv_[0] = recv_[1] = Channel{};
}

void SealedLink::seal_and_send(std::uint8_t channel, const std::uint8_t* p, std::size_t n, bool reliable) {
    out_.resize(kHeaderBytes + kMacBytes + n);
    out_[0] = kVersion;
    out_[1] = channel;
    store_le64(out_.data() + 2, send_counter_[channel]++);
    std::uint8_t nonce[crypto_secretbox_NONCEBYTES];
    nonce_of(out_.data(), static_cast<std::uint8_t>(role_), nonce);
    static const std::uint8_t kNothing = 0;
    crypto_secretbox_easy(out_.data() + kHeaderBytes, n == 0 ? &kNothing : p, n, nonce, conn_key_);
    inner_->send(out_, reliable);
}

bool SealedLink::open_box(const std::vector<std::uint8_t>& d) {
    std::uint8_t nonce[crypto_secretbox_NONCEBYTES];
    nonce_of(d.data(), peer_role(), nonce);
    const std::size_t boxed = d.size() - kHeaderBytes;
    const std::size_t plain = boxed - kMacBytes;
    scratch_.resize(plain + 1);  // never empty, so its data() is a real buffer
    if (crypto_secretbox_open_easy(scratch_.data(), d.data() + kHeaderBytes, boxed, nonce, conn_key_) != 0) {
        bump(counters_->forged);
        return false;
    }
    scratch_.resize(plain);
    return true;
}

void SealedLink::begin_connection() {
    end_connection();
    randombytes_buf(own_nonce_, sizeof own_nonce_);
    started_ = true;
    out_.resize(kHelloBytes);
    out_[0] = kVersion;
    out_[1] = kHello;
    out_[2] = static_cast<std::uint8_t>(role_);
    std::memcpy(out_.data() + 3, own_nonce_, kNonceBytes);
    crypto_auth(out_.data() + kHelloSigned, out_.data(), kHelloSigned, hello_key_);
    inner_->send(out_, true);
}

void SealedLink::on_hello(const std::vector<std::uint8_t>& d) {
    Counters& c = *counters_;
    if (d.size() < kHelloBytes) {
        bump(c.truncated);
        return;
    }
    const std::uint8_t* peer_nonce = d.data() + 3;
    // Refused: the wrong length, no hello expected (before the connection or once it is confirmed), a bad MAC (the
    // wrong key), a hello of our own role (reflected back to us), or the hello already taken (a duplicate).
    if (d.size() != kHelloBytes || !started_ || confirmed_) {
        bump(c.hello_refused);
        return;
    }
    if (crypto_auth_verify(d.data() + kHelloSigned, d.data(), kHelloSigned, hello_key_) != 0) {
        bump(c.hello_refused);
        fail("the handshake failed: the peer's hello does not authenticate with this key (the two ends hold "
             "different keys or passphrases)");
        return;
    }
    if (d[2] != peer_role() || (established_ && sodium_memcmp(peer_nonce, peer_nonce_, kNonceBytes) == 0)) {
        bump(c.hello_refused);
        return;
    }
    // The connection key: keyed BLAKE2b over the listener's nonce, then the joiner's. An authentic hello with another
    // nonce before the confirmation (an old connection's hello replayed ahead of the peer's) derives it again.
    std::memcpy(peer_nonce_, peer_nonce, kNonceBytes);
    std::uint8_t both[2 * kNonceBytes];
    const bool listener = role_ == SealRole::kListener;
    std::memcpy(both, listener ? own_nonce_ : peer_nonce_, kNonceBytes);
    std::memcpy(both + kNonceBytes, listener ? peer_nonce_ : own_nonce_, kNonceBytes);
    crypto_generichash(conn_key_, sizeof conn_key_, both, sizeof both, derive_key_, sizeof derive_key_);
    sodium_memzero(both, sizeof both);
    established_ = true;
    // The key confirmation: an empty sealed datagram, which only a peer holding this connection's key can open.
    seal_and_send(kConfirm, nullptr, 0, true);
}

bool SealedLink::on_confirm(const std::vector<std::uint8_t>& d) {
    Counters& c = *counters_;
    if (!established_) {
        bump(c.early);
        return false;
    }
    if (!open_box(d)) return false;
    if (confirmed_) {
        bump(c.hello_refused);
        return false;
    }
    confirmed_ = true;
    failure_.clear();
    return true;
}

bool SealedLink::open_data(LinkEvent& ev) {
    Counters& c = *counters_;
    if (!confirmed_) {
        bump(c.early);
        return false;
    }
    if (!open_box(ev.data)) return false;
    // Authentic: now the counter must be greater than the newest accepted on its channel.
    const std::uint64_t counter = load_le64(ev.data.data() + 2);
    Channel& r = recv_[ev.data[1]];
    if (r.any && counter <= r.newest) {
        const std::uint64_t behind = r.newest - counter;
        if (behind < kWindow && ((r.window >> behind) & 1u))
            bump(c.replayed);
        else
            bump(c.out_of_order);
        return false;
    }
    const std::uint64_t shift = r.any ? counter - r.newest : 0;
    r.window = (shift >= kWindow ? 0 : r.window << shift) | 1u;
    r.newest = counter;
    r.any = true;
    bump(c.accepted);
    ev.data.swap(scratch_);
    return true;
}

void SealedLink::send(const std::vector<std::uint8_t>& bytes, bool reliable) {
    const std::uint8_t ch = reliable ? kReliable : kUnreliable;
    if (!connected() || send_counter_[ch] == std::numeric_limits<std::uint64_t>::max()) {
        bump(counters_->send_dropped);
        return;
    }
    seal_and_send(ch, bytes.data(), bytes.size(), reliable);
}

bool SealedLink::poll(LinkEvent& ev) {
    Counters& c = *counters_;
    for (int i = 0; i < kMaxInnerEventsPerPoll; ++i) {
        if (!inner_->poll(ev)) return false;
        if (ev.kind == LinkEvent::kConnected) {
            // A new connection (or one taking over without a disconnect first): a fresh nonce, our hello, and a
            // kDisconnected upward if the previous connection was reported.
            const bool was = confirmed_;
            peer_address_.assign(ev.data.begin(), ev.data.end());
            begin_connection();
            if (!was) continue;
            ev.kind = LinkEvent::kDisconnected;
            ev.data.clear();
            return true;
        }
        if (ev.kind == LinkEvent::kDisconnected) {
            const bool was = confirmed_;
            end_connection();
            if (was) return true;
            continue;
        }
        const std::vector<std::uint8_t>& d = ev.data;
        if (d.size() < kHeaderBytes + kMacBytes || d[0] != kVersion) {
            bump(d.size() < kHeaderBytes + kMacBytes ? c.truncated : c.bad_version);
            if (started_ && !confirmed_)
                fail("the handshake failed: the peer sends datagrams that are not sealed (it runs without a key?)");
        } else if (d[1] == kHello) {
            on_hello(d);
        } else if (d[1] == kConfirm) {
            if (on_confirm(d)) {
                ev.kind = LinkEvent::kConnected;
                ev.data.assign(peer_address_.begin(), peer_address_.end());
                return true;
            }
        } else if (d[1] != kReliable && d[1] != kUnreliable) {
            bump(c.forged);
        } else if (open_data(ev)) {
            return true;
        }
    }
    return false;
}

}  // namespace tridex::devices::net
