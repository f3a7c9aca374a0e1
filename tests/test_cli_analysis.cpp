// vrpd analyze, plot and figures from the command line: the files they promise, metrics.json's
// numbers, and one line and exit 2 for bad input with no report left behind.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <cairo.h>
#include <nlohmann/json.hpp>

#include "cli_support.h"

namespace fs = std::filesystem;
using vrpd::test::cli;
using vrpd::test::Run;
using vrpd::test::scratch;
using vrpd::test::slurp;

namespace {
bool is_png(const fs::path& p) { return slurp(p).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }
// A PNG's width and height, from its IHDR chunk (big-endian, at bytes 16-23).
std::pair<unsigned, unsigned> png_size(const fs::path& p) {
    const std::string b = slurp(p);
    if (b.size() < 24 || b.compare(12, 4, "IHDR") != 0) return {0, 0};
    auto be = [&](std::size_t at) {
        return unsigned(static_cast<unsigned char>(b[at])) << 24 |
               unsigned(static_cast<unsigned char>(b[at + 1])) << 16 |
               unsigned(static_cast<unsigned char>(b[at + 2])) << 8 | unsigned(static_cast<unsigned char>(b[at + 3]));
    };
    return {be(16), be(20)};
}
bool is_svg(const fs::path& p) { return slurp(p).find("<svg") != std::string::npos; }
// The pixels of a PNG darker than mid-grey, read back by cairo.
std::size_t dark_pixels(const fs::path& p) {
    cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
    std::size_t dark = 0;
    if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
        const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
        const int stride = cairo_image_surface_get_stride(s);
        const unsigned char* data = cairo_image_surface_get_data(s);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint32_t px;
                std::memcpy(&px, data + std::size_t(y) * std::size_t(stride) + std::size_t(x) * 4, 4);
                dark += ((px >> 16 & 0xFF) + (px >> 8 & 0xFF) + (px & 0xFF)) < 3 * 128;
            }
    }
    cairo_surface_destroy(s);
    return dark;
}
}  // namespace

TEST_CASE("analyze: figures as PNG and SVG, and metrics.json with every number they show", "[cli][analysis]") {
    const fs::path a = scratch() / "an1.csv", b = scratch() / "an2.csv", out = scratch() / "report";
    REQUIRE(cli("sample --radius 0.02 --seed 1 --device cpu -o " + a.string()).code == 0);
    REQUIRE(cli("sample --radius 0.02 --seed 2 --device cpu -o " + b.string()).code == 0);
    const Run run = cli("analyze " + a.string() + " " + b.string() + " --radius 0.02 --device cpu --out " +
                        out.string() + "/");
    INFO(run.err);
    REQUIRE(run.code == 0);
    for (const char* panel : {"points", "spectrum", "radial", "angles", "edges"}) {
        INFO(panel);
        CHECK(is_png(out / (std::string("analysis-") + panel + ".png")));
        CHECK(is_svg(out / (std::string("analysis-") + panel + ".svg")));
    }
    // The stated sizes: square panels 680 x 700 (640 and the margins), plots 640 x 480.
    CHECK(png_size(out / "analysis-spectrum.png") == std::pair{680u, 700u});
    CHECK(png_size(out / "analysis-points.png") == std::pair{680u, 700u});
    CHECK(png_size(out / "analysis-radial.png") == std::pair{640u, 480u});
    CHECK(png_size(out / "analysis-angles.png") == std::pair{640u, 480u});
    CHECK(slurp(out / "analysis-radial.svg").find("width=\"640pt\" height=\"480pt\"") != std::string::npos);
    const auto j = nlohmann::json::parse(slurp(out / "metrics.json"));
    CHECK(j["sets"] == 2);
    CHECK(j["n"].get<double>() > 1500);
    CHECK(j["delta_x"].get<double>() >= 0.75);
    CHECK(j["mean_min_distance"].get<double>() > j["delta_x"].get<double>());
    REQUIRE(j["radial_power"].size() == std::size_t(j["spectrum"]["half_width"]));
    CHECK(j["radial_power"][0][0] == 1.0);
    CHECK(j["anisotropy_db"].size() == j["radial_power"].size());
    // One radius: every Delaunay angle at least 30 degrees, every edge within [Rf, 2 Rc].
    CHECK(j["min_angle_bound_deg"].get<double>() == Approx(30));
    CHECK(j["min_angle_deg"].get<double>() >= 30 - 1e-6);
    CHECK(j["edge_ratio_min"].get<double>() >= 1 - 1e-6);
    CHECK(j["edge_ratio_max"].get<double>() <= 2 + 1e-6);
    CHECK(j["maximal_sets"] == 2);
    CHECK(j["conflicts"] == 0);
    // Without radii: no Delaunay panels.
    const fs::path plain = scratch() / "plain";
    REQUIRE(cli("analyze " + a.string() + " --device cpu --frequencies 40 --out " + plain.string()).code == 0);
    CHECK(fs::exists(plain / "analysis-radial.png"));
    CHECK_FALSE(fs::exists(plain / "analysis-angles.png"));
    CHECK(nlohmann::json::parse(slurp(plain / "metrics.json"))["radial_power"].size() == 40);
}

