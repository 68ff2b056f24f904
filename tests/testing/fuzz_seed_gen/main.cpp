// SPDX-License-Identifier: Apache-2.0
// Writes the generated part of every fuzz target's seed corpus (valid inputs from Mirage's own
// encoders) under a source tree: `mirage_fuzz_seed_gen <source dir>` (make fuzz-seeds).
#include <cstdio>
#include <exception>

#include "seed_writer.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s <source dir>\n", argv[0]);
        return 2;
    }
    try {
        mirage::testing::seeds::SeedWriter w(argv[1]);
        mirage::testing::seeds::write_wire_seeds(w);
        mirage::testing::seeds::write_nav_seeds(w);
        mirage::testing::seeds::write_file_seeds(w);
        std::printf("fuzz seeds: %zu files, %llu bytes\n", w.files(),
                    static_cast<unsigned long long>(w.bytes()));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
