// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>

#include "mirage/nav/nav_sample.hpp"
#include "mirage/novatel/frame.hpp"
#include "mirage/novatel/messages.hpp"

namespace mirage::novatel {

// Protocol enums -> FixQuality. Unlisted values map to Unknown.
nav::FixQuality quality_from_position_type(std::uint32_t position_type);
// INS status alone (INSPVAS): only "no solution" vs solution vs free-running is known.
nav::FixQuality quality_from_ins_status(std::uint32_t ins_status);
// True when the INS status carries a navigation solution (HIGH_VARIANCE, SOLUTION_GOOD,
// SOLUTION_FREE, ALIGNMENT_COMPLETE).
bool ins_status_has_solution(std::uint32_t ins_status);
// FixQuality -> the INS_* position type a SPAN receiver reports (fake INS).
std::uint32_t position_type_for(nav::FixQuality q);
std::uint32_t ins_status_for(nav::FixQuality q);

// Log -> NavSample. Mapping (docs/nav-protocols.md §2.3, NovAtel INSPVA doc):
//  - height: MSL + undulation -> ellipsoidal (BESTPOS, INSPVAX); INSPVA(S) already ellipsoidal;
//  - velocity north/east/up -> NED (down = -up);
//  - azimuth (clockwise from north) -> heading in [0, 2π);
//  - roll/pitch: NovAtel's vehicle frame is X right, Y forward, Z up with roll a right-handed
//    rotation about Y and pitch about X, applied azimuth->pitch->roll. Conjugating by the
//    ENU->NED / RFU->FRD axis swap turns that into Rz(azimuth)·Ry(pitch)·Rx(roll), so aerospace
//    roll = NovAtel roll, pitch = NovAtel pitch (tested with rotation matrices);
//  - time: GPS week + ms (or seconds) is GPS time already, no leap seconds.
// nullopt when a field is NaN/Inf or out of range (counted invalid_field by the decoder).
// When the status says there is no solution, the sample carries only kTime (quality None).
std::optional<nav::NavSample> to_sample(const LongHeader& h, const BestPos& m);
std::optional<nav::NavSample> to_sample(const LongHeader& h, const InsPvaX& m);
// INSPVAS (short header) / INSPVA (long header): time from the body's week + seconds.
std::optional<nav::NavSample> to_sample(const InsPvaS& m);

// NavSample -> log body (inverse of the above). undulation_m: geoid height N used for
// MSL = ellipsoidal − N (ignored when the sample's height is already MSL).
BestPos bestpos_from(const nav::NavSample& s, float undulation_m);
InsPvaX inspvax_from(const nav::NavSample& s, float undulation_m);
InsPvaS inspvas_from(const nav::NavSample& s, float undulation_m = 0.0F);

}  // namespace mirage::novatel
