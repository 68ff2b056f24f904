// SPDX-License-Identifier: Apache-2.0
// gs_usb (candleLight-class) CAN adapter through libusb-1.0 (docs/nav-protocols.md §10).
//
// Transfers are asynchronous: kRxTransfers bulk-IN transfers stay queued (as the Linux driver
// keeps its RX URBs queued) so no frame is lost between receive() calls, and TX echoes are
// consumed even when the caller only sends. One event thread runs libusb's event loop; receive()
// waits on a queue filled by the callbacks.
#include "mirage/can/gsusb_bus.hpp"

#include <fmt/format.h>
#include <libusb.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "gsusb_protocol.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::can {
namespace {

constexpr int kRxTransfers = 8;
constexpr std::size_t kTxSlots = 10;  // echo ids in flight (Linux: GS_MAX_TX_URBS)
constexpr int kRxBufferSize = 80;     // room for a CAN FD frame with timestamp, as Linux sizes it
constexpr unsigned kControlTimeoutMs = 1000;
constexpr unsigned kTxTimeoutMs = 1000;
constexpr std::size_t kMaxQueued = 65536;  // received frames nobody collected; oldest dropped
constexpr int kMaxConsecutiveRxErrors = 16;

std::string device_label(const GsUsbOptions& o) {
    return fmt::format("{:04x}:{:04x}", o.vendor_id, o.product_id);
}

struct Received {
    nav::CanFrame frame;
    std::int64_t host_ns = 0;
    RxStatus status = RxStatus::Frame;
};

class GsUsbBus;

struct TxSlot {
    GsUsbBus* owner = nullptr;
    std::uint32_t echo_id = 0;
    libusb_transfer* transfer = nullptr;
    std::array<std::uint8_t, gsusb::kClassicFrameSize> buffer{};
    bool out_in_flight = false;
    bool awaiting_echo = false;
    bool free() const { return !out_in_flight && !awaiting_echo; }
};

class GsUsbBus final : public CanBus {
  public:
    explicit GsUsbBus(const GsUsbOptions& options);
    ~GsUsbBus() override;
    GsUsbBus(const GsUsbBus&) = delete;
    GsUsbBus& operator=(const GsUsbBus&) = delete;

    bool send(const nav::CanFrame& frame) override;
    RxStatus receive(nav::CanFrame& out, std::int64_t& host_ns,
                     std::chrono::nanoseconds timeout) override;
    BusCounters counters() const override;
    std::string name() const override { return "gsusb:" + label_; }

  private:
    [[noreturn]] void fail(const std::string& what) const;
    void open_device();
    void find_endpoints();
    void start_up();
    void control_out(std::uint8_t request, std::uint16_t value, std::uint8_t* data,
                     std::uint16_t len, const char* what);
    void control_in(std::uint8_t request, std::uint16_t value, std::uint8_t* data,
                    std::uint16_t len, const char* what);
    void submit_rx();
    void shut_down();
    void release();

    static void LIBUSB_CALL on_rx(libusb_transfer* t);
    static void LIBUSB_CALL on_tx(libusb_transfer* t);
    void handle_rx(libusb_transfer* t);
    void handle_tx(TxSlot& slot, libusb_transfer* t);
    void take_packet(const std::uint8_t* p, std::size_t n, std::int64_t host_ns);
    void push(const Received& r);

