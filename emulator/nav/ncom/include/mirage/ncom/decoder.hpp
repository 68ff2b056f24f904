// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/nav/resync_buffer.hpp"
#include "mirage/ncom/packet.hpp"

namespace mirage::ncom {

// What NCOM adds to the common counters.
struct NcomCounters {
    std::uint64_t no_time = 0;     // locked packets before any status channel 0: not emitted
    std::uint64_t not_locked = 0;  // valid packets with nav status 0-3, 5, 6: not emitted
};

struct DecoderOptions {
    // NCOM's altitude is taken as height above the WGS84 ellipsoid; set this for a unit
    // configured to output MSL (the sample then carries kHeightIsMsl).
    bool altitude_is_msl = false;
};

// NCOM decoder (docs/nav-protocols.md §3). Mapping to NavSample: lat/lon radians -> degrees,
// velocity NED as is, heading/pitch/roll × 1e-6 rad (heading wrapped to [0, 2π)), accel/rates
// vehicle frame (x fwd, y right, z down = FRD) -> kAcceleration / kAngularRate; a group with
// any 0x800000 component is left out. Time = channel-0 GPS minutes × 60 s + bytes 1-2 ms; the
// minute is carried forward between channel-0 packets and incremented when the ms wrap.
// Only nav status 4 (locked) gives a sample, and only once channel 0 has been seen (before
// that: counted no_time, nothing emitted). Status-only and trigger packets count unsupported.
// Every valid packet (all three checksums) updates the time state. NaN/Inf or out-of-range
// lat/lon/alt or attitude reject the packet (invalid_field).
class NcomDecoder {
  public:
    explicit NcomDecoder(DecoderOptions options = {}) : options_(options) {}

    // Serial byte stream, any split. Hunts for 0xE7 and checks the checksums; bytes skipped
    // while hunting count garbage. A candidate that fails right after a good packet (in sync)
    // counts bad_checksum (a packet cut short by the next one is indistinguishable with a
    // one-byte sync, so it counts here too); while hunting, a failed candidate is just garbage
    // (a lone 0xE7 in the data is no packet). Counters do not depend on how bytes are split.
    void feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample);
    // One UDP datagram: one or more whole 72-byte packets. A short tail counts truncated, a
    // chunk without the sync garbage.
    void feed_datagram(std::span<const std::uint8_t> datagram, const nav::SampleFn& on_sample);
    // End of the byte stream: a partial packet still buffered counts truncated.
    void finish();
    void reset();

    const nav::DecodeCounters& counters() const { return counters_; }
    const NcomCounters& ncom_counters() const { return ncom_; }
    // The latest status channel 0 (valid once has_time()).
    bool has_time() const { return have_minutes_; }
    const Channel0& channel0() const { return channel0_; }

  private:
    void handle_packet(std::span<const std::uint8_t, kPacketSize> bytes,
                       const nav::SampleFn& on_sample);

    static constexpr std::uint64_t kNotInSync = std::numeric_limits<std::uint64_t>::max();

    DecoderOptions options_;
    nav::ResyncBuffer buf_{kPacketSize};
    std::uint64_t good_end_ = kNotInSync;  // stream offset just past the last good packet
    nav::DecodeCounters counters_;
    NcomCounters ncom_;
    bool have_minutes_ = false;
    std::int64_t minutes_ = 0;
    std::int32_t last_ms_ = 0;
    Channel0 channel0_;
};

}  // namespace mirage::ncom
