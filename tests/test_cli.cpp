// The vrpd command line: bad input gives one clear line and a non-zero exit, never a file;
// a good run writes a CSV that parses, identical across devices; check's exit codes.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "support.h"
#include "vrpd/io.h"

namespace fs = std::filesystem;

using vrpd::DeviceInfo;
using vrpd::list_devices;
using vrpd::test::cli;
using vrpd::test::Run;
using vrpd::test::scratch;
using vrpd::test::slurp;

TEST_CASE("bad input: one line on stderr, non-zero exit, no output file", "[cli]") {
    const fs::path out = scratch() / "never.csv";
    const char* bad[] = {
        "sample --radius 0",
        "sample --radius -0.1",
        "sample --radius nan",
        "sample --radius 0.6",
        "sample --radius 0.01 --extent 0,1",
        "sample --radius 0.01 --extent 1",
        "sample --radius 0.01 --boundary sphere",
        "sample --radius 0.01 --device tpu",
        "sample --radius 0.01 --extent 1,1.41421356 --boundary periodic",
        "sample --radius 1e-9 --boundary free",
        "sample --radius 0.00001",  // fits the lattice, not the 2^31 base cells the kernels index
        "sample --radius 0.00005",  // fits both, not this machine's memory: refused before allocating
        "sample --radius 1e-300",   // cell counts beyond any integer: refused before converting
        "sample --radius 0.1 --extent 1e300,1 --boundary free",
        "sample --radius 0.01 --seed -1",
        "sample --radius 0.01 --seed 1.5",
        "sample --radius 0.01 --seed 4294967296",
        "sample --radius 0.01 --seed 0x10",
        "sample --radius 0.01 --bogus",
        "sample",
        "sample --radius 0.01 --threads 0",
        "sample --rf 0.01",
        "sample --rc 0.02",
        "sample --radius 0.01 --rf 0.01 --rc 0.02",
        "sample --rf 0.02 --rc 0.01",
        "sample --rf 0.01 --rc 0.05",
        "sample --rf 0.1 --rc 0.3",
        "sample --rf 0.01 --rc nan",
    };
    for (const char* args : bad) {
        const Run r = cli(std::string(args) + " -o " + out.string());
        INFO(args << " -> " << r.err);
        CHECK(r.code != 0);
        CHECK(r.err.find("error") != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(fs::exists(out));
    }
    const Run unwritable = cli("sample --radius 0.05 -o /nonexistent/dir/p.csv");
    CHECK(unwritable.code != 0);
    CHECK(unwritable.err.find("cannot write") != std::string::npos);
}

TEST_CASE("two radii from the command line: a file check passes at Rf and Rc", "[cli][two-radii]") {
    const fs::path out = scratch() / "two.csv";
    const Run run = cli("sample --rf 0.02 --rc 0.04 --seed 3 --device cpu -o " + out.string());
    INFO(run.err);
    REQUIRE(run.code == 0);
    CHECK(run.err.find("n*Rf^2/area") != std::string::npos);
    CHECK(cli("check " + out.string() + " --rf 0.02 --rc 0.04").code == 0);
    // The same points miss coverage at a smaller Rc and conflict at a larger Rf.
    CHECK(cli("check " + out.string() + " --rf 0.02 --rc 0.03").code == 1);
    CHECK(cli("check " + out.string() + " --rf 0.03 --rc 0.04").code == 1);
}

TEST_CASE("without a Vulkan driver, gpu says so and points to cpu, and auto runs on cpu and says why", "[cli]") {
    const fs::path out = scratch() / "nodriver.csv";
    const std::string no_driver = "VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json ";
    const fs::path err = scratch() / "nodriver.txt";
    const int status = std::system((no_driver + VRPD_CLI + " sample --radius 0.1 --device gpu -o " + out.string() +
                                    " 2> " + err.string()).c_str());
    CHECK(WEXITSTATUS(status) == 2);
    CHECK(slurp(err).find("--device cpu") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    const int cpu = std::system((no_driver + VRPD_CLI + " sample --radius 0.1 --device cpu -o " + out.string() +
                                 " 2> /dev/null").c_str());
    CHECK(WEXITSTATUS(cpu) == 0);
    CHECK(fs::exists(out));
    const std::string by_cpu = slurp(out);
    fs::remove(out);
    const int automatic = std::system((no_driver + VRPD_CLI + " sample --radius 0.1 -o " + out.string() + " 2> " +
                                       err.string()).c_str());
    CHECK(WEXITSTATUS(automatic) == 0);
    CHECK(slurp(err).find("device cpu") != std::string::npos);
    CHECK(slurp(err).find("(auto: no Vulkan driver") != std::string::npos);
    CHECK(slurp(out) == by_cpu);
    const fs::path listing = scratch() / "devices.txt";
    const int devices = std::system((no_driver + VRPD_CLI + " devices > " + listing.string() + " 2>&1").c_str());
    CHECK(WEXITSTATUS(devices) == 0);
    CHECK(slurp(listing).find("--device auto: cpu (no Vulkan driver") != std::string::npos);
}

TEST_CASE("auto takes a hardware device, a CPU Vulkan driver only when named, and says what it took", "[cli][gpu]") {
    // Where the only Vulkan device is a CPU driver (lavapipe), auto runs the cpu backend; where
    // there is a hardware device, auto runs there. Naming a device (VRPD_DEVICE) takes it.
    std::string hardware;
    for (const DeviceInfo& d : list_devices())
        if (hardware.empty() && d.usable && d.type != "cpu" && d.type != "other") hardware = d.name;
    INFO("hardware device: " << (hardware.empty() ? "none" : hardware));
    const fs::path out = scratch() / "auto.csv";
    const fs::path err = scratch() / "auto.txt";
    CHECK(WEXITSTATUS(std::system((std::string(VRPD_CLI) + " sample --radius 0.05 -o " + out.string() + " 2> " +
                                   err.string()).c_str())) == 0);
    if (hardware.empty()) {
        CHECK(slurp(err).find("device cpu (host") != std::string::npos);
        CHECK(slurp(err).find("(auto: no hardware Vulkan device") != std::string::npos);
    } else {
        CHECK(slurp(err).find("(auto: hardware Vulkan device " + hardware + ")") != std::string::npos);
        CHECK(slurp(err).find("device cpu (host") == std::string::npos);
    }
    CHECK(WEXITSTATUS(std::system(("VRPD_DEVICE=0 " + std::string(VRPD_CLI) + " sample --radius 0.05 -o " +
                                   out.string() + " 2> " + err.string()).c_str())) == 0);
    CHECK(slurp(err).find("(auto: VRPD_DEVICE names a Vulkan device)") != std::string::npos);
    CHECK(slurp(err).find("device cpu (host") == std::string::npos);
    // A sizing field chooses alike.
    const std::string field = " sample --sizing \"0.04 + 0.02*x\" --rule smaller --boundary free -o " + out.string();
    CHECK(WEXITSTATUS(std::system((std::string(VRPD_CLI) + field + " 2> " + err.string()).c_str())) == 0);
    if (hardware.empty()) {
        CHECK(slurp(err).find("device cpu (host, ") != std::string::npos);
        CHECK(slurp(err).find(") (auto: no hardware Vulkan device") != std::string::npos);
    } else {
        CHECK(slurp(err).find("(auto: hardware Vulkan device " + hardware + ")") != std::string::npos);
        CHECK(slurp(err).find("device cpu (host") == std::string::npos);
    }
    CHECK(WEXITSTATUS(
              std::system(("VRPD_DEVICE=0 " + std::string(VRPD_CLI) + field + " 2> " + err.string()).c_str())) == 0);
    CHECK(slurp(err).find("(auto: VRPD_DEVICE names a Vulkan device)") != std::string::npos);
    CHECK(slurp(err).find("device cpu (host") == std::string::npos);
}

TEST_CASE("a good run's CSV parses, and devices give byte-identical files", "[cli][gpu]") {
    const fs::path cpu = scratch() / "cpu.csv", gpu = scratch() / "gpu.csv", bin = scratch() / "gpu.bin";
    REQUIRE(cli("sample --radius 0.02 --seed 7 --device cpu -o " + cpu.string()).code == 0);
    REQUIRE(cli("sample --radius 0.02 --seed 7 --device gpu -o " + gpu.string()).code == 0);
    REQUIRE(cli("sample --radius 0.02 --seed 7 --device gpu -o " + bin.string()).code == 0);
    CHECK(slurp(cpu) == slurp(gpu));
    const auto from_csv = vrpd::read_points(cpu.string());
    const auto from_bin = vrpd::read_points(bin.string());
    CHECK(from_csv.size() > 1000);
    CHECK(from_csv == from_bin);  // the CSV's decimals round-trip the doubles exactly
    CHECK(slurp(cpu).rfind("x,y\n", 0) == 0);
}

TEST_CASE("sample --profile adds a table of phases to the summary, and the same file", "[cli][gpu]") {
    const fs::path plain = scratch() / "plain.csv", timed = scratch() / "timed.csv";
    for (const std::string device : {"cpu", "gpu"}) {
        REQUIRE(cli("sample --radius 0.02 --seed 3 --device " + device + " -o " + plain.string()).code == 0);
        const Run run = cli("sample --radius 0.02 --seed 3 --profile --device " + device + " -o " + timed.string());
        REQUIRE(run.code == 0);
        CHECK(slurp(plain) == slurp(timed));
        CHECK_THAT(run.err, Catch::Contains("vrpd: profile, ") && Catch::Contains("(outside phases)"));
        CHECK_THAT(run.err, Catch::Contains(device == "cpu" ? "  resolve " : "  resolve_darts "));
    }
}

TEST_CASE("check: 0 for a maximal set, 1 when a sample is missing, 2 for bad input", "[cli]") {
    const fs::path good = scratch() / "good.csv", holed = scratch() / "holed.csv", junk = scratch() / "junk.csv";
    REQUIRE(cli("sample --radius 0.05 --seed 2 --device cpu -o " + good.string()).code == 0);
    CHECK(cli("check " + good.string() + " --radius 0.05").code == 0);
    std::string text = slurp(good);
    text.erase(text.find('\n') + 1, text.find('\n', text.find('\n') + 1) - text.find('\n'));  // drop sample 1
    std::ofstream(holed) << text;
    CHECK(cli("check " + holed.string() + " --radius 0.05").code == 1);
    std::ofstream(junk) << "x,y\n0.1,0.2\n0.3,abc\n0.5,0.5\n";
    const Run r = cli("check " + junk.string() + " --radius 0.05");
    CHECK(r.code == 2);
    CHECK(r.err.find(":3:") != std::string::npos);  // names the line
    CHECK(cli("check " + (scratch() / "missing.csv").string() + " --radius 0.05").code == 2);
    CHECK(cli("check " + good.string() + " --rf 0.05 --rc 0.01").code == 2);
    CHECK(cli("check " + good.string() + " --radius 0.05 --tolerance 0.06").code == 2);
    CHECK(cli("check " + good.string() + " --radius 0.05 --tolerance -1").code == 2);
    CHECK(cli("check " + scratch().string() + " --radius 0.05").code == 2);  // a directory
}

// vrpd's files hold lattice points, written with 9 significant digits: their largest empty circle
// may exceed r by half a lattice step plus the rounding. In this run it is 0.00300000012 (found
// by comparing the backends' output and checking it over 14 boxes and radii): the default
// tolerance passes it, a strict check does not, and a missing sample fails either way.
TEST_CASE("check: vrpd's own files pass at the resolution they are written with", "[cli]") {
    const fs::path edge = scratch() / "edge.csv", holed = scratch() / "edge_holed.csv";
    REQUIRE(cli("sample --radius 0.003 --seed 4 --device cpu -o " + edge.string()).code == 0);
    CHECK(cli("check " + edge.string() + " --radius 0.003").code == 0);
    CHECK(cli("check " + edge.string() + " --radius 0.003 --tolerance 0").code == 1);
    std::string text = slurp(edge);
    text.erase(text.find('\n') + 1, text.find('\n', text.find('\n') + 1) - text.find('\n'));  // drop sample 1
    std::ofstream(holed) << text;
    CHECK(cli("check " + holed.string() + " --radius 0.003").code == 1);
    // A radius near the box's side leaves one or a few samples; check judges them too.
    for (const char* radius : {"0.9", "0.6"}) {
        const fs::path few = scratch() / "few.csv";
        REQUIRE(
            cli(std::string("sample --boundary free --device cpu --radius ") + radius + " -o " + few.string()).code ==
            0);
        CHECK(cli("check " + few.string() + " --boundary free --radius " + radius).code == 0);
    }
}

TEST_CASE("bench and check write JSON that says what they measured", "[cli]") {
    const fs::path bench = scratch() / "bench.json", report = scratch() / "report.json", pts = scratch() / "b.csv";
    REQUIRE(cli("bench --radii 0.05 --rc 0.1 --devices cpu serial --repeat 1 --json " + bench.string()).code == 0);
    const auto b = nlohmann::json::parse(slurp(bench));
    REQUIRE(b["rows"].size() == 4);
    CHECK(b["rows"][0]["samples"] == b["rows"][1]["samples"]);  // the same sampling on both devices
    CHECK(b["rows"][0]["points_per_second"].get<double>() > 0);
    CHECK(b["rows"][0]["rc"] == 0.05);
    CHECK(b["rows"][2]["rf"] == 0.05);  // a two-radii row: Rf = Rc / 2
    CHECK(b["rows"][2]["rc"] == 0.1);
    CHECK(b["rows"][2]["samples"] == b["rows"][3]["samples"]);
    CHECK(cli("bench --radii 0.7").code != 0);  // too large for the unit torus
    CHECK(cli("bench --rc 0.3").code != 0);
    // With a hierarchy: a row for the radius and for each field and rule, each after its direct row.
    REQUIRE(
        cli("bench --radii 0.05 --rc 0.1 --fields ramp --hierarchy 3 --devices cpu --repeat 1 --json " + bench.string())
            .code == 0);
    const auto h = nlohmann::json::parse(slurp(bench));
    REQUIRE(h["rows"].size() == 11);
    CHECK(h["rows"][2]["hierarchy_steps"] == 3);
    for (int k = 3; k < 11; k += 2) {
        CHECK(h["rows"][k]["field"] == "ramp");
        CHECK(!h["rows"][k].contains("hierarchy_steps"));
        CHECK(h["rows"][k + 1]["rule"] == h["rows"][k]["rule"]);
        CHECK(h["rows"][k + 1]["hierarchy_steps"] == 3);
        CHECK(h["rows"][k + 1]["samples"].get<int>() > h["rows"][k]["samples"].get<int>() / 2);
        // A field's row counts its one tabulation in its time.
        CHECK(h["rows"][k]["tabulation_seconds"].get<double>() > 0);
        CHECK(h["rows"][k]["best_seconds"].get<double>() > h["rows"][k]["tabulation_seconds"].get<double>());
    }
    CHECK(!h["rows"][0].contains("tabulation_seconds"));

    REQUIRE(cli("sample --radius 0.05 --seed 4 --device cpu -o " + pts.string()).code == 0);
    REQUIRE(cli("check " + pts.string() + " --radius 0.05 --json " + report.string()).code == 0);
    const auto r = nlohmann::json::parse(slurp(report));
    CHECK(r["passed"] == true);
    CHECK(r["conflicts"] == 0);
    CHECK(r["largest_empty_radius"].get<double>() < 0.05);
    CHECK(r["min_angle_degrees"].get<double>() > 30.0);
}

TEST_CASE("output targets: devices and FIFOs written in place, links followed, long names, lost output is an error",
          "[cli]") {
    const fs::path dir = scratch();
    const std::string vrpd = VRPD_CLI;
    auto sh = [](const std::string& cmd) { return WEXITSTATUS(std::system(("bash -c '" + cmd + "'").c_str())); };
    CHECK(sh(vrpd + " sample --radius 0.1 --device cpu -o /dev/null 2> /dev/null") == 0);
    CHECK(fs::is_character_file("/dev/null"));

    const fs::path target = dir / "target.csv", link = dir / "link.csv";
    { std::ofstream(target) << "old\n"; }
    fs::create_symlink(target, link);
    CHECK(sh(vrpd + " sample --radius 0.1 --device cpu -o " + link.string() + " 2> /dev/null") == 0);
    CHECK(fs::is_symlink(link));
    CHECK(slurp(target).rfind("x,y\n", 0) == 0);

    const fs::path fifo = dir / "fifo.csv", drained = dir / "drained.csv";
    REQUIRE(sh("mkfifo " + fifo.string()) == 0);
    CHECK(sh("cat " + fifo.string() + " > " + drained.string() + " & " + vrpd +
             " sample --radius 0.1 --device cpu -o " + fifo.string() + " 2> /dev/null; wait") == 0);
    CHECK(fs::is_fifo(fifo));
    CHECK(slurp(drained).rfind("x,y\n", 0) == 0);

    const fs::path long_name = dir / (std::string(250, 'a') + ".csv");
    CHECK(sh(vrpd + " sample --radius 0.1 --device cpu -o " + long_name.string() + " 2> /dev/null") == 0);
    CHECK(fs::exists(long_name));

    for (const std::string& cmd : {vrpd + " sample --radius 0.01 --device cpu", vrpd + " sample --radius 0.01 -o -",
                                   vrpd + " check " + long_name.string() + " --radius 0.1", vrpd + " devices"}) {
        INFO(cmd);
        const fs::path err = dir / "full.txt";
        CHECK(sh(cmd + " > /dev/full 2> " + err.string()) == 2);
        CHECK(slurp(err) == "vrpd: error: cannot write standard output: No space left on device\n");
    }
    for (const auto& entry : fs::directory_iterator(dir))
        CHECK(entry.path().filename().string().rfind(".vrpd-", 0) == std::string::npos);  // no temporary left
}

TEST_CASE("radii, seeds and limits: refused with one line, never taken silently, never a crash or a hang", "[cli]") {
    const fs::path points = scratch() / "limits.csv";
    REQUIRE(cli("sample --radius 0.05 --device cpu -o " + points.string()).code == 0);
    for (const std::string& args :
         {"check " + points.string() + " --rf 0.05 --rc nan", "check " + points.string() + " --rf 0.05 --rc 0",
          "check " + points.string() + " --rf 0.05 --rc -1", "check " + points.string() + " --radius -0.05",
          std::string("sample --rf 0.01 --rc 0"), std::string("sample --radius 0.1 --seed -18446744073709551615")}) {
        INFO(args);
        const Run r = cli(args);
        CHECK(r.code == 2);
        CHECK(r.err.rfind("vrpd: error: ", 0) == 0);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    CHECK_THAT(cli("check " + points.string() + " --radius -0.05").err, Catch::Contains("got -0.05"));
    // A memory limit the run does not fit, and more threads than the limit lets start. (Not under
    // AddressSanitizer, which cannot map its shadow memory under `ulimit -v`.)
#ifndef __SANITIZE_ADDRESS__
    const fs::path out = scratch() / "limited.csv";
    const auto limited = [&](const std::string& limit, const std::string& args) {
        const fs::path err = scratch() / "limited.txt";
        const int status = std::system(("bash -c 'ulimit -v " + limit + "; timeout 120 " + VRPD_CLI + " " + args +
                                        " -o " + out.string() + "' 2> " + err.string()).c_str());
        return Run{WEXITSTATUS(status), slurp(err)};
    };
    const Run memory = limited("400000", "sample --radius 0.0003 --device cpu --threads 2");
    CHECK(memory.code == 2);
    CHECK_THAT(memory.err, Catch::Contains("address-space limit"));
    // A field's continuous hierarchy: its first level fits, its events would not.
    const Run events =
        limited("400000", "sample --sizing 0.0012 --rule smaller --hierarchy continuous:10 --device cpu --threads 2");
    CHECK(events.code == 2);
    CHECK_THAT(events.err, Catch::Contains("the continuous hierarchy needs about"));
    const Run threads = limited("1000000", "sample --radius 0.1 --device cpu --threads 1024");
    CHECK(threads.code == 2);
    CHECK_THAT(threads.err, Catch::Contains("cannot start 1024 host threads"));
    CHECK_FALSE(fs::exists(out));
#endif
}

TEST_CASE("check: memory follows the points, not the radius", "[cli]") {
    // Two far points judged at r = 3e-5: buckets sized by the radius alone were 1.1e9 (6.3 GB).
    const fs::path far = scratch() / "far.csv";
    { std::ofstream(far) << "x,y\n0.1,0.1\n0.9,0.9\n"; }
#ifndef __SANITIZE_ADDRESS__  // AddressSanitizer cannot map its shadow memory under `ulimit -v`
    const int status = std::system(("bash -c 'ulimit -v 300000; " + std::string(VRPD_CLI) + " check " + far.string() +
                                    " --radius 3e-5 > /dev/null 2>&1'").c_str());
    CHECK(WEXITSTATUS(status) == 1);  // judged (not maximal), within 300 MB
#endif
    CHECK(cli("check " + far.string() + " --radius 3e-5").code == 1);
}

TEST_CASE("sample --runs: a file a seed, each the run of that seed alone, a field tabulated once", "[cli]") {
    const fs::path dir = scratch() / "runs";
    fs::create_directories(dir);
    const auto name = [&](const std::string& stem, const std::string& seed) { return (dir / (stem + seed)).string(); };
    const std::string uniform = "sample --radius 0.03 --device cpu";
    const Run three = cli(uniform + " --seed 7 --runs 3 -o " + name("u_", "{seed}.csv"));
    INFO(three.err);
    REQUIRE(three.code == 0);
    for (const std::string seed : {"7", "8", "9"}) {
        REQUIRE(cli(uniform + " --seed " + seed + " -o " + name("one_", seed + ".csv")).code == 0);
        CHECK(slurp(name("u_", seed + ".csv")) == slurp(name("one_", seed + ".csv")));
        CHECK_THAT(three.err, Catch::Contains("vrpd: seed " + seed + ": "));
    }
    CHECK(std::count(three.err.begin(), three.err.end(), '\n') == 3);
    CHECK(slurp(name("u_", "7.csv")) != slurp(name("u_", "8.csv")));

    // A field whose L passes the bigger rule's bound, up to the last seed there is: the runs share
    // one table and say its warning once.
    const std::string field =
        "sample --sizing \"0.01 + 0.8*x*x\" --rule bigger --weighting density --boundary free "
        "--device serial";
    const Run two = cli(field + " --seed 4294967294 --runs 2 -o " + name("f_", "{seed}.bin"));
    INFO(two.err);
    REQUIRE(two.code == 0);
    CHECK_THAT(two.err, Catch::Contains("vrpd: the field tabulated once for 2 runs"));
    CHECK(std::count(two.err.begin(), two.err.end(), '\n') == 4);  // tabulation, two runs, one warning
    CHECK_THAT(two.err, Catch::Contains("exceeds the bigger rule's bound"));
    for (const std::string seed : {"4294967294", "4294967295"}) {
        REQUIRE(cli(field + " --seed " + seed + " -o " + name("g_", seed + ".bin")).code == 0);
        CHECK(slurp(name("f_", seed + ".bin")) == slurp(name("g_", seed + ".bin")));
    }

    // Refused before any run: no file is written.
    fs::create_directories(dir / "5");
    for (const std::string& args :
         {" --runs 2 -o " + name("r_", ".csv"), std::string(" --runs 2"), " --runs 0 -o " + name("r_", "{seed}.csv"),
          " --seed 4294967295 --runs 2 -o " + name("r_", "{seed}.csv"),
          " --seed 5 --runs 2 -o " + (dir / "{seed}" / "r.csv").string()}) {
        const Run r = cli(uniform + args);
        INFO(args << " -> " << r.err);
        CHECK(r.code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    CHECK_THAT(cli(uniform + " --runs 2").err, Catch::Contains("give an output with {seed} in its name"));
    CHECK_THAT(cli(uniform + " --seed 4294967295 --runs 2 -o " + name("r_", "{seed}.csv")).err,
               Catch::Contains("the last seed would pass 4294967295"));
    for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().filename().string().rfind("r_", 0) != 0);
    CHECK(fs::is_empty(dir / "5"));
}
