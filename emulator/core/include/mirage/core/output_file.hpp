// SPDX-License-Identifier: Apache-2.0
// Cleaning up an output that failed. An output path may name a device or a FIFO (/dev/full,
// /dev/null, a named pipe) as well as a file; only a regular file is ever removed, so a failed
// write to a device never deletes the device node (docs/conventions.md §6).
#pragma once
#include <sys/stat.h>
#include <unistd.h>

#include <string>

namespace mirage::core {

inline void remove_failed_output(const std::string& path) noexcept {
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) ::unlink(path.c_str());
}

}  // namespace mirage::core
