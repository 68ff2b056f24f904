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

// A command's deadline in the tests: far above any test's run, so only a hang reaches it.
inline constexpr int kRunDeadlineS = 300;

// `mirage <args>` under tests/testing/with-deadline: a run that outlives kRunDeadlineS prints its
// threads' stacks and is killed (exit 124), so a hang fails its own test, with its command and
// where it stood, instead of holding the whole suite.
inline std::string mirage_command(const std::string& args) {
    return std::string(MIRAGE_SOURCE_DIR) + "/tests/testing/with-deadline " +
           std::to_string(kRunDeadlineS) + " " + MIRAGE_EXE + " " + args + " 2>&1";
}

// Runs `mirage <args>` through the shell and captures its output and exit status.
inline RunResult run_mirage(const std::string& args) {
    RunResult r;
    FILE* p = ::popen(mirage_command(args).c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = ::pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (r.exit_code == 124) r.output += "\n(test: stopped at its deadline: mirage " + args + ")\n";
    return r;
}

}  // namespace mirage::test
