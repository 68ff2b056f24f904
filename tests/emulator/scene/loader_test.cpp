// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/loader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include "mesh_checks.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/heightfield.hpp"
#include "test_paths.hpp"

namespace mirage::scene {
namespace {

std::string fixture(const std::string& name) {
    return (test::source_dir() / "recordings" / "scenes" / name).string();
}

std::string write(const test::TempDir& dir, const std::string& name, const std::string& text) {
    const std::string path = dir.file(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// Loads `yaml` (written to a temporary file) and expects a ConfigError whose message starts
// with "scene '<that file>'" and contains every fragment.
void expect_scene_error(const std::string& yaml, std::initializer_list<std::string> fragments,
                        const std::string& extra_name = "", const std::string& extra_text = "") {
    test::TempDir dir;
    if (!extra_name.empty()) write(dir, extra_name, extra_text);
    const std::string path = write(dir, "s.yaml", yaml);
    try {
        load_scene(path);
        ADD_FAILURE() << "no exception for:\n" << yaml;
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("scene '" + path + "': ", 0), 0u) << msg;
        for (const auto& frag : fragments) {
            EXPECT_NE(msg.find(frag), std::string::npos) << "'" << frag << "' not in: " << msg;
        }
    }
}

const char* kMaterials = "materials:\n  m: {reflectance: 0.5}\n";

TEST(Loader, example_scene_loads_every_object_type) {
    const Scene s = load_scene(fixture("example.yaml"));
    EXPECT_EQ(s.georef.epsg(), 32632);
    EXPECT_EQ(s.georef.anchor(), Eigen::Vector3d(500000, 5000000, 0));
    ASSERT_EQ(s.materials.size(), 7u);
    EXPECT_EQ(s.materials[1].name, "asphalt");
    EXPECT_DOUBLE_EQ(s.materials[1].reflectance, 0.1);
    EXPECT_EQ(s.materials[1].classification, 11);
    EXPECT_EQ(s.materials[1].red, 60 * 257);
    EXPECT_DOUBLE_EQ(s.materials[3].specular, 0.1);
    EXPECT_TRUE(s.materials[5].retroreflective);
    ASSERT_EQ(s.meshes.size(), 9u);
    ASSERT_EQ(s.instances.size(), 3u);  // the house, placed three times
    // ground 3200, road 2, houses 3·16, PLY house 16, kiosk 12, tank 5120, sign 12,
    // mound 4 (2 of 6 cells: the rest touch a no-data sample), ramp 4.
    EXPECT_EQ(s.placed_triangle_count(), 3200u + 2 + 48 + 16 + 12 + 5120 + 12 + 4 + 4);
    EXPECT_EQ(s.stats.triangles, 3200u + 2 + 16 + 16 + 12 + 5120 + 12 + 4 + 4);
    EXPECT_EQ(s.stats.degenerate_triangles_dropped, 0u);
    // House OBJ: `usemtl roof` faces use the scene's "roof" material (index 3), others "wall".
    const Mesh& house = s.meshes[s.instances[0].mesh];
    EXPECT_EQ(house.name, "house");
    EXPECT_EQ(std::count(house.materials.begin(), house.materials.end(), 3u), 4);
    EXPECT_EQ(std::count(house.materials.begin(), house.materials.end(), 2u), 12);
    // The third instance is rotated by 180° and scaled 1.2 about its origin, then moved.
    const Eigen::Vector3d corner = s.instances[2].transform * Eigen::Vector3d(4, 6, 0);
    EXPECT_TRUE(corner.isApprox(Eigen::Vector3d(6 - 4.8, 9 - 7.2, 0), 1e-12));
    // The DEM mound sits at its UTM header coordinates minus the anchor.
    const Mesh* mound = nullptr;
    for (const Mesh& m : s.meshes) {
        if (m.name == "mound") mound = &m;
    }
    ASSERT_NE(mound, nullptr);
    EXPECT_EQ(mound->vertices[0], Eigen::Vector3f(31, 25, 0.5f));
    const Eigen::AlignedBox3d b = s.bounds();
    EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(-40, -40, 0), 1e-6));
    EXPECT_DOUBLE_EQ(b.max().x(), 40);
}

// The in-memory entry point (fuzz_scene_yaml) names its input in errors and resolves mesh files
// against the folder it is given.
TEST(Loader, text_in_memory_resolves_files_against_the_given_folder) {
    const std::string yaml =
        std::string(kMaterials) + "objects:\n  - {type: mesh, file: house.obj, material: m}\n";
    const Scene s = load_scene_text(yaml, "mem.yaml", test::source_dir() / "recordings" / "scenes");
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].vertices.size(), 10u);
    try {
        load_scene_text("objects: 3\n", "mem.yaml", ".");
        ADD_FAILURE() << "objects: 3 accepted";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("scene 'mem.yaml': objects: ", 0), 0u) << e.what();
    }
}

