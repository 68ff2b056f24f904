// SPDX-License-Identifier: Apache-2.0
// libFuzzer: arbitrary adapter output through SlcanBus (line splitter, Linux state/error lines,
// navcan's parser) in arbitrary read splits. Byte 0 seeds the split sizes.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/slcan_bus.hpp"

namespace {

using mirage::bytestream::ReadStatus;

class FuzzStream final : public mirage::bytestream::ByteStream {
  public:
    FuzzStream(const std::uint8_t* data, std::size_t size, std::uint8_t seed)
        : data_(data), size_(size), seed_(seed) {}
    ReadStatus read(std::span<std::uint8_t> buffer, std::size_t& n, std::int64_t& host_ns,
                    std::chrono::nanoseconds) override {
        n = 0;
        host_ns = 0;
        if (pos_ >= size_) return ReadStatus::Timeout;
        seed_ = static_cast<std::uint8_t>(seed_ * 29u + 7u);
        const std::size_t take = std::min({std::size_t{1} + seed_ % 40u, buffer.size(), size_ - pos_});
        std::copy_n(data_ + pos_, take, buffer.data());
        pos_ += take;
        n = take;
        return ReadStatus::Data;
    }
    bool write(std::span<const std::uint8_t>) override { return true; }
    mirage::bytestream::StreamCounters counters() const override { return {}; }
    std::string name() const override { return "fuzz"; }

  private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
    std::uint8_t seed_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    auto bus = mirage::can::open_slcan(std::make_unique<FuzzStream>(data + 1, size - 1, data[0]),
                                       500'000);
    mirage::nav::CanFrame f;
    std::int64_t t = 0;
    std::size_t frames = 0;
    for (mirage::can::RxStatus st;
         (st = bus->receive(f, t, std::chrono::nanoseconds(0))) != mirage::can::RxStatus::Timeout;) {
        if (f.len > 8) std::abort();
        if (!f.error && f.id > (f.extended ? 0x1FFFFFFFu : 0x7FFu)) std::abort();
        ++frames;
    }
    const auto c = bus->counters();
    if (c.rx_frames + c.error_frames != frames) std::abort();
    return 0;
}
