// libFuzzer target: the sizing-expression parser and evaluator on arbitrary text. A malformed
// expression must end in vrpd::Error; a parsed one must evaluate without a crash or undefined
// behaviour anywhere (NaN and inf are values). Where it has kinks, `taken` must give the plain
// values bit for bit and a mask of its kinks' bits, and `forced` on that mask the same values.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "vrpd/sizing.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const vrpd::SizingExpression r(std::string(reinterpret_cast<const char*>(data), size));
        const vrpd::Box box{2, 1, vrpd::Boundary::Periodic};
        const double xs[6] = {0.0, 0.37, 1.999, 0.0, 0.37, 1.999}, ys[6] = {0.0, 0.0, 0.0, 0.5, 0.5, 0.5};
        double plain[6];
        for (int i = 0; i < 6; ++i) plain[i] = r(xs[i], ys[i], box);
        if (!r.kinked()) return 0;
        double taken[6], forced[6];
        std::uint8_t mask[6];
        r.taken(xs, ys, taken, mask, 6, box);
        r.forced(xs, ys, forced, mask, 6, box);
        for (int i = 0; i < 6; ++i) {
            if (std::memcmp(&taken[i], &plain[i], sizeof(double)) != 0) __builtin_trap();
            if (mask[i] >> r.kinks() != 0) __builtin_trap();
            if (!(forced[i] == plain[i] || (std::isnan(forced[i]) && std::isnan(plain[i])))) __builtin_trap();
        }
    } catch (const vrpd::Error&) {
    }
    return 0;
}
