// SPDX-License-Identifier: Apache-2.0
// The hand-over of a free-running Geiger-mode array's dead time between render() chunks
// (docs/photon-counting.md §2.1): the worker that draws a chunk's last frame puts each pixel's
// carried dead time, the worker of the next chunk takes it before drawing that chunk's first
// frame. Chunks are taken in order and each put is taken once, so a take waits only on the
// chunk before it and never forms a cycle.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

namespace mirage::render {

class CarryChain {
  public:
    // The per-pixel carry into `frame` (ns into its window from which each pixel is armed).
    void put(std::uint64_t frame, std::vector<double> carry) {
        {
            std::lock_guard lock(mu_);
            ready_[frame] = std::move(carry);
        }
        cv_.notify_all();
    }
    // Waits for the carry into `frame`; false if the run was aborted first.
    bool take(std::uint64_t frame, std::vector<double>& carry) {
        std::unique_lock lock(mu_);
        cv_.wait(lock, [&] { return aborted_ || ready_.count(frame) > 0; });
        const auto it = ready_.find(frame);
        if (it == ready_.end()) return false;
        carry = std::move(it->second);
        ready_.erase(it);
        return true;
    }
    // A worker failed: its successor would wait for ever.
    void abort() {
        {
            std::lock_guard lock(mu_);
            aborted_ = true;
        }
        cv_.notify_all();
    }

  private:
    std::mutex mu_;
    std::condition_variable cv_;
    std::map<std::uint64_t, std::vector<double>> ready_;
    bool aborted_ = false;
};

}  // namespace mirage::render
