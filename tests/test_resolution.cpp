// The exact parallel resolution's scans (shared/resolve.h): a dart's scan of rows of base cells
// against a scan of every dart of the round.
#include <catch2/catch.hpp>

#include <random>

#include "plan.h"
#include "shared/sampler.h"
#include "support.h"

using namespace vrpd;
using vrpd::test::options;

TEST_CASE("a dart's scan of rows of base cells decides as a scan of every dart in arrival order", "[sampling]") {
    using namespace shared;
    std::mt19937 rng(5);
    std::uint64_t rows = 0, rejected = 0, waiting = 0;
    for (const bool packed : {true, false})
        for (const Box box : {Box{1, 1, Boundary::Periodic}, Box{1.3, 0.7, Boundary::Free}}) {
            const detail::Plan plan = detail::make_plan(options(0.013, 5, Backend::Cpu, box));
            const Domain& dom = plan.domain;
            INFO("box " << box.width << "x" << box.height << " mask mode " << packed);
            // A round's darts numbered in base cell order. Mask mode (packed) numbers every base
            // cell without a sample; list mode leaves base cells without darts empty. Runs of up
            // to three base cells hold samples (at a corner: they need not be conflict-free here).
            std::vector<uvec2> grid(plan.base_cells);
            std::vector<uvec4> darts;
            const uint side = 1u << dom.cell_bits;
            for (uint b = 0, samples = 0; b < plan.base_cells; ++b) {
                if (samples == 0u && rng() % 8u == 0u) samples = 1u + rng() % 3u;
                const uvec2 corner = base_corner(dom, b);
                if (samples > 0u) {
                    grid[b] = corner;
                    --samples;
                    continue;
                }
                const uint first = uint(darts.size()), count = rng() % 3u == 0u ? 0u : rng() % 4u;
                for (uint j = 0; j < count; ++j) {
                    const uint roll = rng() % 10u;
                    const uint state = roll < 6u ? DART_UNDECIDED : roll < 7u ? DART_ACCEPTED : DART_REJECTED;
                    darts.push_back(uvec4(corner.x + rng() % side, corner.y + rng() % side, rng() % 64u, state));
                }
                grid[b] = packed       ? uvec2(GRID_TAG | GRID_PACKED | first, count << 16u | (count > 0u ? 1u : 0u))
                          : count > 0u ? uvec2(GRID_TAG | first, first + count)
                                       : uvec2(GRID_EMPTY, GRID_EMPTY);
            }
            const uint n = uint(darts.size());
            std::vector<uint> stored(dart_words(n));
            for (uint d = 0; d < n; ++d) store_dart(Darts{stored.data()}, d, darts[d]);
            for (int k = 0; k < 600; ++k) {
                const uint d = rng() % n;
                const DartSite site = dart_site(dom, Darts{stored.data()}, d);
                rows += inside_by(dom, site.cell, conflict_reach(dom.radii)) ? 1u : 0u;
                for (const bool first_pass : {true, false}) {
                    INFO("dart " << d << " first pass " << first_pass);
                    // Every other dart in index order, which both scans follow.
                    uint expected = DART_ACCEPTED;
                    for (uint j = 0; j < n && expected != DART_REJECTED; ++j) {
                        const uint verdict = nearby_verdict(site, d, dart_at(Darts{stored.data()}, j), j);
                        if (verdict != DART_ACCEPTED) expected = verdict;
                        if (verdict == DART_UNDECIDED && first_pass) break;
                    }
                    REQUIRE(resolve_dart(dom, Grid{grid.data()}, Darts{stored.data()}, d, first_pass) == expected);
                    rejected += expected == DART_REJECTED ? 1u : 0u;
                    waiting += expected == DART_UNDECIDED && !first_pass ? 1u : 0u;
                }
            }
        }
    // Most darts take the rows, and each verdict is common.
    CHECK(rows > 2000);
    CHECK(rejected > 500);
    CHECK(waiting > 500);
}