// A leaf's transmission and a mirror fraction as given; glass of n = 1.5 passes (1 − R)² =
// 0.9216 and mirrors the rest, with no diffuse reflectance unless one is given.
TEST(Loader, path_materials_read_their_fractions_and_glass_derives_them) {
    const Scene s = load_scene_text(
        "materials:\n  leaf: {reflectance: 0.3, transmission: 0.4}\n  wet: {reflectance: 0.1, "
        "mirror: 0.6}\n  glass: {refractive_index: 1.5}\nobjects:\n  - {type: plane, "
        "material: leaf, size: [1, 1]}\n",
        "mem.yaml", ".");
    ASSERT_EQ(s.materials.size(), 3u);
    EXPECT_EQ(s.materials[0].transmission, 0.4);
    EXPECT_TRUE(s.materials[0].continues());
    EXPECT_EQ(s.materials[1].mirror, 0.6);
    EXPECT_EQ(s.materials[2].reflectance, 0.0);
    EXPECT_NEAR(s.materials[2].transmission, 0.9216, 1e-12);
    EXPECT_NEAR(s.materials[2].mirror, 0.0784, 1e-12);
}

TEST(Loader, transform_scales_then_rotates_then_translates) {
    test::TempDir dir;
    const std::string yaml = std::string(kMaterials) +
                             "objects:\n"
                             "  - {type: box, material: m, size: [2, 2, 2],\n"
                             "     transform: {translate: [10, 0, 0], rotate_deg: [0, 0, 90],"
                             " scale: [1, 2, 3]}}\n"
                             "  - {type: box, material: m, size: [2, 2, 2],\n"
                             "     transform: {translate: [10, 0, 0], scale: [1, 2, 3],\n"
                             "                 quaternion: [0.7071067811865476, 0, 0, "
                             "0.7071067811865476]}}\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    ASSERT_EQ(s.meshes.size(), 2u);
    const Eigen::AlignedBox3d b = s.bounds();
    EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(8, -1, -3), 1e-6));
    EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(12, 1, 3), 1e-6));
    // Vertex (+1, +1, +1) -> scaled (1, 2, 3) -> yaw 90° (−2, 1, 3) -> moved (8, 1, 3).
    EXPECT_TRUE(s.meshes[0].vertices[7].isApprox(Eigen::Vector3f(8, 1, 3), 1e-6f));
    for (std::size_t i = 0; i < 8; ++i) {
        EXPECT_TRUE(s.meshes[0].vertices[i].isApprox(s.meshes[1].vertices[i], 1e-6f));
    }
    // Transforms keep the box closed with outward normals (volume 2·2·2 · 1·2·3).
    EXPECT_NEAR(test::signed_volume(s.meshes[0]), 48.0, 1e-3);
}

