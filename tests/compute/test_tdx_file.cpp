// tests/compute/test_tdx_file.cpp - the .tdx model file: bit-exact round trips of sculpted models, atomic saves
// (the old file survives a failed save), and refusal with a clear message of every kind of damaged file:
// truncation at many lengths, bit flips in every section, a newer version, huge claimed sizes, bad intervals.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "compute/model/tdx_file.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"
#include "tdx_test_models.hpp"

using namespace tridex;
using namespace tridex::compute;
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kBudget = std::size_t{1} << 30;

fs::path temp_dir() {
    const fs::path d = fs::temp_directory_path() / ("tridex_tdx_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

std::vector<unsigned char> read_all(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

void write_all(const fs::path& p, const std::vector<unsigned char>& bytes) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::uint64_t get64(const std::vector<unsigned char>& b, std::size_t at) {
    std::uint64_t v;
    std::memcpy(&v, b.data() + at, 8);
    return v;
}

/// Offsets of the 6 section headers in a .tdx file's bytes.
std::vector<std::size_t> section_offsets(const std::vector<unsigned char>& b) {
    std::vector<std::size_t> at;
    std::size_t off = 40;
    for (int i = 0; i < 6; ++i) {
        at.push_back(off);
        off += 32 + get64(b, off + 16);
    }
    EXPECT_EQ(off, b.size());
    return at;
}

/// The message load_tdx throws for `bytes`, or "" when it loads.
std::string load_error(const fs::path& p, const std::vector<unsigned char>& bytes, std::size_t budget = kBudget) {
    write_all(p, bytes);
    try {
        load_tdx(p.string(), budget);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

struct Saved {
    TriDexel model;
    fs::path path;
    std::vector<unsigned char> bytes;
};

Saved saved_model(const std::string& name) {
    Saved s{tdx_test::sculpted_sphere(40, 60, 3u), temp_dir() / name, {}};
    s.model.clear_dirty();
    s.model.tiles.dirty[1] = 1;
    save_tdx(s.path.string(), s.model, Mat4(1.0), R"({"resolution": 40})");
    s.bytes = read_all(s.path);
    return s;
}

}  // namespace

TEST(TdxFile, SculptedModelsRoundTripBitForBit) {
    for (std::uint32_t seed : {1u, 2u}) {
        TriDexel m = tdx_test::sculpted_sphere(48, 120, seed);
        std::size_t multi = 0, painted = 0;
        for (const auto& set : m.sets)
            for (const auto& ray : set.rays) {
                multi += ray.size() > 1;
                for (const Interval& iv : ray) painted += iv.enter_material != 0 || iv.exit_material != 0;
            }
        EXPECT_GT(multi, 100u);  // the sculpting made rays of several intervals
        EXPECT_GT(painted, 100u);
        Mat4 to_world(0.0015);
        to_world[3] = glm::dvec4(0.01, -0.2, 0.3, 1.0);
        const std::string settings = R"({"op": "subtract", "resolution": 48, "unicode": "\u00e9"})";
        const fs::path p = temp_dir() / ("roundtrip" + std::to_string(seed) + ".tdx");
        save_tdx(p.string(), m, to_world, settings);
        EXPECT_FALSE(fs::exists(p.string() + ".tmp-" + std::to_string(::getpid())));
        const TdxModel back = load_tdx(p.string(), kBudget);
        tdx_test::expect_identical(m, back.model);
        EXPECT_EQ(back.to_world, to_world);
        EXPECT_EQ(back.settings_json, settings);
    }
}

TEST(TdxFile, EmptyModelAndEmptySettingsRoundTrip) {
    Lattice L;
    L.cells = {3, 1, 2};
    const TriDexel m = TriDexel::empty(L, kBudget);
    const fs::path p = temp_dir() / "empty.tdx";
    save_tdx(p.string(), m, Mat4(1.0), "");
    const TdxModel back = load_tdx(p.string(), kBudget);
    tdx_test::expect_identical(m, back.model);
    EXPECT_EQ(back.settings_json, "");
}

TEST(TdxFile, SavingReplacesTheOldFileAndAFailedSaveLeavesItIntact) {
    Saved s = saved_model("replace.tdx");
    const TriDexel other = tdx_test::sculpted_sphere(24, 5, 9u);
    save_tdx(s.path.string(), other, Mat4(1.0), "{}");
    tdx_test::expect_identical(other, load_tdx(s.path.string(), kBudget).model);
    save_tdx(s.path.string(), s.model, Mat4(1.0), "{}");

    // A full disk, as the file size limit: the write fails, the old file stays, no temporary file is left.
    struct rlimit old {};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
    auto* const old_handler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string message;
    try {
        save_tdx(s.path.string(), other, Mat4(1.0), "{}");
    } catch (const Error& e) {
        message = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, old_handler);
    EXPECT_NE(message.find(s.path.string() + ": cannot write"), std::string::npos) << message;
    EXPECT_NE(message.find("unchanged"), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(s.path.string() + ".tmp-" + std::to_string(::getpid())));
    tdx_test::expect_identical(s.model, load_tdx(s.path.string(), kBudget).model);

    // A folder that does not exist.
    EXPECT_THROW(save_tdx((temp_dir() / "no" / "such" / "m.tdx").string(), other, Mat4(1.0), "{}"), Error);
}

TEST(TdxFile, TruncatedFilesAreRefusedAtEveryLength) {
    Saved s = saved_model("truncated.tdx");
    const fs::path p = temp_dir() / "cut.tdx";
    std::vector<std::size_t> lengths = {0, 1, 7, 8, 39, 40, 41, s.bytes.size() - 1};
    for (std::size_t at : section_offsets(s.bytes))
        for (std::size_t d : {0, 1, 31, 32, 33}) lengths.push_back(at + d);
    for (std::size_t k = 1; k < 300; ++k) lengths.push_back(s.bytes.size() * k / 300);
    for (std::size_t n : lengths) {
        if (n >= s.bytes.size()) continue;
        const std::string msg = load_error(p, std::vector<unsigned char>(s.bytes.begin(), s.bytes.begin() + n));
        ASSERT_FALSE(msg.empty()) << "a file cut to " << n << " bytes loaded";
        EXPECT_EQ(msg.rfind(p.string() + ": ", 0), 0u) << msg;
        if (n >= 40) {
            EXPECT_NE(msg.find("truncated"), std::string::npos) << n << ": " << msg;
        }
    }
    // Extra bytes after the end are refused too.
    std::vector<unsigned char> longer = s.bytes;
    longer.push_back(0);
    EXPECT_FALSE(load_error(p, longer).empty());
}

TEST(TdxFile, BitFlipsInEverySectionAreRefusedNamingTheSection) {
    Saved s = saved_model("flips.tdx");
    const fs::path p = temp_dir() / "flipped.tdx";
    const char* names[] = {"meta", "settings", "rays.x", "rays.y", "rays.z", "tiles"};
    const std::vector<std::size_t> at = section_offsets(s.bytes);
    std::size_t flips = 0;
    for (std::size_t byte = 0; byte < 40; ++byte) {  // every bit of the file header
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<unsigned char> b = s.bytes;
            b[byte] ^= static_cast<unsigned char>(1u << bit);
            EXPECT_FALSE(load_error(p, b).empty()) << "header byte " << byte << " bit " << bit;
            ++flips;
        }
    }
    for (std::size_t i = 0; i < at.size(); ++i) {
        const std::size_t payload = at[i] + 32, end = i + 1 < at.size() ? at[i + 1] : s.bytes.size();
        for (std::size_t byte = at[i]; byte < payload; ++byte) {  // every byte of the section header
            std::vector<unsigned char> b = s.bytes;
            b[byte] ^= static_cast<unsigned char>(1u << (byte % 8));
            EXPECT_FALSE(load_error(p, b).empty()) << names[i] << " header byte " << byte - at[i];
            ++flips;
        }
        const std::size_t step = std::max<std::size_t>(1, (end - payload) / 40);
        for (std::size_t byte = payload; byte < end; byte += step) {  // payload bytes spread over the section
            std::vector<unsigned char> b = s.bytes;
            b[byte] ^= static_cast<unsigned char>(1u << (byte % 8));
            const std::string msg = load_error(p, b);
            ASSERT_FALSE(msg.empty()) << names[i] << " payload byte " << byte - payload;
            EXPECT_NE(msg.find(std::string("'") + names[i] + "'"), std::string::npos) << msg;
            ++flips;
        }
    }
    EXPECT_GT(flips, 600u);
}

TEST(TdxFile, NewerVersionsBadMagicAndHugeClaimedSizesAreRefused) {
    Saved s = saved_model("versions.tdx");
    const fs::path p = temp_dir() / "bad.tdx";
    std::vector<unsigned char> b = s.bytes;
    b[8] = 3;  // version 3
    EXPECT_NE(load_error(p, b).find("format version 3 is newer than this build reads (2)"), std::string::npos);
    b = s.bytes;
    b[0] = 'X';
    EXPECT_NE(load_error(p, b).find("bad magic"), std::string::npos);
    EXPECT_NE(load_error(p, {'h', 'e', 'l', 'l', 'o', '\n'}).find("bad magic"), std::string::npos);

    // Huge sizes in a section header whose own checksum is right: refused before anything is allocated.
    const std::size_t rays_x = section_offsets(s.bytes)[2];
    auto forge = [&](std::size_t field, std::uint64_t value) {
        std::vector<unsigned char> f = s.bytes;
        std::memcpy(f.data() + rays_x + field, &value, 8);
        const std::uint32_t crc = crc32_ieee(f.data() + rays_x, 28);
        std::memcpy(f.data() + rays_x + 28, &crc, 4);
        return f;
    };
    const std::string compressed = load_error(p, forge(16, std::uint64_t{1} << 62));
    EXPECT_NE(compressed.find("truncated: section 3 ('rays.x') needs 4611686018427387904 bytes"), std::string::npos)
        << compressed;
    const std::string raw = load_error(p, forge(8, std::uint64_t{1} << 62));
    EXPECT_NE(raw.find("section 3 ('rays.x') claims 4611686018427387904 bytes, the model needs"), std::string::npos) << raw;
    // A model larger than the memory allowed.
    const std::string budget = load_error(p, s.bytes, 100000);
    EXPECT_NE(budget.find("more than the 0 MiB available"), std::string::npos) << budget;
    EXPECT_TRUE(load_error(p, s.bytes).empty());
}

TEST(TdxFile, NonFiniteOrUnorderedDepthsAreRefusedNamingTheRay) {
    TriDexel m = tdx_test::sculpted_sphere(24, 0, 1u);
    auto bad_after = [&](auto change) {
        TriDexel c = m;
        for (auto& ray : c.sets[1].rays)
            if (!ray.empty()) {
                change(ray);
                break;
            }
        const fs::path p = temp_dir() / "bad_depths.tdx";
        save_tdx(p.string(), c, Mat4(1.0), "{}");
        try {
            load_tdx(p.string(), kBudget);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    for (auto change : std::vector<void (*)(std::vector<Interval>&)>{
             [](std::vector<Interval>& r) { r[0].enter = std::nanf(""); },
             [](std::vector<Interval>& r) { r[0].exit = INFINITY; },
             [](std::vector<Interval>& r) { std::swap(r[0].enter, r[0].exit); },
             [](std::vector<Interval>& r) { r.push_back(r[0]); },  // overlaps the first
             [](std::vector<Interval>& r) { r[0].enter = -0.5f; }}) {
        const std::string msg = bad_after(change);
        EXPECT_NE(msg.find("section 'rays.y': ray ("), std::string::npos) << msg;
    }
    // A material id past the palette, which no session writes and the renderer cannot draw.
    const std::string mat = bad_after([](std::vector<Interval>& r) { r[0].exit_material = 250; });
    EXPECT_NE(mat.find("section 'rays.y': ray ("), std::string::npos) << mat;
    EXPECT_NE(mat.find("material ids 0, 250 are not both material ids (0..7)"), std::string::npos) << mat;
}
