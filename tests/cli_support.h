// Runs of the built vrpd command line from the tests: its exit code and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "support.h"

namespace vrpd::test {

struct Run {
    int code;
    std::string err;
};

// One scratch directory per test process.
inline std::filesystem::path scratch() {
    static const ScratchDir dir("vrpd_cli_test");
    return dir.path;
}

// Runs `vrpd ARGS` with stdout discarded.
inline Run cli(const std::string& args) {
    const std::filesystem::path err = scratch() / "stderr.txt";
    const std::string cmd = std::string(VRPD_CLI) + " " + args + " > /dev/null 2> " + err.string();
    const int status = std::system(cmd.c_str());
    std::ifstream in(err);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

}  // namespace vrpd::test
