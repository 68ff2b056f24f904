// SPDX-License-Identifier: Apache-2.0
// TCP frames are reassembled here by their MBAP length (docs/control.md §3): libmodbus's receive
// frames by function code and blocks per byte, so one client sending half a frame — or a
// function it does not know — would stall or desynchronise every other client. RTU framing
// (silence between frames, CRC) is libmodbus's, on its own thread.
#include "mirage/control/modbus_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <span>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::control {
namespace {

constexpr std::size_t kMbap = 7;                  // transaction, protocol, length, unit
constexpr std::size_t kMaxTcpAdu = 260;           // MODBUS_TCP_MAX_ADU_LENGTH
constexpr std::int64_t kIdleNs = 60'000'000'000;  // a silent TCP client is closed
constexpr int kBurst = 32;                        // requests per client per poll round
constexpr std::int64_t kBackoffMinNs = 100'000'000, kBackoffMaxNs = 5'000'000'000;

}  // namespace

// The types of Impl's fields live in a named namespace: a field whose type is in an anonymous
// namespace is -Wsubobject-linkage once this file is not the main file (unity builds).
namespace modbus_detail {

struct ModbusDeleter {
    void operator()(modbus_t* c) const {
        modbus_close(c);
        modbus_free(c);
    }
};
struct MappingDeleter {
    void operator()(modbus_mapping_t* m) const { modbus_mapping_free(m); }
};
using Ctx = std::unique_ptr<modbus_t, ModbusDeleter>;
using Mapping = std::unique_ptr<modbus_mapping_t, MappingDeleter>;

struct Client {
    int fd = -1;
    std::array<std::uint8_t, kMaxTcpAdu> buf{};
    std::size_t have = 0;
    std::int64_t last_ns = 0;
};

}  // namespace modbus_detail

using modbus_detail::Client;
using modbus_detail::Ctx;
using modbus_detail::Mapping;

namespace {

Mapping make_mapping(const ControlModel& m) {
    Mapping map(modbus_mapping_new_start_address(0, 0, 0, 0, 0, int(m.holding_window()), 0,
                                                 int(m.input_window())));
    if (!map) throw IoError("control: cannot allocate the Modbus register mapping");
    return map;
}

}  // namespace

struct ModbusServer::Impl {
    ControlEndpoint ep;
    ControlModel& model;
    StatusFn status;
    Ctx tcp, rtu;
    Mapping tcp_map, rtu_map;
    int listen_fd = -1;
    std::vector<Client> clients;
    std::thread tcp_thread, rtu_thread;
    std::atomic<bool> stopping{false};
    mutable std::mutex cm;
    ServerCounters c;

    Impl(ControlEndpoint e, ControlModel& m, StatusFn s)
        : ep(std::move(e)), model(m), status(std::move(s)) {}

    void count(std::uint64_t ServerCounters::*field) {
        std::lock_guard lk(cm);
        ++(c.*field);
    }
    bool answer(modbus_t* ctx, modbus_mapping_t* map, const std::uint8_t* req, int len,
                std::size_t header, std::size_t pdu_len);
    Exception decide(const std::uint8_t* pdu, std::size_t pdu_len, Request& r,
                     std::span<std::uint16_t> out);
    void open_tcp();
    void tcp_loop();
    void tcp_readable(Client& cl);
    bool connect_rtu();
    bool reconnect_rtu();
    void open_rtu();
    void rtu_loop();
};

// The model's answer to one PDU: checked, then handled. An internal error (the status callback
// failing) is exception 04, counted, never an escape from the server's thread.
Exception ModbusServer::Impl::decide(const std::uint8_t* pdu, std::size_t pdu_len, Request& r,
                                     std::span<std::uint16_t> out) {
    const Checked chk = check_request({pdu, pdu_len}, model.input_window(), model.holding_window());
    if (chk.exception != Exception::None) {
        model.count_refused();
        return chk.exception;
    }
    r = chk.request;
    try {
        if (r.function == Function::ReadInput && status) model.set_status(status());
        return model.handle(r, hostclock::monotonic_ns(), out);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mirage: control: request failed: %s\n", e.what());
        model.count_refused();
        count(&ServerCounters::internal_errors);
        return Exception::ServerFailure;
    }
}

// One request whose framing is sound: decided by the model, then replied by libmodbus from a
// mapping holding exactly what the model answered. False when the reply could not be sent whole
// (a TCP client that stopped reading: its socket is non-blocking).
bool ModbusServer::Impl::answer(modbus_t* ctx, modbus_mapping_t* map, const std::uint8_t* req,
                                int len, std::size_t header, std::size_t pdu_len) {
    Request r;
    std::array<std::uint16_t, kMaxReadCount> out{};
    const Exception e = decide(req + header, pdu_len, r, out);
    int rc = 0;
    if (e != Exception::None) {
        rc = modbus_reply_exception(ctx, req, static_cast<unsigned>(e));
    } else {
        if (r.function == Function::ReadInput)
            std::copy_n(out.begin(), r.count, map->tab_input_registers + r.address);
        else if (r.function == Function::ReadHolding)
            std::copy_n(out.begin(), r.count, map->tab_registers + r.address);
        rc = modbus_reply(ctx, req, len, map);
    }
    count(&ServerCounters::replies);
    return rc >= 0;
}

