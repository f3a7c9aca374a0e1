// Point files: positions and named attribute columns survive a round trip through CSV and .bin
// bit for bit; version 1 .bin files still read; malformed files are refused with the line.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "shortest.h"
#include "support.h"
#include "vrpd/io.h"

namespace fs = std::filesystem;
using namespace vrpd;

namespace {

fs::path scratch_file(const std::string& name) {
    static const vrpd::test::ScratchDir dir("vrpd_io_test");
    return dir.path / name;
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

Sampling three_samples() {
    Sampling s;
    s.quantum = 0.1;
    s.lattice = {{1, 2}, {30, 4}, {5, 77}};
    return s;
}

}  // namespace

TEST_CASE("point files: x,y alone, and t and r columns, round-trip through CSV and .bin", "[io]") {
    for (int attributes = 0; attributes < 4; ++attributes) {
        Sampling s = three_samples();
        if (attributes & 1) s.birth = {1.0, 0.5, 1.0 / 3.0};
        if (attributes & 2) s.local_radius = {0.01, 0.02, 1e-300};
        for (const char* ext : {".csv", ".bin"}) {
            INFO("attributes " << attributes << " " << ext);
            const fs::path p = scratch_file(std::string("p") + ext);
            write_points(s, p.string());
            const PointSet read = read_point_set(p.string());
            REQUIRE(read.points.size() == 3);
            for (std::size_t i = 0; i < 3; ++i) CHECK(read.points[i] == s.point(i));
            CHECK((read.column("t") != nullptr) == bool(attributes & 1));
            CHECK((read.column("r") != nullptr) == bool(attributes & 2));
            if (attributes & 1) CHECK(*read.column("t") == s.birth);
            if (attributes & 2) CHECK(*read.column("r") == s.local_radius);
            CHECK(read.columns.size() == std::size_t((attributes & 1) + (attributes >> 1)));
        }
    }
    const fs::path p = scratch_file("header.csv");
    Sampling s = three_samples();
    s.birth = {1, 1, 1};
    s.local_radius = {2, 2, 2};
    write_points(s, p.string());
    std::ifstream in(p);
    std::string header;
    std::getline(in, header);
    CHECK(header == "x,y,t,r");
    std::ostringstream csv;
    write_csv(s, csv);
    CHECK(csv.str() == vrpd::test::slurp(p));
}

TEST_CASE("point files: a point set of many columns of the longest numbers round-trips", "[io]") {
    // 40 attribute columns of 24-character numbers: a row of 42 numbers, 1 049 characters (a row
    // buffer sized for 8 columns overflows at the 9th).
    PointSet set;
    set.points = {{0.12345678901234568, -1.7976931348623157e308}, {5e-324, 1}};
    for (int c = 0; c < 40; ++c) {
        set.columns.push_back(fmt::format("c{}", c));
        set.values.push_back({-1.2345678901234568e-300, double(c)});
    }
    for (const char* ext : {".csv", ".bin"}) {
        INFO(ext);
        const fs::path p = scratch_file(std::string("wide") + ext);
        write_point_set(set, p.string());
        const PointSet read = read_point_set(p.string());
        CHECK(read.points == set.points);
        CHECK(read.columns == set.columns);
        CHECK(read.values == set.values);
    }
    // The same CSV to a stream.
    std::ostringstream csv;
    write_csv(set, csv);
    CHECK(csv.str() == vrpd::test::slurp(scratch_file("wide.csv")));
}

TEST_CASE("point files: version 1 .bin and a CSV without a header or with a BOM still read", "[io]") {
    const fs::path v1 = scratch_file("v1.bin");
    std::string bytes = "VRPD";
    auto put = [&](const void* v, std::size_t n) { bytes.append(static_cast<const char*>(v), n); };
    const std::uint32_t version = 1;
    const std::uint64_t count = 2;
    const double xy[4] = {0.25, 0.5, 0.75, 1.0};
    put(&version, 4);
    put(&count, 8);
    put(xy, sizeof xy);
    write_text(v1, bytes);
    const PointSet set = read_point_set(v1.string());
    REQUIRE(set.points.size() == 2);
    CHECK(set.points[1] == glm::dvec2(0.75, 1.0));
    CHECK(set.columns.empty());

    const fs::path bare = scratch_file("bare.csv");
    write_text(bare, "0.5,0.25\n1,2\n");
    CHECK(read_points(bare.string()).size() == 2);
    write_text(bare, "\xEF\xBB\xBFx,y\n0.5,0.25\n");
    CHECK(read_points(bare.string()).size() == 1);
}

TEST_CASE("point files: bad headers, short rows and bad .bin column lists are refused with the place", "[io]") {
    const fs::path p = scratch_file("bad.csv");
    write_text(p, "y,x\n1,2\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains(":1: the first two columns must be x,y"));
    write_text(p, "x,y,t,t\n1,2,3,4\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains("column t is named twice"));
    write_text(p, "x,y,t\n1,2,3\n1,2\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains(":3: expected 3 columns `x,y,t`"));
    write_text(p, "x,y\n1,2,3\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains(":2: expected 2 columns `x,y`"));
    write_text(p, "x,y,r\n1,2,nan\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains(":2: expected 3 finite numbers"));

    const fs::path b = scratch_file("bad.bin");
    std::string bytes = "VRPD";
    const std::uint32_t version = 2, columns = 3;
    const std::uint64_t count = 1;
    bytes.append(reinterpret_cast<const char*>(&version), 4);
    bytes.append(reinterpret_cast<const char*>(&count), 8);
    bytes.append(reinterpret_cast<const char*>(&columns), 4);
    bytes += "\x01x\x01y\x05t";  // the third name runs past the end
    write_text(b, bytes);
    CHECK_THROWS_WITH(read_point_set(b.string()), Catch::Contains("column list ends early"));
    const std::uint32_t future = 3;
    std::memcpy(bytes.data() + 4, &future, 4);
    write_text(b, bytes);
    CHECK_THROWS_WITH(read_point_set(b.string()), Catch::Contains("unsupported .bin version 3"));
}

TEST_CASE("point files: a long or binary line is refused in a short, printable message, and a stream without "
          "newlines ends at the line limit", "[io]") {
    const fs::path p = scratch_file("long.csv");
    write_text(p, "x,y\n1," + std::string(5'000'000, '9') + "\n");
    try {
        read_point_set(p.string());
        FAIL("a 5 MB line was read");
    } catch (const Error& e) {
        const std::string what = e.what();
        CHECK(what.size() < 200);
        CHECK_THAT(what, Catch::Contains("long.csv:2: a line longer than 4096 characters"));
    }
    write_text(p, std::string("x,y\n1,\x1b[31mred") + '\0' + "\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains("got `1,\\x1b[31mred\\x00`"));
    // U+0085 (NEXT LINE) in UTF-8, which some readers take for a line break.
    write_text(p,
               "x,y\n1,\xc2\x85"
               "2\n");
    CHECK_THROWS_WITH(read_point_set(p.string()), Catch::Contains("got `1,\\xc2\\x852`"));
    CHECK_THROWS_WITH(read_point_set("/dev/zero"), Catch::Contains("/dev/zero:1: a line longer than 4096 characters"));
}

TEST_CASE("point files: numbers are written as std::to_chars writes them, byte for byte", "[io]") {
    // Coordinates of the unit square and of large boxes, any bit pattern, few-digit decimals
    // across the exponents (where fixed and scientific notation tie or swap), integers around
    // 2^53, zeros, infinities and NaN.
    std::mt19937_64 random(7);
    auto digits = [](double v) {
        char a[64], b[64];
        const std::size_t want = std::size_t(std::to_chars(a, a + sizeof a, v).ptr - a);
        const std::size_t got = std::size_t(vrpd::detail::write_shortest(b, v) - b);
        return std::pair(std::string(a, want), std::string(b, got));
    };
    std::vector<double> values;
    const std::string special =
        "0 -0 1 0.5 1e-5 1e-4 0.001 0.000123 123456 1e15 1e16 1e17 1e22 1e23 1e100 1e-100 "
        "9007199254740991 9007199254740992 -9007199254740993 5e-324 1.7976931348623157e308 "
        "inf -inf nan";
    const char* const special_end = special.data() + special.size();
    for (const char* p = special.data(); p < special_end; ++p) {
        double v = 0;
        p = std::from_chars(p, special_end, v).ptr;
        values.push_back(v);
    }
    for (int i = 0; i < 400000; ++i) {
        const std::uint64_t u = random();
        const double any = std::bit_cast<double>(u), unit = std::ldexp(double(u >> 11), -53),
                     few_digits = double(u % 100000) * std::pow(10.0, int(u >> 40) % 50 - 25),
                     dyadic = double(u >> 44) * std::ldexp(1.0, int(u % 80) - 20);
        values.push_back(i % 4 == 0 ? unit : i % 4 == 1 ? any : i % 4 == 2 ? few_digits : dyadic);
    }
    REQUIRE(std::isnan(values[23]));
    std::size_t differ = 0;
    for (double v : values) {
        const auto [want, got] = digits(v);
        if (want != got && differ++ < 5) FAIL_CHECK(want << " written as " << got);
    }
    CHECK(differ == 0);
}
