// SPDX-License-Identifier: Apache-2.0
// The reader's share of full-waveform files (docs/file-formats.md §6.1): packet descriptors, the
// waveform packet record (EVLR or .wdp), every point's packet checked against both, and Mirage's
// echo fields from the extra bytes.
#include <fmt/format.h>

#include <cmath>
#include <cstring>

#include "las_layout.hpp"
#include "mirage/las/las_reader.hpp"
#include "wdp_file.hpp"

namespace mirage::las {
namespace {

using namespace layout;

// The record's first EVLR header names a waveform packet record.
bool is_wave_evlr(const std::uint8_t* e) {
    return fixed_text(e + 2, 16) == "LASF_Spec" && get_u16(e + 18) == kWaveformPacketsRecordId;
}

}  // namespace

void LasFile::read_vlr(const std::uint8_t* v, const std::string& user, std::uint16_t id,
                       std::uint16_t len) {
    if (user != "LASF_Spec") return;
    const std::uint8_t* b = v + kVlrHeaderSize;
    if (id > 99 && id < 355) {
        if (len < kWaveDescriptorSize) {
            problems_.push_back(fmt::format("waveform packet descriptor {} is {} bytes (needs {})",
                                            id - 99, len, kWaveDescriptorSize));
            return;
        }
        header_.wave_descriptors.push_back({static_cast<std::uint8_t>(id - 99), b[0], b[1],
                                            get_u32(b + 2), get_u32(b + 6), get_f64(b + 10),
                                            get_f64(b + 18)});
    } else if (id == kExtraBytesRecordId) {
        for (std::size_t k = 0; k + kExtraBytesDescriptorSize <= len;
             k += kExtraBytesDescriptorSize) {
            header_.extra_bytes_types.push_back(b[k + 2]);
            header_.extra_bytes_names.push_back(fixed_text(b + k + 4, 32));
        }
    }
}

const WaveDescriptorInfo* LasFile::descriptor(std::uint8_t index) const {
    for (const auto& d : header_.wave_descriptors)
        if (d.index == index) return &d;
    return nullptr;
}

// The waveform packet record (EVLR header first) and Mirage's echo fields.
void LasFile::load_waves(const std::vector<std::uint8_t>& bytes,
                         const std::vector<std::uint8_t>* wdp) {
    const LasHeaderInfo& h = header_;
    const auto& names = h.extra_bytes_names;
    const bool echo = names.size() >= 3 && names[0] == "amplitude" && names[1] == "echo width" &&
                      names[2] == "deviation" && h.extra_bytes_types[0] == 9 &&
                      h.extra_bytes_types[1] == 9 && h.extra_bytes_types[2] == 9;
    const std::size_t ev = echo ? 3 : 0;  // where the event fields' descriptors start
    const bool events = names.size() >= ev + 3 && names[ev] == "pixel" &&
                        names[ev + 1] == "event" && names[ev + 2] == "time of flight" &&
                        h.extra_bytes_types[ev] == 5 && h.extra_bytes_types[ev + 1] == 1 &&
                        h.extra_bytes_types[ev + 2] == 10;
    const std::size_t base =
        h.point_format < kRecordLengths.size() ? kRecordLengths[h.point_format] : 0;
    if (events && base > 0 && h.record_length >= base + (echo ? 12 : 0) + 13) {
        for (std::size_t k = 0; k < points_.size(); ++k) {
            const std::uint8_t* e =
                bytes.data() + h.offset_to_points + k * h.record_length + base + (echo ? 12 : 0);
            points_[k].pixel = get_u32(e);
            points_[k].event = e[4];
            points_[k].time_of_flight_ns = get_f64(e + 5);
        }
    }
    if (echo && h.point_format < kRecordLengths.size() &&
        h.record_length >= kRecordLengths[h.point_format] + 12) {
        for (std::size_t k = 0; k < points_.size(); ++k) {
            const std::uint8_t* e = bytes.data() + h.offset_to_points + k * h.record_length +
                                    kRecordLengths[h.point_format];
            points_[k].amplitude = get_f32(e);
            points_[k].echo_width_ns = get_f32(e + 4);
            points_[k].deviation = get_f32(e + 8);
        }
    }
    if (wave_fields_at(h.point_format) == 0) return;
    if (h.global_encoding & kGlobalEncodingWaveExternal) {
        if (wdp) waves_ = *wdp;
        return;
    }
    const std::uint64_t at = h.start_of_waveform;
    if (at == 0 || at > bytes.size() || bytes.size() - at < 60) return;
    const std::uint64_t length = get_u64(bytes.data() + at + 20);
    const std::uint64_t room = bytes.size() - at - 60;
    waves_.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                  bytes.begin() + static_cast<std::ptrdiff_t>(at + 60 + std::min(length, room)));
}

