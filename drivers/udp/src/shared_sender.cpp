// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/shared_sender.hpp"

#include <fmt/format.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/pacing_probe.hpp"

namespace mirage::udp {
namespace {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

timespec to_timespec(std::int64_t ns) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return ts;
}

std::uint32_t* word(std::atomic<std::uint32_t>& a) { return reinterpret_cast<std::uint32_t*>(&a); }

// Sleeps while the word still holds `seen`, until the absolute CLOCK_MONOTONIC instant (none:
// forever). FUTEX_WAIT_BITSET takes an absolute time on CLOCK_MONOTONIC, unlike FUTEX_WAIT.
void futex_wait_until(std::atomic<std::uint32_t>& w, std::uint32_t seen, std::int64_t until_ns) {
    const timespec ts = to_timespec(until_ns);
    syscall(SYS_futex, word(w), FUTEX_WAIT_BITSET_PRIVATE, seen,
            until_ns == INT64_MAX ? nullptr : &ts, nullptr, FUTEX_BITSET_MATCH_ANY);
}

void futex_wake_one(std::atomic<std::uint32_t>& w) {
    syscall(SYS_futex, word(w), FUTEX_WAKE_PRIVATE, 1, nullptr, nullptr, 0);
}

}  // namespace

bool SharedSender::later(const Entry& a, const Entry& b) {
    return a.deadline_ns != b.deadline_ns ? a.deadline_ns > b.deadline_ns : a.seq > b.seq;
}

SharedSender::SharedSender(SharedSenderConfig config) : config_(config) {
    if (config_.capacity == 0 || config_.capacity > UINT32_MAX)
        throw ConfigError(fmt::format("shared sender: capacity {}: expected 1 to 2^32-1 packets",
                                      config_.capacity));
    if (config_.spin_margin.count() < 0 || config_.horizon.count() < 0)
        throw ConfigError("shared sender: spin_margin and horizon must not be negative");
    slots_.resize(config_.capacity);
    free_.reserve(config_.capacity);
    heap_.reserve(config_.capacity);
    for (std::size_t i = config_.capacity; i-- > 0;) {
        slots_[i].bytes.resize(config_.slot_bytes);
        free_.push_back(static_cast<std::uint32_t>(i));
    }
    thread_ = std::thread([this] { run(); });
    // Wait for the thread to settle its scheduling policy, so fifo() is meaningful at once.
    std::unique_lock lock(mutex_);
    space_.wait(lock, [this] { return started_.load(std::memory_order_acquire); });
}

SharedSender::~SharedSender() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
        futex_word_.fetch_add(1, std::memory_order_release);
    }
    futex_wake_one(futex_word_);
    cv_.notify_one();
    thread_.join();
}

SharedSender::ChannelId SharedSender::open(UdpSender& dest) {
    std::lock_guard lock(mutex_);
    channels_.push_back(std::make_unique<Channel>(config_.late_threshold));
    channels_.back()->dest = &dest;
    return static_cast<ChannelId>(channels_.size() - 1);
}

void SharedSender::close(ChannelId id) {
    flush(id);
    std::lock_guard lock(mutex_);
    if (id < channels_.size()) channels_[id]->dest = nullptr;
}

void SharedSender::flush(ChannelId id) {
    std::unique_lock lock(mutex_);
    if (id >= channels_.size()) return;
    Channel& ch = *channels_[id];
    ++space_waiters_;
    space_.wait(lock, [&] { return ch.pending == 0; });
    --space_waiters_;
}

std::uint64_t SharedSender::discard(ChannelId id) {
    std::lock_guard lock(mutex_);
    if (id >= channels_.size()) return 0;
    const auto mine = [&](const Entry& e) { return slots_[e.slot].channel == id; };
    std::uint64_t n = 0;
    for (const Entry& e : heap_)
        if (mine(e)) {
            free_.push_back(e.slot);
            ++n;
        }
    if (n == 0) return 0;
    std::erase_if(heap_, mine);
    std::make_heap(heap_.begin(), heap_.end(), later);
    Channel& ch = *channels_[id];
    ch.pending -= n;
    ch.discarded.fetch_add(n, std::memory_order_relaxed);
    if (space_waiters_ > 0) space_.notify_all();
    return n;
}