void ModbusServer::Impl::open_tcp() {
    tcp.reset(modbus_new_tcp(ep.tcp_host.c_str(), ep.tcp_port));
    if (!tcp)
        throw IoError(fmt::format("control: tcp {}: {}", ep.tcp_host, modbus_strerror(errno)));
    listen_fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    ::setsockopt(listen_fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(ep.tcp_port));
    ::inet_pton(AF_INET, ep.tcp_host.c_str(), &a.sin_addr);
    if (::bind(listen_fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        ::listen(listen_fd, 16) != 0) {
        const int err = errno;
        ::close(listen_fd);
        listen_fd = -1;
        throw IoError(
            fmt::format("control: tcp {}:{}: {}", ep.tcp_host, ep.tcp_port, std::strerror(err)));
    }
    tcp_map = make_mapping(model);
}

// A fresh context per opening: libmodbus keeps bus state (a reply of another unit to ignore)
// that must not outlive the line it was learnt on.
bool ModbusServer::Impl::connect_rtu() {
    rtu.reset(modbus_new_rtu(ep.rtu_device.c_str(), ep.baud, ep.parity, 8, ep.stop_bits));
    if (!rtu)
        throw ConfigError(
            fmt::format("control: rtu {}: {}", ep.rtu_device, modbus_strerror(errno)));
    modbus_set_slave(rtu.get(), ep.unit);
    modbus_set_byte_timeout(rtu.get(), 0, 100'000);
    modbus_set_response_timeout(rtu.get(), 0, 50'000);  // the pause before flushing a bad frame
    modbus_set_error_recovery(rtu.get(), MODBUS_ERROR_RECOVERY_PROTOCOL);
    if (modbus_connect(rtu.get()) != 0) return false;
    std::lock_guard lk(cm);
    c.rtu_open = true;
    return true;
}

// From the serial thread: a failure is one more failed attempt, never an escape.
bool ModbusServer::Impl::reconnect_rtu() {
    try {
        return connect_rtu();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mirage: control: %s\n", e.what());
        count(&ServerCounters::internal_errors);
        return false;
    }
}

void ModbusServer::Impl::open_rtu() {
    if (!connect_rtu())
        throw IoError(fmt::format("control: rtu {}: {}", ep.rtu_device, modbus_strerror(errno)));
    rtu_map = make_mapping(model);
}

// Whatever has arrived, without blocking; every complete frame answered. The MBAP header is
// checked first (protocol 0, length 2..254); a frame that fails it ends the connection, as the
// stream cannot be re-synchronised.
void ModbusServer::Impl::tcp_readable(Client& cl) {
    const auto close_client = [&cl] {
        ::close(cl.fd);
        cl.fd = -1;
    };
    // At most kBurst requests per wake-up, so a flooding client leaves the others their turn.
    for (int answered = 0; answered < kBurst;) {
        const std::size_t len = (std::size_t(cl.buf[4]) << 8) | cl.buf[5];
        const std::size_t want = cl.have < 6 ? 6 : 6 + len;
        const ssize_t n = ::recv(cl.fd, cl.buf.data() + cl.have, want - cl.have, MSG_DONTWAIT);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) return close_client();
        if (n < 0) return;
        cl.have += std::size_t(n);
        cl.last_ns = hostclock::monotonic_ns();
        if (cl.have < 6) continue;
        const std::size_t l = (std::size_t(cl.buf[4]) << 8) | cl.buf[5];
        if (cl.buf[2] != 0 || cl.buf[3] != 0 || l < 2 || 6 + l > kMaxTcpAdu) {
            count(&ServerCounters::closed_malformed);
            return close_client();
        }
        if (cl.have < 6 + l) continue;
        modbus_set_socket(tcp.get(), cl.fd);
        const bool sent =
            answer(tcp.get(), tcp_map.get(), cl.buf.data(), int(cl.have), kMbap, cl.have - kMbap);
        modbus_set_socket(tcp.get(), -1);  // the context must not close a client's descriptor
        cl.have = 0;
        ++answered;
        if (!sent) {  // a reply cut short cannot be resumed: the stream is lost
            count(&ServerCounters::closed_unread);
            return close_client();
        }
    }
}

void ModbusServer::Impl::tcp_loop() {
    pthread_setname_np(pthread_self(), "mirage-modbus");
    std::vector<pollfd> fds;
    while (!stopping.load()) {
        fds.assign(1, pollfd{listen_fd, POLLIN, 0});
        for (const auto& cl : clients) fds.push_back(pollfd{cl.fd, POLLIN, 0});
        if (::poll(fds.data(), fds.size(), 50) < 0 && errno != EINTR) break;
        const std::int64_t now = hostclock::monotonic_ns();
        for (std::size_t i = 1; i < fds.size(); ++i) {
            Client& cl = clients[i - 1];
            if (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) tcp_readable(cl);
            if (cl.fd >= 0 && now - cl.last_ns > kIdleNs) {
                ::close(cl.fd);
                cl.fd = -1;
                count(&ServerCounters::closed_idle);
            }
        }
        std::erase_if(clients, [](const Client& cl) { return cl.fd < 0; });
        if (fds[0].revents & POLLIN) {
            // Non-blocking: a client that sends but never reads must not stall this thread.
            const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
            if (fd >= 0 && clients.size() >= std::size_t(ep.max_clients)) {
                ::close(fd);
                count(&ServerCounters::refused_connections);
            } else if (fd >= 0) {
                clients.push_back(Client{fd, {}, 0, now});
                count(&ServerCounters::connections);
            }
        }
        std::lock_guard lk(cm);
        c.clients = int(clients.size());
    }
    for (auto& cl : clients) ::close(cl.fd);
    clients.clear();
}

// A line that errors or hangs up is closed and reopened, waiting 0.1 s doubling to 5 s.
void ModbusServer::Impl::rtu_loop() {
    pthread_setname_np(pthread_self(), "mirage-modbus-rtu");
    std::array<std::uint8_t, MODBUS_RTU_MAX_ADU_LENGTH> q{};
    std::int64_t backoff = kBackoffMinNs, retry_at = 0;
    bool open = true;
    const auto lost = [&] {
        modbus_close(rtu.get());
        open = false;
        retry_at = hostclock::monotonic_ns() + backoff;
        std::lock_guard lk(cm);
        c.rtu_open = false;
    };
    while (!stopping.load()) {
        if (!open) {
            if (hostclock::monotonic_ns() < retry_at) {
                ::usleep(20'000);
                continue;
            }
            if (!reconnect_rtu()) {
                backoff = std::min(backoff * 2, kBackoffMaxNs);
                retry_at = hostclock::monotonic_ns() + backoff;
                continue;
            }
            open = true;
            backoff = kBackoffMinNs;
            std::lock_guard lk(cm);
            ++c.rtu_reopens;
        }
        pollfd p{modbus_get_socket(rtu.get()), POLLIN, 0};
        if (::poll(&p, 1, 50) < 0 && errno != EINTR) continue;
        if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
            lost();
            continue;
        }
        if (!(p.revents & POLLIN)) continue;
        const int rc = modbus_receive(rtu.get(), q.data());
        if (rc == 0) continue;  // addressed to another unit
        if (rc < 0) {
            count(&ServerCounters::frame_errors);
            if (errno == EIO || errno == ENXIO || errno == EBADF || errno == ENODEV) lost();
            continue;
        }
        const auto header = std::size_t(modbus_get_header_length(rtu.get()));
        if (std::size_t(rc) < header + 2) continue;
        answer(rtu.get(), rtu_map.get(), q.data(), rc, header, std::size_t(rc) - header - 2);
    }
}

ModbusServer::ModbusServer(ControlEndpoint endpoint, ControlModel& model, StatusFn status)
    : impl_(std::make_unique<Impl>(std::move(endpoint), model, std::move(status))) {
    if (impl_->ep.tcp_port >= 0) {
        impl_->open_tcp();
        sockaddr_in a{};
        socklen_t len = sizeof a;
        ::getsockname(impl_->listen_fd, reinterpret_cast<sockaddr*>(&a), &len);
        bound_port_ = ntohs(a.sin_port);
    }
    if (!impl_->ep.rtu_device.empty()) impl_->open_rtu();
}

ModbusServer::~ModbusServer() {
    stop();
    if (impl_->listen_fd >= 0) ::close(impl_->listen_fd);
}

void ModbusServer::start() {
    if (impl_->listen_fd >= 0) impl_->tcp_thread = std::thread([this] { impl_->tcp_loop(); });
    if (impl_->rtu) impl_->rtu_thread = std::thread([this] { impl_->rtu_loop(); });
}

void ModbusServer::stop() {
    impl_->stopping = true;
    if (impl_->tcp_thread.joinable()) impl_->tcp_thread.join();
    if (impl_->rtu_thread.joinable()) impl_->rtu_thread.join();
}

ServerCounters ModbusServer::counters() const {
    std::lock_guard lk(impl_->cm);
    return impl_->c;
}

}  // namespace mirage::control
