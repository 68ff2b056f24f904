// SPDX-License-Identifier: Apache-2.0
// The rig's Modbus server (docs/control.md §3): Modbus TCP (several clients) and Modbus RTU over
// a serial line or pty, served by one thread that never touches rendering or pacing. Framing is
// libmodbus's; every request is checked — TCP header, then check_request, then the model — before
// libmodbus replies, so a malformed request gets an exception or a closed connection, never a
// half-applied write. A serial line that vanishes is reopened with backoff.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "mirage/control/control_model.hpp"

namespace mirage::control {

struct ControlEndpoint {
    std::string tcp_host = "127.0.0.1";  // dotted IPv4; "0.0.0.0": every interface
    int tcp_port = 1502;                 // 0: any free port (tests); -1: no TCP server
    int max_clients = 8;                 // more are accepted and closed at once, counted
    std::string rtu_device;              // empty: no RTU server
    int baud = 115200;
    char parity = 'N';  // 'N', 'E', 'O'
    int stop_bits = 1;
    int unit = 1;  // RTU server address; TCP answers any unit id
};

// "host:port" -> tcp_host, tcp_port. Throws ConfigError ("control: tcp '…': …").
void parse_tcp_address(const std::string& text, ControlEndpoint& e);

struct ServerCounters {
    std::uint64_t connections = 0, refused_connections = 0, closed_malformed = 0, closed_idle = 0,
                  closed_unread = 0,  // the client stopped reading: a reply did not fit
        frame_errors = 0, replies = 0, internal_errors = 0, rtu_reopens = 0;
    int clients = 0;
    bool rtu_open = false;
};

class ModbusServer {
  public:
    using StatusFn = std::function<RigStatus()>;
    // Binds the TCP address and opens the serial line now; throws IoError naming the component
    // and address ("control: tcp 127.0.0.1:1502: Address already in use").
    ModbusServer(ControlEndpoint endpoint, ControlModel& model, StatusFn status);
    ~ModbusServer();
    ModbusServer(const ModbusServer&) = delete;
    ModbusServer& operator=(const ModbusServer&) = delete;

    void start();
    void stop();
    int tcp_port() const { return bound_port_; }  // the bound port (0 given: the one chosen)
    ServerCounters counters() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int bound_port_ = -1;
};

}  // namespace mirage::control
