// Point files, with named columns: the position x, y, then the attributes a sampling carries
// (Sampling::birth as "t", Sampling::local_radius as "r"), one sample per row in acceptance order.
//   CSV: a header naming the columns (`x,y`, `x,y,t`, `x,y,t,r`, ...), then one row per sample,
//        each number the shortest decimal that round-trips the double. A file without a header
//        has the two columns x,y.
//   .bin (little-endian), version 2: bytes 0-3 "VRPD", 4-7 uint32 version = 2, 8-15 uint64
//        count, 16-19 uint32 column count C, then C names (uint8 length, then its bytes), then
//        count rows of C float64. Version 1 (no column list: count x (float64 x, float64 y) from
//        byte 16) still reads.
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

// Writes FILE as binary if it ends in ".bin", else CSV; "-" is CSV to standard output. A regular
// file (a symbolic link's target, for a link) is written to a temporary in its directory and
// renamed into place, so a failed run leaves no partial file; a device, FIFO or socket is written
// directly, never replaced. Throws Error with the reason, write errors included.
void write_points(const Sampling& s, const std::string& path);

// Throws Error unless `path` can be written as write_points would (checked before a long run).
void check_writable(const std::string& path);

// Removes the temporary of a write_points in progress, if any. Async-signal-safe: for a program's
// SIGINT and SIGTERM handlers, so that an interrupted write leaves no file behind.
void remove_partial_file() noexcept;

// A point file's contents: the positions, and the columns after x,y by name.
struct PointSet {
    std::vector<glm::dvec2> points;
    std::vector<std::string> columns;         // the attribute columns' names, in file order
    std::vector<std::vector<double>> values;  // values[c][i]: column c of point i
    // The values of column `name`, or null if the file has none.
    const std::vector<double>* column(std::string_view name) const;
};

// Writes a point set (positions and named columns) as write_points writes a sampling.
void write_point_set(const PointSet& set, const std::string& path);

// The CSV that write_points and write_point_set write, to a stream; the caller checks it.
void write_csv(const Sampling& s, std::ostream& out);
void write_csv(const PointSet& set, std::ostream& out);

// Reads a point file: vrpd's .bin (version 1 or 2), or a CSV as above. Throws Error naming the
// line (or point) of the first malformed row, NaN or inf.
PointSet read_point_set(const std::string& path);

// The same for a point file's bytes in memory; `name` stands for the file in error messages.
PointSet parse_point_set(std::string_view bytes, const std::string& name = "<memory>");

// The positions of read_point_set(path).
std::vector<glm::dvec2> read_points(const std::string& path);

}  // namespace vrpd