LatenessHistogram SharedSender::lateness(ChannelId id) const {
    std::lock_guard lock(mutex_);
    return id < channels_.size() ? channels_[id]->stats : LatenessHistogram(config_.late_threshold);
}

LatenessHistogram SharedSender::wake_lateness() const {
    std::lock_guard lock(mutex_);
    return wake_late_;
}

LatenessHistogram SharedSender::send_durations(ChannelId id) const {
    std::lock_guard lock(mutex_);
    return id < channels_.size() ? channels_[id]->send_ns : LatenessHistogram();
}

ChannelCounters SharedSender::counters(ChannelId id) const {
    const Channel* ch = nullptr;
    {
        std::lock_guard lock(mutex_);
        if (id >= channels_.size()) return {};
        ch = channels_[id].get();  // channels are never destroyed before the sender
    }
    ChannelCounters c;
    c.submitted = ch->submitted.load(std::memory_order_relaxed);
    c.sent = ch->sent.load(std::memory_order_relaxed);
    c.failed = ch->failed.load(std::memory_order_relaxed);
    c.late = ch->late.load(std::memory_order_relaxed);
    c.discarded = ch->discarded.load(std::memory_order_relaxed);
    c.worst = core::Nanos{ch->worst_ns.load(std::memory_order_relaxed)};
    return c;
}

std::string SharedSender::fifo_error() const {
    return started_.load(std::memory_order_acquire) ? fifo_error_ : std::string();
}

double SharedSender::cpu_seconds() const {
    clockid_t cid{};
    timespec ts{};
    if (pthread_getcpuclockid(const_cast<std::thread&>(thread_).native_handle(), &cid) != 0 ||
        clock_gettime(cid, &ts) != 0)
        return 0;
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) / 1e9;
}

bool SharedSender::submit(ChannelId id, wire::Stream stream, std::int64_t deadline_ns,
                          std::span<const std::uint8_t> bytes) {
    // Backpressure 1: stay at most `horizon` ahead of the schedule (no lock held while asleep).
    if (deadline_ns - hostclock::monotonic_ns() > config_.horizon.count()) {
        horizon_waits_.fetch_add(1, std::memory_order_relaxed);
        hostclock::sleep_until_monotonic(deadline_ns - config_.horizon.count());
    }
    std::unique_lock lock(mutex_);
    if (id >= channels_.size() || channels_[id]->dest == nullptr) return false;
    Channel& ch = *channels_[id];
    // Backpressure 2: a free slot.
    if (free_.empty()) {
        full_waits_.fetch_add(1, std::memory_order_relaxed);
        ++space_waiters_;
        space_.wait(lock, [this] { return !free_.empty(); });
        --space_waiters_;
    }
    const std::uint32_t s = free_.back();
    free_.pop_back();
    ++ch.pending;
    lock.unlock();

    // The slot is ours until it is queued: copy without holding the lock. A slot's buffer grows
    // only the first time it holds a larger packet.
    Slot& slot = slots_[s];
    if (slot.bytes.size() < bytes.size()) slot.bytes.resize(bytes.size());
    if (!bytes.empty()) std::memcpy(slot.bytes.data(), bytes.data(), bytes.size());
    slot.size = bytes.size();
    slot.channel = id;
    slot.stream = stream;
    ch.submitted.fetch_add(1, std::memory_order_relaxed);

    lock.lock();
    heap_.push_back(Entry{deadline_ns, next_seq_++, s});
    std::push_heap(heap_.begin(), heap_.end(), later);
    // Wake the thread only if it sleeps toward a later instant than this packet needs.
    const bool wake = sleeping_ && deadline_ns - config_.spin_margin.count() < planned_wake_ns_;
    if (wake) {
        planned_wake_ns_ = INT64_MIN;  // one wake-up is enough until it re-plans
        futex_word_.fetch_add(1, std::memory_order_release);
    }
    lock.unlock();
    if (wake) {
        wakeups_.fetch_add(1, std::memory_order_relaxed);
        if (config_.wake == WakeMethod::Futex)
            futex_wake_one(futex_word_);
        else
            cv_.notify_one();
    }
    return true;
}

