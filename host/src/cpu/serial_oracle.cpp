// The oracle: see serial_oracle.h.
#include "serial_oracle.h"

#include <algorithm>
#include <vector>

#include "shared/resolve.h"

namespace vrpd::detail {

using namespace shared;

std::uint64_t resolve_in_arrival_order(const Domain& dom, Grid grid, Darts darts, uint count) {
    std::vector<uint> work;
    for (uint j = 0; j < count; ++j)
        if (dart_at(darts, j).w == DART_UNDECIDED) work.push_back(j);
    std::sort(work.begin(), work.end(), [&](uint a, uint b) {
        return arrives_before(dart_at(darts, a).z, a, dart_at(darts, b).z, b);
    });
    for (uint d : work) set_dart_state(darts, d, serial_decision(dom, grid, darts, d));
    return work.capacity() * sizeof(uint);
}

}  // namespace vrpd::detail
