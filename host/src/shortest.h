// The shortest decimal that reads back as a double, as the point files write it.
#pragma once

namespace vrpd::detail {

// Writes v as std::to_chars(first, last, v) does (the fewest significant digits that read back
// exactly, in fixed or scientific notation, whichever is shorter, fixed on a tie) and returns
// the end; `out` has room for 32 characters, which it may write past the end.
char* write_shortest(char* out, double v);

}  // namespace vrpd::detail
