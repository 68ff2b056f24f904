// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <vector>

#include "mirage/las/las_writer.hpp"
#include "mirage/render/pipeline.hpp"

namespace mirage::las {

// Pipeline output to a LAS file, optionally keeping a copy of the points (for previews). Without
// a copy the render workers encode the records (LasWriter::encode) and this thread only writes.
// finish() closes the writer (the final header).
class LasSink : public render::PointSink {
  public:
    LasSink(las::LasWriter& writer, std::vector<core::PointRecord>* keep = nullptr)
        : writer_(writer), keep_(keep) {}
    void write(std::span<const core::PointRecord> points) override {
        writer_.write(points);
        if (keep_) keep_->insert(keep_->end(), points.begin(), points.end());
    }
    std::unique_ptr<render::EncodedPoints> new_encoded() const override {
        if (keep_) return nullptr;  // the copy needs the points themselves
        return std::make_unique<Encoded>();
    }
    void encode(std::span<const core::PointRecord> points,
                render::EncodedPoints& out) const override {
        writer_.encode(points, static_cast<Encoded&>(out).records);
    }
    void write_recorded(std::span<const core::PointRecord> points,
                        std::span<const std::uint32_t> samples) override {
        writer_.write_recorded(points, samples);
        if (keep_) keep_->insert(keep_->end(), points.begin(), points.end());
    }
    void encode_recorded(std::span<const core::PointRecord> points,
                         std::span<const std::uint32_t> samples,
                         render::EncodedPoints& out) const override {
        writer_.encode_recorded(points, samples, static_cast<Encoded&>(out).records);
    }
    void write_encoded(render::EncodedPoints& chunk) override {
        writer_.write_encoded(static_cast<Encoded&>(chunk).records);
    }
    void finish() override { writer_.close(); }

  private:
    struct Encoded : render::EncodedPoints {
        las::EncodedRecords records;
        void clear() override { records.clear(); }
    };
    las::LasWriter& writer_;
    std::vector<core::PointRecord>* keep_;
};

}  // namespace mirage::las
