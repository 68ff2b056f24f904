// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "mirage/core/georef.hpp"
#include "mirage/core/point.hpp"

namespace mirage::las {

// Point formats 4, 5, 9 and 10: how a pulse's recorded samples are stored (docs/file-formats.md
// §6.1). One descriptor (index 1): every packet holds `samples` samples `spacing_ps` apart.
struct WaveformPackets {
    std::uint8_t bits = 16;           // per stored sample: 8, 16 or 32 (larger values saturate)
    std::uint32_t samples = 0;        // per packet, ≥ 1
    std::uint32_t spacing_ps = 1000;  // ≥ 1
    double gain = 1.0, offset = 0.0;  // value = offset + gain · stored sample
    bool external = false;            // leave the packets in <base>.wdp instead of the EVLR
};

struct LasWriterOptions {
    std::uint8_t point_format = 6;  // 1, 3 (LAS 1.2-compatible), 6, 7; with waveforms 4, 5, 9, 10
    double scale = 0.001;           // 1 mm
    std::uint16_t file_source_id = 0;
    std::string system_identifier = "Mirage emulator";
    std::string generating_software = "mirage";
    // Fixed creation date so the same points always give byte-identical files.
    std::uint16_t creation_day = 1;  // day of year, 1-based
    std::uint16_t creation_year = 2025;
    std::size_t buffer_bytes = 1 << 20;  // pwrite(2) granularity; rounded down to whole records
    WaveformPackets waveform{};          // formats 4, 5, 9, 10 only
    // Extra bytes after each record: amplitude, echo width, deviation (float32 each).
    bool echo_fields = false;
    // Then the photon-event fields: pixel (u32), event kind (u8), time of flight (f64, ns), for
    // array sensors and Geiger-mode detectors (docs/photon-counting.md §4).
    bool event_fields = false;
};

// What records add to the header: their count, counts by return and bounds (stored integers).
struct RecordStats {
    std::uint64_t count = 0;
    std::array<std::uint64_t, 15> by_return{};
    std::array<std::int32_t, 3> min{std::numeric_limits<std::int32_t>::max(),
                                    std::numeric_limits<std::int32_t>::max(),
                                    std::numeric_limits<std::int32_t>::max()};
    std::array<std::int32_t, 3> max{std::numeric_limits<std::int32_t>::min(),
                                    std::numeric_limits<std::int32_t>::min(),
                                    std::numeric_limits<std::int32_t>::min()};
    void merge(const RecordStats& o);
};

// Point records encoded ahead of writing (LasWriter::encode), with their statistics.
struct EncodedRecords {
    std::vector<std::uint8_t> bytes;  // whole records, in point order
    // Formats 4, 5, 9, 10: the packets the records refer to; their offsets count from the first
    // byte here until write_encoded() makes them the file's.
    std::vector<std::uint8_t> waves;
    RecordStats stats;           // of the records in `bytes`
    std::uint64_t rejected = 0;  // points not encodable (see LasWriter::points_rejected)
    std::uint64_t remapped = 0;  // formats 1/3: class > 31 written as 1
    // Empties it and keeps the capacity (a renderer reuses one per chunk).
    void clear() {
        bytes.clear();
        waves.clear();
        stats = {};
        rejected = remapped = 0;
    }
};

// LAS 1.4 writer (hand-written: Debian 12 packages no LAS library). Points arrive in the
// scene's local frame and are written as anchor + local, rounded (not truncated) to the scale,
// with offsets chosen from the anchor so georeferenced coordinates fit int32. Adds an OGC WKT
// CRS VLR (global encoding bit 4) when the georef has a CRS. GPS time is adjusted standard GPS
// time (bit 0). The header (counts, counts by return, bounds) is rewritten on close() and
// by finalize_for_signal(); on a write error (disk full) the file is cut to the last whole
// record, the header is made to match it, and IoError is thrown naming the file.
//
// Offsets: per axis floor(anchor / 1 km) · 1 km, so the stored integers of points within
// ±(2^31 · scale − 1 km) of the anchor fit (±2146 km at 1 mm). A point whose integer would not
// fit, or that is not finite, is not written and is counted in points_rejected().
// Formats 1/3 hold 5-bit classes: codes above 31 are written as 1 and counted.
// Formats 6/7 always carry global-encoding bit 4: the spec makes WKT the only CRS form for
// them and PDAL refuses such files without the bit, even when no CRS VLR follows.
// Formats 4, 5, 9, 10 store each pulse's recorded samples once, as a waveform data packet that
// its returns refer to (write_recorded); packets are streamed to <base>.wdp beside the file, and
// the header says they are external until close() copies them into the file's EVLR (unless
// options.waveform.external) and deletes the .wdp, so an interrupted file is valid with them
// external. A return whose pulse recorded no samples gets descriptor index 0 (no packet).
// Not thread-safe: one thread writes (encode() alone may run on any thread). Buffered
// (options.buffer_bytes) with pwrite(2); after each buffer flush, and after each
// write_encoded() chunk, the on-disk header is updated, so the file is valid between them.
class LasWriter {
  public:
    LasWriter(const std::string& path, const core::Georef& georef, LasWriterOptions opt = {});
    ~LasWriter();  // closes if still open; never throws
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;

    void write(std::span<const core::PointRecord> points);
    // Points with the samples their PointRecord::wave refers to (formats 4, 5, 9, 10; others
    // ignore the samples).
    void write_recorded(std::span<const core::PointRecord> points,
                        std::span<const std::uint32_t> samples);
    // Encodes points exactly as write() would and appends them to `out`, without writing.
    // Thread-safe (reads only the writer's fixed settings): render workers encode their points
    // in parallel, while they are still in cache, and the writing thread appends them in order
    // with write_encoded(). The two kinds of write may be mixed; order is kept.
    void encode(std::span<const core::PointRecord> points, EncodedRecords& out) const;
    void encode_recorded(std::span<const core::PointRecord> points,
                         std::span<const std::uint32_t> samples, EncodedRecords& out) const;
    void write_encoded(const EncodedRecords& records);
    void close();
    // Points accepted (flushed or buffered). After a write error: the whole records on disk.
    std::uint64_t points_written() const;
    std::uint64_t points_flushed() const;            // on disk, covered by the on-disk header
    std::uint64_t points_rejected() const;           // not finite or outside int32 after offset
    std::uint64_t classifications_remapped() const;  // formats 1/3: class > 31 written as 1
    const std::string& path() const;
    std::array<double, 3> offset() const;  // LAS offset per axis (world units)

    // Async-signal-safe finalisation (pwrite of the header only): registered writers are
    // finalised by install_signal_finalizer()'s handler on SIGINT/SIGTERM before exit.
    // Uses the header image of the last completed flush and cuts the file to match it.
    void finalize_for_signal() noexcept;

  private:
    struct Impl;
    Impl* impl_;
};

// Installs SIGINT/SIGTERM handlers that finalise every open LasWriter and then re-raise the
// signal with the default action (so the exit status reports it). Up to 64 writers are
// tracked at once; further writers still work but are not finalised by the handler.
// Idempotent. Replaces any handler installed before for these two signals.
void install_signal_finalizer();

}  // namespace mirage::las