TEST(Loader, instances_compose_the_object_transform_and_store_the_mesh_once) {
    test::TempDir dir;
    const std::string yaml =
        std::string(kMaterials) +
        "objects:\n"
        "  - type: sphere\n    material: m\n    radius: 1\n    subdivisions: 2\n"
        "    transform: {translate: [0, 0, 5]}\n"
        "    instances:\n"
        "      - {translate: [1, 0, 0]}\n"
        "      - {translate: [0, 2, 0], scale: 2}\n"
        "      - {rotate_deg: [90, 0, 0]}\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.placed_triangle_count(), 3u * 320u);
    EXPECT_EQ(s.stats.triangles, 320u);
    EXPECT_TRUE(s.instances[0].transform.translation().isApprox(Eigen::Vector3d(1, 0, 5)));
    EXPECT_TRUE(s.instances[1].transform.translation().isApprox(Eigen::Vector3d(0, 2, 5)));
    EXPECT_NEAR(s.instances[1].transform.linear().determinant(), 8.0, 1e-12);
    // The mesh stays in its own frame (centred on the origin).
    EXPECT_NEAR(s.meshes[0].vertices[0].norm(), 1.0f, 1e-6f);
    const Eigen::AlignedBox3d b = s.bounds();
    EXPECT_NEAR(b.max().z(), 7.0, 1e-6);  // the scale-2 sphere at z = 5
    EXPECT_NEAR(b.min().y(), -1.0, 1e-6);
}

TEST(Loader, function_heightfield_vertices_equal_the_function) {
    test::TempDir dir;
    const std::string yaml =
        "materials: {ground: {classification: 2}}\n"
        "objects:\n"
        "  - type: heightfield\n    material: ground\n"
        "    function: {kind: sine_hills, amplitude: 2, wavelength: 8, height: -1}\n"
        "    size: [16, 8]\n    cell_size: 0.25\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.placed_triangle_count(), 2u * 64u * 32u);
    HeightFunction f;
    f.kind = HeightFunction::Kind::SineHills;
    f.amplitude_m = 2;
    f.wavelength_m = 8;
    f.height_m = -1;
    for (const auto& v : s.meshes[0].vertices) {
        EXPECT_EQ(v.z(), static_cast<float>(f(v.x(), v.y())));
    }
    EXPECT_EQ(s.georef.epsg(), 0);  // no georef: local scene
}

TEST(Loader, pgm_heightfield_uses_cell_size_and_z_scale) {
    test::TempDir dir;
    const std::string yaml =
        "materials: {g: {}}\n"
        "objects:\n"
        "  - {type: heightfield, material: g, raster: " +
        fixture("ramp.pgm") + ", cell_size: 0.5, z_scale: 0.001, z_offset: 2}\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    const Eigen::AlignedBox3d b = s.bounds();
    EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(-0.5, -0.25, 2.0), 1e-6));
    EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(0.5, 0.25, 2.0 + 65.535), 1e-6));
}

TEST(Loader, geodetic_georef_is_converted_to_its_utm_zone) {
    test::TempDir dir;
    const std::string yaml = std::string(kMaterials) +
                             "georef: {lat: 45.0, lon: 9.0, h: 100}\n"
                             "objects: [{type: plane, material: m, size: [1, 1]}]\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    EXPECT_EQ(s.georef.epsg(), 32632);
    // lon 9° is the central meridian of zone 32: easting exactly 500 000 m.
    EXPECT_NEAR(s.georef.anchor().x(), 500000.0, 1e-3);
    EXPECT_NEAR(s.georef.anchor().y(), 4982950.40, 0.01);  // 0.9996 · meridian arc to 45°
    EXPECT_DOUBLE_EQ(s.georef.anchor().z(), 100.0);
}

TEST(Loader, degenerate_mesh_triangles_are_counted_in_the_scene_stats) {
    test::TempDir dir;
    write(dir, "d.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\nf 2 2 4\n");
    const std::string yaml =
        std::string(kMaterials) + "objects: [{type: mesh, file: d.obj, material: m}]\n";
    const Scene s = load_scene(write(dir, "t.yaml", yaml));
    EXPECT_EQ(s.stats.degenerate_triangles_dropped, 2u);
    EXPECT_EQ(s.stats.triangles, 1u);
}

TEST(Loader, resolve_scene_dispatches_demo_specs_and_files) {
    EXPECT_THROW(resolve_scene("demo:abc"), ConfigError);
    EXPECT_THROW(resolve_scene("demo:"), ConfigError);
    EXPECT_THROW(resolve_scene("demo:-1"), ConfigError);
    const Scene s = resolve_scene(fixture("example.yaml"));
    EXPECT_EQ(s.meshes.size(), 9u);
}

