// Small pieces shared by the vrpd CLI's subcommands.
#pragma once

#include <string>

#include "vrpd/vrpd.h"

namespace vrpd::cli {

Backend parse_backend(const std::string& name);
const char* backend_name(Backend b);
// "W,H" -> box extent; throws Error on anything else.
void parse_extent(const std::string& text, Box& box);
Boundary parse_boundary(const std::string& name);

struct BenchOptions {
    std::vector<double> radii{0.01, 0.002, 0.001};
    std::vector<double> coverage_radii{0.002};  // two-radii rows: Rc, with Rf = Rc / coverage_ratio
    double coverage_ratio = 2.0;
    std::vector<std::string> devices{"gpu", "cpu", "serial"};
    unsigned repeat = 3;
    std::uint32_t seed = 1;
    std::string json;
};
int run_bench(const BenchOptions& options);

}  // namespace vrpd::cli
