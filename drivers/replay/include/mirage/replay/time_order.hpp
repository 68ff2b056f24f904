// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <algorithm>
#include <cstdint>
#include <queue>
#include <vector>

#include "mirage/pcap/pcap.hpp"

namespace mirage::replay {

// Datagrams read one socket at a time carry kernel receive stamps that interleave across the
// sockets; a capture must list them in time order (a replayer schedules by it). Records wait here
// until they are `hold_ns` old, then leave oldest first; one that arrives after a later one has
// already left (read more than hold_ns after its stamp) still leaves, and is counted.
class TimeOrder {
  public:
    struct Record {
        std::int64_t time_ns = 0;
        pcap::Endpoint src, dst;
        std::vector<std::uint8_t> payload;
    };

    explicit TimeOrder(std::int64_t hold_ns) : hold_ns_(hold_ns) {}

    void add(Record r) { heap_.push({std::move(r), next_++}); }

    // Hands fn every record stamped at or before now_ns − hold_ns, oldest first (all of them when
    // `all`); stops at the first fn that returns false.
    template <class Fn>
    bool release(std::int64_t now_ns, bool all, Fn&& fn) {
        while (!heap_.empty() && (all || heap_.top().record.time_ns <= now_ns - hold_ns_)) {
            const Record& r = heap_.top().record;
            if (r.time_ns < last_ns_) ++late_;
            last_ns_ = std::max(last_ns_, r.time_ns);
            if (!fn(r)) return false;
            heap_.pop();
        }
        return true;
    }

    std::uint64_t out_of_order() const { return late_; }

  private:
    struct Entry {
        Record record;
        std::uint64_t seq;  // arrival order breaks ties: equal stamps keep their order
        bool operator<(const Entry& o) const {  // priority_queue is a max-heap
            return record.time_ns != o.record.time_ns ? record.time_ns > o.record.time_ns
                                                      : seq > o.seq;
        }
    };
    std::priority_queue<Entry> heap_;
    std::int64_t hold_ns_;
    std::int64_t last_ns_ = INT64_MIN;
    std::uint64_t next_ = 0, late_ = 0;
};

}  // namespace mirage::replay
