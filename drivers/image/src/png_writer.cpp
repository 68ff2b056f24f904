// SPDX-License-Identifier: Apache-2.0
#include "mirage/image/png_writer.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include "mirage/core/error.hpp"
#include "mirage/core/output_file.hpp"

namespace mirage::image {
namespace {

// Everything libpng's error path touches. Plain data only: libpng reports errors by
// longjmp, which must not skip C++ destructors, so the libpng calls live in encode() below,
// whose locals are all trivially destructible, and C++ objects stay in write_png().
struct PngJob {
    std::FILE* file = nullptr;
    const std::uint8_t* rgb = nullptr;
    png_uint_32 width = 0, height = 0;
    char error[256] = {};
};

extern "C" void on_png_error(png_structp png, png_const_charp msg) {
    auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
    std::snprintf(job->error, sizeof job->error, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

extern "C" void on_png_warning(png_structp, png_const_charp) {}

bool encode(PngJob& job) {
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, on_png_error, on_png_warning);
    if (png == nullptr) {
        std::snprintf(job.error, sizeof job.error, "cannot create libpng write struct");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        std::snprintf(job.error, sizeof job.error, "cannot create libpng info struct");
        return false;
    }
    // png and info are not modified after setjmp, so they keep their values after longjmp.
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, job.file);
    png_set_IHDR(png, info, job.width, job.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (png_uint_32 row = 0; row < job.height; ++row) {
        png_write_row(png, job.rgb + static_cast<std::size_t>(row) * job.width * 3);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

void write_png(const std::string& path, const RgbImage& image) {
    const std::string prefix = "png writer '" + path + "': ";
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
        throw ConfigError(prefix + "image is empty or its buffer does not match " +
                          std::to_string(image.width) + "x" + std::to_string(image.height));
    }
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
    if (!file) throw IoError(prefix + "cannot create: " + std::strerror(errno));

    PngJob job;
    job.file = file.get();
    job.rgb = image.rgb.data();
    job.width = static_cast<png_uint_32>(image.width);
    job.height = static_cast<png_uint_32>(image.height);
    bool ok = encode(job);
    std::string why = job.error;
    if (ok && std::fflush(file.get()) != 0) {
        ok = false;
        why = std::strerror(errno);
    }
    if (ok && std::ferror(file.get())) {
        ok = false;
        why = "write error";
    }
    if (std::fclose(file.release()) != 0 && ok) {
        ok = false;
        why = std::strerror(errno);
    }
    if (!ok) {
        core::remove_failed_output(path);
        throw IoError(prefix + why);
    }
}

}  // namespace mirage::image