void SharedSender::sleep_until(std::int64_t wake_ns, std::unique_lock<std::mutex>& lock) {
    planned_wake_ns_ = wake_ns;
    sleeping_ = true;
    if (config_.wake == WakeMethod::Futex) {
        const std::uint32_t seen = futex_word_.load(std::memory_order_acquire);
        lock.unlock();
        futex_wait_until(futex_word_, seen, wake_ns);
        const std::int64_t woke = hostclock::monotonic_ns();
        lock.lock();
        // A submit that moved the plan (planned_wake_ns_ reset) cut the sleep short on purpose.
        if (wake_ns != INT64_MAX && planned_wake_ns_ == wake_ns && woke >= wake_ns)
            wake_late_.add(core::Nanos{woke - wake_ns});
    } else if (wake_ns == INT64_MAX) {
        cv_.wait(lock);
    } else {
        // libstdc++'s steady_clock is CLOCK_MONOTONIC and waits with pthread_cond_clockwait.
        cv_.wait_until(lock,
                       std::chrono::steady_clock::time_point(std::chrono::nanoseconds(wake_ns)));
    }
    sleeping_ = false;
    planned_wake_ns_ = INT64_MAX;
}

void SharedSender::run() {
    pthread_setname_np(pthread_self(), "mirage-sender");  // for top, perf and ps
    // Timer slack (50 µs by default) would delay every wake-up by most of the spin margin.
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    if (config_.cpu >= 0) {
        std::string why;
        if (!hostclock::pin_current_thread(config_.cpu, why)) fifo_error_ = "not pinned: " + why;
    }
    if (config_.fifo_priority > 0) {
        std::string why;
        const bool ok = set_realtime_priority(config_.fifo_priority, why);
        if (!ok) fifo_error_ += (fifo_error_.empty() ? "" : "; ") + why;
        fifo_.store(ok, std::memory_order_release);
    }
    {
        std::lock_guard lock(mutex_);
        started_.store(true, std::memory_order_release);
    }
    space_.notify_all();

    const std::int64_t margin = config_.spin_margin.count();
    std::unique_lock lock(mutex_);
    for (;;) {
        if (heap_.empty()) {
            if (stop_) break;
            sleep_until(INT64_MAX, lock);
            continue;
        }
        const Entry top = heap_.front();
        const std::int64_t wake = top.deadline_ns - margin;
        if (hostclock::monotonic_ns() < wake) {
            sleep_until(wake, lock);
            continue;  // re-plan: an earlier packet may have arrived
        }
        std::pop_heap(heap_.begin(), heap_.end(), later);
        heap_.pop_back();
        Channel* ch = channels_[slots_[top.slot].channel].get();
        UdpSender* dest = ch->dest;
        lock.unlock();

        // The last microseconds: spinning is exact where a timer wake-up is not. The pause
        // hint leaves the core's execution units to a hyper-thread sibling (a renderer).
        std::int64_t now = hostclock::monotonic_ns();
        while (now < top.deadline_ns) {
            hostclock::cpu_relax();
            now = hostclock::monotonic_ns();
        }
        const core::Nanos lateness{now - top.deadline_ns};
        const Slot& slot = slots_[top.slot];
        const bool ok =
            dest != nullptr && dest->send(slot.stream, std::span(slot.bytes.data(), slot.size));
        ch->send_ns.add(core::Nanos{hostclock::monotonic_ns() - now});
        ch->stats.add(lateness);
        (ok ? ch->sent : ch->failed).fetch_add(1, std::memory_order_relaxed);
        if (lateness > ch->stats.threshold()) ch->late.fetch_add(1, std::memory_order_relaxed);
        if (lateness.count() > ch->worst_ns.load(std::memory_order_relaxed))
            ch->worst_ns.store(lateness.count(), std::memory_order_relaxed);

        lock.lock();
        free_.push_back(top.slot);
        --ch->pending;
        if (space_waiters_ > 0) space_.notify_all();
    }
}

}  // namespace mirage::udp
