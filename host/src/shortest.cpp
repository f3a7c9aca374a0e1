// The shortest decimal that reads back as a double (shortest.h).
#include "shortest.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

namespace vrpd {

namespace detail {

namespace {

// The eight decimal digits of v < 10^8 as ASCII, the first in the lowest byte (the first in
// memory): v split into two halves of four digits, each into two pairs, each pair into two
// digits, all in one word. The divisions are multiplications by 10486 / 2^20 (exact below 10^4
// for /100) and 103 / 2^10 (exact below 100 for /10).
static_assert(std::endian::native == std::endian::little);
std::uint64_t eight_digits(std::uint32_t v) {
    std::uint64_t x = v / 10000 | std::uint64_t(v % 10000) << 32;
    std::uint64_t q = (x * 10486) >> 20 & 0x0000007F0000007Fu;
    x = q | (x - 100 * q) << 16;
    q = (x * 103) >> 10 & 0x000F000F000F000Fu;
    x = q | (x - 10 * q) << 8;
    return x + 0x3030303030303030u;
}

}  // namespace

char* write_shortest(char* out, double v) {
    // The digits come from fmt's Dragonbox (a third of std::to_chars's instructions). Past 2^53
    // to_chars writes an integer's exact digits, not the shortest ones padded with zeros, and
    // infinities and NaNs have no digits: those go to it.
    if (!(std::fabs(v) < 9007199254740992.0)) return std::to_chars(out, out + 32, v).ptr;
    if (std::signbit(v)) *out++ = '-';
    if (v == 0) {
        *out++ = '0';
        return out;
    }
    const auto decimal = fmt::detail::dragonbox::to_decimal(std::fabs(v));
    // The significand's digits (at most 17), right-aligned in the first 24 bytes: the first in
    // byte 7, then two groups of eight; 24 more bytes let the common forms copy 24 at once. Each
    // form writes within the 32 characters the caller gives, some past its end.
    const std::uint64_t s = decimal.significand, high = s / 100000000;
    const std::uint64_t groups[6] = {std::uint64_t('0' + high / 100000000) << 56,
                                     eight_digits(std::uint32_t(high % 100000000)),
                                     eight_digits(std::uint32_t(s % 100000000)),
                                     0,
                                     0,
                                     0};
    char buf[48];
    std::memcpy(buf, groups, sizeof buf);
    const int n = fmt::detail::count_digits(s);
    const char* const digits = buf + 24 - n;
    const char* const end = buf + 24;
    const int e = decimal.exponent + n - 1;  // v = d.ddd 10^e
    const int magnitude = std::abs(e);
    const int fixed = e >= 0 ? (n <= e + 1 ? e + 1 : n + 1) : n + 1 - e;
    const int scientific = n + (n > 1) + 2 + (magnitude >= 100 ? 3 : 2);
    if (fixed <= scientific) {
        if (e < 0) {
            // At most 3 zeros after the point: fixed is then no longer than scientific.
            std::memcpy(out, "0.000", 5);
            out += 1 - e;
            std::memcpy(out, digits, 24);
            return out + n;
        }
        if (n <= e + 1) return std::fill_n(std::copy(digits, end, out), e + 1 - n, '0');
        out = std::copy(digits, digits + e + 1, out);
        *out++ = '.';
        return std::copy(digits + e + 1, end, out);
    }
    *out++ = digits[0];
    if (n > 1) {
        *out++ = '.';
        std::memcpy(out, digits + 1, 24);
        out += n - 1;
    }
    *out++ = 'e';
    *out++ = e < 0 ? '-' : '+';
    if (magnitude >= 100) *out++ = char('0' + magnitude / 100);
    *out++ = char('0' + magnitude / 10 % 10);
    *out++ = char('0' + magnitude % 10);
    return out;
}

}  // namespace detail

}  // namespace vrpd
