// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace mirage::test {

struct RunResult {
    int exit_code = -1;
    std::string output;  // stdout and stderr
};

// Runs `mirage <args>` through the shell and captures its output and exit status.
inline RunResult run_mirage(const std::string& args) {
    RunResult r;
    const std::string cmd = std::string(MIRAGE_EXE) + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = ::pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

}  // namespace mirage::test
