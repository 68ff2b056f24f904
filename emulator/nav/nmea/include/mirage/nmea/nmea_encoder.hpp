// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "mirage/nav/nav_sample.hpp"

namespace mirage::nmea {

// Formatting choices and the fields a NavSample does not carry. Defaults match a modern
// high-precision receiver/INS; the test vectors of docs/nav-protocols.md §1 are reproduced by
// changing them (e.g. 3 minute decimals and integer seconds for the 1990s GGA example).
struct EncodeOptions {
    std::string talker = "GP";
    int time_decimals = 2;        // hhmmss.ss in GGA, RMC, ZDA (0: hhmmss)
    int pashr_time_decimals = 3;  // OxTS prints hhmmss.sss
    int avr_time_decimals = 1;    // Trimble prints hhmmss.s
    // Minutes decimals of lat/lon: 7 → 1.9e-4 mm of latitude, far below the 1 mm round trip.
    int minute_decimals = 7;
    int height_decimals = 3;  // GGA altitude and geoid separation
    // GGA: the MSL altitude sent is height − geoid separation (the sample is ellipsoidal). A
    // sample flagged kHeightIsMsl is sent as is, with the separation field empty.
    double geoid_separation_m = 0.0;
    double hdop = 1.0;
    int hdop_decimals = 1;
    // RMC/VTG speed (knots) and track (degrees): decimals and minimum integer digits
    // (zero-padded, "022.4").
    int speed_decimals = 3, speed_int_digits = 1;
    int track_decimals = 3, track_int_digits = 1;
    std::optional<double> magnetic_variation_deg;  // RMC fields 10/11 (east positive)
    char rmc_mode = 'A';  // FAA mode field; '\0' omits it (NMEA 2.0). 'A' becomes 'D' for DGPS.
    int heading_decimals = 2;  // HDT
    // ZDA local zone (hours, minutes); nullopt leaves both fields empty.
    std::optional<int> zda_zone_hours = 0;
    int zda_zone_minutes = 0;
    // PASHR fields a NavSample lacks.
    double heave_m = 0.0;
    double roll_sigma_deg = 0.0, pitch_sigma_deg = 0.0, heading_sigma_deg = 0.0;
    int aiding_status = 1, imu_status = 0;
    // PTNL,AVR fields a NavSample lacks.
    double avr_range_m = 1.0;
    double avr_pdop = 1.0;
};

// Sentence selection for encode_epoch (bit mask).
enum SentenceMask : std::uint32_t {
    kGga = 1u << 0,
    kRmc = 1u << 1,
    kVtg = 1u << 2,
    kHdt = 1u << 3,
    kZda = 1u << 4,
    kPashr = 1u << 5,
    kPtnlAvr = 1u << 6,
};

// Each returns one CRLF-terminated sentence with its checksum. Fields the sample does not have
// (no kTime, kPosition, kVelocity, kAttitude/kHeading) are left empty, which NMEA reads as
// "no data". Times are UTC (GPS − leap seconds), rounded to the printed decimals; an instant
// inside an inserted leap second prints as the following 00:00:00 (no ":60" is produced).
std::string encode_gga(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_rmc(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_vtg(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_hdt(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_zda(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_pashr(const nav::NavSample& s, const EncodeOptions& o = {});
std::string encode_ptnl_avr(const nav::NavSample& s, const EncodeOptions& o = {});

// The selected sentences of one epoch, in the order ZDA, RMC, GGA, VTG, HDT, PASHR, PTNL,AVR
// (date first, so a decoder starting mid-stream dates the rest of the epoch).
std::string encode_epoch(const nav::NavSample& s, std::uint32_t which, const EncodeOptions& o = {});

}  // namespace mirage::nmea
