// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mirage::replay {

struct RecordConfig {
    std::vector<std::uint16_t> ports;  // listen on each (0: ephemeral, see Recorder::ports())
    std::string bind_host = "0.0.0.0";
    std::string out;                // classic pcap, ns timestamps
    std::int64_t duration_ns = -1;  // -1: until stopped
    std::int64_t flush_interval_ns = 1'000'000'000;
    int receive_buffer_bytes = 4 << 20;
};

struct RecordStatus {
    std::vector<std::uint16_t> ports;
    std::vector<std::uint64_t> packets;       // per port, so far
    std::vector<std::uint64_t> packets_last;  // per port, since the previous status
    std::int64_t interval_ns = 0;
    std::uint64_t bytes = 0;
};

struct RecordResult {
    RecordStatus totals;
    std::uint64_t written = 0;    // datagrams in the file
    std::uint64_t truncated = 0;  // longer than the receive buffer (cut, MSG_TRUNC)
    // Records are written in receive-time order across the ports; these few were read so late
    // (over 50 ms after their stamp) that a later one had already been written.
    std::uint64_t out_of_order = 0;
    std::uint64_t file_bytes = 0;
    std::string error;  // write error (the file was cut to its last whole record)
};

// Receives UDP datagrams on several ports (recvmmsg, SO_TIMESTAMPNS kernel receive time,
// IP_PKTINFO for the destination address) and writes each into a nanosecond pcap with
// synthesised Ethernet/IPv4/UDP headers carrying the real source address and ports. Flushes every
// flush_interval_ns; on a write error (disk full) it stops, and cuts the file to its last whole
// record so it stays valid.
class Recorder {
  public:
    // Opens and binds the sockets and creates the file. Throws ConfigError / IoError naming the
    // address, port or file.
    explicit Recorder(const RecordConfig& config);
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    const std::vector<std::uint16_t>& ports() const { return ports_; }  // as bound
    // Datagrams received so far (any thread may ask while run() goes on).
    std::uint64_t received() const { return received_.load(std::memory_order_relaxed); }
    // Records until `stop`, the duration or a write error; closes the file. Never throws.
    RecordResult run(const std::atomic<bool>& stop,
                     const std::function<void(const RecordStatus&)>& on_status = {});

  private:
    std::atomic<std::uint64_t> received_{0};
    RecordConfig config_;
    std::vector<int> fds_;
    std::vector<std::uint16_t> ports_;
};

}  // namespace mirage::replay
