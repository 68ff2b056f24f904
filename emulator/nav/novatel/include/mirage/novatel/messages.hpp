// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace mirage::novatel {

// Message IDs (docs/nav-protocols.md §2.1).
inline constexpr std::uint16_t kBestPosId = 42;
inline constexpr std::uint16_t kInsPvaId = 507;   // long header, same body as INSPVAS
inline constexpr std::uint16_t kInsPvaSId = 508;  // short header
inline constexpr std::uint16_t kInsPvaXId = 1465;

inline constexpr std::size_t kBestPosBodySize = 72;
inline constexpr std::size_t kInsPvaSBodySize = 88;
inline constexpr std::size_t kInsPvaXBodySize = 126;

// OEM7 position types used here (BESTPOS, INSPVAX).
enum PositionType : std::uint32_t {
    kPosNone = 0,
    kPosFixedPos = 1,
    kPosFixedHeight = 2,
    kPosDopplerVelocity = 8,
    kPosSingle = 16,
    kPosPsrDiff = 17,
    kPosWaas = 18,
    kPosPropagated = 19,
    kPosL1Float = 32,
    kPosIonoFreeFloat = 33,
    kPosNarrowFloat = 34,
    kPosL1Int = 48,
    kPosWideInt = 49,
    kPosNarrowInt = 50,
    kPosRtkDirectIns = 51,
    kPosInsSbas = 52,
    kPosInsPsrSp = 53,
    kPosInsPsrDiff = 54,
    kPosInsRtkFloat = 55,
    kPosInsRtkFixed = 56,
    kPosPppConverging = 68,
    kPosPpp = 69,
    kPosInsPppConverging = 73,
    kPosInsPpp = 74,
};

// OEM7 inertial solution status (INSPVA(S/X)).
enum InsStatus : std::uint32_t {
    kInsInactive = 0,
    kInsAligning = 1,
    kInsHighVariance = 2,
    kInsSolutionGood = 3,
    kInsSolutionFree = 6,
    kInsAlignmentComplete = 7,
    kInsDeterminingOrientation = 8,
    kInsWaitingInitialPos = 9,
    kInsWaitingAzimuth = 10,
    kInsInitializingBiases = 11,
    kInsMotionDetect = 12,
};

// BESTPOS body, 72 bytes (§2.3). Height above MSL; ellipsoidal = height_msl_m + undulation_m.
struct BestPos {
    std::uint32_t solution_status = 0;  // 0 SOL_COMPUTED
    std::uint32_t position_type = kPosNone;
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double height_msl_m = 0.0;
    float undulation_m = 0.0F;
    std::uint32_t datum = 61;  // WGS84
    float lat_sigma_m = 0.0F;
    float lon_sigma_m = 0.0F;
    float height_sigma_m = 0.0F;
    std::array<char, 4> base_station_id{};
    float differential_age_s = 0.0F;
    float solution_age_s = 0.0F;
    std::uint8_t svs_tracked = 0;
    std::uint8_t svs_in_solution = 0;
    std::uint8_t svs_l1 = 0;
    std::uint8_t svs_multi = 0;
    std::uint8_t reserved = 0;
    std::uint8_t extended_status = 0;
    std::uint8_t galileo_beidou_mask = 0;
    std::uint8_t gps_glonass_mask = 0;
};

// INSPVAS / INSPVA body, 88 bytes. Height ellipsoidal; velocity north/east/UP; azimuth
// clockwise from north.
struct InsPvaS {
    std::uint32_t week = 0;
    double seconds_of_week = 0.0;
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double height_m = 0.0;
    double vel_north_mps = 0.0;
    double vel_east_mps = 0.0;
    double vel_up_mps = 0.0;
    double roll_deg = 0.0;
    double pitch_deg = 0.0;
    double azimuth_deg = 0.0;
    std::uint32_t ins_status = kInsInactive;
};

// INSPVAX body, 126 bytes. Height above MSL + undulation.
struct InsPvaX {
    std::uint32_t ins_status = kInsInactive;
    std::uint32_t position_type = kPosNone;
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double height_msl_m = 0.0;
    float undulation_m = 0.0F;
    double vel_north_mps = 0.0;
    double vel_east_mps = 0.0;
    double vel_up_mps = 0.0;
    double roll_deg = 0.0;
    double pitch_deg = 0.0;
    double azimuth_deg = 0.0;
    std::array<float, 3> position_sigma_m{};
    std::array<float, 3> velocity_sigma_mps{};
    std::array<float, 3> attitude_sigma_deg{};
    std::uint32_t extended_status = 0;
    std::uint16_t seconds_since_update = 0;
};

std::array<std::uint8_t, kBestPosBodySize> pack(const BestPos& m);
std::array<std::uint8_t, kInsPvaSBodySize> pack(const InsPvaS& m);
std::array<std::uint8_t, kInsPvaXBodySize> pack(const InsPvaX& m);

// nullopt when the body is shorter than the log's size (longer bodies are accepted: later
// firmware may append fields).
std::optional<BestPos> unpack_bestpos(std::span<const std::uint8_t> body);
std::optional<InsPvaS> unpack_inspvas(std::span<const std::uint8_t> body);
std::optional<InsPvaX> unpack_inspvax(std::span<const std::uint8_t> body);

}  // namespace mirage::novatel