TEST_CASE("plot: a PNG or an SVG, coloured by a column", "[cli][analysis]") {
    const fs::path a = scratch() / "plot.csv";
    REQUIRE(cli("sample --radius 0.05 --seed 1 --device cpu -o " + a.string()).code == 0);
    REQUIRE(cli("plot " + a.string() + " --radius 0.05 -o " + (scratch() / "p.png").string()).code == 0);
    CHECK(is_png(scratch() / "p.png"));
    CHECK_FALSE(fs::exists(scratch() / "p.svg"));
    REQUIRE(cli("plot " + a.string() + " -o " + (scratch() / "q.svg").string()).code == 0);
    CHECK(is_svg(scratch() / "q.svg"));
    const fs::path coloured = scratch() / "coloured.csv";
    {
        std::ofstream f(coloured);
        f << "x,y,t\n0.1,0.1,1\n0.5,0.5,0.5\n0.9,0.2,0.25\n";
    }
    REQUIRE(cli("plot " + coloured.string() + " --colour t -o " + (scratch() / "c.png").string()).code == 0);
    CHECK(is_png(scratch() / "c.png"));
    // --disks: each point's disk of radius r/2 from its r column. One point of r = 0.4 in the
    // 640-pixel square is a disk of 128 pixels' radius (about 51 000 pixels); as a dot, a few.
    const fs::path sized = scratch() / "sized.csv";
    std::ofstream(sized) << "x,y,r\n0.5,0.5,0.4\n";
    REQUIRE(cli("plot " + sized.string() + " --disks -o " + (scratch() / "d.png").string()).code == 0);
    REQUIRE(cli("plot " + sized.string() + " -o " + (scratch() / "e.png").string()).code == 0);
    CHECK(dark_pixels(scratch() / "d.png") > 45000);
    CHECK(dark_pixels(scratch() / "e.png") < 10000);
}

TEST_CASE("analyze, plot, figures: bad input is one line, exit 2, and leaves no report", "[cli][analysis]") {
    const fs::path a = scratch() / "bad.csv", out = scratch() / "never", negative = scratch() / "negative_r.csv";
    REQUIRE(cli("sample --radius 0.1 --seed 1 --device cpu -o " + a.string()).code == 0);
    std::ofstream(negative) << "x,y,r\n0.5,0.5,0.1\n0.2,0.2,-0.1\n";
    const std::string file = a.string(), to = " --out " + out.string();
    const std::string bad[] = {
        "analyze " + file + to + " --radius 0",
        "analyze " + file + to + " --rf 0.1 --rc 0.05",
        "analyze " + file + to + " --rc 0.05",
        "analyze " + file + to + " --frequencies 2000",
        "analyze " + file + to + " --extent 0.5,0.5",  // points outside the box
        "analyze " + file + to + " --device quantum",
        "analyze " + (scratch() / "missing.csv").string() + to,
        "analyze " + file + " --out " + file,  // a file, not a directory
        "plot " + file + " --colour t -o " + (out / "p.png").string(),
        "plot " + file + " -o " + (scratch() / "p.jpg").string(),
        "plot " + file + " --disks -o " + (out / "p.png").string(),  // no r column
        "plot " + negative.string() + " --disks -o " + (out / "p.png").string(),
        "figures --sets 0" + to,
    };
    for (const std::string& args : bad) {
        const Run r = cli(args);
        INFO(args << "\n" << r.err);
        CHECK(r.code == 2);
        CHECK(r.err.rfind("vrpd: error: ", 0) == 0);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(fs::exists(out));
    }
    for (const auto& entry : fs::directory_iterator(scratch()))
        CHECK(entry.path().filename().string().rfind(".vrpd-report-", 0) != 0);
}

