// app/scene/workpiece_spec.hpp - one workpiece of a session beyond its first: where it comes from (a mesh or a saved
// model), its lattice and where it stands (SessionSpec::more_workpieces).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/math.hpp"

namespace tridex::app {

/// A workpiece of a session after its first (a scene's "workpieces"[1..]). The first keeps these fields in SessionSpec
/// itself (mesh_path, model_path, resolution, stock_m, workpiece_centre_m, workpiece_turn, workpiece_shift_m,
/// workpiece_position_m); each field here means what the SessionSpec field of the same name means (SI units).
struct WorkpieceSpec {
    std::string mesh_path;             ///< closed mesh file (absolute once read from a scene); unused with a model
    std::uint32_t mesh_crc32 = 0;      ///< CRC-32 (IEEE) of the mesh file; 0 = not known
    std::uint64_t mesh_bytes = 0;      ///< size of the mesh file, bytes
    std::string model_path;            ///< saved model (.tdx) instead of the mesh; "" = scan-convert the mesh
    std::uint32_t model_crc32 = 0;     ///< CRC-32 (IEEE) of the model file; 0 = not known
    std::uint64_t model_bytes = 0;     ///< size of the model file, bytes
    int resolution = 256;              ///< lattice cells along the longest side
    double stock_m = 0.3;              ///< longest side of the placed workpiece, m
    Vec3 centre_m{0.0, 0.0, 0.3};      ///< the lattice's centre in the workpiece's model frame, m
    Quat turn{1.0, 0.0, 0.0, 0.0};     ///< model -> world turn about centre_m (unit quaternion)
    Vec3 shift_m{0.0};                 ///< then moved by this much, world m
    std::optional<Vec3> position_m{};  ///< a saved model's centre as the scene placed it, world m, until it loads
};

}  // namespace tridex::app
