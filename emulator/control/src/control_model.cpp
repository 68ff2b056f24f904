// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/control_model.hpp"

#include <algorithm>
#include <limits>

namespace mirage::control {
namespace {

constexpr std::uint16_t kWatchdogMinMs = 100, kWatchdogMaxMs = 60000;

// Word `i` (0 = most significant) of a 64-bit value spread over four registers (ABCD).
std::uint16_t word64(std::uint64_t v, unsigned i) {
    return static_cast<std::uint16_t>(v >> (48 - 16 * i));
}
// Word `i` of a 32-bit value, saturated: a counter past 2³²-1 reads all ones.
std::uint16_t word32(std::uint64_t v, unsigned i) {
    const std::uint64_t s = std::min<std::uint64_t>(v, 0xFFFFFFFFu);
    return static_cast<std::uint16_t>(i == 0 ? s >> 16 : s);
}

bool is_fault_field(std::uint16_t a, std::size_t sensors, std::size_t& sensor,
                    std::uint16_t& field) {
    if (a < hr::kFaultBase) return false;
    const std::size_t rel = a - hr::kFaultBase;
    sensor = rel / hr::kFaultStride;
    field = static_cast<std::uint16_t>(rel % hr::kFaultStride);
    return sensor < sensors && field < hr::kFaultFields;
}

bool writable(std::uint16_t a, std::size_t sensors) {
    std::size_t s = 0;
    std::uint16_t f = 0;
    return a <= hr::kWatchdogMs || is_fault_field(a, sensors, s, f);
}

bool flag_ok(std::uint16_t v) { return v <= 1; }

}  // namespace

ControlModel::ControlModel(Identity id, std::vector<FaultSettings> defaults,
                           std::uint16_t watchdog_ms)
    : id_(id), defaults_(std::move(defaults)), watchdog_ms_(watchdog_ms) {
    defaults_.resize(id_.sensors);
    faults_ = defaults_;
    for (std::size_t i = 0; i < id_.sensors; ++i) {
        cells_.push_back(std::make_unique<FaultCell>());
        cells_.back()->store(faults_[i]);
    }
    status_.sensors.resize(id_.sensors);
}

Exception ControlModel::refuse(Exception e, ErrorCode why) {
    last_error_ = why;
    ++exceptions_;
    return e;
}

void ControlModel::count_refused() {
    std::lock_guard lk(m_);
    ++requests_;
    ++exceptions_;
}

// Addresses first (02), then each value's range (03), then the state (06): nothing is applied
// unless the whole request passes.
std::pair<Exception, ErrorCode> ControlModel::check_write(const Request& r) const {
    for (std::size_t i = 0; i < r.count; ++i)
        if (!writable(static_cast<std::uint16_t>(r.address + i), id_.sensors))
            return {Exception::IllegalAddress, ErrorCode::NotWritable};
    bool command = false, scenario = false;
    for (std::size_t i = 0; i < r.count; ++i) {
        const auto a = static_cast<std::uint16_t>(r.address + i);
        const std::uint16_t v = r.values[i];
        std::size_t s = 0;
        std::uint16_t f = 0;
        bool ok = true;
        if (a == hr::kCommand) {
            ok = v >= 1 && v <= 4;
            command = true;
        } else if (a == hr::kScenario) {
            ok = v < id_.scenarios;
            scenario = true;
        } else if (a == hr::kWatchdogMs) {
            ok = v == 0 || (v >= kWatchdogMinMs && v <= kWatchdogMaxMs);
        } else if (is_fault_field(a, id_.sensors, s, f)) {
            switch (f) {
                case hr::kDropRate:
                    ok = v <= 10000;
                    break;
                case hr::kDropBurst:
                    ok = v >= 1 && v <= 1000;
                    break;
                case hr::kFreezeNav:
                    ok = flag_ok(v) && (v == 0 || id_.can_freeze_nav);
                    break;
                case hr::kRangeNoise:
                    ok = v <= 10000;
                    break;
                case hr::kStaleNav:
                case hr::kStopSensor:
                    ok = flag_ok(v);
                    break;
                default:
                    break;  // range bias: any int16
            }
        }
        if (!ok) return {Exception::IllegalValue, ErrorCode::ValueOutOfRange};
    }
    if (scenario && (state_ == RigState::Armed || state_ == RigState::Running))
        return {Exception::ServerBusy, ErrorCode::ScenarioWhileBusy};
    if (command) {
        const auto c = static_cast<Command>(r.values[hr::kCommand - r.address]);
        const RigState s = state_;
        const bool ok = c == Command::Reset ||
                        (c == Command::Arm &&
                         (s == RigState::Idle || s == RigState::Stopped || s == RigState::Armed)) ||
                        (c == Command::Start && s == RigState::Armed) ||
                        (c == Command::Stop && (s == RigState::Armed || s == RigState::Running));
        if (!ok) return {Exception::ServerBusy, ErrorCode::CommandInState};
    }
    return {Exception::None, ErrorCode::None};
}

Exception ControlModel::handle(const Request& r, std::int64_t now_ns,
                               std::span<std::uint16_t> out) {
    std::lock_guard lk(m_);
    ++requests_;
    if (r.function == Function::ReadHolding || r.function == Function::ReadInput) {
        const std::size_t n = std::min<std::size_t>(r.count, out.size());
        for (std::size_t i = 0; i < n; ++i) {
            const auto a = static_cast<std::uint16_t>(r.address + i);
            out[i] = r.function == Function::ReadInput ? input(a) : holding(a);
        }
        return Exception::None;
    }
    const auto [e, why] = check_write(r);
    if (e != Exception::None) return refuse(e, why);
    // Settings before the command, so one request can select a scenario and arm it.
    std::optional<std::uint16_t> cmd;
    for (std::size_t i = 0; i < r.count; ++i) {
        const auto a = static_cast<std::uint16_t>(r.address + i);
        if (a == hr::kCommand)
            cmd = r.values[i];
        else
            apply(a, r.values[i], now_ns);
    }
    // Each sensor's faults published once, so its threads see the whole request or none of it.
    for (std::size_t i = 0; i < cells_.size(); ++i) cells_[i]->store(faults_[i]);
    if (cmd) command(static_cast<Command>(*cmd), now_ns);
    return Exception::None;
}

void ControlModel::apply(std::uint16_t a, std::uint16_t v, std::int64_t now_ns) {
    std::size_t s = 0;
    std::uint16_t f = 0;
    if (a == hr::kScenario) {
        selected_ = v;
    } else if (a == hr::kHeartbeat) {
        heartbeat_ = v;
        heartbeat_ns_ = now_ns;
    } else if (a == hr::kWatchdogMs) {
        watchdog_ms_ = v;
        heartbeat_ns_ = now_ns;
    } else if (is_fault_field(a, id_.sensors, s, f)) {
        FaultSettings& x = faults_[s];
        switch (f) {
            case hr::kDropRate:
                x.drop_rate = v;
                break;
            case hr::kDropBurst:
                x.drop_burst = v;
                break;
            case hr::kFreezeNav:
                x.freeze_nav = v != 0;
                break;
            case hr::kRangeBias:
                x.range_bias_mm = static_cast<std::int16_t>(v);
                break;
            case hr::kRangeNoise:
                x.range_noise_mm = v;
                break;
            case hr::kStaleNav:
                x.stale_nav = v != 0;
                break;
            case hr::kStopSensor:
                x.stop = v != 0;
                break;
            default:
                break;
        }
    }
}

void ControlModel::command(Command c, std::int64_t now_ns) {
    last_command_ = c;
    switch (c) {
        case Command::Arm:
            state_ = RigState::Armed;
            loaded_ = selected_;
            heartbeat_ns_ = now_ns;
            break;
        case Command::Start:
            state_ = RigState::Running;
            heartbeat_ns_ = now_ns;
            ++runs_;
            break;
        case Command::Stop:
            state_ = RigState::Stopped;
            break;
        case Command::Reset:
            state_ = RigState::Idle;
            last_error_ = ErrorCode::None;
            faults_ = defaults_;
            for (std::size_t i = 0; i < cells_.size(); ++i) cells_[i]->store(faults_[i]);
            break;
        case Command::None:
            break;
    }
}

std::uint16_t ControlModel::holding(std::uint16_t a) const {
    std::size_t s = 0;
    std::uint16_t f = 0;
    if (a == hr::kCommand) return static_cast<std::uint16_t>(last_command_);
    if (a == hr::kScenario) return selected_;
    if (a == hr::kHeartbeat) return heartbeat_;
    if (a == hr::kWatchdogMs) return watchdog_ms_;
    if (!is_fault_field(a, id_.sensors, s, f)) return 0;
    const FaultSettings& x = faults_[s];
    switch (f) {
        case hr::kDropRate:
            return x.drop_rate;
        case hr::kDropBurst:
            return x.drop_burst;
        case hr::kFreezeNav:
            return x.freeze_nav;
        case hr::kRangeBias:
            return static_cast<std::uint16_t>(x.range_bias_mm);
        case hr::kRangeNoise:
            return x.range_noise_mm;
        case hr::kStaleNav:
            return x.stale_nav;
        case hr::kStopSensor:
            return x.stop;
        default:
            return 0;
    }
}

std::uint16_t ControlModel::input(std::uint16_t a) const {
    const auto in = [a](std::uint16_t base, unsigned words) {
        return a >= base && a < base + words;
    };
    if (a == ir::kProduct) return kProductId;
    if (in(ir::kVersion, 3)) return id_.version[a - ir::kVersion];
    if (in(ir::kRigHash, 4)) return word64(id_.rig_hash, a - ir::kRigHash);
    if (a == ir::kState) return static_cast<std::uint16_t>(state_);
    if (a == ir::kLastError) return static_cast<std::uint16_t>(last_error_);
    if (a == ir::kScenario) return loaded_;
    if (a == ir::kScenarioCount) return id_.scenarios;
    if (a == ir::kSensorCount) return static_cast<std::uint16_t>(id_.sensors);
    if (a == ir::kWatchdogExpiries)
        return static_cast<std::uint16_t>(std::min<std::uint64_t>(expiries_, 0xFFFF));
    if (in(ir::kRequests, 2)) return word32(requests_, a - ir::kRequests);
    if (in(ir::kExceptions, 2)) return word32(exceptions_, a - ir::kExceptions);
    if (a == ir::kRuns) return static_cast<std::uint16_t>(std::min<std::uint64_t>(runs_, 0xFFFF));
    if (in(ir::kSimTime, 4))
        return word64(static_cast<std::uint64_t>(status_.sim_time_ns), a - ir::kSimTime);
    if (in(ir::kNavRate, 2)) return word32(status_.nav_rate, a - ir::kNavRate);
    if (in(ir::kNavRejected, 2)) return word32(status_.nav_rejected, a - ir::kNavRejected);
    if (in(ir::kPoseAge, 2))
        return word32(status_.pose_age_ms
                          ? std::uint64_t(std::max<std::int64_t>(*status_.pose_age_ms, 0))
                          : std::numeric_limits<std::uint64_t>::max(),
                      a - ir::kPoseAge);
    if (a < ir::kSensorBase) return 0;
    const std::size_t s = (a - ir::kSensorBase) / ir::kSensorStride;
    const auto off = static_cast<std::uint16_t>((a - ir::kSensorBase) % ir::kSensorStride);
    if (s >= status_.sensors.size()) return 0;
    const SensorStatus& x = status_.sensors[s];
    const auto field = [off](std::uint16_t at) { return off >= at && off < at + 2; };
    if (off == ir::kSensorState) return static_cast<std::uint16_t>(x.state);
    if (field(ir::kPackets)) return word32(x.packets, off - ir::kPackets);
    if (field(ir::kPoints)) return word32(x.points, off - ir::kPoints);
    if (field(ir::kLate)) return word32(x.late, off - ir::kLate);
    if (field(ir::kSendFailed)) return word32(x.send_failed, off - ir::kSendFailed);
    if (field(ir::kStalePeriods)) return word32(x.stale_periods, off - ir::kStalePeriods);
    if (field(ir::kDropped)) return word32(x.dropped, off - ir::kDropped);
    return 0;
}

void ControlModel::set_status(RigStatus s) {
    std::lock_guard lk(m_);
    s.sensors.resize(id_.sensors);
    status_ = std::move(s);
}

RigState ControlModel::state() const {
    std::lock_guard lk(m_);
    return state_;
}

ControlModel::Order ControlModel::order() const {
    std::lock_guard lk(m_);
    return {state_, runs_, loaded_};
}

ErrorCode ControlModel::last_error() const {
    std::lock_guard lk(m_);
    return last_error_;
}

std::uint64_t ControlModel::runs() const {
    std::lock_guard lk(m_);
    return runs_;
}

void ControlModel::tick(std::int64_t now_ns) {
    std::lock_guard lk(m_);
    if (watchdog_ms_ == 0 || (state_ != RigState::Armed && state_ != RigState::Running)) return;
    if (now_ns - heartbeat_ns_ <= std::int64_t{watchdog_ms_} * 1'000'000) return;
    ++expiries_;
    state_ = RigState::Fault;
    last_error_ = ErrorCode::WatchdogExpired;
}

void ControlModel::run_ended(std::uint64_t run) {
    std::lock_guard lk(m_);
    if (run == runs_ && state_ == RigState::Running) state_ = RigState::Stopped;
}

void ControlModel::fault(std::uint64_t run, ErrorCode reason) {
    std::lock_guard lk(m_);
    if (run != runs_ || state_ != RigState::Running) return;
    state_ = RigState::Fault;
    last_error_ = reason;
}

}  // namespace mirage::control
