// Each thread decides the undecided darts of its part of the round (spatial order), one at a time:
// a dart left undecided waits for an earlier one, which is decided first (depth first; each wait
// is for an earlier arrival, so the chains end). A first sweep takes the darts with nothing to wait
// for. Each dart's scan runs about once, where the GPU's passes scan the undecided again in every
// pass. Threads may decide the same dart near their parts' border: both reach the same final
// state. Should another thread decide the dart waited for between the two scans, the dart is
// simply tried again; only a dart that waits for no dart while none decides (a bug) stops the run.
#include "parallel_resolution.h"

#include <atomic>
#include <vector>

#include "../engine.h"
#include "shared/resolve.h"

namespace vrpd::detail {

using namespace shared;

namespace {
// Times a dart may find nothing to wait for (another thread decided it meanwhile) and be tried
// again, before the resolution is called stuck; each retry needs a dart decided by another thread.
constexpr uint kMaxRetries = 1u << 20;
}  // namespace

void decide_in_parallel(const Domain& dom, Grid grid, Darts darts, std::size_t count, ThreadPool& pool) {
    std::atomic<bool> stuck = false;
    pool.parallel_for(count, [&](std::size_t b, std::size_t e, unsigned) {
        for (std::size_t j = b; j < e; ++j) {
            if (dart_at(darts, uint(j)).w != DART_UNDECIDED) continue;
            const uint state = resolve_dart(dom, grid, darts, uint(j), false);
            if (state != DART_UNDECIDED) set_dart_state(darts, uint(j), state);
        }
        std::vector<uint> stack;
        for (std::size_t j = b; j < e; ++j) {
            stack.push_back(uint(j));
            uint retries = 0;
            while (!stack.empty()) {
                const uint t = stack.back();
                if (dart_at(darts, t).w != DART_UNDECIDED) {
                    stack.pop_back();
                    continue;
                }
                const uint state = resolve_dart(dom, grid, darts, t, false);
                if (state != DART_UNDECIDED) {
                    set_dart_state(darts, t, state);
                    stack.pop_back();
                    continue;
                }
                const uint wait = undecided_before(dom, grid, darts, t);
                if (wait != GRID_EMPTY) {
                    stack.push_back(wait);
                } else if (++retries > kMaxRetries) {
                    stuck = true;
                    return;
                }
            }
        }
    });
    if (stuck) throw Error("internal: an undecided dart waits for no earlier dart");
}

}  // namespace vrpd::detail
