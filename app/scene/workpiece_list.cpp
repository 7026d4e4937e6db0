// app/scene/workpiece_list.cpp - a session's several workpieces.
#include "app/scene/workpiece_list.hpp"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

namespace {

using nlohmann::json;

json vec_json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

std::string index_name(std::size_t k) { return "workpieces[" + std::to_string(k) + "]"; }

}  // namespace

std::size_t workpiece_count(const SessionSpec& s) { return 1 + s.more_workpieces.size(); }

WorkpieceSpec workpiece_at(const SessionSpec& s, std::size_t k) {
    if (k >= workpiece_count(s))
        throw Error("workpiece " + std::to_string(k) + ": the session holds " + std::to_string(workpiece_count(s)));
    if (k > 0) return s.more_workpieces[k - 1];
    WorkpieceSpec w;
    w.mesh_path = s.mesh_path;
    w.mesh_crc32 = s.mesh_crc32;
    w.mesh_bytes = s.mesh_bytes;
    w.model_path = s.model_path;
    w.model_crc32 = s.model_crc32;
    w.model_bytes = s.model_bytes;
    w.resolution = s.resolution;
    w.stock_m = s.stock_m;
    w.centre_m = s.workpiece_centre_m;
    w.turn = s.workpiece_turn;
    w.shift_m = s.workpiece_shift_m;
    w.position_m = s.workpiece_position_m;
    return w;
}

void set_first_workpiece(SessionSpec& s, const WorkpieceSpec& w) {
    s.mesh_path = w.mesh_path;
    s.mesh_crc32 = w.mesh_crc32;
    s.mesh_bytes = w.mesh_bytes;
    s.model_path = w.model_path;
    s.model_crc32 = w.model_crc32;
    s.model_bytes = w.model_bytes;
    s.resolution = w.resolution;
    s.stock_m = w.stock_m;
    s.workpiece_centre_m = w.centre_m;
    s.workpiece_turn = w.turn;
    s.workpiece_shift_m = w.shift_m;
    s.workpiece_position_m = w.position_m;
}

SessionSpec spec_for_workpiece(const SessionSpec& s, std::size_t k) {
    const WorkpieceSpec w = workpiece_at(s, k);
    SessionSpec one = s;
    one.more_workpieces.clear();
    set_first_workpiece(one, w);
    return one;
}

std::string path_for_workpiece(const std::string& path, std::size_t k) {
    if (k == 0 || path.empty()) return path;
    const std::filesystem::path p(path);
    const std::string name = p.stem().string() + "-wp" + std::to_string(k + 1) + p.extension().string();
    return (p.parent_path() / name).string();
}

json more_workpieces_json(const SessionSpec& s) {
    json a = json::array();
    for (const WorkpieceSpec& w : s.more_workpieces)
        a.push_back({{"mesh_path", w.mesh_path},
                     {"mesh_crc32", w.mesh_crc32},
                     {"mesh_bytes", w.mesh_bytes},
                     {"model_path", w.model_path},
                     {"model_crc32", w.model_crc32},
                     {"model_bytes", w.model_bytes},
                     {"resolution", w.resolution},
                     {"stock_m", w.stock_m},
                     {"workpiece_centre_m", vec_json(w.centre_m)},
                     {"workpiece_turn", json::array({w.turn.w, w.turn.x, w.turn.y, w.turn.z})},
                     {"workpiece_shift_m", vec_json(w.shift_m)}});
    return a;
}

void read_more_workpieces(const json& a, SessionSpec& s, const std::string& source) {
    if (!a.is_array() || a.size() + 1 > haptics::kMaxLoopWorkpieces)
        throw Error(source + ": settings field 'more_workpieces' must be an array of at most " +
                    std::to_string(haptics::kMaxLoopWorkpieces - 1) + " objects");
    s.more_workpieces.clear();
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string at = source + ": settings field 'more_workpieces[" + std::to_string(i) + "].";
        const json& o = a[i];
        const auto field = [&](const char* name) -> const json& {
            if (!o.is_object() || !o.contains(name)) throw Error(at + name + "' is missing");
            return o.at(name);
        };
        const auto get = [&](const char* name, auto& out) {
            try {
                field(name).get_to(out);
            } catch (const json::exception&) {
                throw Error(at + name + "' has the wrong type");
            }
        };
        const auto numbers = [&](const char* name, std::size_t n, double* out) {
            const json& v = field(name);
            if (!v.is_array() || v.size() != n) throw Error(at + name + "' must be an array of " + std::to_string(n) + " numbers");
            for (std::size_t c = 0; c < n; ++c) {
                if (!v[c].is_number()) throw Error(at + name + "' must be an array of " + std::to_string(n) + " numbers");
                out[c] = v[c].get<double>();
            }
        };
        WorkpieceSpec w;
        get("mesh_path", w.mesh_path);
        get("mesh_crc32", w.mesh_crc32);
        get("mesh_bytes", w.mesh_bytes);
        get("model_path", w.model_path);
        get("model_crc32", w.model_crc32);
        get("model_bytes", w.model_bytes);
        get("resolution", w.resolution);
        get("stock_m", w.stock_m);
        double c[3], q[4], d[3];
        numbers("workpiece_centre_m", 3, c);
        numbers("workpiece_turn", 4, q);
        numbers("workpiece_shift_m", 3, d);
        w.centre_m = Vec3(c[0], c[1], c[2]);
        w.turn = Quat(q[0], q[1], q[2], q[3]);
        w.shift_m = Vec3(d[0], d[1], d[2]);
        s.more_workpieces.push_back(w);
    }
}

void validate_more_workpieces(const SessionSpec& s, const std::string& source) {
    if (s.more_workpieces.empty()) return;
    if (workpiece_count(s) > haptics::kMaxLoopWorkpieces)
        throw Error(source + ": workpieces: at most " + std::to_string(haptics::kMaxLoopWorkpieces) + ", got " +
                    std::to_string(workpiece_count(s)));
    if (!s.study_model.empty()) throw Error(source + ": workpieces: a study scene has one workpiece, its felt walls");
    for (std::size_t k = 1; k < workpiece_count(s); ++k) {
        const WorkpieceSpec& w = s.more_workpieces[k - 1];
        if (w.mesh_path.empty() == w.model_path.empty())
            throw Error(source + ": " + index_name(k) + ": needs a mesh or a saved model, not both");
        validate_spec(spec_for_workpiece(s, k), source + ": " + index_name(k));
    }
}

}  // namespace tridex::app
