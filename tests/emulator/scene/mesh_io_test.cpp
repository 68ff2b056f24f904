// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/mesh_io.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

#include "mesh_checks.hpp"
#include "mirage/core/error.hpp"
#include "test_paths.hpp"

namespace mirage::scene {
namespace {

using test::expect_error;

std::string fixture(const std::string& name) {
    return (test::source_dir() / "recordings" / "scenes" / name).string();
}

Mesh obj(const std::string& text, LoadStats* stats = nullptr) {
    LoadStats local;
    MaterialBinding b;
    b.fallback = 0;
    b.by_name["roof"] = 1;
    return parse_obj(text, "t.obj", b, stats ? *stats : local);
}

Mesh ply(const std::string& bytes, LoadStats* stats = nullptr) {
    LoadStats local;
    return parse_ply(bytes, "t.ply", MaterialBinding{}, stats ? *stats : local);
}

void put_le_f32(std::string& s, float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int i = 0; i < 4; ++i) s += static_cast<char>((u >> (8 * i)) & 0xff);
}
void put_le_u32(std::string& s, std::uint32_t u) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>((u >> (8 * i)) & 0xff);
}

TEST(MeshIo, house_fixtures_in_obj_and_all_ply_formats_load_to_identical_geometry) {
    MaterialBinding b;
    b.fallback = 4;
    b.by_name["roof"] = 9;
    LoadStats stats;
    const Mesh ref = read_obj(fixture("house.obj"), b, stats);
    ASSERT_EQ(ref.vertices.size(), 10u);
    ASSERT_EQ(ref.triangles.size(), 16u);  // 4 quads·2 + 2 pentagons·3 + ... = 16
    EXPECT_EQ(stats.degenerate_triangles_dropped, 0u);
    EXPECT_EQ(ref.vertices[9], Eigen::Vector3f(2, 6, 4.5f));
    EXPECT_TRUE(test::is_closed_and_consistent(ref));
    // Box 4 × 6 × 3 plus a roof prism ½·4·1.5·6: 72 + 18 m³, positive = outward normals.
    EXPECT_NEAR(test::signed_volume(ref), 90.0, 1e-9);
    // Faces after `usemtl roof` take the scene material; `usemtl unknown_material` falls back.
    int roof = 0;
    for (std::uint32_t m : ref.materials) {
        EXPECT_TRUE(m == 4 || m == 9);
        roof += m == 9;
    }
    EXPECT_EQ(roof, 4);
    for (const char* name : {"house_ascii.ply", "house_le.ply", "house_be.ply"}) {
        SCOPED_TRACE(name);
        const Mesh m = read_ply(fixture(name), b, stats);
        EXPECT_EQ(m.vertices, ref.vertices);
        EXPECT_EQ(m.triangles, ref.triangles);
        EXPECT_EQ(m.materials, std::vector<std::uint32_t>(16, 4));  // PLY: fallback only
    }
}

TEST(MeshIo, obj_polygons_are_fan_triangulated_with_relative_indices) {
    const Mesh m =
        obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
            "f -4 -3 -2 -1   # quad with relative indices\n"
            "v 0 0 1 0.5 0.5 0.5\n"
            "f 1/1/1 2//3 5\n");
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[0], Eigen::Vector3i(0, 1, 2));
    EXPECT_EQ(m.triangles[1], Eigen::Vector3i(0, 2, 3));
    EXPECT_EQ(m.triangles[2], Eigen::Vector3i(0, 1, 4));
    EXPECT_EQ(m.vertices[4], Eigen::Vector3f(0, 0, 1));
}

TEST(MeshIo, obj_degenerate_triangles_are_dropped_and_counted) {
    LoadStats stats;
    const Mesh m =
        obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n"
            "f 1 2 4\nf 1 2 3\nf 1 1 4\nf 4 4 4\n",
            &stats);
    EXPECT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(stats.degenerate_triangles_dropped, 3u);
}

