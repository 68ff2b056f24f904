// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "mirage/pcap/pcap.hpp"

namespace mirage::pcap {

// Link and IP details of written frames. The destination MAC follows the destination IP for
// broadcast (ff:..) and multicast (01:00:5e + low 23 bits, RFC 1112); otherwise dst_mac.
struct FrameOptions {
    std::array<std::uint8_t, 6> src_mac{0x60, 0x76, 0x88, 0x00, 0x00, 0x01};  // Velodyne OUI
    std::array<std::uint8_t, 6> dst_mac{0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
    std::uint8_t ttl = 64;
    bool udp_checksum = true;  // false: checksum field 0 ("not computed", RFC 768)
};

// Writes UDP datagrams to a classic pcap file (linktype Ethernet) through libpcap's dumper, each
// framed as Ethernet II + IPv4 (IHL 5) + UDP. Datagrams longer than 1472 bytes are fragmented as
// a Linux host with MTU 1500 does: 1480-byte pieces in offset order, the UDP header in the first,
// the same IP id, DF only on unfragmented packets. Frames shorter than 60 bytes are padded as on
// the wire. Not thread-safe.
class Writer {
  public:
    static constexpr std::size_t kMaxPayload = 65507;  // 65535 - 20 (IPv4) - 8 (UDP)
    static constexpr std::size_t kMtu = 1500;

    // nanosecond: file magic a1b23c4d (ns timestamps) or a1b2c3d4 (µs, times truncated).
    // Throws IoError naming the file when it cannot be created.
    explicit Writer(const std::string& path, bool nanosecond = true, FrameOptions options = {});
    ~Writer();  // close(); an error there is printed to stderr (destructors do not throw)
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    // One datagram captured at time_ns (ns since the Unix epoch). Never throws: a payload over
    // kMaxPayload or a write after close() returns false and is counted in rejected(); disk
    // errors surface at flush() / close().
    bool write(std::int64_t time_ns, const Endpoint& src, const Endpoint& dst,
               std::span<const std::uint8_t> payload);
    // Pushes buffered records to the file. Throws IoError naming the file on a write error
    // (e.g. disk full); the file then holds whole records up to some point plus at most one
    // cut record, which Reader reports as Truncated.
    void flush();
    // Flushes and closes; idempotent. Throws IoError like flush().
    void close();

    std::uint64_t datagrams() const { return datagrams_; }
    std::uint64_t frames() const { return frames_; }
    std::uint64_t rejected() const { return rejected_; }
    const std::string& path() const { return path_; }

  private:
    struct Impl;
    Impl* impl_;
    std::string path_;
    std::uint64_t datagrams_ = 0, frames_ = 0, rejected_ = 0;
};

// Cuts a classic pcap file (either byte order, µs or ns) after its last whole record, e.g. after
// a write error left a partial one. Returns the new size; throws IoError naming the file when it
// cannot be read, is not a classic pcap, or cannot be truncated.
std::uint64_t cut_to_whole_records(const std::string& path);

}  // namespace mirage::pcap
