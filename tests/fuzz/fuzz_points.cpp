// libFuzzer target: the point-file reader (vrpd/io.h) on arbitrary bytes, as CSV or .bin, and the
// CSV writer on what it read. Bad input must end in vrpd::Error; anything else (a crash, a
// sanitizer finding, a PointSet whose columns disagree with its points, or one that does not
// read back bit for bit from the CSV written of it) is a finding.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string_view>

#include "vrpd/io.h"

namespace {

bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    vrpd::PointSet set;
    try {
        set = vrpd::parse_point_set(std::string_view(reinterpret_cast<const char*>(data), size));
    } catch (const vrpd::Error&) {
        return 0;
    }
    if (set.values.size() != set.columns.size()) __builtin_trap();
    for (const auto& column : set.values)
        if (column.size() != set.points.size()) __builtin_trap();
    std::ostringstream csv;
    vrpd::write_csv(set, csv);
    const vrpd::PointSet again = vrpd::parse_point_set(csv.str());
    if (again.columns != set.columns || again.points.size() != set.points.size()) __builtin_trap();
    for (std::size_t i = 0; i < set.points.size(); ++i)
        if (!same(again.points[i].x, set.points[i].x) || !same(again.points[i].y, set.points[i].y)) __builtin_trap();
    for (std::size_t c = 0; c < set.values.size(); ++c)
        for (std::size_t i = 0; i < set.points.size(); ++i)
            if (!same(again.values[c][i], set.values[c][i])) __builtin_trap();
    return 0;
}
