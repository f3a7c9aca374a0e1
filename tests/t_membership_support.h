// Configurations of the T test (shared/t_membership.h) for its tests: disks around a dart or a
// quadtree cell's corner, as the sampler meets them.
#ifndef VRPD_TESTS_T_MEMBERSHIP_SUPPORT_H
#define VRPD_TESTS_T_MEMBERSHIP_SUPPORT_H
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "shared/sampler.h"

namespace vrpd::test {

struct Config {
    std::vector<glm::ivec2> disks;  // centres, offsets from the origin
    glm::ivec2 lo, hi;              // the box, as offsets from the origin (FAR_SIDE: no side)
    bool in_disk = true;            // the region: the dart's closed disk in the box, or a cell (the box)
};

inline std::string describe(const Config& c) {
    std::string text = "box (" + std::to_string(c.lo.x) + "," + std::to_string(c.lo.y) + ")-(" +
                       std::to_string(c.hi.x) + "," + std::to_string(c.hi.y) + "), disks";
    for (const glm::ivec2& d : c.disks) text += " (" + std::to_string(d.x) + "," + std::to_string(d.y) + ")";
    return text;
}

// Random configurations as the sampler meets them: disk centres >= Rf apart and >= Rf from the
// dart, within 2 Rc of it, inside the box. A cell (not in_disk): a square of side up to Rf / sqrt(2)
// with its corner at the origin, the disks anywhere within 2 Rc of the corner.
inline Config random_config(std::mt19937_64& rng, double rc, double rf, bool boxed, bool in_disk = true) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Config c;
    const int far = shared::FAR_SIDE;
    c.lo = {-far, -far};
    c.hi = {far, far};
    if (boxed) {
        // Each side near the dart (within 1.3 Rc) or far, as at the box's sides and corners.
        std::uniform_real_distribution<double> side(0.0, 1.3 * rc);
        auto pick = [&]() { return rng() % 3 == 0 ? far : int(side(rng)); };
        c.lo = {-pick(), -pick()};
        c.hi = {pick(), pick()};
    }
    if (!in_disk) {
        std::uniform_real_distribution<double> side(1.0, rf / std::sqrt(2.0));
        const int s = int(side(rng));
        c.in_disk = false;
        c.lo = {0, 0};
        c.hi = {boxed ? 1 + int(rng() % s) : s, s};  // boxed: a free boundary cuts the cell
    }
    const int wanted = 1 + int(rng() % (rng() % 2 ? 8 : 48));
    for (int tries = 0; tries < 400 && int(c.disks.size()) < wanted; ++tries) {
        const glm::dvec2 p{2 * rc * u(rng), 2 * rc * u(rng)};
        const glm::ivec2 q{int(std::lround(p.x)), int(std::lround(p.y))};
        auto d2 = [](glm::ivec2 a, glm::ivec2 b) {
            const glm::dvec2 v(a - b);
            return std::hypot(v.x, v.y);
        };
        if (d2(q, {0, 0}) > 2 * rc || (in_disk && d2(q, {0, 0}) < rf)) continue;
        if (in_disk && (q.x < c.lo.x || q.y < c.lo.y || q.x > c.hi.x || q.y > c.hi.y)) continue;
        bool apart = true;
        for (const glm::ivec2& d : c.disks) apart = apart && d2(q, d) >= rf;
        if (apart) c.disks.push_back(q);
    }
    return c;
}

}  // namespace vrpd::test
#endif
