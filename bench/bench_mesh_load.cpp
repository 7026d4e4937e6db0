// bench/bench_mesh_load.cpp - `tridex bench --mesh-load`: tridex's strict OFF and PLY readers against OpenMesh's
// readers on the same files (the bundled bunny and a generated sphere in ASCII and binary), time and throughput.
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "compute/mesh/mesh_text.hpp"
#include "compute/mesh/off_reader.hpp"
#include "compute/mesh/openmesh_log.hpp"
#include "compute/mesh/ply_reader.hpp"
#include "core/error.hpp"

namespace tridex::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A latitude-longitude sphere of about `triangles` triangles (closed: poles are single vertices).
TriMesh sphere(int triangles) {
    const int rings = std::max(4, static_cast<int>(std::sqrt(triangles / 4.0)));
    const int segments = 2 * rings;
    TriMesh m;
    m.positions.push_back(Vec3(0, 0, 1));
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double th = M_PI * r / rings, ph = 2 * M_PI * s / segments;
            m.positions.push_back(Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
        }
    m.positions.push_back(Vec3(0, 0, -1));
    const auto ring = [&](int r, int s) { return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments)); };
    const auto south = static_cast<std::uint32_t>(m.positions.size() - 1);
    for (int s = 0; s < segments; ++s) {
        m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
        for (int r = 1; r + 1 < rings; ++r) {
            m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
            m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
        }
        m.triangles.push_back({south, ring(rings - 1, s + 1), ring(rings - 1, s)});
    }
    return m;
}

void put_be32(std::string& s, std::uint32_t v) {
    for (int i = 3; i >= 0; --i) s.push_back(static_cast<char>(v >> (8 * i)));
}

/// The sphere as ASCII OFF, ASCII PLY, binary little-endian PLY and binary OFF files in `dir`.
std::vector<std::string> write_sphere_files(const TriMesh& m, const fs::path& dir) {
    std::string off = "OFF\n" + std::to_string(m.positions.size()) + " " + std::to_string(m.triangles.size()) + " 0\n";
    std::string ply = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.positions.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    std::string bply = ply;
    bply.replace(bply.find("ascii"), 5, "binary_little_endian");
    std::string boff = "OFF BINARY\n";
    put_be32(boff, static_cast<std::uint32_t>(m.positions.size()));
    put_be32(boff, static_cast<std::uint32_t>(m.triangles.size()));
    put_be32(boff, 0);
    char line[96];
    for (const Vec3& p : m.positions) {
        std::snprintf(line, sizeof line, "%.7g %.7g %.7g\n", p.x, p.y, p.z);
        off += line;
        ply += line;
        for (int k = 0; k < 3; ++k) {
            const float f = static_cast<float>(p[k]);
            bply.append(reinterpret_cast<const char*>(&f), 4);
            put_be32(boff, std::bit_cast<std::uint32_t>(f));
        }
    }
    for (const auto& t : m.triangles) {
        std::snprintf(line, sizeof line, "3 %u %u %u\n", t[0], t[1], t[2]);
        off += line;
        ply += line;
        bply.push_back(3);
        bply.append(reinterpret_cast<const char*>(t.data()), 12);
        put_be32(boff, 3);
        for (auto i : t) put_be32(boff, i);
        put_be32(boff, 0);
    }
    std::vector<std::string> paths;
    for (const auto& [name, bytes] : {std::pair{"sphere_ascii.off", &off}, {"sphere_ascii.ply", &ply},
                                      {"sphere_binary.ply", &bply}, {"sphere_binary.off", &boff}}) {
        const fs::path p = dir / name;
        std::ofstream(p, std::ios::binary) << *bytes;
        paths.push_back(p.string());
    }
    return paths;
}

template <class F>
double median_ms(int repeats, F&& f) {
    std::vector<double> ms;
    for (int i = 0; i < repeats; ++i) {
        const auto t0 = Clock::now();
        f();
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

void run_mesh_load_bench(const BenchCommon& c, int triangles) {
    fs::create_directories(c.out);
    std::vector<std::string> files{c.mesh.empty() ? app::bundled_asset("bunny.off", "workpiece", "pass --mesh FILE") : c.mesh};
    for (const auto& p : write_sphere_files(sphere(triangles), c.out)) files.push_back(p);
    std::printf("%-22s %9s %9s %11s %11s %9s %8s\n", "file", "MB", "triangles", "tridex ms", "OpenMesh ms", "ratio", "MB/s");
    nlohmann::json rows = nlohmann::json::array();
    for (const std::string& path : files) {
        const double mb = static_cast<double>(fs::file_size(path)) / 1e6;
        const bool is_off = fs::path(path).extension() == ".off";
        std::size_t tris = 0;
        const double ours = median_ms(3, [&] {
            const std::string bytes = compute::read_file_bytes(path);
            tris = (is_off ? compute::read_off(path, bytes) : compute::read_ply(path, bytes)).triangles.size();
        });
        bool peer_ok = true;
        const double peer = median_ms(3, [&] {
            OpenMesh::PolyMesh_ArrayKernelT<> om;
            std::lock_guard<std::mutex> lock(compute::CaptureOpenMeshLog::mutex());
            compute::CaptureOpenMeshLog quiet;
            try {
                peer_ok = OpenMesh::IO::read_mesh(om, path) && om.n_faces() > 0;
            } catch (const std::bad_alloc&) {  // OpenMesh reads binary OFF's big-endian counts as little-endian
                peer_ok = false;
            }
        });
        const std::string name = fs::path(path).filename().string();
        if (peer_ok)
            std::printf("%-22s %9.2f %9zu %11.1f %11.1f %9.2f %8.1f\n", name.c_str(), mb, tris, ours, peer, ours / peer, mb / ours * 1e3);
        else
            std::printf("%-22s %9.2f %9zu %11.1f %11s %9s %8.1f\n", name.c_str(), mb, tris, ours, "failed", "-", mb / ours * 1e3);
        rows.push_back({{"file", name}, {"megabytes", mb}, {"triangles", tris}, {"tridex_ms", ours},
                        {"openmesh_ms", peer_ok ? nlohmann::json(peer) : nlohmann::json()},
                        {"ratio_tridex_over_openmesh", peer_ok ? nlohmann::json(ours / peer) : nlohmann::json()}});
    }
    std::printf("ratio < 1: tridex's reader is faster; OpenMesh builds a half-edge mesh as it reads, tridex a soup; "
                "'failed': OpenMesh could not read the file\n");
    app::write_json_file((fs::path(c.out) / "mesh_load_bench.json").string(), {{"rows", rows}, {"sphere_triangles", triangles}});
}

BenchRun setup_mesh_load_bench(CLI::App& bench) {
    auto triangles = std::make_shared<int>(1'000'000);
    bench.add_option("--mesh-load-triangles", *triangles, "With --mesh-load: triangles of the generated sphere")
        ->check(CLI::Range(100, 20'000'000));
    return [triangles](const BenchCommon& c) { run_mesh_load_bench(c, *triangles); };
}

const BenchmarkRegistration kRegistration{
    {"mesh-load",
     "Mesh reading: tridex's strict OFF and PLY readers against OpenMesh's on the bundled bunny and a generated "
     "sphere (ASCII and binary OFF and PLY)",
     95, setup_mesh_load_bench}};

}  // namespace
}  // namespace tridex::bench
