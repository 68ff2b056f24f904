// SPDX-License-Identifier: Apache-2.0
#include "mirage/las/las_writer.hpp"

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <vector>

#include "las_layout.hpp"
#include "las_vlrs.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/output_file.hpp"
#include "mirage/core/rounding.hpp"
#include "mirage/core/time.hpp"
#include "signal_registry.hpp"
#include "wdp_file.hpp"

namespace mirage::las {
namespace {

using namespace layout;

// Red, green, blue u16 at `at` (formats 3 and 7 differ only in where they start).
void put_rgb(std::uint8_t* at, const core::PointRecord& p) {
    put_u16(at, p.red);
    put_u16(at + 2, p.green);
    put_u16(at + 4, p.blue);
}

constexpr double kOffsetGrid_m = 1000.0;

// Full positional write; returns the bytes written and sets err on failure. Signal-safe.
std::size_t pwrite_all(int fd, const std::uint8_t* data, std::size_t n, off_t pos,
                       int& err) noexcept {
    std::size_t done = 0;
    err = 0;
    while (done < n) {
        const ssize_t w = ::pwrite(fd, data + done, n - done, pos + static_cast<off_t>(done));
        if (w < 0) {
            if (errno == EINTR) continue;
            err = errno;
            break;
        }
        if (w == 0) {
            err = EIO;
            break;
        }
        done += static_cast<std::size_t>(w);
    }
    return done;
}

}  // namespace

void RecordStats::merge(const RecordStats& o) {
    count += o.count;
    for (std::size_t i = 0; i < by_return.size(); ++i) by_return[i] += o.by_return[i];
    for (std::size_t a = 0; a < 3; ++a) {
        min[a] = std::min(min[a], o.min[a]);
        max[a] = std::max(max[a], o.max[a]);
    }
}

struct LasWriter::Impl {
    struct Snapshot {
        std::array<std::uint8_t, kHeaderSize14> header{};
        off_t size = 0;
    };

    std::string path;
    LasWriterOptions opt;
    std::atomic<int> fd{-1};  // read by the signal handler, possibly on another thread
    bool registered = false;
    std::uint16_t record_length = 0;
    std::uint16_t base_length = 0;  // the format's own fields; echo fields follow
    std::size_t wave_at = 0;        // offset of the wave packet fields, 0: none
    std::uint32_t packet_bytes = 0;
    std::unique_ptr<WdpFile> wdp;  // formats 4, 5, 9, 10
    std::uint64_t evlr_bytes = 0;  // after the points, once close() has copied the packets
    std::uint8_t return_mask = 0;
    std::uint32_t data_offset = 0;
    std::array<double, 3> offset{};
    std::array<double, 3> shift{};  // anchor − offset: small, exact, added before dividing
    std::array<std::uint8_t, kHeaderSize14> header_template{};
    std::vector<std::uint8_t> buffer;
    std::size_t used = 0;
    RecordStats flushed;
    std::uint64_t buffered_points = 0, rejected = 0, remapped = 0;
    // Double-buffered header images: the signal handler reads the published one while the
    // writer prepares the other, so it always sees a complete header matching `size`.
    std::array<Snapshot, 2> snapshots{};
    std::atomic<int> published{0};

    std::string prefix() const { return "las writer '" + path + "': "; }

