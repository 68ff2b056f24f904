// SPDX-License-Identifier: Apache-2.0
#pragma once
// A fake candleLight (gs_usb) device for umockdev (docs/nav-protocols.md §13.3): answers the
// usbdevfs ioctls libusb issues on /dev/bus/usb/001/002, serves the gs_usb control requests, echoes
// bulk-OUT frames and lets the test inject bulk-IN packets or unplug the device.
//
// The handler runs on umockdev's worker thread; the test thread talks to it through `mutex_`.
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <umockdev.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace mirage::test {

class FakeCandleLight {
  public:
    struct Control {
        std::uint8_t request_type = 0;
        std::uint8_t request = 0;
        std::uint16_t value = 0;
        std::uint16_t index = 0;
        std::vector<std::uint8_t> data;  // OUT: what the host sent; IN: what we answered
    };

    static constexpr std::uint32_t kFclk = 48'000'000;  // candleLight (STM32F042) CAN clock
    static constexpr const char* kSerial = "MIRAGE0001";

    FakeCandleLight() : handler_(umockdev_ioctl_base_new()) {
        g_signal_connect(handler_, "handle-ioctl", G_CALLBACK(&FakeCandleLight::on_ioctl), this);
    }
    ~FakeCandleLight() {
        {
            std::lock_guard lock(mutex_);
            for (UMockdevIoctlData* d : pending_in_) g_object_unref(d);
            for (UMockdevIoctlData* d : reap_) g_object_unref(d);
            pending_in_.clear();
            reap_.clear();
        }
        g_object_unref(handler_);
    }
    FakeCandleLight(const FakeCandleLight&) = delete;
    FakeCandleLight& operator=(const FakeCandleLight&) = delete;

    UMockdevIoctlBase* handler() { return handler_; }

    // Device → host: queued until the host has a bulk-IN URB waiting.
    void inject(std::vector<std::uint8_t> packet) {
        std::lock_guard lock(mutex_);
        to_host_.push_back(std::move(packet));
        match_locked();
    }

    // The cable is pulled: queued IN URBs die with -ESHUTDOWN, every later ioctl fails ENODEV.
    void unplug() {
        std::lock_guard lock(mutex_);
        unplugged_ = true;
        while (!pending_in_.empty()) {
            UMockdevIoctlData* urb = pending_in_.front();
            pending_in_.pop_front();
            auto* u = reinterpret_cast<usbdevfs_urb*>(urb->data);
            u->status = -ESHUTDOWN;
            u->actual_length = 0;
            reap_.push_back(urb);
        }
    }

    void set_echo(bool on) {
        std::lock_guard lock(mutex_);
        echo_ = on;
    }

    std::vector<Control> controls() const {
        std::lock_guard lock(mutex_);
        return controls_;
    }
    std::vector<std::vector<std::uint8_t>> bulk_out() const {
        std::lock_guard lock(mutex_);
        return bulk_out_;
    }
    int discards() const {
        std::lock_guard lock(mutex_);
        return discards_;
    }
    std::size_t pending_in() const {
        std::lock_guard lock(mutex_);
        return pending_in_.size();
    }
    std::vector<unsigned long> unknown_requests() const {
        std::lock_guard lock(mutex_);
        return unknown_;
    }

    // Waits (condition variable, bounded) until `pred` holds for the fake's state.
    bool wait_until(const std::function<bool()>& pred,
                    std::chrono::milliseconds limit = std::chrono::milliseconds(2000)) {
        std::unique_lock lock(mutex_);
        return cv_.wait_for(lock, limit, [&] {
            lock.unlock();
            const bool ok = pred();
            lock.lock();
            return ok;
        });
    }

  private:
    static gboolean on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self) {
        return static_cast<FakeCandleLight*>(self)->handle(client);
    }

    static void put_u32(std::vector<std::uint8_t>& v, std::uint32_t x) {
        for (int i = 0; i < 4; ++i) v.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
    }

    // Answers one control request. Returns the data stage for IN requests, or false to stall.
    bool control(const std::uint8_t* setup, std::vector<std::uint8_t>& in_data,
                 const std::uint8_t* out_data) {
        Control c;
        c.request_type = setup[0];
        c.request = setup[1];
        c.value = static_cast<std::uint16_t>(setup[2] | (setup[3] << 8));
        c.index = static_cast<std::uint16_t>(setup[4] | (setup[5] << 8));
        const std::uint16_t length = static_cast<std::uint16_t>(setup[6] | (setup[7] << 8));
        bool ok = true;
        if (c.request_type == 0x41) {
            c.data.assign(out_data, out_data + length);
        } else if (c.request_type == 0xC1 && c.request == 5) {  // DEVICE_CONFIG
            in_data = {0, 0, 0, 0};                             // reserved[3], icount = 0
            put_u32(in_data, 2);                                // sw_version
            put_u32(in_data, 1);                                // hw_version
        } else if (c.request_type == 0xC1 && c.request == 4) {  // BT_CONST
            for (std::uint32_t v : {0u, kFclk, 1u, 16u, 1u, 8u, 4u, 1u, 1024u, 1u})
                put_u32(in_data, v);
        } else if (c.request_type == 0x80 && c.request == 6 && (c.value >> 8) == 3) {
            const unsigned index = c.value & 0xFF;  // string descriptor
            const std::string s = index == 1   ? "bytewerk"
                                  : index == 2 ? "candleLight USB to CAN adapter"
                                  : index == 3 ? kSerial
                                               : "";
            if (index == 0) {
                in_data = {4, 3, 0x09, 0x04};  // LANGID en-US
            } else if (!s.empty()) {
                in_data = {static_cast<std::uint8_t>(2 + 2 * s.size()), 3};
                for (char ch : s) {
                    in_data.push_back(static_cast<std::uint8_t>(ch));
                    in_data.push_back(0);
                }
            } else {
                ok = false;
            }
        } else {
            ok = false;
        }
        if (in_data.size() > length) in_data.resize(length);
        if (c.request_type & 0x80) c.data = in_data;
        if (c.request_type == 0x41 || c.request_type == 0xC1) controls_.push_back(c);
        return ok;
    }

    // Completes waiting bulk-IN URBs with queued device → host packets. mutex_ held.
    void match_locked() {
        while (!to_host_.empty() && !pending_in_.empty() && !unplugged_) {
            UMockdevIoctlData* urb = pending_in_.front();
            pending_in_.pop_front();
            auto* u = reinterpret_cast<usbdevfs_urb*>(urb->data);
            const std::vector<std::uint8_t>& p = to_host_.front();
            const std::size_t n = std::min(p.size(), static_cast<std::size_t>(u->buffer_length));
            std::memcpy(u->buffer, p.data(), n);  // `buffer` was resolved to local memory
            u->actual_length = static_cast<int>(n);
            u->status = 0;
            to_host_.pop_front();
            reap_.push_back(urb);
        }
        cv_.notify_all();
    }

    gboolean handle(UMockdevIoctlClient* client) {
        const unsigned long request = umockdev_ioctl_client_get_request(client);
        UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
        GError* error = nullptr;
        std::lock_guard lock(mutex_);
        long result = 0;
        int err = 0;
        if (request == USBDEVFS_GET_CAPABILITIES) {
            UMockdevIoctlData* caps =
                umockdev_ioctl_data_resolve(arg, 0, sizeof(std::uint32_t), &error);
            if (caps != nullptr) {
                std::memset(caps->data, 0, sizeof(std::uint32_t));
                g_object_unref(caps);
            }
        } else if (unplugged_ && request != USBDEVFS_REAPURBNDELAY && request != USBDEVFS_REAPURB) {
            result = -1;
            err = ENODEV;
        } else if (request == USBDEVFS_CLAIMINTERFACE || request == USBDEVFS_RELEASEINTERFACE ||
                   request == USBDEVFS_DISCONNECT_CLAIM) {
            // Claimed; no kernel driver to detach.
        } else if (request == USBDEVFS_GETDRIVER || request == USBDEVFS_IOCTL) {
            result = -1;
            err = ENODATA;
        } else if (request == USBDEVFS_SUBMITURB) {
            UMockdevIoctlData* urb =
                umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), &error);
            if (urb == nullptr) {
                umockdev_ioctl_client_complete(client, -1, EFAULT);
                if (error != nullptr) g_error_free(error);
                return TRUE;
            }
            auto* u = reinterpret_cast<usbdevfs_urb*>(urb->data);
            UMockdevIoctlData* buf = umockdev_ioctl_data_resolve(
                urb, offsetof(usbdevfs_urb, buffer), static_cast<gsize>(u->buffer_length), &error);
            auto* bytes = buf != nullptr ? buf->data : nullptr;
            if (buf != nullptr) g_object_unref(buf);  // `urb` keeps its buffer alive
            // resolve() returned a reference to `urb`; it is kept until the URB is reaped.
            if (u->type == USBDEVFS_URB_TYPE_CONTROL && bytes != nullptr) {
                std::vector<std::uint8_t> in_data;
                if (control(bytes, in_data, bytes + 8)) {
                    std::memcpy(bytes + 8, in_data.data(), in_data.size());
                    u->actual_length =
                        (bytes[0] & 0x80) ? static_cast<int>(in_data.size()) : u->buffer_length - 8;
                    u->status = 0;
                } else {
                    u->actual_length = 0;
                    u->status = -EPIPE;  // stall
                }
                reap_.push_back(urb);
            } else if (u->type == USBDEVFS_URB_TYPE_BULK && (u->endpoint & 0x80) == 0) {
                std::vector<std::uint8_t> out(bytes, bytes + u->buffer_length);
                bulk_out_.push_back(out);
                u->actual_length = u->buffer_length;
                u->status = 0;
                reap_.push_back(urb);
                if (echo_) to_host_.push_back(out);  // TX confirmation, same echo_id
            } else if (u->type == USBDEVFS_URB_TYPE_BULK) {
                pending_in_.push_back(urb);
            } else {
                g_object_unref(urb);
                result = -1;
                err = EINVAL;
            }
            match_locked();
        } else if (request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY) {
            match_locked();
            if (reap_.empty()) {
                result = -1;
                err = unplugged_ ? ENODEV : EAGAIN;
            } else {
                UMockdevIoctlData* urb = reap_.front();
                reap_.pop_front();
                UMockdevIoctlData* ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), &error);
                umockdev_ioctl_data_set_ptr(ptr, 0, urb);  // the parent now holds it
                g_object_unref(urb);
                g_object_unref(ptr);
            }
        } else if (request == USBDEVFS_DISCARDURB) {
            // libusb cancels with DISCARDURB and then waits to reap the URB: hand it back with
            // -ENOENT (§13.3 pitfall), or libusb waits forever.
            const unsigned long addr = *reinterpret_cast<unsigned long*>(arg->data);
            result = -1;
            err = EINVAL;
            for (auto it = pending_in_.begin(); it != pending_in_.end(); ++it) {
                if ((*it)->client_addr != addr) continue;
                auto* u = reinterpret_cast<usbdevfs_urb*>((*it)->data);
                u->status = -ENOENT;
                u->actual_length = 0;
                reap_.push_back(*it);
                pending_in_.erase(it);
                ++discards_;
                result = 0;
                err = 0;
                break;
            }
        } else {
            unknown_.push_back(request);
            result = -1;
            err = ENOTTY;
        }
        if (error != nullptr) g_error_free(error);
        umockdev_ioctl_client_complete(client, result, err);
        cv_.notify_all();
        return TRUE;
    }

    UMockdevIoctlBase* handler_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::vector<Control> controls_;
    std::vector<std::vector<std::uint8_t>> bulk_out_;
    std::deque<std::vector<std::uint8_t>> to_host_;
    std::deque<UMockdevIoctlData*> pending_in_;
    std::deque<UMockdevIoctlData*> reap_;
    std::vector<unsigned long> unknown_;
    int discards_ = 0;
    bool unplugged_ = false;
    bool echo_ = true;
};

}  // namespace mirage::test
