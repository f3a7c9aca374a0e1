// libFuzzer target: the sizing-expression parser and evaluator on arbitrary text. A malformed
// expression must end in vrpd::Error; a parsed one must evaluate without a crash or undefined
// behaviour anywhere (NaN and inf are values).
#include <cstdint>
#include <string>

#include "vrpd/sizing.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const vrpd::SizingExpression r(std::string(reinterpret_cast<const char*>(data), size));
        const vrpd::Box box{2, 1, vrpd::Boundary::Periodic};
        for (double x : {0.0, 0.37, 1.999})
            for (double y : {0.0, 0.5}) (void)r(x, y, box);
    } catch (const vrpd::Error&) {
    }
    return 0;
}
