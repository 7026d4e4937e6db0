// app/scene/workpiece_list.hpp - a session's several workpieces: the k-th as a one-workpiece spec of its own, their
// settings JSON and their checks (app/scene/workpiece_source.hpp prepares them).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "app/scene/session_spec.hpp"
#include "app/scene/workpiece_spec.hpp"

namespace tridex::app {

/// How many workpieces `s` holds: its first and its more_workpieces.
std::size_t workpiece_count(const SessionSpec& s);

/// The k-th workpiece's fields (0: the spec's own). Throws tridex::Error for k >= workpiece_count(s).
WorkpieceSpec workpiece_at(const SessionSpec& s, std::size_t k);

/// Puts `w` in s's own workpiece fields (the first workpiece); more_workpieces is left as it is.
void set_first_workpiece(SessionSpec& s, const WorkpieceSpec& w);

/// The spec of `s`'s k-th workpiece alone: `s` with that workpiece's fields as its own and no more_workpieces. A
/// session gives each workpiece its journal, saved model and final mesh under this spec, so `tridex recover`,
/// `export` and `replay` read each as a one-workpiece session. Throws tridex::Error for k >= workpiece_count(s).
SessionSpec spec_for_workpiece(const SessionSpec& s, std::size_t k);

/// A file beside `path` for the k-th workpiece: `path` itself for k = 0, else "<stem>-wp<k+1><extension>"
/// ("out/session.tdj" -> "out/session-wp2.tdj"); "" stays "".
std::string path_for_workpiece(const std::string& path, std::size_t k);

/// s.more_workpieces as its settings JSON keeps them: an array of objects with the fields of WorkpieceSpec
/// ("mesh_path", "mesh_crc32", "mesh_bytes", "model_path", "model_crc32", "model_bytes", "resolution", "stock_m",
/// "workpiece_centre_m", "workpiece_turn" [w, x, y, z], "workpiece_shift_m").
nlohmann::json more_workpieces_json(const SessionSpec& s);

/// Reads more_workpieces_json's array into s.more_workpieces. Throws tridex::Error "<source>: settings field
/// 'more_workpieces[i].<name>' ..." for a missing or ill-typed field, and for more than haptics::kMaxLoopWorkpieces - 1.
void read_more_workpieces(const nlohmann::json& a, SessionSpec& s, const std::string& source);

/// Checks each further workpiece as validate_spec checks the first (spec_for_workpiece), and refuses more than
/// haptics::kMaxLoopWorkpieces workpieces in all, and further workpieces beside a study model. Throws tridex::Error
/// "<source>: workpieces[k]: settings field ..." naming the workpiece.
void validate_more_workpieces(const SessionSpec& s, const std::string& source);

}  // namespace tridex::app
