// SPDX-License-Identifier: Apache-2.0
#pragma once
// The concrete streams behind open_byte_stream(); internal to the library.
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/bytestream/byte_stream.hpp"

namespace mirage::bytestream::detail {

enum class Parity : std::uint8_t { None, Even, Odd };

struct SerialOptions {
    std::string path;
    std::uint32_t baud = 115'200;
    int bits = 8;
    Parity parity = Parity::None;
    int stop = 1;
};

// True when termios has a speed constant for `baud`.
bool serial_baud_supported(std::uint32_t baud);

// Throw IoError naming the endpoint when the first open fails.
std::unique_ptr<ByteStream> open_serial(const SerialOptions& options);
std::unique_ptr<ByteStream> open_tcp_client(const std::string& host, std::uint16_t port);
std::unique_ptr<ByteStream> open_udp_receiver(const std::string& bind_host, std::uint16_t port);
std::unique_ptr<ByteStream> open_udp_sender(const std::string& host, std::uint16_t port);

}  // namespace mirage::bytestream::detail
