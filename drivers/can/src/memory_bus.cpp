// SPDX-License-Identifier: Apache-2.0
#include "mirage/can/memory_bus.hpp"

#include <time.h>

#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <vector>

#include "bus_counting.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::can {
namespace {

struct Port;

// One named bus: the ports attached to it. A single mutex per hub keeps send order identical
// for every receiver.
struct Hub {
    std::mutex mutex;
    std::vector<Port*> ports;
};

struct Entry {
    nav::CanFrame frame;
    std::int64_t t_ns;
};

struct Port {
    std::condition_variable cv;
    std::deque<Entry> queue;  // guarded by the hub's mutex
    detail::AtomicBusCounters counters;
};

// Names -> hubs; a hub lives while a bus holds it.
std::mutex registry_mutex;
std::map<std::string, std::weak_ptr<Hub>>& registry() {
    static std::map<std::string, std::weak_ptr<Hub>> r;
    return r;
}

class MemoryBus final : public CanBus {
  public:
    explicit MemoryBus(std::string name) : name_(std::move(name)) {
        {
            std::lock_guard lock(registry_mutex);
            auto& slot = registry()[name_];
            hub_ = slot.lock();
            if (!hub_) {
                hub_ = std::make_shared<Hub>();
                slot = hub_;
            }
        }
        std::lock_guard lock(hub_->mutex);
        hub_->ports.push_back(&port_);
    }

    ~MemoryBus() override {
        {
            std::lock_guard lock(hub_->mutex);
            std::erase(hub_->ports, &port_);
        }
        std::lock_guard lock(registry_mutex);
        auto it = registry().find(name_);
        hub_.reset();
        if (it != registry().end() && it->second.expired()) registry().erase(it);
    }

    bool send(const nav::CanFrame& frame) override {
        if (frame.len > 8 || (!frame.extended && !frame.error && frame.id > 0x7FF) ||
            frame.id > 0x1FFFFFFF) {
            ++port_.counters.tx_failed;
            return false;
        }
        const Entry e{frame, hostclock::monotonic_ns()};
        {
            std::lock_guard lock(hub_->mutex);
            for (Port* p : hub_->ports) {
                if (p == &port_) continue;
                if (p->queue.size() >= kMemoryBusQueue) {
                    ++p->counters.rx_overruns;
                    continue;
                }
                p->queue.push_back(e);
                p->cv.notify_one();
            }
        }
        ++port_.counters.tx_frames;
        return true;
    }

    RxStatus receive(nav::CanFrame& out, std::int64_t& host_ns,
                     std::chrono::nanoseconds timeout) override {
        std::unique_lock lock(hub_->mutex);
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        if (!port_.cv.wait_until(lock, deadline, [&] { return !port_.queue.empty(); }))
            return RxStatus::Timeout;
        const Entry e = port_.queue.front();
        port_.queue.pop_front();
        lock.unlock();
        out = e.frame;
        host_ns = e.t_ns;
        return port_.counters.count_rx(out);
    }

    BusCounters counters() const override { return port_.counters.snapshot(); }
    std::string name() const override { return "memory:" + name_; }

  private:
    std::string name_;
    std::shared_ptr<Hub> hub_;
    Port port_;
};

}  // namespace

std::unique_ptr<CanBus> open_memory_bus(const std::string& name) {
    return std::make_unique<MemoryBus>(name);
}

}  // namespace mirage::can
