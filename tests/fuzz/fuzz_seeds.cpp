// tests/fuzz/fuzz_seeds.cpp - writes the seed inputs the fuzz targets cannot take from ../shared/data or assets/:
// small valid files and datagrams of every format, made by tridex's own writers and encoders (so checksums
// hold), one folder per target. Usage: fuzz_seeds OUT_DIR (writes OUT_DIR/<target>/<name>).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/session/cluster/net_transport_wire.hpp"
#include "app/session/shared/shared_message.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/tridexel.hpp"
#include "core/active_surface.hpp"
#include "core/primitives.hpp"
#include "devices/falcon/falcon_protocol.hpp"
#include "devices/net/link_wire.hpp"
#include "devices/net/surface_codec.hpp"
#include "devices/recording.hpp"
#include "tests/fuzz/fuzz_mesh_seeds.hpp"

namespace fs = std::filesystem;
using namespace tridex;

namespace {

/// Writes `bytes` to dir/target/name.
void put(const fs::path& dir, const std::string& target, const std::string& name, const std::string& bytes) {
    fs::create_directories(dir / target);
    std::ofstream(dir / target / name, std::ios::binary) << bytes;
}

/// Writes a datagram to dir/target/name.
void put(const fs::path& dir, const std::string& target, const std::string& name, const std::vector<std::uint8_t>& d) {
    put(dir, target, name, std::string(d.begin(), d.end()));
}

/// A small sculpted-free model: a sphere scan-converted on an 8 x 9 x 7 lattice, saved as .tdx.
void tdx_seeds(const fs::path& dir) {
    fs::create_directories(dir / "tdx");
    compute::Lattice lattice;
    lattice.origin_m = Vec3(-0.01);
    lattice.cell_m = 0.0025;
    lattice.cells = {8, 9, 7};
    compute::TriDexel model = compute::TriDexel::empty(lattice, std::size_t{1} << 26);
    compute::save_tdx((dir / "tdx" / "empty.tdx").string(), model, Mat4(1.0), "{}", 1);
    compute::scan_convert(icosphere_mesh(Vec3(0.0), 0.008, 1), model);
    compute::save_tdx((dir / "tdx" / "sphere.tdx").string(), model, Mat4(1.0), "{\"resolution\": 8}", 1);
}

/// A three-tick recording with marks, version 2.
void recording_seeds(const fs::path& dir) {
    fs::create_directories(dir / "recording");
    devices::Recording rec;
    rec.header.device_name = "omni";
    rec.header.workspace_mode = "moving";
    rec.header.notes = "fuzz seed";
    rec.header.marks = std::vector<devices::RecordedMark>{};
    for (int i = 0; i < 3; ++i) {
        devices::RecordedTick t;
        t.t_s = 0.001 * (i + 1);
        t.device.t_s = t.t_s;
        t.force_n = Vec3(0.0, 0.1 * i, 0.0);
        rec.ticks.push_back(t);
    }
    devices::write_recording((dir / "recording" / "three_ticks.trdxrec").string(), rec);
}

/// A journal with two batches, a stroke end, a coarseness change and an intake record (its samples the tail).
void journal_seeds(const fs::path& dir) {
    fs::create_directories(dir / "journal");
    compute::JournalWriter writer((dir / "journal" / "session.tdj").string(), "{\"seed\": 1}");
    std::vector<ToolSample> batch(3);
    for (std::size_t i = 0; i < batch.size(); ++i) {
        batch[i].t_s = 0.001 * static_cast<double>(i + 1);
        batch[i].position = Vec3(0.001 * static_cast<double>(i), 0.0, 0.05);
        batch[i].op = ToolOp::kSubtract;
        batch[i].tool.radius_m = 0.003;
    }
    writer.append(batch);
    writer.mark(compute::kJournalStrokeEnd, 1);
    writer.mark(compute::kJournalLattice, 2, 96);
    writer.append(batch);
    writer.intake(6, batch);
    writer.close();
}

/// One datagram of every link message type, and a surface snapshot with a few rays.
void net_seeds(const fs::path& dir) {
    namespace net = devices::net;
    std::vector<std::uint8_t> d;
    net::encode(net::Header{}, net::Hello{}, d), put(dir, "net", "hello", d);
    net::encode(net::Header{}, net::welcome_from(devices::DeviceProfile{}), d), put(dir, "net", "welcome", d);
    net::encode_refuse(net::Header{}, "version 2 is not served", d), put(dir, "net", "refuse", d);
    net::StateMsg state;
    state.has_tool = true;
    net::encode(net::Header{}, state, d), put(dir, "net", "state", d);
    net::encode(net::Header{}, net::ForceMsg{}, d), put(dir, "net", "force", d);
    net::ContactMsg contact;
    contact.point_count = 2;
    net::encode(net::Header{}, contact, d), put(dir, "net", "contact", d);
    net::encode_heartbeat(net::Header{}, d), put(dir, "net", "heartbeat", d);
    static ActiveSurface surface;
    surface.sequence = 1;
    surface.cell_m = 0.001;
    surface.nodes = {16, 16, 16};
    surface.sets[0].nu = surface.sets[0].nv = 2;
    surface.sets[0].count[0] = 1;
    surface.sets[0].depth[1] = 3.0f;
    net::encode_surface(net::Header{}, surface, d), put(dir, "net", "surface", d);
}

/// Operation lists as fuzz_sealed reads them (tests/fuzz/fuzz_sealed.cpp: 0 raw, 1 seal, 2 replay, 3 flip,
/// 4 truncate, 5 reconnect; the joiner's kept datagrams are its hello, its confirmation, then its data).
void sealed_seeds(const fs::path& dir) {
    const auto put_ops = [&](const std::string& name, std::vector<std::uint8_t> ops) { put(dir, "sealed", name, ops); };
    put_ops("seal-replay", {1, 0x81, 1, 2, 2, 2, 3, 2, 4});
    put_ops("flip", {1, 1, 3, 2, 0, 0x80, 3, 2, 12, 1, 3, 2, 30, 0xff});
    put_ops("truncate", {1, 4, 2, 25, 4, 2, 10, 4, 2, 0});
    put_ops("reconnect", {1, 0x81, 5, 2, 2, 2, 3, 1});
    put_ops("hello-again", {2, 0, 2, 1, 1});
    std::vector<std::uint8_t> raw = {0, 40, 1, 0};
    raw.resize(44, 0x5a);
    put_ops("raw", raw);
}

/// One message of each kind of a shared session (tests/fuzz/fuzz_shared.cpp).
void shared_seeds(const fs::path& dir) {
    const auto put_msg = [&](const std::string& name, const std::vector<unsigned char>& b) { put(dir, "shared", name, b); };
    put_msg("join", app::encode_join(app::JoinMessage{app::kSharedProtocol, "Bo", Vec3(0.2, 0.4, 0.6)}));
    put_msg("welcome", app::encode_welcome(app::WelcomeMessage{1, "Ann", "{}", {1, 2, 3}, 42}));
    app::WelcomeMessage late{2, "Ann", "{}", {1, 2, 3}, 42};  // a late join: history, sweeps, the record it starts at
    late.first_record = 1200;
    late.history = {'T', 'D', 'X', 'H', 1, 0, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0};
    late.prevs.resize(2);
    late.prevs[1].site = 1;
    late.last_closed_serial = 9;
    put_msg("welcome_late", app::encode_welcome(late));
    ToolSample s;
    s.op = ToolOp::kSubtract;
    s.tool.radius_m = 0.004;
    s.site = 1;
    const std::vector<ToolSample> samples = {s, s};
    put_msg("samples", app::encode_samples(samples));
    put_msg("request", app::encode_request(app::SculptRequest::kUndo));
    app::RecordsMessage r;
    r.records.resize(2);
    r.records[0].samples = samples;
    r.records[1].kind = compute::JournalKind::kStrokeEnd;
    r.records[1].serial = 3;
    r.check_digest = 7;
    r.check_after = 1;
    put_msg("records", app::encode_records(r));
    r.records.assign(60, r.records[0]);  // long enough to be sent packed
    put_msg("records_packed", app::encode_records(r));
    put_msg("refused", app::encode_refused(app::RefusedMessage{app::SculptRequest::kRedo, 2, "Cy"}));
    app::PresenceMessage headed;
    headed.site = 2;
    headed.name = "Cy";
    headed.colour = Vec3(0.5);
    headed.tool_radius_m = 0.004;
    put_msg("presence", app::encode_presence(headed));
    headed.head_tracked = true;
    headed.head = Pose{Vec3(0.0, 0.3, 0.8), Quat(1, 0, 0, 0)};
    headed.head_size_m = app::kHeadRadiusM;
    put_msg("presence_head", app::encode_presence(headed));
    put_msg("end", app::encode_end(app::EndMessage{9, 120, "the host ended the session"}));
}

/// A wall's datagrams as fuzz_cluster_wire reads them (each a u16 length, then its bytes): a claim and its answers, a
/// message of three parts, an acknowledgement and an abort.
void cluster_wire_seeds(const fs::path& dir) {
    namespace wire = app::netwire;
    const auto framed = [](const std::vector<std::vector<std::uint8_t>>& datagrams) {
        std::string out;
        for (const std::vector<std::uint8_t>& d : datagrams) {
            out += static_cast<char>(d.size() & 0xff);
            out += static_cast<char>(d.size() >> 8);
            out.append(d.begin(), d.end());
        }
        return out;
    };
    put(dir, "cluster_wire", "claim", framed({wire::encode_claim(2)}));
    put(dir, "cluster_wire", "answers", framed({wire::encode_accept(2), wire::encode_refuse("render rank 2 is held"),
                                                wire::encode_ack(3, 700), wire::encode_abort(5)}));
    std::vector<std::vector<std::uint8_t>> parts;
    const std::vector<unsigned char> message(1000, 0x42);
    for (std::size_t i = 0; i < 3; ++i) {
        std::vector<std::uint8_t> d = {static_cast<std::uint8_t>(i < 2 ? wire::Kind::kDataMore : wire::Kind::kDataLast)};
        d.insert(d.end(), message.begin() + static_cast<std::ptrdiff_t>(i * 300), message.begin() + static_cast<std::ptrdiff_t>(i * 300 + 300));
        parts.push_back(d);
    }
    put(dir, "cluster_wire", "message", framed(parts));
    std::vector<std::uint8_t> one;
    wire::make_chunk(message, 0, one);
    put(dir, "cluster_wire", "chunk", framed({one}));
}

/// IN packets as fuzz_falcon reads them (a length byte, two modem bytes, data): whole, torn and doubled frames.
void falcon_seeds(const fs::path& dir) {
    namespace falcon = devices::falcon;
    falcon::FalconState s;
    s.encoder = {120, -340, 5};
    s.homing_status = falcon::kAllHomed;
    s.grip_buttons = 0x5;
    const falcon::Frame f = falcon::encode_state(s);
    const std::string frame(f.begin(), f.end());
    const std::string modem = {static_cast<char>(falcon::kModemIdle.modem), static_cast<char>(falcon::kModemIdle.line)};
    auto packet = [&](const std::string& data) { return std::string(1, static_cast<char>(2 + data.size())) + modem + data; };
    put(dir, "falcon", "one_frame", packet(frame));
    put(dir, "falcon", "torn_frame", packet(frame.substr(0, 7)) + packet(frame.substr(7)));
    put(dir, "falcon", "two_frames", packet(frame + frame));
    const falcon::Frame c = falcon::encode_command(falcon::FalconCommand{{100, -200, 300}, falcon::kLedGreen, true});
    put(dir, "falcon", "command", std::string(c.begin(), c.end()));
}

/// DTrack datagrams of every line type the parser reads.
void dtrack_seeds(const fs::path& dir) {
    put(dir, "dtrack", "bodies",
        "fr 21753\r\nts 39596.024023\r\n6dcal 2\r\n6d 2 [0 1.000][100.000 1650.000 900.000 0.0000 90.0000 0.0000]"
        "[0 0 -1 0 1 0 1 0 0] [1 -1.000][0 0 0][1 0 0 0 1 0 0 0 1]\r\n");
    put(dir, "dtrack", "flystick",
        "fr 7\nts2 1700000000 250 1200\n6df2 1 1 [0 0.950 8 2][-250.500 1200.000 600.250][1 0 0 0 1 0 0 0 1]"
        "[5 0.500 -1.000]\n3d 0\ngl 0\n");
}

}  // namespace

/// Writes every seed under argv[1]; exit 0, or 1 with the reason.
int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR\n");
        return 1;
    }
    try {
        const fs::path dir = argv[1];
        tdx_seeds(dir);
        recording_seeds(dir);
        journal_seeds(dir);
        net_seeds(dir);
        falcon_seeds(dir);
        sealed_seeds(dir);
        shared_seeds(dir);
        cluster_wire_seeds(dir);
        dtrack_seeds(dir);
        for (const auto& seed : fuzz::mesh_seeds()) put(dir, seed.target, seed.name, seed.bytes);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
