// libFuzzer target: the options a command line sets (radius, coverage radius, extent, boundary,
// lattice resolution) through validate() and make_plan(), on arbitrary doubles. Bad options must
// end in vrpd::Error; a plan that is made must keep the invariants the kernels rely on. Under
// UndefinedBehaviorSanitizer a float-to-integer overflow or a division by zero is a finding.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "plan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    double v[4] = {};
    if (size < sizeof v + 2) return 0;
    std::memcpy(v, data, sizeof v);
    vrpd::SampleOptions o;
    o.radius = v[0];
    o.coverage = data[sizeof v] & 1 ? v[1] : 0.0;
    o.box = {v[2], v[3], data[sizeof v] & 2 ? vrpd::Boundary::Free : vrpd::Boundary::Periodic};
    const std::uint32_t bits = 1 + data[sizeof v + 1] % 30;
    try {
        const vrpd::detail::Plan plan = vrpd::detail::make_plan(o, bits);
        const auto& d = plan.domain;
        const std::uint64_t side = std::uint64_t(1) << d.cell_bits;
        const bool ok = d.lattice.extent_x < 0x80000000u && d.lattice.extent_y < 0x80000000u &&
                        plan.base_cells == std::uint64_t(d.cells_x) * d.cells_y && plan.base_cells < (1ull << 31) &&
                        d.radii.inhibition2 > 2 * (side - 1) * (side - 1) &&
                        d.radii.coverage2 >= d.radii.inhibition2 && (d.radii.reach & 0xFFu) <= 3u;
        if (!ok) __builtin_trap();
    } catch (const vrpd::Error&) {
    }
    return 0;
}
