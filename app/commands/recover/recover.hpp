// app/commands/recover/recover.hpp - `tridex recover`: the model of a session rebuilt from its journal, after a crash, a SIGKILL or a
// power loss.
#pragma once

#include <string>

namespace tridex::app {

/// Reads the session journal at `journal_path` (compute/journal), rebuilds the workpiece from the session spec in its
/// header exactly as the session did (prepare_workpiece with the spec's mesh, resolution, stock and centre), applies
/// every valid record's tool samples through the CPU reference Booleans in the session's batches, and writes into
/// `out` (created): sculpted.ply (the CPU contour of the final model, as SessionRuntime::final_mesh) and report.json
/// {journal, settings, recovered_device_time_s (t_s of the last sample, s), records, samples, booleans,
/// volume_dexel_m3, volume_after_m3, volume_removed_m3 (m^3), truncated_at (null, or {record, byte_offset, reason}),
/// mesh {vertices, triangles}, wall_s}. A damaged tail is cut at the last valid record with one line on stderr
/// naming the record index and byte offset. Throws tridex::Error (one line) for a file that is not a journal, of
/// another version, with a damaged header or spec, or whose workpiece mesh is missing or changed (CRC-32).
void run_recover(const std::string& journal_path, const std::string& out);

}  // namespace tridex::app