    GsUsbOptions options_;
    std::string label_;
    libusb_context* ctx_ = nullptr;
    libusb_device_handle* handle_ = nullptr;
    bool claimed_ = false;
    std::uint8_t ep_in_ = 0x81;
    std::uint8_t ep_out_ = 0x02;
    std::thread events_;
    std::atomic<bool> stop_events_{false};

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Received> queue_;
    BusCounters counters_;
    bool closed_ = false;
    bool stopping_ = false;
    int rx_active_ = 0;
    int rx_errors_in_row_ = 0;
    std::vector<libusb_transfer*> rx_;
    std::vector<std::vector<std::uint8_t>> rx_buffers_;
    std::array<TxSlot, kTxSlots> tx_{};
};

GsUsbBus::GsUsbBus(const GsUsbOptions& options) : options_(options), label_(device_label(options)) {
    try {
        open_device();
        find_endpoints();
        for (std::size_t i = 0; i < kTxSlots; ++i) {
            tx_[i].owner = this;
            tx_[i].echo_id = static_cast<std::uint32_t>(i);
            tx_[i].transfer = libusb_alloc_transfer(0);
            if (tx_[i].transfer == nullptr) fail("out of memory for transfers");
        }
        for (int i = 0; i < kRxTransfers; ++i) {
            libusb_transfer* t = libusb_alloc_transfer(0);
            if (t == nullptr) fail("out of memory for transfers");
            rx_.push_back(t);
            rx_buffers_.emplace_back(kRxBufferSize);
        }
        events_ = std::thread([this] {
            while (!stop_events_.load()) {
                timeval tv{0, 100'000};
                libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
            }
        });
        start_up();
    } catch (...) {
        shut_down();
        release();
        throw;
    }
}

GsUsbBus::~GsUsbBus() {
    bool reset = false;
    {
        std::lock_guard lock(mutex_);
        reset = !closed_;
    }
    if (reset && handle_ != nullptr) {
        // Leave the controller off the bus, as Linux does on close (best effort).
        auto mode = gsusb::encode_mode(gsusb::kModeReset, 0);
        libusb_control_transfer(handle_, gsusb::kRequestTypeOut, gsusb::kReqMode, options_.channel,
                                0, mode.data(), static_cast<std::uint16_t>(mode.size()), 200);
    }
    shut_down();
    release();
}

void GsUsbBus::fail(const std::string& what) const {
    throw IoError(fmt::format("gsusb {}: {}", label_, what));
}

void GsUsbBus::open_device() {
    int r = libusb_init(&ctx_);
    if (r != 0) {
        ctx_ = nullptr;
        // No usbfs at all (container, no USB subsystem) means no device either.
        fail(fmt::format("no such device (libusb_init: {})", libusb_error_name(r)));
    }
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx_, &list);
    if (n < 0)
        fail(fmt::format("no such device (enumeration: {})",
                         libusb_error_name(static_cast<int>(n))));
    std::string open_error;
    bool vid_pid_seen = false;
    for (ssize_t i = 0; i < n && handle_ == nullptr; ++i) {
        libusb_device_descriptor desc{};
        if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
        if (desc.idVendor != options_.vendor_id || desc.idProduct != options_.product_id) continue;
        vid_pid_seen = true;
        libusb_device_handle* h = nullptr;
        r = libusb_open(list[i], &h);
        if (r != 0) {
            open_error =
                fmt::format("cannot open bus {} device {}: {}", libusb_get_bus_number(list[i]),
                            libusb_get_device_address(list[i]), libusb_error_name(r));
            continue;
        }
        if (!options_.serial.empty()) {
            unsigned char serial[256] = {};
            const int len = desc.iSerialNumber == 0
                                ? -1
                                : libusb_get_string_descriptor_ascii(h, desc.iSerialNumber, serial,
                                                                     sizeof(serial) - 1);
            if (len < 0 || options_.serial != std::string(reinterpret_cast<char*>(serial),
                                                          static_cast<std::size_t>(len))) {
                libusb_close(h);
                continue;
            }
        }
        handle_ = h;
    }
    libusb_free_device_list(list, 1);
    if (handle_ == nullptr) {
        if (!open_error.empty()) fail(open_error + " (permissions? udev rule for the adapter)");
        if (vid_pid_seen && !options_.serial.empty())
            fail(fmt::format("no such device with serial '{}'", options_.serial));
        fail("no such device");
    }
    // A bound gs_usb kernel driver would hold the interface; take it over for the session.
    libusb_set_auto_detach_kernel_driver(handle_, 1);
    r = libusb_claim_interface(handle_, 0);
    if (r != 0) fail(fmt::format("cannot claim interface 0: {}", libusb_error_name(r)));
    claimed_ = true;
}

void GsUsbBus::find_endpoints() {
    // Defaults are candleLight's (0x81 / 0x02); take the first bulk pair of interface 0 if the
    // descriptor says otherwise (clones differ).
    libusb_device* dev = libusb_get_device(handle_);
    libusb_config_descriptor* cfg = nullptr;
    if (libusb_get_active_config_descriptor(dev, &cfg) != 0 || cfg == nullptr) return;
    if (cfg->bNumInterfaces > 0 && cfg->interface[0].num_altsetting > 0) {
        const libusb_interface_descriptor& alt = cfg->interface[0].altsetting[0];
        bool in = false, out = false;
        for (int e = 0; e < alt.bNumEndpoints; ++e) {
            const libusb_endpoint_descriptor& ep = alt.endpoint[e];
            if ((ep.bmAttributes & 0x03) != LIBUSB_TRANSFER_TYPE_BULK) continue;
            if ((ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) != 0) {
                if (!in) ep_in_ = ep.bEndpointAddress;
                in = true;
            } else {
                if (!out) ep_out_ = ep.bEndpointAddress;
                out = true;
            }
        }
    }
    libusb_free_config_descriptor(cfg);
}

void GsUsbBus::control_out(std::uint8_t request, std::uint16_t value, std::uint8_t* data,
                           std::uint16_t len, const char* what) {
    const int r = libusb_control_transfer(handle_, gsusb::kRequestTypeOut, request, value, 0, data,
                                          len, kControlTimeoutMs);
    if (r < 0) fail(fmt::format("{} failed: {}", what, libusb_error_name(r)));
    if (r != len) fail(fmt::format("{}: device took {} of {} bytes", what, r, len));
}

void GsUsbBus::control_in(std::uint8_t request, std::uint16_t value, std::uint8_t* data,
                          std::uint16_t len, const char* what) {
    const int r = libusb_control_transfer(handle_, gsusb::kRequestTypeIn, request, value, 0, data,
                                          len, kControlTimeoutMs);
    if (r < 0) fail(fmt::format("{} failed: {}", what, libusb_error_name(r)));
    if (r != len) fail(fmt::format("{}: expected {} bytes, got {}", what, len, r));
}

void GsUsbBus::start_up() {
    // The Linux driver's order (gs_usb_probe, gs_can_open); wValue 1 for the two device-wide
    // requests, the channel for the others.
    auto host_format = gsusb::encode_host_format();
    control_out(gsusb::kReqHostFormat, 1, host_format.data(), 4, "HOST_FORMAT");

    std::array<std::uint8_t, gsusb::kDeviceConfigSize> dc{};
    control_in(gsusb::kReqDeviceConfig, 1, dc.data(), static_cast<std::uint16_t>(dc.size()),
               "DEVICE_CONFIG");
    const gsusb::DeviceConfig config = gsusb::parse_device_config(dc.data());
    if (options_.channel > config.icount)
        throw ConfigError(fmt::format("gsusb {}: channel {} requested, the device has {}", label_,
                                      options_.channel, config.icount + 1));

    std::array<std::uint8_t, gsusb::kBtConstSize> btc{};
    control_in(gsusb::kReqBtConst, options_.channel, btc.data(),
               static_cast<std::uint16_t>(btc.size()), "BT_CONST");
    const gsusb::BtConst limits = gsusb::parse_bt_const(btc.data());
    const auto timing = gsusb::compute_bit_timing(limits, options_.bitrate);
    if (!timing)
        throw ConfigError(fmt::format(
            "gsusb {}: bitrate {} not reachable with fclk {} Hz (tseg1 {}..{}, tseg2 {}..{}, "
            "brp {}..{})",
            label_, options_.bitrate, limits.fclk_can, limits.tseg1_min, limits.tseg1_max,
            limits.tseg2_min, limits.tseg2_max, limits.brp_min, limits.brp_max));
    auto bt = gsusb::encode_bit_timing(*timing);
    control_out(gsusb::kReqBitTiming, options_.channel, bt.data(),
                static_cast<std::uint16_t>(bt.size()), "BITTIMING");

    // RX transfers go in before the controller starts, so the first frame finds one waiting.
    submit_rx();
    auto mode = gsusb::encode_mode(gsusb::kModeStart,
                                   options_.listen_only ? gsusb::kModeFlagListenOnly : 0);
    control_out(gsusb::kReqMode, options_.channel, mode.data(),
                static_cast<std::uint16_t>(mode.size()), "MODE START");
}

void GsUsbBus::submit_rx() {
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < rx_.size(); ++i) {
        libusb_fill_bulk_transfer(rx_[i], handle_, ep_in_, rx_buffers_[i].data(), kRxBufferSize,
                                  &GsUsbBus::on_rx, this, 0);
        const int r = libusb_submit_transfer(rx_[i]);
        if (r != 0) fail(fmt::format("cannot queue bulk IN transfers: {}", libusb_error_name(r)));
        ++rx_active_;
    }
}

