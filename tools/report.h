// The analysis behind `vrpd analyze` and `vrpd figures`, and the directory their reports go to.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "vrpd/analysis.h"

namespace vrpd::cli {

using Json = nlohmann::json;
using Sets = std::vector<std::vector<glm::dvec2>>;

// A report directory written whole or not at all: files go to a fresh directory beside the
// target and move into it (each rename atomic) only when all are written.
class ReportDir {
public:
    explicit ReportDir(const std::string& target);
    ReportDir(const ReportDir&) = delete;
    ReportDir& operator=(const ReportDir&) = delete;
    ~ReportDir();
    // Where a report file is written before commit().
    std::string path(const std::string& name) const { return (staging_ / name).string(); }
    void commit();

private:
    std::filesystem::path target_, staging_;
};

void write_json(const std::string& path, const Json& j);

// The analysis of one group of sets: figures STEM-points, -spectrum, -radial and, with radii,
// -angles and -edges (Delaunay histograms with Propositions 1-2's bounds); returns the numbers
// the figures show. A spectrum half width of 0 means 2 sqrt(n), at least 32.
Json analyse(const Sets& sets, const Box& box, std::optional<RadiiGiven> radii, SpectrumOptions spectrum_options,
             const ReportDir& dir, const std::string& stem, const std::string& name);

// Figures 11, 12 and 16 (spatially varying radii), drawn into `dir`; their numbers go to
// all["11"], ["12"], ["16"]. Returns their part of the page. `full`: Figure 16 at the paper's
// scale (about 2.2 M samples).
std::string sizing_figures(const ReportDir& dir, Backend backend, bool full, Json& all);

}  // namespace vrpd::cli
