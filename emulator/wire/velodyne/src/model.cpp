// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/model.hpp"

#include <algorithm>
#include <array>
#include <memory>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/sensor/spinning.hpp"

namespace mirage::velodyne {

const char* to_string(ReturnMode mode) {
    switch (mode) {
        case ReturnMode::Strongest:
            return "strongest";
        case ReturnMode::Last:
            return "last";
        case ReturnMode::Dual:
            return "dual";
    }
    return "?";
}

ReturnMode parse_return_mode(const std::string& text) {
    if (text == "strongest") return ReturnMode::Strongest;
    if (text == "last") return ReturnMode::Last;
    if (text == "dual") return ReturnMode::Dual;
    throw ConfigError("velodyne: return mode '" + text + "': expected strongest, last or dual");
}

int ModelDescriptor::sequences_per_packet(ReturnMode mode) const {
    const int single = 12 * sequences_per_block / blocks_per_sequence;
    return mode == ReturnMode::Dual ? single / 2 : single;
}

BlockSlot ModelDescriptor::locate(ReturnMode mode, int q, int l, int r) const {
    const bool dual = mode == ReturnMode::Dual;
    if (blocks_per_sequence == 2) {  // HDL-64E: (upper, lower) pairs, quads in dual mode
        const int half = l / 32;
        return {dual ? 4 * q + 2 * r + half : 2 * q + half, l % 32};
    }
    const int b = q / sequences_per_block;
    return {dual ? 2 * b + r : b, (q % sequences_per_block) * lasers + l};
}

ModelDescriptor::SlotInfo ModelDescriptor::slot_info(ReturnMode mode, int block, int slot) const {
    const bool dual = mode == ReturnMode::Dual;
    if (blocks_per_sequence == 2) {
        const int l = 32 * (block % 2) + slot;
        return dual ? SlotInfo{block / 4, l, (block % 4) / 2} : SlotInfo{block / 2, l, 0};
    }
    const int b = dual ? block / 2 : block;
    return {b * sequences_per_block + slot / lasers, slot % lasers, dual ? block % 2 : 0};
}

std::uint16_t ModelDescriptor::block_flag(int block) const {
    return (blocks_per_sequence == 2 && block % 2 == 1) ? std::uint16_t{0xDDFF}
                                                        : std::uint16_t{0xEEFF};
}

double ModelDescriptor::azimuth_step_deg(double rpm) const {
    // Same expression as SpinningPattern: 360·period/rev_ns, rev_ns = 1e9/f.
    return 360.0 * static_cast<double>(sequence_period_ns) / (1e9 / (rpm / 60.0));
}

std::int64_t ModelDescriptor::last_firing_offset_ns() const {
    std::int64_t last = 0;
    for (const auto& l : laser) last = std::max(last, l.firing_offset_ns);
    return last;
}

namespace {

// Angles of the preset the pipeline renders with.
std::vector<LaserInfo> preset_angles(std::string_view name) {
    const sensor::SensorModel m = sensor::preset(std::string(name));
    const auto* sp = dynamic_cast<const sensor::SpinningPattern*>(m.scan.get());
    if (sp == nullptr)
        throw ConfigError("velodyne: preset '" + std::string(name) + "' is not spinning");
    std::vector<LaserInfo> out;
    for (const auto& l : sp->config().lasers)
        out.push_back({l.elevation_deg, l.azimuth_offset_deg, 0});
    return out;
}

ModelDescriptor make(Model model) {
    ModelDescriptor d;
    d.model = model;
    // The VLP-16 manual: "about 14 to 1" data : position packets; the HDL-32E capture of §6
    // shows ≈ 200 position packets/s.
    switch (model) {
        case Model::Vlp16:
        case Model::Vlp16HiRes:
            d.name = model == Model::Vlp16 ? "vlp16" : "vlp16-hires";
            d.product = model == Model::Vlp16 ? "VLP-16" : "VLP-16 Hi-Res";
            d.product_id = model == Model::Vlp16 ? 0x22 : 0x24;
            d.distance_lsb_m = 0.002;
            d.sequence_period_ns = 55'296;  // 16 × 2.304 µs + 18.432 µs recharge
            d.lasers = 16;
            d.sequences_per_block = 2;
            d.position_layout = PositionLayout::Vlp16;
            d.position_period_ns = 14 * 12 * 110'592;
            break;
        case Model::Vlp32c:
            d.name = "vlp32c";
            d.product = "VLP-32C";
            d.product_id = 0x28;
            d.distance_lsb_m = 0.004;
            d.sequence_period_ns = 55'296;
            d.lasers = 32;
            d.position_layout = PositionLayout::Vlp32c;
            d.position_period_ns = 14 * 12 * 55'296;
            break;
        case Model::Hdl32e:
            d.name = "hdl32e";
            d.product = "HDL-32E";
            d.product_id = 0x21;
            d.distance_lsb_m = 0.002;
            d.sequence_period_ns = 46'080;  // 32 × 1.152 µs
            d.lasers = 32;
            d.position_layout = PositionLayout::Hdl32e;
            d.position_period_ns = 5'000'000;
            break;
        case Model::Hdl64eS3:
            d.name = "hdl64e-s3";
            d.product = "HDL-64E S3";
            d.product_id = 0;
            d.hdl64_status = true;
            d.distance_lsb_m = 0.002;
            d.sequence_period_ns = 48'000;
            d.lasers = 64;
            d.blocks_per_sequence = 2;
            d.position_layout = PositionLayout::None;
            d.position_period_ns = 0;
            break;
    }
    d.laser = preset_angles(d.name);
    if (static_cast<int>(d.laser.size()) != d.lasers)
        throw ConfigError("velodyne: preset '" + std::string(d.name) + "' has " +
                          std::to_string(d.laser.size()) + " lasers, the wire format " +
                          std::to_string(d.lasers));
    // Firing offsets in ns from §1.4/§1.6 (independent of the preset; a test compares them).
    for (int l = 0; l < d.lasers; ++l) {
        std::int64_t t = 0;
        switch (model) {
            case Model::Vlp16:
            case Model::Vlp16HiRes:
                t = 2'304 * l;
                break;
            case Model::Vlp32c:
                t = 2'304 * (l / 2);  // pairs (2k, 2k+1) fire together
                break;
            case Model::Hdl32e:
                t = 1'152 * l;
                break;
            case Model::Hdl64eS3: {
                // VeloView: slot c fires T[rc mod 4] + 6·⌊rc/4⌋ µs before the end of its 48 µs
                // cycle, rc = 31 − c, T = {2.34, 3.54, 4.74, 6.0}; upper u and lower 32 + u
                // together.
                static constexpr std::array<std::int64_t, 4> kT = {2'340, 3'540, 4'740, 6'000};
                const int u = l % 32;
                t = 6'000 * (u / 4) + (6'000 - kT[static_cast<std::size_t>(3 - u % 4)]);
                break;
            }
        }
        d.laser[static_cast<std::size_t>(l)].firing_offset_ns = t;
    }
    return d;
}

}  // namespace

const ModelDescriptor& descriptor(Model model) {
    // Built once, thread-safe (magic statics); the presets are pure functions.
    static const std::array<ModelDescriptor, 5> all = {make(Model::Vlp16), make(Model::Vlp16HiRes),
                                                       make(Model::Vlp32c), make(Model::Hdl32e),
                                                       make(Model::Hdl64eS3)};
    return all[static_cast<std::size_t>(model)];
}

std::optional<Model> model_from_name(std::string_view name) {
    for (Model m : kAllModels)
        if (descriptor(m).name == name) return m;
    return std::nullopt;
}

std::optional<Model> model_from_product_id(std::uint8_t id) {
    switch (id) {
        case 0x22:
            return Model::Vlp16;
        case 0x24:
            return Model::Vlp16HiRes;
        case 0x28:
            return Model::Vlp32c;
        case 0x21:
            return Model::Hdl32e;
        default:
            return std::nullopt;
    }
}

}  // namespace mirage::velodyne
