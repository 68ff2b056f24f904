// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "mirage/core/georef.hpp"
#include "mirage/core/point.hpp"

namespace mirage::las {

struct LasWriterOptions {
    std::uint8_t point_format = 6;        // 1, 3 (LAS 1.2-compatible) or 6, 7
    double scale = 0.001;                 // 1 mm
    std::uint16_t file_source_id = 0;
    std::string system_identifier = "Mirage emulator";
    std::string generating_software = "mirage";
};

// LAS 1.4 writer (hand-written: Debian 12 packages no LAS library). Points arrive in the
// scene's local frame and are written as anchor + local, rounded (not truncated) to the scale,
// with offsets chosen from the anchor so georeferenced coordinates fit int32. Adds an OGC WKT
// CRS VLR (global encoding bit 4) when the georef has a CRS. GPS time is adjusted standard GPS
// time (bit 0). The header (counts, counts by return, bounds) is rewritten on close() and
// by finalize_for_signal(); on a write error (disk full) the file is cut to the last whole
// record, the header is made to match it, and IoError is thrown naming the file.
class LasWriter {
public:
    LasWriter(const std::string& path, const core::Georef& georef, LasWriterOptions opt = {});
    ~LasWriter();   // closes if still open; never throws
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;

    void write(std::span<const core::PointRecord> points);
    void close();
    std::uint64_t points_written() const;
    const std::string& path() const;

    // Async-signal-safe finalisation (pwrite of the header only): registered writers are
    // finalised by install_signal_finalizer()'s handler on SIGINT/SIGTERM before exit.
    void finalize_for_signal() noexcept;

private:
    struct Impl;
    Impl* impl_;
};

// Installs SIGINT/SIGTERM handlers that finalise every open LasWriter and then re-raise the
// signal with the default action (so the exit status reports it).
void install_signal_finalizer();

}  // namespace mirage::las