TEST(LoaderErrors, unknown_keys_name_the_key_path) {
    expect_scene_error(std::string(kMaterials) + "colour: red\nobjects: []\n",
                       {"colour: unknown key", "(line 3)"});
    expect_scene_error(std::string(kMaterials) +
                           "objects:\n  - {type: box, material: m, size: [1, 1, 1]}\n"
                           "  - {type: box, material: m, size: [1, 1, 1], colour: 3}\n",
                       {"objects[1].colour: unknown key", "line 5"});
    expect_scene_error("materials:\n  m: {reflectivity: 0.5}\nobjects: []\n",
                       {"materials.m.reflectivity: unknown key"});
    expect_scene_error(std::string(kMaterials) +
                           "objects:\n  - {type: box, material: m, size: [1, 1, 1],\n"
                           "     transform: {translate: [0, 0, 0], shear: 1}}\n",
                       {"objects[0].transform.shear: unknown key"});
    expect_scene_error(std::string(kMaterials) +
                           "objects:\n  - {type: box, material: m, size: [1, 1, 1],"
                           " size: [2, 2, 2]}\n",
                       {"duplicate key"});
}

TEST(LoaderErrors, bad_values_name_the_key_path) {
    const std::string m = kMaterials;
    expect_scene_error(m + "objects:\n  - {type: plane, material: m, size: [1, 1]}\n"
                           "  - {type: plane, material: m, size: [1, 1]}\n"
                           "  - {type: box, material: m, size: [1, 1]}\n",
                       {"objects[2].size: expected 3 numbers", "(line 6)"});
    expect_scene_error(m + "objects:\n  - {type: box, material: m, size: [1, -1, 1]}\n",
                       {"objects[0].size[1]: must be positive"});
    expect_scene_error(m + "objects:\n  - {type: box, material: m, size: [1, 1, 1],"
                           " transform: {translate: [0, .nan, 0]}}\n",
                       {"objects[0].transform.translate[1]: expected a finite number"});
    expect_scene_error(m + "objects:\n  - {type: box, material: m, size: [1, 1, .inf]}\n",
                       {"objects[0].size[2]: expected a finite number"});
    expect_scene_error(m + "objects:\n  - {type: box, material: glas, size: [1, 1, 1]}\n",
                       {"objects[0].material: unknown material 'glas'"});
    expect_scene_error(m + "objects:\n  - {type: cone, material: m}\n",
                       {"objects[0].type: unknown type 'cone'"});
    expect_scene_error(m + "objects:\n  - {material: m}\n", {"objects[0].type: missing"});
    expect_scene_error(
        m + "objects:\n  - {type: sphere, material: m, radius: 1, subdivisions: 9}\n",
        {"objects[0].subdivisions: must be in 0..8"});
    expect_scene_error("materials:\n  m: {reflectance: 1.5}\nobjects: []\n",
                       {"materials.m.reflectance: must be in [0, 1]"});
    expect_scene_error("materials:\n  m: {reflectance: 0.8, specular: 0.5}\nobjects: []\n",
                       {"materials.m.specular: reflectance + specular must not exceed 1"});
    expect_scene_error("materials:\n  m: {classification: 300}\nobjects: []\n",
                       {"materials.m.classification: must be in 0..255"});
    expect_scene_error("materials:\n  m: {color: [1, 2]}\nobjects: []\n",
                       {"materials.m.color: expected 3 integers"});
    expect_scene_error("materials:\n  m: {reflectance: 0.5, transmission: 0.6}\nobjects: []\n",
                       {"materials.m.transmission: reflectance + specular + transmission + mirror "
                        "must not exceed 1"});
    expect_scene_error(
        "materials:\n  m: {reflectance: 0.5, mirror: 0.3, transmission: 0.3}\n"
        "objects: []\n",
        {"materials.m.mirror: reflectance + specular + transmission + mirror"});
    expect_scene_error("materials:\n  m: {refractive_index: 0.9}\nobjects: []\n",
                       {"materials.m.refractive_index: must be in [1, 10]"});
    expect_scene_error("materials:\n  m: {refractive_index: 1.5, transmission: 0.5}\nobjects: []\n",
                       {"materials.m.refractive_index: glass sets its own transmission"});
    expect_scene_error("materials:\n  m: {refractive_index: 1.5, reflectance: 0.1}\nobjects: []\n",
                       {"materials.m.refractive_index: reflectance + specular"});
    expect_scene_error("materials:\n  m: {retroreflective: maybe}\nobjects: []\n",
                       {"materials.m.retroreflective: expected true or false"});
    expect_scene_error(m + "objects: []\n", {"objects: expected a non-empty list"});
    expect_scene_error(
        m + "objects:\n  - {type: box, material: m, size: [1, 1, 1], instances: []}\n",
        {"objects[0].instances: expected a non-empty list"});
    expect_scene_error(m + "objects:\n  - {type: box, material: m, size: [1, 1, 1],"
                           " instances: [{translate: [1, 2]}]}\n",
                       {"objects[0].instances[0].translate: expected 3 numbers"});
    expect_scene_error(m + "objects:\n  - {type: box, material: m, size: [1, 1, 1],"
                           " transform: {rotate_deg: [0, 0, 1], quaternion: [1, 0, 0, 0]}}\n",
                       {"objects[0].transform.quaternion: give either rotate_deg or quaternion"});
    expect_scene_error(m + "georef: {epsg: 32632, anchor: [1, 2, 3], lat: 45}\nobjects: []\n",
                       {"georef.anchor: give either anchor or lat/lon/h"});
    expect_scene_error(m + "georef: {anchor: [1, 2, 3]}\nobjects: []\n", {"georef.epsg: missing"});
    expect_scene_error(m + "objects:\n  - {type: heightfield, material: m, size: [4, 4],"
                           " cell_size: 3, function: {kind: flat}}\n",
                       {"objects[0].size: heightfield width 4", "not a multiple"});
    expect_scene_error(m + "objects:\n  - {type: heightfield, material: m, size: [4, 4],"
                           " cell_size: 1, function: {kind: sine_hills, amplitude: 1}}\n",
                       {"objects[0].function.wavelength: missing"});
    expect_scene_error(m + "objects:\n  - {type: heightfield, material: m, size: [4, 4],"
                           " cell_size: 1}\n",
                       {"objects[0]: a heightfield needs exactly one of raster or function"});
}

