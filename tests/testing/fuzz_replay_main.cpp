// SPDX-License-Identifier: Apache-2.0
// Replays a fuzz target's committed seed corpus through its LLVMFuzzerTestOneInput once, for
// builds without libFuzzer (cmake/mirage_fuzz.cmake): every file of each folder given, in name
// order. A crash or sanitizer report fails the test; so does an empty corpus.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (int i = 1; i < argc; ++i) {
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(argv[i], ec))
            if (e.is_regular_file()) files.push_back(e.path());
        if (ec) std::fprintf(stderr, "fuzz replay: %s: %s\n", argv[i], ec.message().c_str());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        std::ifstream in(f, std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                      std::istreambuf_iterator<char>());
        // A valid address for an empty input, as libFuzzer passes.
        static const std::uint8_t empty = 0;
        LLVMFuzzerTestOneInput(
            bytes.empty() ? &empty : reinterpret_cast<const std::uint8_t*>(bytes.data()),
            bytes.size());
    }
    std::printf("fuzz replay: %zu inputs\n", files.size());
    return files.empty() ? 1 : 0;
}