// LAS 1.4 §2.4, §2.6, §4 and §5 on waveform packets: one place (internal xor external), a
// packet record with its EVLR header, a descriptor for every index used, and each point's packet
// inside the record, of the descriptor's size, with its return inside the packet's time span.
void LasFile::check_waves() {
    const LasHeaderInfo& h = header_;
    if (wave_fields_at(h.point_format) == 0) return;
    auto problem = [this](std::string s) { problems_.push_back(std::move(s)); };
    const bool internal = h.global_encoding & kGlobalEncodingWaveInternal;
    const bool external = h.global_encoding & kGlobalEncodingWaveExternal;
    if (internal == external)
        problem("point format " + std::to_string(h.point_format) +
                ": global encoding must set exactly one of bits 1 (waveforms internal) and 2 "
                "(external)");
    if (internal && h.start_of_waveform == 0)
        problem("waveforms internal but the start of the waveform data packet record is 0");
    if (external && h.start_of_waveform != 0)
        problem("waveforms external but the start of the waveform data packet record is not 0");
    if ((internal || external) && (waves_.size() < 60 || !is_wave_evlr(waves_.data()))) {
        problem("no waveform data packet record (EVLR LASF_Spec 65535) where the header says");
        return;
    }
    if (!internal && !external) return;
    if (get_u64(waves_.data() + 20) != waves_.size() - 60)
        problem(fmt::format("waveform data packet record says {} bytes, {} are present",
                            get_u64(waves_.data() + 20), waves_.size() - 60));
    std::uint64_t bad = 0;
    std::string first;
    for (std::size_t k = 0; k < points_.size(); ++k) {
        const LasPoint& p = points_[k];
        if (p.wave_index == 0) continue;
        const WaveDescriptorInfo* d = descriptor(p.wave_index);
        std::string why;
        if (!d)
            why = fmt::format("descriptor {} missing", p.wave_index);
        else if (d->bits != 8 && d->bits != 16 && d->bits != 32)
            why = fmt::format("{} bits per sample (this reader: 8, 16, 32)", d->bits);
        else if (d->compression != 0)
            why = "compressed";
        else if (p.wave_size != std::uint64_t{d->samples} * (d->bits / 8u))
            why = fmt::format("packet of {} bytes, descriptor says {}", p.wave_size,
                              std::uint64_t{d->samples} * (d->bits / 8u));
        else if (p.wave_offset < 60 || p.wave_offset > waves_.size() ||
                 waves_.size() - p.wave_offset < p.wave_size)
            why = fmt::format("packet at {} (+{}) outside the record's {} bytes", p.wave_offset,
                              p.wave_size, waves_.size());
        else if (!(p.wave_location_ps >= 0.0f) ||
                 p.wave_location_ps > double(d->samples - 1) * d->spacing_ps)
            why = fmt::format("return at {} ps outside the packet's {} ps", p.wave_location_ps,
                              double(d->samples - 1) * d->spacing_ps);
        if (why.empty()) continue;
        if (bad++ == 0) first = fmt::format("point {}: {}", k, why);
    }
    if (bad > 0)
        problem(fmt::format("{} points have invalid waveform packets (first: {})", bad, first));
}

std::vector<std::uint32_t> LasFile::waveform(const LasPoint& p) const {
    std::vector<std::uint32_t> out;
    const WaveDescriptorInfo* d = p.wave_index ? descriptor(p.wave_index) : nullptr;
    if (!d || (d->bits != 8 && d->bits != 16 && d->bits != 32) || d->compression != 0) return out;
    const std::uint64_t size = std::uint64_t{d->samples} * (d->bits / 8u);
    if (p.wave_size != size || p.wave_offset < 60 || p.wave_offset > waves_.size() ||
        waves_.size() - p.wave_offset < size)
        return out;
    const std::uint8_t* s = waves_.data() + p.wave_offset;
    out.resize(d->samples);
    for (std::uint32_t i = 0; i < d->samples; ++i)
        out[i] = d->bits == 8 ? s[i] : d->bits == 16 ? get_u16(s + 2 * i) : get_u32(s + 4 * i);
    return out;
}

}  // namespace mirage::las
