// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <vector>

#include "mirage/las/las_writer.hpp"
#include "mirage/render/pipeline.hpp"

namespace mirage::hil {

// Pipeline output to a LAS file, optionally keeping a copy of the points (for previews).
class LasSink : public render::PointSink {
  public:
    LasSink(las::LasWriter& writer, std::vector<core::PointRecord>* keep = nullptr)
        : writer_(writer), keep_(keep) {}
    void write(std::span<const core::PointRecord> points) override {
        writer_.write(points);
        if (keep_) keep_->insert(keep_->end(), points.begin(), points.end());
    }

  private:
    las::LasWriter& writer_;
    std::vector<core::PointRecord>* keep_;
};

}  // namespace mirage::hil
