// devices/net/sealed_link.hpp - a DatagramLink that authenticates and encrypts every datagram of another one
// (ENet or the in-process shim) with libsodium: a long-term key from a passphrase (Argon2id) or a key file, a fresh
// key per connection from a handshake of random nonces (keyed BLAKE2b), XSalsa20-Poly1305 on every datagram, and
// strictly increasing counters per direction and channel. docs/devices/sealed-link.md gives the threat model, the
// handshake and the byte layout. Reference: the libsodium 1.0.18 documentation (doc.libsodium.org): "Password
// hashing", "Key derivation", "Generic hashing", "Secret-key authentication", "Authenticated encryption".
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "devices/net/datagram_link.hpp"

namespace tridex::devices::net {

/// The long-term key the sites of a session share (32 bytes), from key_from_passphrase() or key_from_file().
/// Its bytes are wiped (sodium_memzero) when it is destroyed or overwritten.
class SessionKey {
public:
    static constexpr std::size_t kBytes = 32;  ///< key length, bytes
    /// An all-zero key (a placeholder to assign to; never a key to use).
    SessionKey() = default;
    /// A key of these 32 bytes (the caller wipes its own copy).
    explicit SessionKey(const std::uint8_t (&bytes)[kBytes]);
    /// A copy of another key's bytes (each copy wipes its own).
    SessionKey(const SessionKey& other);
    /// Overwrites this key's bytes with another's.
    SessionKey& operator=(const SessionKey& other);
    /// Wipes the key's bytes (sodium_memzero).
    ~SessionKey();
    /// The 32 key bytes.
    const std::uint8_t* data() const { return bytes_; }
    /// Constant-time comparison (sodium_memcmp).
    bool operator==(const SessionKey& other) const;

private:
    std::uint8_t bytes_[kBytes] = {};
};

/// The key of a passphrase: Argon2id (crypto_pwhash, ALG_ARGON2ID13) with the interactive limits
/// (OPSLIMIT_INTERACTIVE = 2 passes over MEMLIMIT_INTERACTIVE = 64 MiB: one key per session start, not per datagram)
/// and a fixed application salt (sound here because every connection derives a fresh key from random nonces; see
/// docs/devices/sealed-link.md). Throws tridex::Error when the passphrase is empty or Argon2id runs out of memory.
SessionKey key_from_passphrase(std::string_view passphrase);

/// The key in a file: exactly 32 raw bytes, or exactly 64 hexadecimal characters (either case) optionally followed by
/// one line end ("\n" or "\r\n"). Throws tridex::Error "key file 'PATH': ..." naming the file and what was wrong
/// (cannot open, empty, its length, or the offset of a character that is not hexadecimal). The bytes read are wiped.
SessionKey key_from_file(const std::string& path);

/// Where the long-term key of a sealed link comes from, as a command line or a scene file gives it: a key file, or
/// the name of an environment variable that holds a passphrase (never the passphrase itself, so that it shows
/// neither in `ps` nor in a scene file).
struct KeySettings {
    std::string key_file;        ///< a file key_from_file() reads; "" = none
    std::string passphrase_env;  ///< an environment variable whose value key_from_passphrase() derives; "" = none
    std::string key_file_name = "--key-file";              ///< how errors name the key file setting
    std::string passphrase_env_name = "--passphrase-env";  ///< how errors name the passphrase setting
    /// True when either source is given.
    bool any() const { return !key_file.empty() || !passphrase_env.empty(); }
};

/// The key the settings give, or std::nullopt when they give none (the link is then not authenticated). Throws
/// tridex::Error naming the setting: both given ("choose one"), the environment variable unset or empty, or what
/// key_from_file() or key_from_passphrase() refused (prefixed with the setting's name).
std::optional<SessionKey> key_from_settings(const KeySettings& settings);

/// Where the settings take the key from, for messages: "key file 'PATH'", "the passphrase in $VAR", or "" for none.
std::string key_source_text(const KeySettings& settings);

/// Which end of the connection a SealedLink is: it fixes the order of the nonces in the connection key and the
/// direction byte of every datagram's nonce, so the two ends must differ (a hello from the same role is refused).
enum class SealRole : std::uint8_t {
    kListener = 0,  ///< the end that listens (a session's host, a device server)
    kJoiner = 1,    ///< the end that connects (a joiner, a net driver)
};

/// What a SealedLink refused and accepted so far (a snapshot of its atomic counters). Each refused datagram is
/// counted once, under the first check it fails, in this order: truncated, bad_version, then by channel byte (hello:
/// truncated or hello_refused; confirmation or data: early, forged, then replayed or out_of_order for data).
struct SealStats {
    /// Data datagrams authenticated, in order, delivered upward.
    std::uint64_t accepted = 0;
    /// The MAC failed (a changed byte anywhere, the wrong key, a datagram of an earlier connection), or the channel
    /// byte is none of the four.
    std::uint64_t forged = 0;
    /// Authentic, and its counter is one accepted before on its channel (among the 64 newest counters).
    std::uint64_t replayed = 0;
    /// Authentic, its counter below the newest accepted on its channel, and not known as accepted (unseen within the
    /// 64 newest, or older than them).
    std::uint64_t out_of_order = 0;
    /// Shorter than header + MAC (26 bytes), or a hello shorter than 67 bytes.
    std::uint64_t truncated = 0;
    /// The first byte is not SealedLink::kVersion.
    std::uint64_t bad_version = 0;
    /// A hello that failed authentication (the wrong key), came from our own role (reflected), had the wrong length,
    /// repeated the hello already taken, or came while none was expected (before the connection or after it was
    /// confirmed); or an authentic confirmation after the first.
    std::uint64_t hello_refused = 0;
    /// A data datagram or confirmation before the handshake allowed it (no connection key yet, or not confirmed).
    std::uint64_t early = 0;
    /// send() calls dropped because the handshake had not completed (not a refusal of the peer's).
    std::uint64_t send_dropped = 0;
    /// Every datagram refused, whatever the reason (all but accepted and send_dropped).
    std::uint64_t refused() const {
        return forged + replayed + out_of_order + truncated + bad_version + hello_refused + early;
    }
};

/// A decorator that seals every datagram of an inner DatagramLink. On the inner link's kConnected both ends send a
/// hello (a fresh 32-byte random nonce, authenticated with a subkey of the long-term key); when the peer's hello is
/// in, each end derives the connection key from both nonces and sends a key confirmation (an empty datagram sealed
/// under it); when the peer's confirmation opens, kConnected goes upward. Until then send() drops (counted in
/// send_dropped, as the DatagramLink contract drops while not connected()) and nothing is delivered. Each datagram is
/// [version][channel][64-bit little-endian counter][XSalsa20-Poly1305 box of the payload]; the receiver accepts a
/// counter only when it is greater than the newest accepted on that channel. Bad datagrams are counted and dropped:
/// poll() never throws for them and never allocates more than one datagram's size. Not thread-safe (one thread sends
/// and polls), except stats(), which any thread may call.
class SealedLink final : public DatagramLink {
public:
    static constexpr std::uint8_t kVersion = 1;          ///< byte 0 of every datagram
    static constexpr std::size_t kHeaderBytes = 10;      ///< version, channel, counter
    static constexpr std::size_t kMacBytes = 16;         ///< Poly1305 tag (crypto_secretbox_MACBYTES)
    static constexpr std::size_t kHelloBytes = 67;       ///< version, channel, role, 32-byte nonce, 32-byte tag
    static constexpr int kMaxInnerEventsPerPoll = 1024;  ///< a flood cannot hold poll() longer than this many events

