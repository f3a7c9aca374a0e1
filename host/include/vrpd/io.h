// Point files: CSV (header `x,y`, one sample per row in acceptance order, shortest decimal that
// round-trips the double) and binary (.bin, little-endian):
//   bytes 0-3 "VRPD", 4-7 uint32 version = 1, 8-15 uint64 count, then count x (float64 x, float64 y).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

void write_csv(const Sampling& s, std::ostream& out);

// Writes FILE as binary if it ends in ".bin", else CSV. Writes a temporary beside it and renames
// it into place, so a failed run leaves no partial file. Throws Error with the reason.
void write_points(const Sampling& s, const std::string& path);

// Throws Error unless `path` can be created or replaced (checked before a long run).
void check_writable(const std::string& path);

// Reads a point file: vrpd's .bin, or a CSV of two numeric columns (an optional header line `x,y`).
// Throws Error naming the line of the first malformed row, NaN or inf.
std::vector<glm::dvec2> read_points(const std::string& path);

}  // namespace vrpd
