// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <regex>
#include <string>

namespace mirage::test {

// `mirage <args>` running in the background, its stdout and stderr read as they come.
struct BackgroundMirage {
    FILE* pipe = nullptr;
    std::string output;
    // Reads lines until one matches `re`; returns it (empty on EOF).
    std::string wait_for(const std::regex& re) {
        char buf[1024];
        while (pipe && std::fgets(buf, sizeof buf, pipe)) {
            output += buf;
            if (std::regex_search(buf, re)) return buf;
        }
        return {};
    }
    // Reads the rest and returns the exit status.
    int finish() {
        if (!pipe) return -1;
        char buf[4096];
        while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
        const int st = ::pclose(pipe);
        pipe = nullptr;
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
};

inline BackgroundMirage start_mirage(const std::string& args) {
    BackgroundMirage b;
    b.pipe = ::popen((std::string(MIRAGE_EXE) + " " + args + " 2>&1").c_str(), "r");
    return b;
}

}  // namespace mirage::test
