// core/units.hpp - conversions from the units devices and files use to SI, applied at the edges.
#pragma once

namespace tridex::units {

constexpr double kMetresPerMillimetre = 1e-3;  ///< 1 mm in m.
constexpr double kMetresPerInch = 0.0254;      ///< 1 in in m (exact).
constexpr double kMetresPerFoot = 0.3048;      ///< 1 ft in m (exact).

/// Millimetres to metres.
constexpr double mm(double v) { return v * kMetresPerMillimetre; }
/// Inches to metres.
constexpr double inch(double v) { return v * kMetresPerInch; }
/// Feet to metres.
constexpr double ft(double v) { return v * kMetresPerFoot; }
/// N/mm (the unit device datasheets use for stiffness) to N/m.
constexpr double n_per_mm(double v) { return v * 1e3; }

}  // namespace tridex::units
