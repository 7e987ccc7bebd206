#include "field/mesh/morton.h"

#include <algorithm>

namespace rosy::field {

uint64_t mortonCode(const Vec3 &p, const Vec3 &lo, double scale) {
    auto spread = [](uint64_t x) { // bits of x to every third bit
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffULL;
        x = (x | x << 16) & 0x1f0000ff0000ffULL;
        x = (x | x << 8) & 0x100f00f00f00f00fULL;
        x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
        x = (x | x << 2) & 0x1249249249249249ULL;
        return x;
    };
    uint64_t c[3];
    for (int k = 0; k < 3; ++k) {
        const double t = (p[k] - lo[k]) * scale * 2097151.0;
        c[k] = t > 0 ? uint64_t(std::min(t, 2097151.0)) : 0; // NaN -> 0: no undefined conversion
    }
    return spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2;
}

} // namespace rosy::field