// Cancels every transfer still queued and waits for libusb to hand them back: a transfer may only
// be freed once its callback has run (the device answers DISCARDURB by completing the URB).
void GsUsbBus::shut_down() {
    std::unique_lock lock(mutex_);
    stopping_ = true;
    if (events_.joinable()) {
        for (libusb_transfer* t : rx_) libusb_cancel_transfer(t);
        for (TxSlot& s : tx_)
            if (s.out_in_flight) libusb_cancel_transfer(s.transfer);
        const bool drained = cv_.wait_for(lock, std::chrono::seconds(2), [this] {
            if (rx_active_ > 0) return false;
            for (const TxSlot& s : tx_)
                if (s.out_in_flight) return false;
            return true;
        });
        if (!drained) {
            // Never free a transfer libusb still owns; leak them instead.
            rx_.clear();
            for (TxSlot& s : tx_) s.transfer = nullptr;
        }
    }
    lock.unlock();
    stop_events_.store(true);
    if (ctx_ != nullptr) libusb_interrupt_event_handler(ctx_);
    if (events_.joinable()) events_.join();
}

void GsUsbBus::release() {
    for (libusb_transfer* t : rx_) libusb_free_transfer(t);
    rx_.clear();
    for (TxSlot& s : tx_) {
        if (s.transfer != nullptr) libusb_free_transfer(s.transfer);
        s.transfer = nullptr;
    }
    if (handle_ != nullptr) {
        if (claimed_) libusb_release_interface(handle_, 0);
        libusb_close(handle_);
        handle_ = nullptr;
    }
    if (ctx_ != nullptr) libusb_exit(ctx_);
    ctx_ = nullptr;
}