TEST(MeshIo, obj_errors_name_the_file_and_line) {
    expect_error([] { obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"); },
                 {"obj 't.obj'", "line 4", "malformed face vertex 'x'"});
    std::string twelve;
    for (int i = 0; i < 12; ++i) twelve += "v " + std::to_string(i) + " 0 0\n";
    expect_error([&] { obj(twelve + "# comment\n\n\n\nf 1 2 40\n"); },
                 {"obj 't.obj'", "line 17", "face index 40 out of range (12 vertices)"});
    expect_error([] { obj("v 0 0 0\nv 1 nan 0\n"); },
                 {"obj 't.obj'", "line 2", "non-finite vertex value 'nan'"});
    expect_error([] { obj("v 0 0 0\nv inf 0 0\n"); }, {"line 2", "non-finite"});
    expect_error([] { obj("v 0 0 0\nv 1 0 0\nf 1 2\n"); },
                 {"line 3", "face needs at least 3 vertices, got 2"});
    expect_error([] { obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n"); },
                 {"line 4", "face index 0 is invalid"});
    expect_error([] { obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -4 1 2\n"); },
                 {"line 4", "face index -4 out of range (3 vertices)"});
    expect_error([] { obj("v 0 0\n"); }, {"line 1", "vertex needs 3 coordinates"});
    expect_error([] { obj("v 0 0 0\nbanana 3\n"); }, {"line 2", "unknown statement 'banana'"});
    expect_error([] { obj(std::string("\x89PNG\r\n\x1a\n", 8)); }, {"line 1", "unknown statement"});
}

TEST(MeshIo, missing_mesh_file_is_an_io_error_naming_the_path) {
    LoadStats stats;
    try {
        read_obj("/nonexistent/tree.obj", MaterialBinding{}, stats);
        ADD_FAILURE() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("obj '/nonexistent/tree.obj'"), std::string::npos);
    }
    EXPECT_THROW(read_ply("/nonexistent/tree.ply", MaterialBinding{}, stats), IoError);
}

TEST(MeshIo, ply_header_errors_name_the_header_line) {
    expect_error(
        [] { ply("ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\nend_header\n"); },
        {"ply 't.ply'", "header line 4", "unknown type 'flot'"});
    expect_error([] { ply("plx\nformat ascii 1.0\nend_header\n"); }, {"ply 't.ply'", "magic"});
    expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex 3\n"); },
                 {"ply 't.ply'", "no end_header"});
    expect_error([] { ply("ply\nformat binary_middle_endian 1.0\nend_header\n"); },
                 {"header line 2", "unknown format 'binary_middle_endian'"});
    expect_error([] { ply("ply\nformat ascii 1.0\nproperty float x\nend_header\n"); },
                 {"header line 3", "property before any element"});
    expect_error([] { ply("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n"); },
                 {"header line 3", "bad element count"});
    expect_error(
        [] {
            ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                "property float y\nelement face 0\nproperty list uchar int vertex_indices\n"
                "end_header\n1 2\n");
        },
        {"header line 3", "no 'z' property"});
    expect_error(
        [] {
            ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                "property float y\nproperty float z\nend_header\n1 2 3\n");
        },
        {"no face element"});
}

const char* kTriangleHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
    "property float y\nproperty float z\nelement face 1\n"
    "property list uchar uint vertex_indices\nend_header\n";

std::string binary_triangle(float bad_y = 0) {
    std::string s = kTriangleHeader;
    const float v[9] = {0, 0, 0, 1, bad_y, 0, 0, 1, 0};
    for (float f : v) put_le_f32(s, f);
    s += '\x03';
    for (std::uint32_t i : {0u, 1u, 2u}) put_le_u32(s, i);
    return s;
}

TEST(MeshIo, binary_ply_round_trips_a_triangle) {
    const Mesh m = ply(binary_triangle());
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.vertices[1], Eigen::Vector3f(1, 0, 0));
}

