// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mirage::velodyne {

// Velodyne 1206-byte-data-packet models (docs/wire-formats.md §1.2–§1.7).
enum class Model : std::uint8_t { Vlp16, Vlp16HiRes, Vlp32c, Hdl32e, Hdl64eS3 };
inline constexpr Model kAllModels[] = {Model::Vlp16, Model::Vlp16HiRes, Model::Vlp32c,
                                       Model::Hdl32e, Model::Hdl64eS3};

// Factory byte 1 (payload offset 1204), §1.3.
enum class ReturnMode : std::uint8_t { Strongest = 0x37, Last = 0x38, Dual = 0x39 };
inline constexpr ReturnMode kAllReturnModes[] = {ReturnMode::Strongest, ReturnMode::Last,
                                                 ReturnMode::Dual};
const char* to_string(ReturnMode mode);
// "strongest" | "last" | "dual"; throws ConfigError naming the text otherwise.
ReturnMode parse_return_mode(const std::string& text);

// Which position-packet generation a model sends (§1.9); None: the model sends none (HDL-64E
// reports time and GPS state through its cycling status bytes instead, §1.10).
enum class PositionLayout : std::uint8_t { None, Vlp16, Vlp32c, Hdl32e };

// One laser, indexed by laser id (= PointRecord.channel of the matching sensor preset).
struct LaserInfo {
    double elevation_deg = 0;
    double azimuth_offset_deg = 0;      // δ = −rot_correction: beam azimuth = rotor azimuth + δ
    std::int64_t firing_offset_ns = 0;  // from the first firing of its sequence (§1.6)
};

// Where a return of sequence q (of a packet) and laser l sits in the packet.
struct BlockSlot {
    int block = 0;  // 0..11
    int slot = 0;   // 0..31
};

// One descriptor per model serves the packetizer and the decoder.
struct ModelDescriptor {
    Model model = Model::Vlp16;
    std::string_view name;        // sensor preset name: "vlp16", "vlp16-hires", ...
    std::string_view product;     // "VLP-16", ...
    std::uint8_t product_id = 0;  // byte 1205; HDL-64E carries a status value there instead
    bool hdl64_status = false;    // bytes 1204/1205 = cycling status type/value (§1.10)
    double distance_lsb_m = 0.002;
    std::int64_t sequence_period_ns = 0;  // one firing of every laser
    int lasers = 0;
    int sequences_per_block = 1;   // VLP-16: 2 (slots 0–15, 16–31)
    int blocks_per_sequence = 1;   // HDL-64E: 2 (upper 0xEEFF lasers 0–31, lower 0xDDFF 32–63)
    std::vector<LaserInfo> laser;  // by laser id
    double rpm_min = 300, rpm_max = 1200, rpm_default = 600;
    PositionLayout position_layout = PositionLayout::None;
    std::int64_t position_period_ns = 0;  // 0 when the model sends no position packets

    // Firing sequences per data packet: 12 blocks hold 12·spb/bps sequences, half in dual mode.
    int sequences_per_packet(ReturnMode mode) const;
    std::int64_t packet_period_ns(ReturnMode mode) const {
        return sequences_per_packet(mode) * sequence_period_ns;
    }
    double packets_per_second(ReturnMode mode) const {
        return 1e9 / static_cast<double>(packet_period_ns(mode));
    }
    // Block and slot of (sequence q within the packet, laser l, return r); r = 0 is the single
    // return, in dual mode r = 0 the last and r = 1 the strongest / second strongest (§1.5).
    BlockSlot locate(ReturnMode mode, int q, int l, int r) const;
    // Inverse of locate for a block and slot: sequence within the packet, laser and return index.
    struct SlotInfo {
        int sequence = 0;
        int laser = 0;
        int ret = 0;
    };
    SlotInfo slot_info(ReturnMode mode, int block, int slot) const;
    // Sequence (within the packet) whose first firing a block's azimuth belongs to.
    int block_sequence(ReturnMode mode, int block) const {
        return slot_info(mode, block, 0).sequence;
    }
    // Block flag of block b: 0xEEFF, or 0xDDFF for the HDL-64E lower block.
    std::uint16_t block_flag(int block) const;
    // Rotor azimuth advance per sequence at `rpm`, degrees.
    double azimuth_step_deg(double rpm) const;
    // Largest encodable range (raw 65535).
    double max_encodable_range_m() const { return 65535.0 * distance_lsb_m; }
    // Last firing offset of a sequence.
    std::int64_t last_firing_offset_ns() const;
};

// The built-in descriptors. Angles are those the sensor presets render with (one source of
// truth, so the packets agree with the scan pattern); timing and packet layout follow §1.4–§1.6.
const ModelDescriptor& descriptor(Model model);
// By preset name ("vlp16", "vlp16-hires", "vlp32c", "hdl32e", "hdl64e-s3"); nullopt if unknown.
std::optional<Model> model_from_name(std::string_view name);
// By product id byte (HDL-64E has none).
std::optional<Model> model_from_product_id(std::uint8_t id);

}  // namespace mirage::velodyne
