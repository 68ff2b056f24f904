// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/messages.hpp"

#include "le_bytes.hpp"

namespace mirage::novatel {
using namespace detail;

// Offsets follow the tables of docs/nav-protocols.md §2.3.

std::array<std::uint8_t, kBestPosBodySize> pack(const BestPos& m) {
    std::array<std::uint8_t, kBestPosBodySize> b{};
    std::uint8_t* p = b.data();
    put_u32(p + 0, m.solution_status);
    put_u32(p + 4, m.position_type);
    put_f64(p + 8, m.lat_deg);
    put_f64(p + 16, m.lon_deg);
    put_f64(p + 24, m.height_msl_m);
    put_f32(p + 32, m.undulation_m);
    put_u32(p + 36, m.datum);
    put_f32(p + 40, m.lat_sigma_m);
    put_f32(p + 44, m.lon_sigma_m);
    put_f32(p + 48, m.height_sigma_m);
    for (std::size_t i = 0; i < 4; ++i) p[52 + i] = static_cast<std::uint8_t>(m.base_station_id[i]);
    put_f32(p + 56, m.differential_age_s);
    put_f32(p + 60, m.solution_age_s);
    p[64] = m.svs_tracked;
    p[65] = m.svs_in_solution;
    p[66] = m.svs_l1;
    p[67] = m.svs_multi;
    p[68] = m.reserved;
    p[69] = m.extended_status;
    p[70] = m.galileo_beidou_mask;
    p[71] = m.gps_glonass_mask;
    return b;
}

std::optional<BestPos> unpack_bestpos(std::span<const std::uint8_t> body) {
    if (body.size() < kBestPosBodySize) return std::nullopt;
    const std::uint8_t* p = body.data();
    BestPos m;
    m.solution_status = get_u32(p + 0);
    m.position_type = get_u32(p + 4);
    m.lat_deg = get_f64(p + 8);
    m.lon_deg = get_f64(p + 16);
    m.height_msl_m = get_f64(p + 24);
    m.undulation_m = get_f32(p + 32);
    m.datum = get_u32(p + 36);
    m.lat_sigma_m = get_f32(p + 40);
    m.lon_sigma_m = get_f32(p + 44);
    m.height_sigma_m = get_f32(p + 48);
    for (std::size_t i = 0; i < 4; ++i) m.base_station_id[i] = static_cast<char>(p[52 + i]);
    m.differential_age_s = get_f32(p + 56);
    m.solution_age_s = get_f32(p + 60);
    m.svs_tracked = p[64];
    m.svs_in_solution = p[65];
    m.svs_l1 = p[66];
    m.svs_multi = p[67];
    m.reserved = p[68];
    m.extended_status = p[69];
    m.galileo_beidou_mask = p[70];
    m.gps_glonass_mask = p[71];
    return m;
}

std::array<std::uint8_t, kInsPvaSBodySize> pack(const InsPvaS& m) {
    std::array<std::uint8_t, kInsPvaSBodySize> b{};
    std::uint8_t* p = b.data();
    put_u32(p + 0, m.week);
    put_f64(p + 4, m.seconds_of_week);
    put_f64(p + 12, m.lat_deg);
    put_f64(p + 20, m.lon_deg);
    put_f64(p + 28, m.height_m);
    put_f64(p + 36, m.vel_north_mps);
    put_f64(p + 44, m.vel_east_mps);
    put_f64(p + 52, m.vel_up_mps);
    put_f64(p + 60, m.roll_deg);
    put_f64(p + 68, m.pitch_deg);
    put_f64(p + 76, m.azimuth_deg);
    put_u32(p + 84, m.ins_status);
    return b;
}

std::optional<InsPvaS> unpack_inspvas(std::span<const std::uint8_t> body) {
    if (body.size() < kInsPvaSBodySize) return std::nullopt;
    const std::uint8_t* p = body.data();
    InsPvaS m;
    m.week = get_u32(p + 0);
    m.seconds_of_week = get_f64(p + 4);
    m.lat_deg = get_f64(p + 12);
    m.lon_deg = get_f64(p + 20);
    m.height_m = get_f64(p + 28);
    m.vel_north_mps = get_f64(p + 36);
    m.vel_east_mps = get_f64(p + 44);
    m.vel_up_mps = get_f64(p + 52);
    m.roll_deg = get_f64(p + 60);
    m.pitch_deg = get_f64(p + 68);
    m.azimuth_deg = get_f64(p + 76);
    m.ins_status = get_u32(p + 84);
    return m;
}

std::array<std::uint8_t, kInsPvaXBodySize> pack(const InsPvaX& m) {
    std::array<std::uint8_t, kInsPvaXBodySize> b{};
    std::uint8_t* p = b.data();
    put_u32(p + 0, m.ins_status);
    put_u32(p + 4, m.position_type);
    put_f64(p + 8, m.lat_deg);
    put_f64(p + 16, m.lon_deg);
    put_f64(p + 24, m.height_msl_m);
    put_f32(p + 32, m.undulation_m);
    put_f64(p + 36, m.vel_north_mps);
    put_f64(p + 44, m.vel_east_mps);
    put_f64(p + 52, m.vel_up_mps);
    put_f64(p + 60, m.roll_deg);
    put_f64(p + 68, m.pitch_deg);
    put_f64(p + 76, m.azimuth_deg);
    for (std::size_t i = 0; i < 3; ++i) {
        put_f32(p + 84 + 4 * i, m.position_sigma_m[i]);
        put_f32(p + 96 + 4 * i, m.velocity_sigma_mps[i]);
        put_f32(p + 108 + 4 * i, m.attitude_sigma_deg[i]);
    }
    put_u32(p + 120, m.extended_status);
    put_u16(p + 124, m.seconds_since_update);
    return b;
}

std::optional<InsPvaX> unpack_inspvax(std::span<const std::uint8_t> body) {
    if (body.size() < kInsPvaXBodySize) return std::nullopt;
    const std::uint8_t* p = body.data();
    InsPvaX m;
    m.ins_status = get_u32(p + 0);
    m.position_type = get_u32(p + 4);
    m.lat_deg = get_f64(p + 8);
    m.lon_deg = get_f64(p + 16);
    m.height_msl_m = get_f64(p + 24);
    m.undulation_m = get_f32(p + 32);
    m.vel_north_mps = get_f64(p + 36);
    m.vel_east_mps = get_f64(p + 44);
    m.vel_up_mps = get_f64(p + 52);
    m.roll_deg = get_f64(p + 60);
    m.pitch_deg = get_f64(p + 68);
    m.azimuth_deg = get_f64(p + 76);
    for (std::size_t i = 0; i < 3; ++i) {
        m.position_sigma_m[i] = get_f32(p + 84 + 4 * i);
        m.velocity_sigma_mps[i] = get_f32(p + 96 + 4 * i);
        m.attitude_sigma_deg[i] = get_f32(p + 108 + 4 * i);
    }
    m.extended_status = get_u32(p + 120);
    m.seconds_since_update = get_u16(p + 124);
    return m;
}

}  // namespace mirage::novatel
