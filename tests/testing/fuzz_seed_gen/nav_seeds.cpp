// SPDX-License-Identifier: Apache-2.0
// Seeds of the navigation targets, from Mirage's own encoders: NMEA sentences, NovAtel logs, NCOM
// packets, OxTS and SBG CAN frames (as records, candump lines and slcan lines), gs_usb frames and
// navigation logs of each protocol.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_can_record.hpp"
#include "gsusb_protocol.hpp"
#include "mirage/navcan/candump.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"
#include "mirage/navcan/slcan.hpp"
#include "mirage/ncom/encoder.hpp"
#include "mirage/nmea/nmea_encoder.hpp"
#include "mirage/novatel/encoder.hpp"
#include "seed_writer.hpp"

namespace mirage::testing::seeds {
namespace {

using Bytes = std::vector<std::uint8_t>;
using nav::Protocol;

constexpr std::uint32_t kAllSentences =
    nmea::kGga | nmea::kRmc | nmea::kVtg | nmea::kHdt | nmea::kZda | nmea::kPashr | nmea::kPtnlAvr;

template <class T>
void append(std::vector<T>& a, const auto& b) {
    a.insert(a.end(), b.begin(), b.end());
}

std::string nmea_text(int samples, std::uint32_t which) {
    std::string text;
    for (int k = 0; k < samples; ++k)
        text += nmea::encode_epoch(drive_sample(k, Protocol::Nmea), which);
    return text;
}

Bytes novatel_bytes(int samples) {
    novatel::NovatelEncoder enc;
    Bytes b;
    for (int k = 0; k < samples; ++k) {
        const auto s = drive_sample(k, Protocol::Novatel);
        append(b, enc.bestpos(s));
        append(b, enc.inspvax(s));
        append(b, enc.inspvas(s));
    }
    return b;
}

Bytes ncom_bytes(int samples) {
    // Channels given as a vector built here: g++ 12 reports a false maybe-uninitialized on
    // the default member's initializer list once this is inlined.
    static const std::uint8_t channels[] = {0, 1, 2};
    ncom::EncoderOptions options;
    options.channels.assign(std::begin(channels), std::end(channels));
    ncom::NcomEncoder enc(options);
    Bytes b;
    for (int k = 0; k < samples; ++k) append(b, enc.encode(drive_sample(k, Protocol::Ncom)));
    return b;
}

// Stamped frames of `samples` epochs: one group per epoch, its frames 0.1 ms apart.
std::vector<nav::StampedCanFrame> can_frames(bool oxts, int samples, bool extended = false) {
    std::vector<nav::StampedCanFrame> out;
    navcan::SbgCanEncoderConfig sbg;
    sbg.ids.extended = extended;
    navcan::OxtsCanIds ids;
    ids.extended = extended;
    for (int k = 0; k < samples; ++k) {
        const auto s = drive_sample(k, oxts ? Protocol::OxtsCan : Protocol::SbgCan);
        std::vector<nav::CanFrame> frames;
        if (oxts) {
            frames = navcan::oxts_can_encode(s, ids);
        } else {
            frames = navcan::sbg_can_encode_utc(s.t, sbg);
            append(frames, navcan::sbg_can_encode(s, sbg));
        }
        const std::int64_t t0 = core::unix_ns_from_gps(s.t);
        for (std::size_t i = 0; i < frames.size(); ++i)
            out.push_back({t0 + static_cast<std::int64_t>(i) * 100'000, frames[i]});
    }
    return out;
}

Bytes can_records(const std::vector<nav::StampedCanFrame>& frames) {
    Bytes b;
    std::int64_t last = frames.empty() ? 0 : frames.front().time_ns;
    for (const auto& f : frames) {
        navcan::test::append_record(b, f.frame,
                                    static_cast<std::uint8_t>((f.time_ns - last) / 1'000'000));
        last = f.time_ns;
    }
    return b;
}

std::string candump_text(const std::vector<nav::StampedCanFrame>& frames) {
    std::string text;
    for (const auto& f : frames)
        text += navcan::format_candump_line(f.time_ns, "can0", f.frame) + "\n";
    return text;
}

std::string slcan_text(const std::vector<nav::StampedCanFrame>& frames, bool stamps) {
    std::string text = navcan::slcan_open_sequence(500'000);
    std::uint16_t ms = 59'990;  // wraps at 60000
    for (const auto& f : frames) {
        text += stamps ? navcan::slcan_encode(f.frame, ms) : navcan::slcan_encode(f.frame);
        ms = static_cast<std::uint16_t>((ms + 7) % 60'000);
    }
    return text + "\r\a";
}

void byte_protocols(SeedWriter& w) {
    w.put("fuzz_nmea", "epochs.nmea", nmea_text(3, kAllSentences));
    w.put("fuzz_nmea", "gga_rmc.nmea", nmea_text(2, nmea::kGga | nmea::kRmc));
    w.put("fuzz_nmea", "pashr.nmea", nmea_text(1, nmea::kPashr | nmea::kZda));
    novatel::NovatelEncoder enc;
    const auto s = drive_sample(0, Protocol::Novatel);
    w.put("fuzz_novatel", "bestpos.bin", enc.bestpos(s));
    w.put("fuzz_novatel", "inspvax.bin", enc.inspvax(s));
    w.put("fuzz_novatel", "inspvas.bin", enc.inspvas(s));
    w.put("fuzz_novatel", "stream.bin", novatel_bytes(2));
    w.put("fuzz_ncom", "packet.bin", ncom_bytes(1));
    w.put("fuzz_ncom", "stream.bin", ncom_bytes(6));
}

void can_protocols(SeedWriter& w) {
    const auto oxts = can_frames(true, 3), sbg = can_frames(false, 3);
    w.put("fuzz_navcan", "oxts", 0, can_records(oxts));
    w.put("fuzz_navcan", "sbg", 1, can_records(sbg));
    w.put("fuzz_navcan", "oxts_extended", 2, can_records(can_frames(true, 2, true)));
    w.put("fuzz_navcan", "sbg_extended", 3, can_records(can_frames(false, 2, true)));
    w.put("fuzz_candump", "oxts.log", candump_text(oxts));
    w.put("fuzz_candump", "sbg.log", candump_text(sbg));
    w.put("fuzz_slcan", "oxts.slcan", slcan_text(oxts, false));
    w.put("fuzz_slcan", "sbg_stamped.slcan", slcan_text(sbg, true));
    w.put("fuzz_slcan_bus", "oxts", 0x11, as_bytes(slcan_text(oxts, false)));
    w.put("fuzz_slcan_bus", "sbg_stamped", 0x5A, as_bytes(slcan_text(sbg, true)));
}

// gs_usb: byte 0 & 1 is the channel the harness expects, so echo IDs ending in 1 fit channel 1.
void gsusb(SeedWriter& w) {
    const auto frames = can_frames(true, 1);
    using namespace can::gsusb;
    const auto rx = encode_host_frame(frames[0].frame, kEchoIdRx, 1);
    w.put("fuzz_gsusb", "rx_frame", rx);
    w.put("fuzz_gsusb", "echo_frame", encode_host_frame(frames[1].frame, 0x11, 1));
    nav::CanFrame ext = frames[2].frame;
    ext.extended = true;
    ext.id = 0x18FF'1234;
    w.put("fuzz_gsusb", "rx_extended", encode_host_frame(ext, kEchoIdRx, 1));
    // BT_CONST of a candleLight (48 MHz) and a bit rate of 500 kbit/s.
    Bytes bt(kBtConstSize + 4);
    const std::uint32_t v[] = {0, 48'000'000, 1, 16, 1, 8, 4, 1, 1024, 1, 500'000};
    for (std::size_t i = 0; i < std::size(v); ++i) put_u32(bt.data() + 4 * i, v[i]);
    w.put("fuzz_gsusb", "bt_const_500k", bt);
}

// Byte 0: the protocol, in navproto::NavProtocol order.
void nav_logs(SeedWriter& w) {
    w.put("fuzz_nav_log", "nmea", 0, as_bytes(nmea_text(3, nmea::kGga | nmea::kRmc | nmea::kHdt)));
    w.put("fuzz_nav_log", "novatel", 1, novatel_bytes(3));
    w.put("fuzz_nav_log", "ncom", 2, ncom_bytes(5));
    w.put("fuzz_nav_log", "oxts_can", 3, as_bytes(candump_text(can_frames(true, 3))));
    w.put("fuzz_nav_log", "sbg_can", 4, as_bytes(candump_text(can_frames(false, 3))));
}

}  // namespace

void write_nav_seeds(SeedWriter& w) {
    byte_protocols(w);
    can_protocols(w);
    gsusb(w);
    nav_logs(w);
}

}  // namespace mirage::testing::seeds
