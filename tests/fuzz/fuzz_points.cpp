// libFuzzer target: the point-file reader (vrpd/io.h) on arbitrary bytes, as CSV or .bin. Bad input
// must end in vrpd::Error; anything else (a crash, a sanitizer finding, a PointSet whose columns
// disagree with its points) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "vrpd/io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const vrpd::PointSet set = vrpd::parse_point_set(std::string_view(reinterpret_cast<const char*>(data), size));
        if (set.values.size() != set.columns.size()) __builtin_trap();
        for (const auto& column : set.values)
            if (column.size() != set.points.size()) __builtin_trap();
    } catch (const vrpd::Error&) {
    }
    return 0;
}