TEST_CASE("figures: the paper's figures, an index page that links every file, their numbers", "[cli][analysis]") {
    const fs::path out = scratch() / "figures";
    const Run run = cli("figures --sets 1 --device cpu --out " + out.string());
    INFO(run.err);
    REQUIRE(run.code == 0);
    const std::string html = slurp(out / "index.html");
    for (const char* id : {"Figure 4:", "Figure 5:", "Figure 6:", "Figure 7:", "Figure 8:", "Figure 9:", "Figure 10:",
                           "Figure 11:", "Figure 12:", "Figures 14 and 15", "Figure 16:"}) {
        INFO(id);
        CHECK(html.find(id) != std::string::npos);
    }
    CHECK(html.find("not built") == std::string::npos);
    for (const char* png : {"figure4-points.png", "figure5-angles.png", "figure8-edges.png", "figure10-spectrum.png"})
        CHECK(is_png(out / png));
    // The page links every figure written, PNG and SVG.
    std::size_t linked = 0;
    for (const auto& entry : fs::directory_iterator(out)) {
        const std::string name = entry.path().filename().string(), ext = entry.path().extension().string();
        if (ext != ".png" && ext != ".svg") continue;
        INFO(name);
        CHECK(html.find("\"" + name + "\"") != std::string::npos);
        ++linked;
    }
    // 7 figures x 3 panels, 6 with radii x 2 Delaunay panels; Figure 11's 4 ramps and 4 angle
    // histograms, 12 and 16 one each.
    CHECK(linked == 2 * (7 * 3 + 6 * 2 + 8 + 2));
    const auto j = nlohmann::json::parse(slurp(out / "figures.json"));
    CHECK(j["4"]["paper_count"] == 6656);
    CHECK(j["6"]["paper_count"] == 6727);
    // The hierarchy's final level is a maximal sampling at r = 0.01: every Delaunay angle >= 30.
    CHECK(j["6"]["min_angle_deg"].get<double>() >= 30 - 1e-6);
    CHECK(j["6"]["maximal_sets"] == 1);
    // Two radii Rc = 2 Rf: the smallest angle obeys asin(1/4) = 14.48 degrees.
    CHECK(j["5"]["min_angle_bound_deg"].get<double>() == Approx(14.4775).epsilon(1e-4));
    CHECK(j["5"]["min_angle_deg"].get<double>() >= j["5"]["min_angle_bound_deg"].get<double>());
    CHECK(j["10"]["delta_x"].get<double>() < 0.2);  // uniform random points are not spread out
    // Figure 11: each rule's smallest angle on the sine obeys Table 1, and smaller's is the largest
    // (the paper: "the smaller-disk construction yields a larger minimum angle").
    for (const char* rule : {"prior", "current", "bigger", "smaller"}) {
        INFO(rule);
        CHECK(j["11"][rule]["min_angle_deg"].get<double>() >= j["11"][rule]["angle_bound_deg"].get<double>());
        CHECK(j["11"][rule]["ramp_samples"].get<double>() > 1500);
    }
    for (const char* rule : {"prior", "current", "bigger"})
        CHECK(j["11"]["smaller"]["min_angle_deg"].get<double>() > j["11"][rule]["min_angle_deg"].get<double>());
    CHECK(j["12"]["samples"].get<double>() > 1000);
    CHECK(j["16"]["samples"].get<double>() > 20000);
}