TEST(MeshIo, truncated_binary_ply_fails_with_the_element_index) {
    const std::string full = binary_triangle();
    // Cut inside the face's index list: the reader must stop at the end, not run past it.
    expect_error([&] { ply(full.substr(0, full.size() - 3)); },
                 {"ply 't.ply'", "face[0]", "runs past the end"});
    // Cut inside the vertices: caught by the size check before anything is allocated.
    const std::size_t header = std::strlen(kTriangleHeader);
    expect_error([&] { ply(full.substr(0, header + 20)); },
                 {"ply 't.ply'", "element 'vertex'", "3 items", "only 20 bytes are left"});
    // Every prefix of the file fails cleanly (never crashes, never succeeds).
    for (std::size_t n = 0; n < full.size(); ++n) {
        EXPECT_THROW(ply(full.substr(0, n)), ConfigError) << "prefix " << n;
    }
    // The house fixture cut short inside its last face.
    const std::string house = read_file_bytes(fixture("house_le.ply"), "ply");
    expect_error([&] { ply(house.substr(0, house.size() - 1)); }, {"face[6]", "truncated"});
}

TEST(MeshIo, huge_ply_counts_are_rejected_before_allocation) {
    expect_error(
        [] {
            ply("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                "property float x\nproperty float y\nproperty float z\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                "abcdefgh");
        },
        {"element 'vertex'", "4000000000 items", "only 8 bytes"});
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list uint uint vertex_indices\nend_header\n";
    for (int i = 0; i < 9; ++i) put_le_f32(s, static_cast<float>(i));
    put_le_u32(s, 0xFFFFFFFFu);
    put_le_u32(s, 0);
    expect_error([&] { ply(s); }, {"face[0]", "list of 4294967295 items runs past the end"});
}

TEST(MeshIo, ply_nan_vertices_and_bad_indices_name_the_item) {
    expect_error([] { ply(binary_triangle(NAN)); }, {"ply 't.ply'", "vertex[1]", "non-finite"});
    const std::string ascii =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    expect_error([&] { ply(ascii + "0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n"); },
                 {"line 11", "vertex[1]", "non-finite"});
    expect_error([&] { ply(ascii + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"); },
                 {"line 13", "face[0]", "vertex index 7 out of range (3 vertices)"});
    expect_error([&] { ply(ascii + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"); },
                 {"face[0]", "face with 2 vertices"});
    expect_error([&] { ply(ascii + "0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n"); },
                 {"line 11", "vertex[1]", "malformed number 'x'"});
    expect_error([&] { ply(ascii + "0 0 0\n1 0 0\n"); }, {"element 'vertex'", "truncated file?"});
    expect_error([&] { ply(ascii + "0 0 0\n1 0 0\n0 1 0\n3 0 1     \n"); },
                 {"face[0]", "truncated"});
}

TEST(MeshIo, ply_degenerate_faces_are_dropped_and_counted) {
    const std::string ascii =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 3\n3 0 1 2\n3 3 3 1\n";
    LoadStats stats;
    const Mesh m = ply(ascii, &stats);
    EXPECT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(stats.degenerate_triangles_dropped, 2u);
}

TEST(MeshIo, corrupted_fixtures_either_load_or_throw_config_errors) {
    // Every byte of every fixture replaced by a few troublesome values: the readers must
    // return a mesh or throw ConfigError, never anything else (run under ASan in CI).
    const char kValues[] = {'\0', '\xff', '9', '-', '\n', ' '};
    int loaded = 0, rejected = 0;
    for (const char* name : {"house.obj", "house_ascii.ply", "house_le.ply", "house_be.ply"}) {
        const std::string orig = read_file_bytes(fixture(name), "fixture");
        const bool is_obj = std::string(name).ends_with(".obj");
        for (std::size_t i = 0; i < orig.size(); ++i) {
            for (char v : kValues) {
                std::string bad = orig;
                bad[i] = v;
                try {
                    LoadStats st;
                    const Mesh m = is_obj ? parse_obj(bad, name, MaterialBinding{}, st)
                                          : parse_ply(bad, name, MaterialBinding{}, st);
                    for (const auto& t : m.triangles) {
                        for (int k = 0; k < 3; ++k) {
                            ASSERT_GE(t[k], 0);
                            ASSERT_LT(t[k], static_cast<int>(m.vertices.size()));
                        }
                    }
                    for (const auto& p : m.vertices) ASSERT_TRUE(p.allFinite());
                    ++loaded;
                } catch (const ConfigError&) {
                    ++rejected;
                }
            }
        }
    }
    EXPECT_GT(loaded, 0);
    EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace mirage::scene