void LIBUSB_CALL GsUsbBus::on_rx(libusb_transfer* t) {
    static_cast<GsUsbBus*>(t->user_data)->handle_rx(t);
}

void LIBUSB_CALL GsUsbBus::on_tx(libusb_transfer* t) {
    auto* slot = static_cast<TxSlot*>(t->user_data);
    slot->owner->handle_tx(*slot, t);
}

void GsUsbBus::push(const Received& r) {
    if (queue_.size() >= kMaxQueued) queue_.pop_front();
    queue_.push_back(r);
}

// Called with mutex_ held.
void GsUsbBus::take_packet(const std::uint8_t* p, std::size_t n, std::int64_t host_ns) {
    const gsusb::DecodedHostFrame d = gsusb::decode_host_frame(p, n, options_.channel);
    switch (d.kind) {
        case gsusb::HostFrameKind::Malformed:
            ++counters_.malformed;
            return;
        case gsusb::HostFrameKind::Echo: {
            if (d.echo_id >= kTxSlots || !tx_[d.echo_id].awaiting_echo) {
                ++counters_.malformed;  // an echo for nothing we sent
                return;
            }
            tx_[d.echo_id].awaiting_echo = false;
            ++counters_.tx_frames;
            return;
        }
        case gsusb::HostFrameKind::Received:
            break;
    }
    Received r;
    r.frame = d.frame;
    r.host_ns = host_ns;
    if (d.frame.error) {
        r.status = RxStatus::ErrorFrame;
        ++counters_.error_frames;
        if ((d.frame.id & gsusb::kCanErrBusOff) != 0) ++counters_.bus_off;
    } else {
        ++counters_.rx_frames;
    }
    push(r);
}