    void open(const std::string& p, const core::Georef& georef, LasWriterOptions o);
    bool quantise(double local, int axis, std::int32_t& out) const noexcept;
    void check_format() const;
    std::vector<std::uint8_t> vlrs(const core::Georef& georef) const;
    bool encode(const core::PointRecord& p, std::uint8_t* r,
                std::uint64_t& remapped_count) const noexcept;
    void put_wave(const core::PointRecord& p, std::uint8_t* r, bool packet,
                  std::uint64_t offset) const noexcept;
    void put_packet(std::span<const std::uint32_t> samples, std::vector<std::uint8_t>& out) const;
    void append_waves(const EncodedRecords& records, std::vector<std::uint8_t>& rebased);
    void embed_waves();
    void accumulate(const std::uint8_t* records, std::size_t n) noexcept;
    void tally(const std::uint8_t* record, RecordStats& s) const noexcept;
    void append(const std::uint8_t* records, std::size_t bytes, const RecordStats* stats);
    void build_header(const RecordStats& s, std::uint8_t* out) const noexcept;
    void publish() noexcept;
    void flush();
    [[noreturn]] void fail(int err);
    void release() noexcept;
};

void LasWriter::Impl::open(const std::string& p, const core::Georef& georef, LasWriterOptions o) {
    path = p;
    opt = std::move(o);
    check_format();
    const std::uint8_t f = opt.point_format;
    base_length = kRecordLengths[f];
    record_length =
        static_cast<std::uint16_t>(base_length + (opt.echo_fields ? kEchoExtraBytes : 0) +
                                   (opt.event_fields ? kEventExtraBytes : 0));
    wave_at = wave_fields_at(f);
    packet_bytes = opt.waveform.samples * (opt.waveform.bits / 8u);
    return_mask = f < 6 ? 0x07 : 0x0F;
    for (int a = 0; a < 3; ++a) {
        const double anchor = georef.anchor()[a];
        if (!std::isfinite(anchor)) throw ConfigError(prefix() + "anchor is not finite");
        offset[a] = std::floor(anchor / kOffsetGrid_m) * kOffsetGrid_m;
        shift[a] = anchor - offset[a];
    }
    const std::vector<std::uint8_t> vlr = vlrs(georef);
    data_offset = static_cast<std::uint32_t>(kHeaderSize14 + vlr.size());

    std::uint16_t encoding = kGlobalEncodingAdjustedGps;
    if (georef.has_crs() || f >= 6) encoding |= kGlobalEncodingWkt;
    if (wave_at) encoding |= kGlobalEncodingWaveExternal;  // until close() embeds the packets
    std::uint8_t* h = header_template.data();
    std::memcpy(h + kSignature, "LASF", 4);
    put_u16(h + kFileSourceId, opt.file_source_id);
    put_u16(h + kGlobalEncoding, encoding);
    put_u8(h + kVersionMajor, 1);
    put_u8(h + kVersionMinor, 4);
    put_text(h + kSystemIdentifier, 32, opt.system_identifier);
    put_text(h + kGeneratingSoftware, 32, opt.generating_software);
    put_u16(h + kCreationDay, opt.creation_day);
    put_u16(h + kCreationYear, opt.creation_year);
    put_u16(h + kHeaderSize, static_cast<std::uint16_t>(kHeaderSize14));
    put_u32(h + kOffsetToPoints, data_offset);
    put_u32(h + kVlrCount, static_cast<std::uint32_t>(georef.has_crs()) +
                               static_cast<std::uint32_t>(wave_at != 0) +
                               static_cast<std::uint32_t>(opt.echo_fields || opt.event_fields));
    put_u8(h + kPointFormat, f);
    put_u16(h + kRecordLength, record_length);
    for (int a = 0; a < 3; ++a) {
        put_f64(h + kScale + 8 * a, opt.scale);
        put_f64(h + kOffset + 8 * a, offset[a]);
    }

    const std::size_t records = std::max<std::size_t>(1, opt.buffer_bytes / record_length);
    buffer.assign(records * record_length, 0);

    fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(prefix() + "cannot create: " + std::strerror(errno));
    publish();
    const auto& snap = snapshots[published.load(std::memory_order_relaxed)];
    std::vector<std::uint8_t> head(snap.header.begin(), snap.header.end());
    head.insert(head.end(), vlr.begin(), vlr.end());
    int err = 0;
    pwrite_all(fd, head.data(), head.size(), 0, err);
    if (err == 0 && wave_at) {
        try {
            wdp = std::make_unique<WdpFile>(path);
        } catch (const IoError&) {
            ::close(fd);
            fd = -1;
            core::remove_failed_output(path);
            throw;
        }
    }
    if (err != 0) {
        ::close(fd);
        fd = -1;
        core::remove_failed_output(path);
        throw IoError(prefix() + "cannot write header: " + std::strerror(err));
    }
}

void LasWriter::Impl::check_format() const {
    const std::uint8_t f = opt.point_format;
    if (f == 0 || f == 2 || f == 8 || f > 10) {
        throw ConfigError(prefix() + "point format " + std::to_string(f) +
                          " not supported (1, 3, 6, 7; with waveforms 4, 5, 9, 10)");
    }
    if (!(opt.scale > 0.0) || !std::isfinite(opt.scale)) {
        throw ConfigError(prefix() + "scale must be a positive number");
    }
    if (wave_fields_at(f) == 0) return;
    const WaveformPackets& w = opt.waveform;
    if (w.bits != 8 && w.bits != 16 && w.bits != 32)
        throw ConfigError(prefix() + "waveform bits per sample must be 8, 16 or 32");
    if (w.samples == 0 || w.samples > (1u << 24))
        throw ConfigError(prefix() + "waveform samples per packet must be 1 to 2^24");
    if (w.spacing_ps == 0) throw ConfigError(prefix() + "waveform sample spacing must be > 0 ps");
    if (!std::isfinite(w.gain) || !std::isfinite(w.offset))
        throw ConfigError(prefix() + "waveform gain and offset must be finite");
}

// The VLRs after the header: CRS, waveform packet descriptor, extra bytes (each if used).
std::vector<std::uint8_t> LasWriter::Impl::vlrs(const core::Georef& georef) const {
    std::vector<std::uint8_t> v;
    if (georef.has_crs()) {
        const std::string wkt = georef.wkt();
        if (wkt.empty())
            throw ConfigError(prefix() + "no WKT for EPSG " + std::to_string(georef.epsg()));
        v = wkt_vlr(wkt, prefix());
    }
    if (wave_at) {
        const auto d = waveform_descriptor_vlr(opt.waveform);
        v.insert(v.end(), d.begin(), d.end());
    }
    if (opt.echo_fields || opt.event_fields) {
        const auto e = extra_bytes_vlr(opt.echo_fields, opt.event_fields);
        v.insert(v.end(), e.begin(), e.end());
    }
    return v;
}

// Round to nearest (docs/physics.md §3.3: truncation biases by up to a whole step) and refuse
// anything that would not fit int32, including NaN.
bool LasWriter::Impl::quantise(double local, int axis, std::int32_t& out) const noexcept {
    const double q = (shift[axis] + local) / opt.scale;
    if (!(q > -2147483648.5 && q < 2147483647.5)) return false;
    out = static_cast<std::int32_t>(core::round_half_away(q));
    return true;
}

bool LasWriter::Impl::encode(const core::PointRecord& p, std::uint8_t* r,
                             std::uint64_t& remapped_count) const noexcept {
    std::int32_t x, y, z;
    if (!quantise(p.x, 0, x) || !quantise(p.y, 1, y) || !quantise(p.z, 2, z)) return false;
    put_i32(r + 0, x);
    put_i32(r + 4, y);
    put_i32(r + 8, z);
    put_u16(r + 12, p.intensity);
    const double gps = core::adjusted_standard_gps_seconds(p.t);
    const auto flag = [](std::uint8_t v) { return static_cast<unsigned>(v != 0); };
    const double angle = std::isfinite(p.scan_angle_deg) ? p.scan_angle_deg : 0.0;
    if (opt.point_format < 6) {
        // Table 8: return number 3 bits, number of returns 3 bits, scan direction, edge.
        const unsigned rn = std::clamp<unsigned>(p.return_number, 1, 7);
        const unsigned nr = std::clamp<unsigned>(p.number_of_returns, 1, 7);
        r[14] = static_cast<std::uint8_t>(rn | nr << 3 | flag(p.scan_direction) << 6 |
                                          flag(p.edge_of_flight_line) << 7);
        std::uint8_t cls = p.classification;
        if (cls > 31) {  // 5-bit field; the upper bits are synthetic/key-point/withheld flags
            cls = 1;
            ++remapped_count;
        }
        r[15] = cls;
        r[16] = static_cast<std::uint8_t>(
            static_cast<std::int8_t>(core::round_half_away(std::clamp(angle, -90.0, 90.0))));
        r[17] = 0;
        put_u16(r + 18, p.point_source_id);
        put_f64(r + 20, gps);
        if (opt.point_format == 3 || opt.point_format == 5) put_rgb(r + 28, p);
    } else {
        // Table 13: return number 4 bits, number of returns 4 bits; then classification
        // flags (4), scanner channel (2, scanner head: always 0 here), scan direction, edge.
        const unsigned rn = std::clamp<unsigned>(p.return_number, 1, 15);
        const unsigned nr = std::clamp<unsigned>(p.number_of_returns, 1, 15);
        r[14] = static_cast<std::uint8_t>(rn | nr << 4);
        r[15] = static_cast<std::uint8_t>(flag(p.scan_direction) << 6 | flag(p.edge_of_flight_line)
                                                                            << 7);
        r[16] = p.classification;
        r[17] = 0;
        const double units = std::clamp(angle / kScanAngleUnit_deg, -30000.0, 30000.0);
        put_i16(r + 18, static_cast<std::int16_t>(core::round_half_away(units)));
        put_u16(r + 20, p.point_source_id);
        put_f64(r + 22, gps);
        if (opt.point_format == 7 || opt.point_format == 10) put_rgb(r + 30, p);
        if (opt.point_format == 10) put_u16(r + 36, 0);  // NIR: not simulated
    }
    if (opt.echo_fields) {
        put_f32(r + base_length, p.amplitude);
        put_f32(r + base_length + 4, p.echo_width_ns);
        put_f32(r + base_length + 8, p.deviation);
    }
    if (opt.event_fields) {
        constexpr double kNsPerMeterTwoWay = 2e9 / 299'792'458.0;
        std::uint8_t* e = r + base_length + (opt.echo_fields ? kEchoExtraBytes : 0);
        put_u32(e, p.pixel);
        put_u8(e + 4, p.event);
        put_f64(e + 5, double(p.range_m) * kNsPerMeterTwoWay);
    }
    return true;
}

// The wave packet fields (formats 4, 5, 9, 10). The parametric line points back along the beam,
// c/2 per ps, so the packet's first sample lies at the point + location · (dx, dy, dz) and
// sample i at that − i·spacing·(dx, dy, dz) (docs/file-formats.md §6.1).
void LasWriter::Impl::put_wave(const core::PointRecord& p, std::uint8_t* r, bool packet,
                               std::uint64_t at) const noexcept {
    std::uint8_t* w = r + wave_at;
    if (!packet) {
        std::memset(w, 0, kWavePacketFieldsSize);
        return;
    }
    constexpr double kMetersPerPs = 0.5 * 299'792'458.0 * 1e-12;
    put_u8(w, 1);
    put_u64(w + 1, at);
    put_u32(w + 9, packet_bytes);
    put_f32(w + 13, p.wave_location_ps);
    put_f32(w + 17, static_cast<float>(-p.beam_dx * kMetersPerPs));
    put_f32(w + 21, static_cast<float>(-p.beam_dy * kMetersPerPs));
    put_f32(w + 25, static_cast<float>(-p.beam_dz * kMetersPerPs));
}

// One packet: the samples at the descriptor's width, little-endian, saturating.
void LasWriter::Impl::put_packet(std::span<const std::uint32_t> samples,
                                 std::vector<std::uint8_t>& out) const {
    const std::size_t at = out.size();
    out.resize(at + packet_bytes);
    std::uint8_t* o = out.data() + at;
    switch (opt.waveform.bits) {
        case 8:
            for (const std::uint32_t v : samples)
                *o++ = static_cast<std::uint8_t>(std::min(v, 255u));
            break;
        case 16:
            for (const std::uint32_t v : samples) {
                put_u16(o, static_cast<std::uint16_t>(std::min(v, 65535u)));
                o += 2;
            }
            break;
        default:
            for (const std::uint32_t v : samples) {
                put_u32(o, v);
                o += 4;
            }
    }
}

// Statistics from the encoded bytes, so a partial write accounts exactly for what hit disk.
void LasWriter::Impl::accumulate(const std::uint8_t* records, std::size_t n) noexcept {
    for (std::size_t k = 0; k < n; ++k) tally(records + k * record_length, flushed);
}

// One encoded record's share of the header: count, count by return, bounds.
void LasWriter::Impl::tally(const std::uint8_t* r, RecordStats& s) const noexcept {
    for (std::size_t a = 0; a < 3; ++a) {
        const std::int32_t v = get_i32(r + 4 * a);
        s.min[a] = std::min(s.min[a], v);
        s.max[a] = std::max(s.max[a], v);
    }
    ++s.by_return[(r[14] & return_mask) - 1u];
    ++s.count;
}

void LasWriter::Impl::build_header(const RecordStats& s, std::uint8_t* out) const noexcept {
    std::memcpy(out, header_template.data(), kHeaderSize14);
    // Formats 0–5 must also fill the legacy fields when the count fits; 6–10 leave them 0.
    const bool legacy =
        opt.point_format < 6 && s.count <= std::numeric_limits<std::uint32_t>::max();
    put_u32(out + kLegacyPointCount, legacy ? static_cast<std::uint32_t>(s.count) : 0u);
    for (int i = 0; i < 5; ++i) {
        put_u32(out + kLegacyByReturn + 4 * i,
                legacy ? static_cast<std::uint32_t>(s.by_return[i]) : 0u);
    }
    for (int a = 0; a < 3; ++a) {
        const double hi = s.count ? offset[a] + s.max[a] * opt.scale : 0.0;
        const double lo = s.count ? offset[a] + s.min[a] * opt.scale : 0.0;
        put_f64(out + kMaxX + 16 * a, hi);
        put_f64(out + kMaxX + 16 * a + 8, lo);
    }
    put_u64(out + kPointCount, s.count);
    for (int i = 0; i < 15; ++i) put_u64(out + kByReturn + 8 * i, s.by_return[i]);
}

void LasWriter::Impl::publish() noexcept {
    const int next = 1 - published.load(std::memory_order_relaxed);
    build_header(flushed, snapshots[next].header.data());
    snapshots[next].size =
        static_cast<off_t>(data_offset + flushed.count * std::uint64_t{record_length} + evlr_bytes);
    published.store(next, std::memory_order_release);
}

// Writes whole records after those on disk and then the header that covers them. `stats`, when
// given, are the records' own (computed by encode on another thread); after a short write the
// statistics come from the bytes that reached the disk.
void LasWriter::Impl::append(const std::uint8_t* records, std::size_t bytes,
                             const RecordStats* stats) {
    const off_t end = static_cast<off_t>(data_offset + flushed.count * record_length);
    int err = 0;
    const std::size_t done = pwrite_all(fd, records, bytes, end, err);
    if (stats && done == bytes) {
        flushed.merge(*stats);
    } else {
        accumulate(records, done / record_length);
    }
    if (err != 0) fail(err);
    publish();
    const auto& snap = snapshots[published.load(std::memory_order_relaxed)];
    pwrite_all(fd, snap.header.data(), snap.header.size(), 0, err);
    if (err != 0) fail(err);
}

void LasWriter::Impl::flush() {
    if (used == 0) return;
    const std::size_t n = used;
    used = 0;
    buffered_points = 0;
    append(buffer.data(), n, nullptr);
}

// The whole records that reached the disk are already in `flushed`: cut the file after them,
// make the header match, close, and report.
void LasWriter::Impl::fail(int err) {
    used = 0;
    buffered_points = 0;
    publish();
    const auto& snap = snapshots[published.load(std::memory_order_relaxed)];
    int repair_err = ::ftruncate(fd, snap.size) == 0 ? 0 : errno;
    int header_err = 0;
    pwrite_all(fd, snap.header.data(), snap.header.size(), 0, header_err);
    if (repair_err == 0) repair_err = header_err;
    const std::string n = std::to_string(flushed.count);
    std::string msg = prefix() + std::strerror(err) + " after " + n + " points; file cut to " + n +
                      " whole records";
    if (repair_err != 0) msg += std::string(" (repair failed: ") + std::strerror(repair_err) + ")";
    release();
    throw IoError(msg);
}

void LasWriter::Impl::release() noexcept {
    const int old = fd;
    fd = -1;  // first, so a signal arriving now finds nothing to finalise
    if (old >= 0) ::close(old);
}

LasWriter::LasWriter(const std::string& path, const core::Georef& georef, LasWriterOptions opt)
    : impl_(new Impl) {
    try {
        impl_->open(path, georef, std::move(opt));
    } catch (...) {
        delete impl_;
        throw;
    }
    impl_->registered = detail::register_writer(this);
}

LasWriter::~LasWriter() {
    try {
        close();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
    }
    if (impl_->registered) detail::unregister_writer(this);
    delete impl_;
}

void LasWriter::write(std::span<const core::PointRecord> points) {
    Impl& im = *impl_;
    if (im.fd < 0) throw IoError(im.prefix() + "write after close or after a write error");
    if (im.wave_at) {  // records refer to packets: written with them, through write_encoded
        write_recorded(points, {});
        return;
    }
    const std::size_t len = im.record_length;
    for (const core::PointRecord& p : points) {
        if (im.used + len > im.buffer.size()) im.flush();
        if (im.encode(p, im.buffer.data() + im.used, im.remapped)) {
            im.used += len;
            ++im.buffered_points;
        } else {
            ++im.rejected;
        }
    }
}

void LasWriter::write_recorded(std::span<const core::PointRecord> points,
                               std::span<const std::uint32_t> samples) {
    Impl& im = *impl_;
    if (!im.wave_at) {
        write(points);
        return;
    }
    EncodedRecords chunk;
    encode_recorded(points, samples, chunk);
    write_encoded(chunk);
}

void LasWriter::encode(std::span<const core::PointRecord> points, EncodedRecords& out) const {
    encode_recorded(points, {}, out);
}

// A pulse's returns follow each other and share one window of samples: its packet is stored
// once, for the first of them.
void LasWriter::encode_recorded(std::span<const core::PointRecord> points,
                                std::span<const std::uint32_t> samples, EncodedRecords& out) const {
    const Impl& im = *impl_;
    const std::size_t len = im.record_length;
    const std::size_t n = im.opt.waveform.samples;
    const std::size_t at = out.bytes.size();
    out.bytes.resize(at + points.size() * len);
    std::uint8_t* r = out.bytes.data() + at;
    std::uint32_t last_wave = core::PointRecord::kNoWave;
    std::uint64_t last_at = 0;
    for (const core::PointRecord& p : points) {
        if (!im.encode(p, r, out.remapped)) {
            ++out.rejected;
            continue;
        }
        if (im.wave_at) {
            const bool packet =
                p.wave != core::PointRecord::kNoWave && std::size_t{p.wave} + n <= samples.size();
            if (packet && p.wave != last_wave) {
                last_wave = p.wave;
                last_at = out.waves.size();
                im.put_packet(samples.subspan(p.wave, n), out.waves);
            }
            im.put_wave(p, r, packet, last_at);
        }
        im.tally(r, out.stats);
        r += len;
    }
    out.bytes.resize(static_cast<std::size_t>(r - out.bytes.data()));
}

void LasWriter::write_encoded(const EncodedRecords& records) {
    Impl& im = *impl_;
    if (im.fd < 0) throw IoError(im.prefix() + "write after close or after a write error");
    if (records.bytes.size() != records.stats.count * im.record_length)
        throw IoError(im.prefix() + "encoded records of another length");  // another writer's
    im.rejected += records.rejected;
    im.remapped += records.remapped;
    if (records.stats.count == 0) return;
    im.flush();  // what write() buffered comes first
    if (!im.wave_at) {
        im.append(records.bytes.data(), records.bytes.size(), &records.stats);
        return;
    }
    std::vector<std::uint8_t> rebased;
    im.append_waves(records, rebased);
    im.append(rebased.data(), rebased.size(), &records.stats);
}

// The chunk's packets to the .wdp (before the records that refer to them, so every record on
// disk has its packet), and the records with their offsets made the file's.
void LasWriter::Impl::append_waves(const EncodedRecords& records,
                                   std::vector<std::uint8_t>& rebased) {
    const std::uint64_t base = wdp->end();
    if (const int err = wdp->append(records.waves.data(), records.waves.size()); err != 0)
        fail(err);
    rebased = records.bytes;
    for (std::size_t k = 0; k < rebased.size(); k += record_length) {
        std::uint8_t* w = rebased.data() + k + wave_at;
        if (w[0] != 0) put_u64(w + 1, get_u64(w + 1) + base);
    }
}

// close() of an internal-waveform file: the .wdp becomes the file's one EVLR, the header says
// so, and the .wdp goes. On a write error the file is cut back to its points and keeps its
// packets external (still valid), and IoError says where they are.
void LasWriter::Impl::embed_waves() {
    const std::uint64_t start = data_offset + flushed.count * std::uint64_t{record_length};
    if (const int err = wdp->copy_to(fd, static_cast<off_t>(start)); err != 0) {
        const int cut = ::ftruncate(fd, static_cast<off_t>(start));
        (void)cut;
        throw IoError(prefix() + "cannot copy the waveform packets into the file (" +
                      std::strerror(err) + "); they stay in '" + wdp->path() +
                      "' and the file refers to it");
    }
    std::uint8_t* h = header_template.data();
    put_u16(h + kGlobalEncoding, static_cast<std::uint16_t>(
                                     (get_u16(h + kGlobalEncoding) & ~kGlobalEncodingWaveExternal) |
                                     kGlobalEncodingWaveInternal));
    put_u64(h + kWaveformStart, start);
    put_u64(h + kFirstEvlr, start);
    put_u32(h + kEvlrCount, 1);
    evlr_bytes = wdp->end();
    publish();
    const auto& snap = snapshots[published.load(std::memory_order_relaxed)];
    int err = 0;
    pwrite_all(fd, snap.header.data(), snap.header.size(), 0, err);
    if (err != 0) throw IoError(prefix() + "cannot write header: " + std::strerror(err));
    wdp->remove();
}

void LasWriter::close() {
    Impl& im = *impl_;
    if (im.fd < 0) return;
    im.flush();  // rewrites the header for everything on disk
    if (im.wdp && !im.opt.waveform.external) im.embed_waves();
    // Unregister before closing the descriptor so the handler never touches a closed fd.
    if (im.registered) {
        detail::unregister_writer(this);
        im.registered = false;
    }
    const int fd = im.fd;
    im.fd = -1;
    if (::close(fd) != 0) throw IoError(im.prefix() + "close: " + std::strerror(errno));
}

std::uint64_t LasWriter::points_written() const {
    return impl_->flushed.count + impl_->buffered_points;
}
std::uint64_t LasWriter::points_flushed() const { return impl_->flushed.count; }
std::uint64_t LasWriter::points_rejected() const { return impl_->rejected; }
std::uint64_t LasWriter::classifications_remapped() const { return impl_->remapped; }
const std::string& LasWriter::path() const { return impl_->path; }
std::array<double, 3> LasWriter::offset() const { return impl_->offset; }

void LasWriter::finalize_for_signal() noexcept {
    const Impl& im = *impl_;
    const int fd = im.fd;
    if (fd < 0) return;
    const auto& snap = im.snapshots[im.published.load(std::memory_order_acquire)];
    int err = 0;
    pwrite_all(fd, snap.header.data(), snap.header.size(), 0, err);
    // Drops a partly written buffer beyond the last published flush.
    const int cut = ::ftruncate(fd, snap.size);
    (void)cut;
}

}  // namespace mirage::las
