// Helpers shared by the tests: exact lattice checks that do not trust the sampler's grid.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "plan.h"
#include "vrpd/vrpd.h"

namespace vrpd::test {

// A fresh directory for a test process, removed with its contents when it goes. (A directory
// named by the pid outlived its run and was found again when the pid came round.)
struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& prefix) {
        std::string name = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
        if (!::mkdtemp(name.data())) throw std::runtime_error("cannot create a scratch directory");
        path = name;
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

// A file's bytes.
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline SampleOptions options(double radius, std::uint32_t seed, Backend backend, Box box = {}) {
    SampleOptions o;
    o.radius = radius;
    o.seed = seed;
    o.backend = backend;
    o.box = box;
    return o;
}

// Squared lattice distance, the shorter way round on a torus (independent of shared/domain.h).
inline std::uint64_t lattice_distance2(const detail::Plan& plan, glm::uvec2 a, glm::uvec2 b) {
    auto gap = [&](std::uint32_t p, std::uint32_t q, std::uint32_t extent) {
        std::uint64_t d = p > q ? p - q : q - p;
        if (plan.domain.lattice.periodic && d > extent - d) d = extent - d;
        return d * d;
    };
    return gap(a.x, b.x, plan.domain.lattice.extent_x) + gap(a.y, b.y, plan.domain.lattice.extent_y);
}

// Pairs of samples closer than r, by brute force over all pairs.
inline std::uint64_t brute_force_conflicts(const detail::Plan& plan, const Sampling& s) {
    std::uint64_t conflicts = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
        for (std::size_t j = i + 1; j < s.size(); ++j)
            if (lattice_distance2(plan, s.lattice[i], s.lattice[j]) < plan.domain.radii.inhibition2) ++conflicts;
    return conflicts;
}

inline std::vector<glm::dvec2> points_of(const Sampling& s) {
    std::vector<glm::dvec2> p(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
    return p;
}

}  // namespace vrpd::test
