#pragma once
/// \file morton.h
/// Morton (Z-order) codes: points near each other in space get codes near each
/// other, so sorting by the code lays them out near each other in memory.

#include "field/mesh/mesh.h"

#include <cstdint>

namespace rosy::field {

/// A 63-bit Morton code of p in the box [lo, lo + 1/scale]³ (21 bits per axis;
/// coordinates outside the box, and NaN, clamp to its faces).
uint64_t mortonCode(const Vec3 &p, const Vec3 &lo, double scale);

} // namespace rosy::field