    /// Wraps `inner` (which must not have been polled yet) with the long-term key `key` as end `role`. Throws
    /// tridex::Error when inner is null or libsodium cannot initialise (sodium_init).
    SealedLink(std::unique_ptr<DatagramLink> inner, const SessionKey& key, SealRole role);
    /// Wipes the subkeys and the connection key (sodium_memzero).
    ~SealedLink() override;
    /// Not copyable (it owns the inner link and key material).
    SealedLink(const SealedLink&) = delete;
    SealedLink& operator=(const SealedLink&) = delete;

    /// Seals `bytes` (any length) on the reliable or unreliable channel and queues it on the inner link; dropped
    /// (counted in send_dropped) until the handshake completed, or once a channel's counter would wrap.
    void send(const std::vector<std::uint8_t>& bytes, bool reliable) override;
    /// The next event upward: kConnected once the handshake completed (data: the peer's address the inner link gave),
    /// kDisconnected when a connection that was reported connected ends, kData with the opened payload. Processes at
    /// most kMaxInnerEventsPerPoll inner events per call (returns false after them even if more wait).
    bool poll(LinkEvent& ev) override;
    /// True while the inner link is connected and the handshake completed.
    bool connected() const override;
    /// The inner link's where().
    const char* where() const override { return inner_->where(); }
    /// The inner link's traffic() (what reached its socket, sealed or not).
    LinkTraffic traffic() const override { return inner_->traffic(); }
    /// The inner link's connected(): the transport reached the peer, whether the handshake completed or not.
    bool reached() const override { return inner_->connected(); }
    /// While the handshake has not completed: "the handshake failed: ..." once a hello failed authentication (the two
    /// ends hold different keys), or a datagram that is not sealed arrived after the inner link connected (the peer
    /// runs without a key); "" otherwise, and again once a handshake completes. One injected datagram can set it: a
    /// caller that gives up on it trades waiting for a clear message, as the threat model leaves denial of service
    /// open anyway. When it is set the link also drops the peer (drop_peer(): a listener then serves the next peer
    /// instead of one that cannot complete the handshake, which keeps our hello, queued before, and so learns why).
    std::string handshake_failure() const override;
    /// The inner link's drop_peer().
    void drop_peer() override { inner_->drop_peer(); }
    /// The counters so far; any thread may call it.
    SealStats stats() const;
    bool sealed() const override { return true; }
    std::uint64_t refused() const override { return stats().refused(); }

private:
    struct Counters;
    struct Channel {  // the receiving state of one channel
        std::uint64_t newest = 0;
        std::uint64_t window = 0;  // bit i: counter newest - i was accepted
        bool any = false;
    };
    void fail(const char* why);
    void begin_connection();
    void end_connection();
    void on_hello(const std::vector<std::uint8_t>& d);
    bool on_confirm(const std::vector<std::uint8_t>& d);
    bool open_data(LinkEvent& ev);
    bool open_box(const std::vector<std::uint8_t>& d);
    void seal_and_send(std::uint8_t channel, const std::uint8_t* p, std::size_t n, bool reliable);
    std::uint8_t peer_role() const;
    void nonce_of(const std::uint8_t* header, std::uint8_t sender_role, std::uint8_t* nonce) const;

