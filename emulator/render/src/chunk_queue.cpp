// SPDX-License-Identifier: Apache-2.0
#include "chunk_queue.hpp"

namespace mirage::render {

ChunkQueue::ChunkQueue(std::uint64_t chunks, std::uint64_t window, const std::atomic<bool>* stop)
    : chunks_(chunks), window_(window), stop_(stop) {}

bool ChunkQueue::take(std::uint64_t& c) {
    std::unique_lock lk(mu_);
    cv_space_.wait(lk, [&] { return abort_ || next_ >= chunks_ || next_ < written_ + window_; });
    if (abort_ || next_ >= chunks_) return false;
    if (stop_ && stop_->load()) {
        abort_ = true;
        cv_done_.notify_all();
        return false;
    }
    c = next_++;
    return true;
}

std::unique_ptr<ChunkResult> ChunkQueue::result() {
    std::unique_ptr<ChunkResult> r;
    {
        std::lock_guard lk(mu_);
        if (!pool_free_.empty()) {
            r = std::move(pool_free_.back());
            pool_free_.pop_back();
        }
    }
    if (!r) r = std::make_unique<ChunkResult>();
    r->shaded.points.clear();
    r->shaded.samples.clear();
    r->shaded.stats = {};
    if (r->encoded) r->encoded->clear();
    return r;
}

void ChunkQueue::put(std::uint64_t c, std::unique_ptr<ChunkResult> r) {
    std::lock_guard lk(mu_);
    const std::uint64_t k = c - written_;
    if (slots_.size() <= k) slots_.resize(k + 1);
    slots_[k] = std::move(r);
    cv_done_.notify_all();
}

std::unique_ptr<ChunkResult> ChunkQueue::next() {
    std::unique_lock lk(mu_);
    cv_done_.wait(lk, [&] {
        return written_ >= chunks_ || (!slots_.empty() && slots_.front()) ||
               (abort_ && (slots_.empty() || !slots_.front()));
    });
    if (written_ >= chunks_) return nullptr;
    if (slots_.empty() || !slots_.front()) return nullptr;  // ended and nothing ready in order
    std::unique_ptr<ChunkResult> r = std::move(slots_.front());
    slots_.pop_front();
    ++written_;  // with the pop, so slots_[k] stays chunk written_ + k for the workers
    return r;
}

void ChunkQueue::recycle(std::unique_ptr<ChunkResult> r) {
    {
        std::lock_guard lk(mu_);
        pool_free_.push_back(std::move(r));
    }
    cv_space_.notify_all();
}

void ChunkQueue::fail(std::exception_ptr e) {
    std::lock_guard lk(mu_);
    if (!error_) error_ = std::move(e);
    abort_ = true;
    cv_done_.notify_all();
    cv_space_.notify_all();
}

void ChunkQueue::close() {
    {
        std::lock_guard lk(mu_);
        abort_ = true;
    }
    cv_space_.notify_all();
}

void ChunkQueue::rethrow() const {
    if (error_) std::rethrow_exception(error_);
}

}  // namespace mirage::render
