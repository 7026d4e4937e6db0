// The sealed link's long-term key (devices/net/sealed_link.hpp): from a passphrase (Argon2id) and from a key file
// (32 raw bytes or 64 hexadecimal characters), and each refusal naming the file and what was wrong.
#include <gtest/gtest.h>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "devices/net/sealed_link.hpp"

namespace {

using namespace tridex::devices::net;
namespace fs = std::filesystem;

/// A temporary folder for key files, removed at the end of the test.
struct KeyDir {
    fs::path dir;
    KeyDir() {
        dir = fs::temp_directory_path() /
              ("tridex-sealed-key-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~KeyDir() { fs::remove_all(dir); }
    /// Writes `bytes` to `name`; returns its path.
    std::string write(const std::string& name, const std::string& bytes) const {
        const fs::path p = dir / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }
};

/// The bytes 0, 7, 14, ... (32 of them), raw and as hexadecimal text.
std::string raw_key() {
    std::string s;
    for (int i = 0; i < 32; ++i) s.push_back(static_cast<char>(i * 7));
    return s;
}
std::string hex_key(bool upper) {
    static const char* lo = "0123456789abcdef";
    static const char* up = "0123456789ABCDEF";
    std::string s;
    for (unsigned char c : raw_key()) {
        s.push_back((upper ? up : lo)[c >> 4]);
        s.push_back((upper ? up : lo)[c & 15]);
    }
    return s;
}

/// The message key_from_file throws for `path`, or "" when it does not throw.
std::string refusal(const std::string& path) {
    try {
        key_from_file(path);
    } catch (const tridex::Error& e) {
        return e.what();
    }
    return "";
}

TEST(SealedKey, FileOf32RawBytesOr64HexCharactersIsAccepted) {
    KeyDir d;
    const SessionKey raw = key_from_file(d.write("raw.key", raw_key()));
    EXPECT_EQ(key_from_file(d.write("hex.key", hex_key(false))), raw);
    EXPECT_EQ(key_from_file(d.write("upper.key", hex_key(true))), raw);
    EXPECT_EQ(key_from_file(d.write("newline.key", hex_key(false) + "\n")), raw);
    EXPECT_EQ(key_from_file(d.write("crlf.key", hex_key(false) + "\r\n")), raw);
    std::uint8_t bytes[32];
    for (int i = 0; i < 32; ++i) bytes[i] = static_cast<std::uint8_t>(i * 7);
    EXPECT_EQ(raw, SessionKey(bytes));
}

TEST(SealedKey, BadKeyFilesAreRefusedNamingTheFileAndTheFault) {
    KeyDir d;
    struct Case {
        std::string name, bytes, says;
    };
    const Case cases[] = {
        {"empty.key", "", "is empty"},
        {"short.key", raw_key().substr(0, 31), "31 bytes"},
        {"short-hex.key", hex_key(false).substr(0, 31), "31 hexadecimal characters"},
        {"long-hex.key", hex_key(false) + "0", "65 hexadecimal characters"},
        {"non-hex.key", hex_key(false).substr(0, 10) + "g" + hex_key(false).substr(11), "byte 10 is not a hexadecimal"},
        {"two-newlines.key", hex_key(false) + "\n\n", "byte 64 is not a hexadecimal"},
        {"huge.key", std::string(4096, 'a'), "longer than 66 bytes"},
    };
    for (const Case& c : cases) {
        const std::string path = d.write(c.name, c.bytes);
        const std::string msg = refusal(path);
        EXPECT_NE(msg.find("key file '" + path + "'"), std::string::npos) << c.name << ": " << msg;
        EXPECT_NE(msg.find(c.says), std::string::npos) << c.name << ": " << msg;
    }
    const std::string missing = (d.dir / "missing.key").string();
    const std::string msg = refusal(missing);
    EXPECT_NE(msg.find("key file '" + missing + "': cannot open"), std::string::npos) << msg;
}

TEST(SealedKey, PassphraseGivesTheSameKeyEachTimeAndRefusesEmpty) {
    const SessionKey a = key_from_passphrase("a passphrase for the shared session");
    EXPECT_EQ(key_from_passphrase("a passphrase for the shared session"), a);
    EXPECT_FALSE(key_from_passphrase("a passphrase for the shared session.") == a);
    EXPECT_THROW(key_from_passphrase(""), tridex::Error);
    SessionKey copy;
    copy = a;
    EXPECT_EQ(copy, a);
}

// The settings a command line or scene gives: none, a key file, or a variable's passphrase; each refusal names the
// setting (and the file or variable).
TEST(SealedKey, KeySettingsGiveTheKeyOrRefuseNamingTheSetting) {
    const KeyDir d;
    const auto refusal = [](const KeySettings& k) {
        try {
            (void)key_from_settings(k);
        } catch (const tridex::Error& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    KeySettings none;
    EXPECT_FALSE(none.any());
    EXPECT_FALSE(key_from_settings(none).has_value());
    EXPECT_EQ(key_source_text(none), "");

    KeySettings file;
    file.key_file = d.write("k.raw", raw_key());
    ASSERT_TRUE(key_from_settings(file).has_value());
    EXPECT_EQ(*key_from_settings(file), key_from_file(file.key_file));
    EXPECT_EQ(key_source_text(file), "key file '" + file.key_file + "'");
    file.key_file = (d.dir / "missing.key").string();
    file.key_file_name = "device.key_file";
    EXPECT_EQ(refusal(file).rfind("device.key_file: key file '" + file.key_file + "': cannot open", 0), 0u)
        << refusal(file);

    KeySettings env;
    env.passphrase_env = "TRIDEX_TEST_KEY_SETTINGS";
    ASSERT_EQ(setenv("TRIDEX_TEST_KEY_SETTINGS", "a passphrase for the shared session", 1), 0);
    ASSERT_TRUE(key_from_settings(env).has_value());
    EXPECT_EQ(*key_from_settings(env), key_from_passphrase("a passphrase for the shared session"));
    EXPECT_EQ(key_source_text(env), "the passphrase in $TRIDEX_TEST_KEY_SETTINGS");
    ASSERT_EQ(setenv("TRIDEX_TEST_KEY_SETTINGS", "", 1), 0);
    EXPECT_EQ(refusal(env), "--passphrase-env TRIDEX_TEST_KEY_SETTINGS: the environment variable "
                            "TRIDEX_TEST_KEY_SETTINGS is empty");
    ASSERT_EQ(unsetenv("TRIDEX_TEST_KEY_SETTINGS"), 0);
    EXPECT_EQ(refusal(env), "--passphrase-env TRIDEX_TEST_KEY_SETTINGS: the environment variable "
                            "TRIDEX_TEST_KEY_SETTINGS is not set");
    env.passphrase_env = "X=secret";  // a passphrase given where its variable's name belongs
    EXPECT_NE(refusal(env).find("is not the name of an environment variable"), std::string::npos) << refusal(env);

    KeySettings both;
    both.key_file = d.write("k2.raw", raw_key());
    both.passphrase_env = "HOME";
    EXPECT_EQ(refusal(both), "--key-file, --passphrase-env: choose one");
}

}  // namespace