    std::unique_ptr<DatagramLink> inner_;
    SealRole role_;
    std::unique_ptr<Counters> counters_;
    std::uint8_t hello_key_[32] = {};   // crypto_kdf subkey 1: crypto_auth of the hellos
    std::uint8_t derive_key_[32] = {};  // crypto_kdf subkey 2: the BLAKE2b key of the connection key
    std::uint8_t conn_key_[32] = {};    // the connection's crypto_secretbox key
    std::uint8_t own_nonce_[32] = {};
    std::uint8_t peer_nonce_[32] = {};
    bool started_ = false;      // the inner link is connected and our hello was sent
    bool established_ = false;  // an authentic hello is in; conn_key_ holds the connection key; our confirm was sent
    bool confirmed_ = false;    // the peer's confirm opened: kConnected went upward (so kDisconnected does too)
    std::string failure_;       // what failed in the handshake since the last one completed ("" = nothing)
    std::vector<std::uint8_t> peer_address_;
    std::uint64_t send_counter_[4] = {0, 0, 0, 0};  // by channel byte: reliable, unreliable, (hello), confirm
    Channel recv_[2];
    std::vector<std::uint8_t> out_;      // the sealed datagram being sent
    std::vector<std::uint8_t> scratch_;  // the opened payload, swapped into the event
};

}  // namespace tridex::devices::net
