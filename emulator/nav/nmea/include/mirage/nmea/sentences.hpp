// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>

#include "mirage/nmea/fields.hpp"
#include "mirage/nmea/sentence.hpp"

namespace mirage::nmea {

// Typed contents of the decoded sentence types (docs/nav-protocols.md §1). Empty fields (no data)
// are nullopt; present fields are validated (finite, in range).

enum class ParseStatus : std::uint8_t {
    Ok,
    Unsupported,   // framed fine but not a variant we decode (e.g. Ashtech $PASHR,POS)
    InvalidField,  // malformed, NaN/Inf or out-of-range value
};

struct Gga {
    std::optional<UtcTime> time;
    std::optional<double> lat_deg, lon_deg;
    int quality = 0;  // 0..8 as sent (empty = 0)
    std::optional<int> satellites;
    std::optional<double> hdop;
    std::optional<double> altitude_msl_m;
    std::optional<double> geoid_separation_m;  // ellipsoid height = MSL + separation
};

struct Rmc {
    std::optional<UtcTime> time;
    bool valid = false;  // status 'A'
    std::optional<double> lat_deg, lon_deg;
    std::optional<double> speed_knots;
    std::optional<double> track_deg;  // true course over ground
    std::optional<Date> date;
    std::optional<double> magnetic_variation_deg;  // east positive
    char mode = '\0';                              // FAA mode (NMEA 2.3+), '\0' if absent
};

struct Vtg {
    std::optional<double> track_deg;    // true
    std::optional<double> speed_knots;  // from the km/h field when the knots field is empty
};

struct Hdt {
    std::optional<double> heading_deg;
};

struct Zda {
    std::optional<UtcTime> time;
    std::optional<Date> date;
    std::optional<int> zone_hours, zone_minutes;
};

// OxTS RT variant of $PASHR (Ashtech's alphabetic-field-1 form is Unsupported).
struct Pashr {
    std::optional<UtcTime> time;
    std::optional<double> heading_deg;  // true
    std::optional<double> roll_deg, pitch_deg, heave_m;
    std::optional<double> roll_sigma_deg, pitch_sigma_deg, heading_sigma_deg;
    std::optional<int> aiding_status, imu_status;
};

// Trimble $PTNL,AVR: attitude of the moving-baseline vector.
struct PtnlAvr {
    std::optional<UtcTime> time;
    std::optional<double> yaw_deg, tilt_deg, roll_deg;
    std::optional<double> range_m;
    int quality = 0;  // 0 invalid, 1 autonomous, 2 RTK float, 3 RTK fixed, 4 DGPS
    std::optional<double> pdop;
    std::optional<int> satellites;
};

ParseStatus parse_gga(const Sentence& s, Gga& out);
ParseStatus parse_rmc(const Sentence& s, Rmc& out);
ParseStatus parse_vtg(const Sentence& s, Vtg& out);
ParseStatus parse_hdt(const Sentence& s, Hdt& out);
ParseStatus parse_zda(const Sentence& s, Zda& out);
ParseStatus parse_pashr(const Sentence& s, Pashr& out);
ParseStatus parse_ptnl_avr(const Sentence& s, PtnlAvr& out);

}  // namespace mirage::nmea
