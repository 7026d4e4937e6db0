// haptics/materials.hpp - contact material parameters per ActiveSurface material id.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace tridex::haptics {

/// Contact parameters of one material, SI units: the proSense-style set of Singapogu's thesis
/// (Clemson 2007, ch. 3: stiffness, damping, static and dynamic friction) used by the god-object.
/// Defaults: 700 N/m and 0.5 N*s/m (Omni-class values of DESIGN.md, stable at 1 kHz), no friction.
struct Material {
    double stiffness_n_per_m = 700.0;  ///< spring constant kp of the proxy-HIP coupling, N/m, finite >= 0
    double damping_n_s_per_m = 0.5;    ///< kd on the penetration rate, N*s/m, finite >= 0
    double static_friction = 0.0;      ///< Coulomb mu_s (dimensionless), finite >= 0: sticks while |F_t| <= mu_s*|F_n|
    double dynamic_friction = 0.0;     ///< Coulomb mu_d (dimensionless), 0 <= mu_d <= mu_s: |F_t| = mu_d*|F_n| sliding
};

/// Throws tridex::Error naming `where` and the field when a Material field is negative or not finite,
/// or when dynamic_friction > static_friction. `where` is e.g. "ContactParams" or "MaterialTable[3]".
void validate_material(const Material& m, const std::string& where);

/// Up to 256 materials indexed by the ActiveSurface interval material id (0 = the workpiece's own
/// material). Every entry starts as the same material (the default Material unless given); set()
/// changes one. Lookups are O(1), allocation-free and safe from the haptic thread once the table is
/// no longer modified (share it as std::shared_ptr<const MaterialTable>). 8 KiB.
class MaterialTable {
public:
    static constexpr int kSize = 256;  ///< one entry per possible uint8 material id

    /// Every entry is the default Material.
    MaterialTable() = default;
    /// Every entry is `all`; throws tridex::Error (validate_material) when `all` is invalid.
    explicit MaterialTable(const Material& all);
    /// Sets entry `id`; throws tridex::Error naming the entry when id is outside [0, 255] or m is invalid.
    void set(int id, const Material& m);
    /// The material of id (any uint8 is valid).
    const Material& operator[](std::uint8_t id) const { return entries_[id]; }

private:
    std::array<Material, kSize> entries_{};
};

}  // namespace tridex::haptics
