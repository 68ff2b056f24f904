// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <regex>
#include <string>

#include "cli_run.hpp"

namespace mirage::test {

// `mirage <args>` running in the background, its stdout and stderr read as they come, straight
// from the pipe's descriptor (no stdio buffer), so a wait can have a deadline.
struct BackgroundMirage {
    FILE* pipe = nullptr;
    std::string output;
    std::string pending;  // read but not yet a whole line
    // Reads lines until one matches `re` and returns it; empty on EOF or after `seconds`.
    std::string wait_for(const std::regex& re, double seconds = 60) {
        const auto deadline =
            std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        for (;;) {
            for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
                std::string line = pending.substr(0, nl + 1);
                pending.erase(0, nl + 1);
                output += line;
                if (std::regex_search(line, re)) return line;
            }
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                deadline - std::chrono::steady_clock::now());
            if (!pipe || left.count() <= 0) return {};
            pollfd p{::fileno(pipe), POLLIN, 0};
            if (::poll(&p, 1, int(left.count())) <= 0) continue;
            char buf[4096];
            const ssize_t n = ::read(p.fd, buf, sizeof buf);
            if (n <= 0) {
                output += pending;
                pending.clear();
                return {};
            }
            pending.append(buf, std::size_t(n));
        }
    }
    // Reads the rest and returns the exit status.
    int finish() {
        if (!pipe) return -1;
        output += pending;
        pending.clear();
        char buf[4096];
        for (ssize_t n; (n = ::read(::fileno(pipe), buf, sizeof buf)) > 0;)
            output.append(buf, std::size_t(n));
        const int st = ::pclose(pipe);
        pipe = nullptr;
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
};

// Under the same deadline as run_mirage (cli_run.hpp), so finish() cannot wait forever.
inline BackgroundMirage start_mirage(const std::string& args) {
    BackgroundMirage b;
    b.pipe = ::popen(mirage_command(args).c_str(), "r");
    return b;
}

}  // namespace mirage::test
