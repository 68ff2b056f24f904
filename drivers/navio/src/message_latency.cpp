// SPDX-License-Identifier: Apache-2.0
#include "mirage/navio/message_latency.hpp"

#include <algorithm>

namespace mirage::navio {
namespace {

std::size_t track_index(navpose::Track t) { return t == navpose::Track::Position ? 0 : 1; }

}  // namespace

void MessageLatency::applied(const std::vector<AppliedMessage>& messages) {
    for (const AppliedMessage& m : messages) {
        pending_[m.tag.seq] = {m.tag.arrival_ns, m.position, m.attitude, false};
        ++messages_;
    }
}

void MessageLatency::rendered(const std::vector<navpose::UsedMessage>& used) {
    for (const navpose::UsedMessage& u : used) {
        const std::size_t k = track_index(u.track);
        if (!any_used_[k] || u.tag.seq > newest_used_[k]) newest_used_[k] = u.tag.seq;
        any_used_[k] = true;
        const auto it = pending_.find(u.tag.seq);
        if (it == pending_.end() || it->second.rendered) continue;  // not timed, or already due
        it->second.rendered = true;
        due_.push_back(u.tag.seq);
    }
}

void MessageLatency::data_packet_sent(std::int64_t sent_ns) {
    for (const std::uint64_t seq : due_) {
        const auto it = pending_.find(seq);
        latency_.add(core::Nanos(std::max<std::int64_t>(0, sent_ns - it->second.arrival_ns)));
        pending_.erase(it);
    }
    due_.clear();
}

MessageLatency::Unused MessageLatency::unused() const {
    Unused u;
    for (const auto& [seq, m] : pending_) {
        const bool pos_newer = !m.position || (any_used_[0] && newest_used_[0] > seq);
        const bool att_newer = !m.attitude || (any_used_[1] && newest_used_[1] > seq);
        if (!m.rendered && pos_newer && att_newer)
            ++u.superseded;
        else
            ++u.waiting;
    }
    return u;
}

}  // namespace mirage::navio