void GsUsbBus::handle_rx(libusb_transfer* t) {
    const std::int64_t now = hostclock::monotonic_ns();
    std::lock_guard lock(mutex_);
    bool resubmit = !stopping_ && !closed_;
    switch (t->status) {
        case LIBUSB_TRANSFER_COMPLETED:
            rx_errors_in_row_ = 0;
            if (t->actual_length > 0)
                take_packet(t->buffer, static_cast<std::size_t>(t->actual_length), now);
            break;
        case LIBUSB_TRANSFER_TIMED_OUT:  // not armed (timeout 0); harmless
            break;
        case LIBUSB_TRANSFER_CANCELLED:
            resubmit = false;
            break;
        case LIBUSB_TRANSFER_NO_DEVICE:
            closed_ = true;
            resubmit = false;
            break;
        case LIBUSB_TRANSFER_OVERFLOW:  // more bytes than any gs_host_frame
            ++counters_.malformed;
            break;
        case LIBUSB_TRANSFER_ERROR:
        case LIBUSB_TRANSFER_STALL:
            // Transient on a flaky cable; persistent means the adapter is gone or wedged.
            if (++rx_errors_in_row_ > kMaxConsecutiveRxErrors) {
                closed_ = true;
                resubmit = false;
            }
            break;
    }
    if (resubmit) {
        const int r = libusb_submit_transfer(t);
        if (r != 0) {
            resubmit = false;
            if (r == LIBUSB_ERROR_NO_DEVICE) closed_ = true;
        }
    }
    if (!resubmit) {
        --rx_active_;
        // With no IN transfer left nothing can arrive any more.
        if (rx_active_ == 0 && !stopping_) closed_ = true;
    }
    cv_.notify_all();
}

void GsUsbBus::handle_tx(TxSlot& slot, libusb_transfer* t) {
    std::lock_guard lock(mutex_);
    slot.out_in_flight = false;
    if (t->status != LIBUSB_TRANSFER_COMPLETED || t->actual_length != t->length) {
        // The device never got it, so no echo will come.
        if (slot.awaiting_echo) ++counters_.tx_failed;
        slot.awaiting_echo = false;
        if (t->status == LIBUSB_TRANSFER_NO_DEVICE) closed_ = true;
    }
    cv_.notify_all();
}

bool GsUsbBus::send(const nav::CanFrame& frame) {
    std::lock_guard lock(mutex_);
    if (closed_ || stopping_ || !gsusb::valid_tx_frame(frame)) {
        ++counters_.tx_failed;
        return false;
    }
    TxSlot* slot = nullptr;
    for (TxSlot& s : tx_)
        if (s.free() && s.transfer != nullptr) {
            slot = &s;
            break;
        }
    if (slot == nullptr) {  // every echo id in flight: the device is not getting frames out
        ++counters_.tx_failed;
        return false;
    }
    slot->buffer = gsusb::encode_host_frame(frame, slot->echo_id, options_.channel);
    libusb_fill_bulk_transfer(slot->transfer, handle_, ep_out_, slot->buffer.data(),
                              static_cast<int>(slot->buffer.size()), &GsUsbBus::on_tx, slot,
                              kTxTimeoutMs);
    const int r = libusb_submit_transfer(slot->transfer);
    if (r != 0) {
        if (r == LIBUSB_ERROR_NO_DEVICE) closed_ = true;
        ++counters_.tx_failed;
        return false;
    }
    slot->out_in_flight = true;
    slot->awaiting_echo = true;
    return true;
}

RxStatus GsUsbBus::receive(nav::CanFrame& out, std::int64_t& host_ns,
                           std::chrono::nanoseconds timeout) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, timeout, [this] { return !queue_.empty() || closed_; });
    if (!queue_.empty()) {
        const Received r = queue_.front();
        queue_.pop_front();
        out = r.frame;
        host_ns = r.host_ns;
        return r.status;
    }
    return closed_ ? RxStatus::Closed : RxStatus::Timeout;
}

BusCounters GsUsbBus::counters() const {
    std::lock_guard lock(mutex_);
    return counters_;
}

}  // namespace

std::unique_ptr<CanBus> open_gsusb(const GsUsbOptions& options) {
    return std::make_unique<GsUsbBus>(options);
}

}  // namespace mirage::can
