// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/udp/lateness_histogram.hpp"
#include "mirage/udp/udp_sender.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::udp {

// How a producer wakes the sending thread when it submits a packet due before the instant the
// thread sleeps toward. Both sleep on an absolute CLOCK_MONOTONIC deadline.
enum class WakeMethod : std::uint8_t {
    Futex,    // FUTEX_WAIT_BITSET on a sequence word; a submit only calls FUTEX_WAKE when needed
    CondVar,  // std::condition_variable::wait_until(steady_clock) under the queue mutex
};

struct SharedSenderConfig {
    core::Nanos spin_margin{50'000};  // sleep until this long before a deadline, then spin
    // submit() blocks while a deadline is further ahead. A producer is late only if it stays
    // off the CPU longer than this: 20 ms was exceeded several times a minute on a loaded
    // 2-core VM (recordings/bench/streams.md), 100 ms was not.
    core::Nanos horizon{100'000'000};
    core::Nanos late_threshold{100'000};  // what counts as "late" in the statistics
    // Packets queued at most (all channels together): a horizon of the three benchmark streams
    // (~9000 packets/s) with room to spare. Slots are reused last-in first-out, so only as many
    // as are ever queued at once grow to the largest packet.
    std::size_t capacity = 4096;
    std::size_t slot_bytes = 1500;  // initial buffer per slot; grows once to the largest
    int fifo_priority = 0;          // > 0: the sending thread asks for SCHED_FIFO
    // >= 0: the sending thread pins itself to this CPU, the one --keep-awake keeps out of idle
    // (hostclock::sending_cpu(); docs/time.md §5). A refusal is reported as fifo_error() is.
    int cpu = -1;
    WakeMethod wake = WakeMethod::Futex;
};

// What one channel (a producer's destination) has seen so far; readable while streaming.
struct ChannelCounters {
    std::uint64_t submitted = 0, sent = 0, failed = 0, late = 0;
    std::uint64_t discarded = 0;  // queued, then dropped unsent by discard()
    core::Nanos worst{0};
};

// One thread sends the packets of any number of streams in deadline order. Producers (render
// writer threads) submit a copy of each packet with its absolute CLOCK_MONOTONIC deadline; the
// thread sleeps (clock-absolute, 1 ns timer slack) to spin_margin before the earliest deadline,
// spins, sends and records the lateness (send time − deadline) per channel. A submitted packet
// due earlier than the thread's planned wake-up wakes it. Packets already due go out at once.
// Buffers come from a fixed pool of `capacity` slots: no allocation per packet once each slot
// has held the largest packet. Never throws after construction; send failures are counted.
class SharedSender {
  public:
    using ChannelId = std::uint32_t;

    // Starts the sending thread. Throws ConfigError for a zero capacity or negative margins.
    explicit SharedSender(SharedSenderConfig config = {});
    ~SharedSender();  // sends what is queued, then stops the thread
    SharedSender(const SharedSender&) = delete;
    SharedSender& operator=(const SharedSender&) = delete;

    // A destination for packets. `dest` must outlive the channel (close it first). Thread-safe.
    ChannelId open(UdpSender& dest);
    // Waits until the channel's queued packets are sent, then forgets its destination.
    void close(ChannelId id);

    // Queues a copy of `bytes` for `stream` of channel `id`, due at CLOCK_MONOTONIC
    // deadline_ns. Blocks while the deadline is more than `horizon` ahead or the queue is full
    // (backpressure); returns false only for an unknown / closed channel. Never throws.
    bool submit(ChannelId id, wire::Stream stream, std::int64_t deadline_ns,
                std::span<const std::uint8_t> bytes);

    // Waits until every packet submitted to `id` so far has been sent.
    void flush(ChannelId id);
    // Drops the channel's queued packets unsent (a device switched off mid-stream) and returns
    // how many; a packet already being sent still goes.
    std::uint64_t discard(ChannelId id);
    // The channel's lateness histogram: call after flush() from the producer (the thread writes
    // it otherwise).
    LatenessHistogram lateness(ChannelId id) const;
    ChannelCounters counters(ChannelId id) const;  // any time, any thread

    // Submits that had to wait for the horizon / for a free slot (backpressure seen).
    std::uint64_t horizon_waits() const { return horizon_waits_.load(std::memory_order_relaxed); }
    std::uint64_t full_waits() const { return full_waits_.load(std::memory_order_relaxed); }
    // Times a submit woke the sending thread early.
    std::uint64_t wakeups() const { return wakeups_.load(std::memory_order_relaxed); }
    // Whether the thread runs SCHED_FIFO, and why not when asked for (valid after the first
    // packet has been sent, or after flush()).
    bool fifo() const { return fifo_.load(std::memory_order_acquire); }
    std::string fifo_error() const;
    // How late the thread's timed sleeps ended against the instant asked for (timer and
    // scheduler latency; a sleep cut short by a submit is not counted), and how long each send
    // call of a channel took. Call after flush() or with the streams stopped: the thread writes
    // them.
    LatenessHistogram wake_lateness() const;
    LatenessHistogram send_durations(ChannelId id) const;
    // CPU seconds the sending thread has used so far.
    double cpu_seconds() const;
    const SharedSenderConfig& config() const { return config_; }

  private:
    struct Slot {
        std::vector<std::uint8_t> bytes;
        std::size_t size = 0;
        ChannelId channel = 0;
        wire::Stream stream = wire::Stream::Data;
    };
    struct Entry {
        std::int64_t deadline_ns;
        std::uint64_t seq;  // submission order breaks ties: equal deadlines stay FIFO
        std::uint32_t slot;
    };
    struct Channel {
        UdpSender* dest = nullptr;
        std::uint64_t pending = 0;  // submitted, not yet sent (under mutex_)
        LatenessHistogram stats;
        LatenessHistogram send_ns;  // duration of each send call
        std::atomic<std::uint64_t> submitted{0}, sent{0}, failed{0}, late{0}, discarded{0};
        std::atomic<std::int64_t> worst_ns{0};
        explicit Channel(core::Nanos threshold) : stats(threshold) {}
    };
    static bool later(const Entry& a, const Entry& b);

    void run();
    void sleep_until(std::int64_t wake_ns, std::unique_lock<std::mutex>& lock);
    void wake_sender();
    void send_one(const Entry& e);

    SharedSenderConfig config_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;     // the sender's sleep (CondVar method)
    std::condition_variable space_;  // producers waiting for a slot or a flush
    std::vector<Slot> slots_;
    std::vector<std::uint32_t> free_;  // free slot indices (stack)
    std::vector<Entry> heap_;          // min-heap on (deadline, seq)
    std::vector<std::unique_ptr<Channel>> channels_;
    std::uint64_t next_seq_ = 0;
    std::int64_t planned_wake_ns_ = INT64_MAX;  // the sender sleeps toward this (under mutex_)
    bool sleeping_ = false;
    bool stop_ = false;
    std::size_t space_waiters_ = 0;
    alignas(4) std::atomic<std::uint32_t> futex_word_{0};
    std::atomic<std::uint64_t> horizon_waits_{0}, full_waits_{0}, wakeups_{0};
    std::atomic<bool> fifo_{false};
    std::string fifo_error_;  // written by the thread before fifo_ / started_ is published
    std::atomic<bool> started_{false};
    std::atomic<std::int64_t> cpu_ns_{0};
    LatenessHistogram wake_late_;  // under mutex_
    std::thread thread_;
};

}  // namespace mirage::udp