TEST(LoaderErrors, file_problems_name_the_scene_key_and_the_inner_file_line) {
    const std::string m = kMaterials;
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: tree.obj}\n",
                       {"objects[0].file: file not found", "tree.obj"});
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: tree.obj}\n",
                       {"objects[0].file: obj '", "tree.obj': line 3: malformed face vertex 'q'"},
                       "tree.obj", "v 0 0 0\nv 1 0 0\nf 1 2 q\n");
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: tree.obj}\n",
                       {"objects[0].file: obj '", "line 2: non-finite vertex value 'nan'"},
                       "tree.obj", "v 0 0 0\nv 1 nan 0\n");
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: t.ply}\n",
                       {"objects[0].file: ply '", "t.ply': header line 2: unknown format"}, "t.ply",
                       "ply\nformat bin 1.0\nend_header\n");
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: t.stl}\n",
                       {"objects[0].file: unsupported mesh format '.stl'"}, "t.stl", "solid x\n");
    expect_scene_error(m + "objects:\n  - {type: heightfield, material: m, raster: d.asc}\n",
                       {"objects[0].raster: asc '", "d.asc': line 2: unknown header key"}, "d.asc",
                       "ncols 2\nrows 2\n");
    expect_scene_error(m + "objects:\n  - {type: heightfield, material: m, raster: d.pgm}\n",
                       {"objects[0].cell_size: missing (needed for .pgm)"}, "d.pgm",
                       "P5 2 2 255\n");
    expect_scene_error(m + "objects:\n  - {type: mesh, material: m, file: e.obj}\n",
                       {"objects[0]: no triangles left (1 degenerate ones dropped)"}, "e.obj",
                       "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    expect_scene_error("objects: [\n", {"YAML syntax error"});
    expect_scene_error("- just\n- a list\n", {"expected a map"});
}

TEST(LoaderErrors, missing_scene_file_is_a_config_error_naming_it) {
    try {
        load_scene("/nonexistent/scene.yaml");
        ADD_FAILURE() << "no exception";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "scene '/nonexistent/scene.yaml': cannot open file");
    }
}

}  // namespace
}  // namespace mirage::scene
