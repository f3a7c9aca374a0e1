// The vrpd command line: sample, check (with the geometry target), devices, bench.
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_common.h"
#include "vrpd/io.h"
#include "vrpd/vrpd.h"

namespace vrpd::cli {

Backend parse_backend(const std::string& name) {
    if (name == "gpu") return Backend::Gpu;
    if (name == "cpu") return Backend::Cpu;
    if (name == "serial") return Backend::Serial;
    throw Error(fmt::format("unknown device '{}': use gpu, cpu or serial", name));
}

const char* backend_name(Backend b) {
    switch (b) {
    case Backend::Gpu: return "gpu";
    case Backend::Cpu: return "cpu";
    case Backend::Serial: return "serial";
    }
    return "?";
}

Boundary parse_boundary(const std::string& name) {
    if (name == "periodic") return Boundary::Periodic;
    if (name == "free") return Boundary::Free;
    throw Error(fmt::format("unknown boundary '{}': use periodic or free", name));
}

void parse_extent(const std::string& text, Box& box) {
    double w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf%c", &w, &h, &tail) != 2)
        throw Error(fmt::format("extent must be W,H (two numbers), got '{}'", text));
    box.width = w;
    box.height = h;
}

}  // namespace vrpd::cli

int main(int argc, char** argv) {
    using namespace vrpd;
    CLI::App app{"vrpd: maximal Poisson-disk sampling on Vulkan compute"};
    app.set_version_flag("--version", std::string("vrpd ") + version());
    app.require_subcommand(1);

    SampleOptions opt;
    std::string extent = "1,1", boundary = "periodic", device = "gpu", output;
    auto* sample_cmd = app.add_subcommand("sample", "maximal Poisson-disk sampling of a box");
    sample_cmd->add_option("--radius,-r", opt.radius, "disk radius r (inhibition = coverage)")->required();
    sample_cmd->add_option("--extent", extent, "box W,H (default 1,1)");
    sample_cmd->add_option("--boundary", boundary, "periodic (default) or free");
    sample_cmd->add_option("--seed", opt.seed, "random seed (default 0)");
    sample_cmd->add_option("--device", device, "gpu (default; $VRPD_DEVICE picks the Vulkan device), cpu or serial");
    sample_cmd->add_option("-o,--output", output, "FILE.csv or FILE.bin (default: CSV to stdout)");

    auto* devices_cmd = app.add_subcommand("devices", "list Vulkan devices");

    cli::BenchOptions bench;
    auto* bench_cmd = app.add_subcommand("bench", "time sampling per radius and device");
    bench_cmd->add_option("--radii", bench.radii, "radii on the unit torus (default 0.01 0.002 0.001)");
    bench_cmd->add_option("--devices", bench.devices, "gpu cpu serial (default all)");
    bench_cmd->add_option("--repeat", bench.repeat, "runs per case, best time kept (default 3)");
    bench_cmd->add_option("--json", bench.json, "also write the table as JSON to FILE");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }

    try {
        if (*sample_cmd) {
            opt.backend = cli::parse_backend(device);
            opt.box.boundary = cli::parse_boundary(boundary);
            cli::parse_extent(extent, opt.box);
            validate(opt);
            if (!output.empty()) check_writable(output);
            Sampling s = sample(opt);
            if (output.empty()) write_csv(s, std::cout);
            else write_points(s, output);
            const double area = s.box.width * s.box.height;
            std::cerr << fmt::format("vrpd: {} samples, n*r^2/area {:.5f}, {:.3f} s, {:.3g} points/s, {} levels, {} darts, device {}\n",
                                     s.size(), double(s.size()) * s.radius * s.radius / area, s.stats.seconds,
                                     double(s.size()) / s.stats.seconds, s.stats.levels, s.stats.darts, s.device);
            return 0;
        }
        if (*devices_cmd) {
            for (const DeviceInfo& d : list_devices())
                std::cout << fmt::format("{}: {} ({}, {}){}\n", d.index, d.name, d.type, d.driver,
                                         d.usable ? "" : " - not usable: needs Vulkan 1.2, shaderInt64, bufferDeviceAddress");
            return 0;
        }
        if (*bench_cmd) return cli::run_bench(bench);
    } catch (const Error& e) {
        std::cerr << "vrpd: error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "vrpd: error: out of host memory\n";
        return 2;
    }
    return 0;
}
