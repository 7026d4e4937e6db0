// devices/net/sealed_key.cpp - the long-term key of a sealed link: from a passphrase (libsodium's Argon2id) or a key
// file (32 raw bytes or 64 hexadecimal characters), wiped wherever it is dropped.
#include <sodium.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::devices::net {

namespace {

// The fixed application salt of key_from_passphrase (crypto_pwhash_SALTBYTES = 16 bytes).
constexpr char kSalt[] = "tridex-sealed-v1";
static_assert(sizeof kSalt - 1 == crypto_pwhash_SALTBYTES);
static_assert(SessionKey::kBytes == crypto_secretbox_KEYBYTES);

void init_sodium() {
    if (sodium_init() < 0) throw Error("sealed link: libsodium could not initialise (sodium_init failed)");
}

// Wipes a buffer of key material when it goes out of scope.
struct Wiped {
    unsigned char* p;
    std::size_t n;
    ~Wiped() { sodium_memzero(p, n); }
};

bool is_hex(unsigned char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

}  // namespace

SessionKey::SessionKey(const std::uint8_t (&bytes)[kBytes]) { std::memcpy(bytes_, bytes, kBytes); }

SessionKey::SessionKey(const SessionKey& other) { std::memcpy(bytes_, other.bytes_, kBytes); }

SessionKey& SessionKey::operator=(const SessionKey& other) {
    if (this != &other) std::memcpy(bytes_, other.bytes_, kBytes);
    return *this;
}

SessionKey::~SessionKey() { sodium_memzero(bytes_, kBytes); }

bool SessionKey::operator==(const SessionKey& other) const { return sodium_memcmp(bytes_, other.bytes_, kBytes) == 0; }

SessionKey key_from_passphrase(std::string_view passphrase) {
    init_sodium();
    if (passphrase.empty()) throw Error("sealed link: the passphrase is empty");
    std::uint8_t out[SessionKey::kBytes];
    Wiped wipe{out, sizeof out};
    if (crypto_pwhash(out, sizeof out, passphrase.data(), passphrase.size(),
                      reinterpret_cast<const unsigned char*>(kSalt), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                      crypto_pwhash_MEMLIMIT_INTERACTIVE, crypto_pwhash_ALG_ARGON2ID13) != 0)
        throw Error("sealed link: Argon2id ran out of memory deriving the key (it needs 64 MiB)");
    return SessionKey(out);
}

SessionKey key_from_file(const std::string& path) {
    init_sodium();
    const std::string what = "key file '" + path + "': ";
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Error(what + "cannot open (" + std::strerror(errno) + ")");
    // Read at most 67 bytes: one more than the longest accepted file (64 hex characters and "\r\n") tells it is too long.
    unsigned char buf[67];
    Wiped wipe_buf{buf, sizeof buf};
    const std::size_t n = std::fread(buf, 1, sizeof buf, f);
    const bool read_error = std::ferror(f) != 0;
    std::fclose(f);
    if (read_error) throw Error(what + "cannot read it");
    if (n == 0) throw Error(what + "is empty; expected 32 raw bytes or 64 hexadecimal characters");
    if (n == SessionKey::kBytes) {
        std::uint8_t key[SessionKey::kBytes];
        Wiped wipe_key{key, sizeof key};
        std::memcpy(key, buf, sizeof key);
        return SessionKey(key);
    }
    if (n == sizeof buf)
        throw Error(what + "is longer than 66 bytes; expected 32 raw bytes or 64 hexadecimal characters");
    // Hexadecimal: the characters before an optional final line end.
    std::size_t hex_n = n;
    if (hex_n > 0 && buf[hex_n - 1] == '\n') --hex_n;
    if (hex_n > 0 && buf[hex_n - 1] == '\r' && hex_n + 1 == n) --hex_n;
    for (std::size_t i = 0; i < hex_n; ++i)
        if (!is_hex(buf[i]))
            throw Error(what + "byte " + std::to_string(i) + " is not a hexadecimal character (" + std::to_string(n) +
                        " bytes: neither 32 raw bytes nor 64 hexadecimal characters)");
    if (hex_n != 2 * SessionKey::kBytes)
        throw Error(what + std::to_string(hex_n) +
                    " hexadecimal characters; expected 32 raw bytes or exactly 64 hexadecimal characters");
    std::uint8_t key[SessionKey::kBytes];
    Wiped wipe_key{key, sizeof key};
    std::size_t bin_n = 0;
    if (sodium_hex2bin(key, sizeof key, reinterpret_cast<const char*>(buf), hex_n, nullptr, &bin_n, nullptr) != 0 ||
        bin_n != sizeof key)
        throw Error(what + "cannot decode its 64 hexadecimal characters");
    return SessionKey(key);
}

std::optional<SessionKey> key_from_settings(const KeySettings& k) {
    if (!k.key_file.empty() && !k.passphrase_env.empty())
        throw Error(k.key_file_name + ", " + k.passphrase_env_name + ": choose one");
    if (!k.key_file.empty()) {
        try {
            return key_from_file(k.key_file);
        } catch (const Error& e) {
            throw Error(k.key_file_name + ": " + e.what());
        }
    }
    if (k.passphrase_env.empty()) return std::nullopt;
    const std::string what = k.passphrase_env_name + " " + k.passphrase_env + ": ";
    if (k.passphrase_env.find('=') != std::string::npos)
        throw Error(what + "is not the name of an environment variable (it names the variable, not the passphrase)");
    const char* value = std::getenv(k.passphrase_env.c_str());
    if (!value) throw Error(what + "the environment variable " + k.passphrase_env + " is not set");
    if (*value == '\0') throw Error(what + "the environment variable " + k.passphrase_env + " is empty");
    try {
        return key_from_passphrase(value);
    } catch (const Error& e) {
        throw Error(what + e.what());
    }
}

std::string key_source_text(const KeySettings& k) {
    if (!k.key_file.empty()) return "key file '" + k.key_file + "'";
    if (!k.passphrase_env.empty()) return "the passphrase in $" + k.passphrase_env;
    return "";
}

}  // namespace tridex::devices::net
