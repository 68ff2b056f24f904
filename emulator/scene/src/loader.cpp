// SPDX-License-Identifier: Apache-2.0
// Scene YAML loader.
//
// ---- Scene file format (docs/file-formats.md §1) ------------------------------------
// A YAML map with up to three keys; every other key, anywhere, is an error. Lengths in metres,
// angles in degrees, all numbers finite.
//
//   georef:                       # optional; absent -> local scene (EPSG 0, anchor 0,0,0)
//     epsg: 32632                 #   projected CRS code, and
//     anchor: [500000, 5000000, 200]   # the world point that becomes local (0, 0, 0)
//   # or: {lat: 48.1, lon: 11.5, h: 520, epsg: 25832}  geodetic anchor (WGS84 degrees,
//   #     ellipsoidal height, default 0); converted once to `epsg`, by default its UTM zone.
//
//   materials:                    # name -> optical properties (all keys optional)
//     asphalt:
//       reflectance: 0.1          # Lambertian ρ_d, 0..1                       (default 0.5)
//       specular: 0.05            # Phong lobe weight, 0..1 − reflectance      (default 0)
//       specular_exponent: 20     # > 0                                         (default 20)
//       retroreflective: false    # corner-cube sheeting                        (default false)
//       retro_gain: 100           # retroreflective BRDF at the source, sr⁻¹, >= 0 (default 100)
//       classification: 11        # LAS class code 0..255                       (default 1)
//       color: [60, 60, 60]       # RGB 0..255 (stored ×257 as 16-bit LAS colour) (default grey)
//
//   objects:                      # list; each item:
//     - type: box                 # mesh | plane | box | sphere | heightfield   (required)
//       material: asphalt         # a key of `materials`                      (required)
//       name: kiosk               # optional label (default: file stem or type)
//       transform:                # optional: p' = translate + R · (scale ⊙ p)
//         translate: [x, y, z]
//         rotate_deg: [roll, pitch, yaw]   # R = Rz(yaw)·Ry(pitch)·Rx(roll); or instead
//         quaternion: [w, x, y, z]         # (normalised on load)
//         scale: 2                # or [sx, sy, sz], all > 0
//       instances:                # optional, non-empty: the mesh is stored once and placed at
//         - {translate: [..], rotate_deg: [..], scale: ..}   # transform · instance for each
//     Per type:
//       mesh:   file: tree.obj | tree.ply   (relative to this YAML's folder). OBJ `usemtl <name>`
//               picks the scene material of that name when it exists, else `material`.
//       plane:  size: [w, l]        centred on the origin, in z = 0, normal +z (2 triangles)
//       box:    size: [x, y, z]     centred on the origin (12 triangles)
//       sphere: radius: r, subdivisions: n (0..8, default 4 -> 20·4^n = 5120 triangles)
//       heightfield: 2 triangles per grid cell, one of
//         raster: dem.asc           ESRI ASCII grid, placed at its header coordinates taken in
//                                   the scene CRS (local = header − anchor); cell size from the
//                                   header; optional z_scale, z_offset (z = z_offset + z_scale·v)
//         raster: dem.pgm           binary PGM (P5, 8 or 16 bit), centred on the origin;
//                                   cell_size required; optional z_scale (default 1), z_offset
//         function: {kind: sine_hills, amplitude: 3, wavelength: 50, height: 0}
//                                   with size: [w, l] and cell_size (centred on the origin).
//                                   kinds: flat {height}, ramp {height, slope: [dz/dx, dz/dy]},
//                                   sine_hills {height, amplitude, wavelength}:
//                                   z = height + amplitude·sin(2πx/λ)·sin(2πy/λ)
//
// Errors throw ConfigError "scene '<file>': <key path>: <problem> (line N)", e.g.
// "scene 'town.yaml': objects[2].size: expected 3 numbers (line 14)"; problems inside a mesh or
// raster file are reported with that file's line or element, e.g.
// "scene 'town.yaml': objects[0].file: obj 'tree.obj': line 17: face index 40 out of range
// (12 vertices)". Degenerate triangles are dropped and counted in Scene::stats.
// -------------------------------------------------------------------------------------------------
#include "mirage/scene/loader.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/scene/demo_town.hpp"
#include "mirage/scene/heightfield.hpp"
#include "mirage/scene/mesh_io.hpp"
#include "mirage/scene/mesh_ops.hpp"
#include "mirage/scene/primitives.hpp"
#include "mirage/scene/yaml_reader.hpp"
#include "text_util.hpp"

namespace mirage::scene {

namespace {

namespace fs = std::filesystem;
using detail::quote;

std::string lower_ext(const fs::path& p) {
    std::string e = p.extension().string();
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

class SceneLoader : private YamlReader {
  public:
    // `file` names the scene in errors; relative mesh/raster paths resolve against `dir`.
    SceneLoader(std::string file, fs::path dir)
        : YamlReader("scene '" + file + "'"), file_(std::move(file)), dir_(std::move(dir)) {}

    // `text`: the YAML itself, or nullptr to read file_.
    Scene run(const std::string* text) {
        const YAML::Node root = load(file_, text);
        if (!root.IsMap()) fail("", "expected a map with georef, materials, objects", root);
        check_keys(root, "", {"georef", "materials", "objects", "description"});
        if (root["description"] && !root["description"].IsScalar()) {
            fail("description", "expected a string", root["description"]);
        }
        if (root["description"]) scene_.description = root["description"].Scalar();
        if (root["georef"]) georef(root["georef"], "georef");
        if (root["materials"]) materials(root["materials"], "materials");
        if (!root["objects"]) fail("objects", "missing (a scene needs at least one object)", root);
        objects(root["objects"], "objects");
        return std::move(scene_);
    }

  private:
    // ---- georef ---------------------------------------------------------------------------
    void georef(const YAML::Node& n, const std::string& path) {
        require_map(n, path);
        check_keys(n, path, {"epsg", "anchor", "lat", "lon", "h"});
        const bool geodetic = n["lat"] || n["lon"] || n["h"];
        int epsg = 0;
        if (n["epsg"]) epsg = static_cast<int>(integer(n["epsg"], sub(path, "epsg"), 1, 999999));
        try {
            if (geodetic) {
                if (n["anchor"])
                    fail(sub(path, "anchor"), "give either anchor or lat/lon/h", n["anchor"]);
                if (!n["lat"]) fail(sub(path, "lat"), "missing (needed with lon)", n);
                if (!n["lon"]) fail(sub(path, "lon"), "missing (needed with lat)", n);
                const double lat = number_in(n["lat"], sub(path, "lat"), -90, 90);
                const double lon = number_in(n["lon"], sub(path, "lon"), -180, 180);
                const double h = n["h"] ? number(n["h"], sub(path, "h")) : 0.0;
                scene_.georef = core::Georef::geodetic(lat, lon, h, epsg);
            } else {
                if (!n["anchor"]) fail(sub(path, "anchor"), "missing (or give lat/lon/h)", n);
                if (!n["epsg"]) fail(sub(path, "epsg"), "missing (needed with anchor)", n);
                const auto a = numbers(n["anchor"], sub(path, "anchor"), 3);
                scene_.georef = core::Georef::projected(epsg, {a[0], a[1], a[2]});
            }
        } catch (const Error& e) {
            const std::string what = e.what();
            if (what.rfind("scene '", 0) == 0) throw;
            fail(path, what, n);
        }
    }

    // ---- materials ------------------------------------------------------------------------
    void materials(const YAML::Node& n, const std::string& path) {
        require_map(n, path);
        check_keys_any(n, path);
        for (const auto& kv : n) {
            const YAML::Node key = kv.first;
            const YAML::Node m = kv.second;
            const std::string name = key.Scalar();
            const std::string p = sub(path, name);
            Material mat;
            mat.name = name;
            if (m.IsNull()) {
                // `name:` with no body: all defaults.
            } else {
                require_map(m, p);
                check_keys(m, p,
                           {"reflectance", "specular", "specular_exponent", "retroreflective",
                            "retro_gain", "transmission", "mirror", "refractive_index",
                            "classification", "color"});
                if (m["reflectance"])
                    mat.reflectance = number_in(m["reflectance"], sub(p, "reflectance"), 0, 1);
                if (m["specular"])
                    mat.specular = number_in(m["specular"], sub(p, "specular"), 0, 1);
                if (mat.reflectance + mat.specular > 1 + 1e-12) {
                    fail(sub(p, "specular"), "reflectance + specular must not exceed 1 (energy)",
                         m["specular"] ? m["specular"] : m);
                }
                if (m["specular_exponent"]) {
                    mat.specular_exponent =
                        number_in(m["specular_exponent"], sub(p, "specular_exponent"), 1e-6, 1e6);
                }
                if (m["retroreflective"])
                    mat.retroreflective = boolean(m["retroreflective"], sub(p, "retroreflective"));
                if (m["retro_gain"])
                    mat.retro_gain = number_in(m["retro_gain"], sub(p, "retro_gain"), 0, 1e9);
                paths(m, p, mat);
                if (m["classification"]) {
                    mat.classification = static_cast<std::uint8_t>(
                        integer(m["classification"], sub(p, "classification"), 0, 255));
                }
                if (m["color"]) {
                    const YAML::Node& c = m["color"];
                    if (!c.IsSequence() || c.size() != 3)
                        fail(sub(p, "color"), "expected 3 integers 0..255", c);
                    std::uint16_t rgb[3];
                    for (std::size_t i = 0; i < 3; ++i) {
                        // 8-bit -> 16-bit LAS colour: v · 257 maps 255 to 65535 exactly.
                        rgb[i] = static_cast<std::uint16_t>(
                            integer(c[i], item(sub(p, "color"), i), 0, 255) * 257);
                    }
                    mat.red = rgb[0];
                    mat.green = rgb[1];
                    mat.blue = rgb[2];
                }
            }
            by_name_.by_name[name] = scene_.add_material(std::move(mat));
        }
    }

    // Transmission, mirror and glass (docs/file-formats.md §1): impossible optics name the key.
    void paths(const YAML::Node& m, const std::string& p, Material& mat) {
        if (m["transmission"])
            mat.transmission = number_in(m["transmission"], sub(p, "transmission"), 0, 1);
        if (m["mirror"]) mat.mirror = number_in(m["mirror"], sub(p, "mirror"), 0, 1);
        if (m["refractive_index"]) {
            const YAML::Node& n = m["refractive_index"];
            mat.refractive_index = number_in(n, sub(p, "refractive_index"), 1, 10);
            if (m["transmission"] || m["mirror"])
                fail(sub(p, "refractive_index"),
                     "glass sets its own transmission and mirror fractions; remove those keys", n);
            if (!m["reflectance"]) mat.reflectance = 0.0;  // clear glass
            const double r = face_reflectance(mat.refractive_index);
            mat.transmission = (1 - r) * (1 - r);
            mat.mirror = 1 - mat.transmission;
        }
        const double sum = mat.reflectance + mat.specular + mat.transmission + mat.mirror;
        if (sum > 1 + 1e-12) {
            const char* key = m["refractive_index"] ? "refractive_index"
                              : m["mirror"]         ? "mirror"
                              : m["transmission"]   ? "transmission"
                                                    : "specular";
            fail(sub(p, key),
                 "reflectance + specular + transmission + mirror must not exceed 1 (energy); "
                 "glass passes and mirrors all of it",
                 m[key] ? m[key] : m);
        }
    }

    // Material maps have free-form keys; only shape and uniqueness are checked.
    void check_keys_any(const YAML::Node& map, const std::string& path) const {
        std::set<std::string> seen;
        for (const auto& kv : map) {
            const YAML::Node key = kv.first;
            if (!key.IsScalar() || key.Scalar().empty()) {
                fail(path, "names must be non-empty strings", key);
            }
            if (!seen.insert(key.Scalar()).second) {
                fail(sub(path, key.Scalar()), "duplicate name", key);
            }
        }
    }

    // ---- transforms -----------------------------------------------------------------------
    Eigen::Affine3d transform(const YAML::Node& n, const std::string& path) const {
        require_map(n, path);
        check_keys(n, path, {"translate", "rotate_deg", "quaternion", "scale"});
        Eigen::Affine3d t = Eigen::Affine3d::Identity();
        Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
        if (n["rotate_deg"] && n["quaternion"]) {
            fail(sub(path, "quaternion"), "give either rotate_deg or quaternion", n["quaternion"]);
        }
        if (n["rotate_deg"]) {
            const auto r = numbers(n["rotate_deg"], sub(path, "rotate_deg"), 3);
            constexpr double d = std::numbers::pi / 180.0;
            q = Eigen::AngleAxisd(r[2] * d, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(r[1] * d, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(r[0] * d, Eigen::Vector3d::UnitX());
        }
        if (n["quaternion"]) {
            const auto v = numbers(n["quaternion"], sub(path, "quaternion"), 4);
            q = Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
            if (q.norm() < 1e-9) fail(sub(path, "quaternion"), "zero quaternion", n["quaternion"]);
            q.normalize();
        }
        Eigen::Vector3d s = Eigen::Vector3d::Ones();
        if (const YAML::Node& sn = n["scale"]) {
            if (sn.IsSequence()) {
                const auto v = numbers(sn, sub(path, "scale"), 3);
                s = {v[0], v[1], v[2]};
                for (std::size_t i = 0; i < 3; ++i) {
                    if (v[i] <= 0) fail(item(sub(path, "scale"), i), "must be positive", sn[i]);
                }
            } else {
                s.setConstant(positive(sn, sub(path, "scale")));
            }
        }
        Eigen::Vector3d tr = Eigen::Vector3d::Zero();
        if (n["translate"]) {
            const auto v = numbers(n["translate"], sub(path, "translate"), 3);
            tr = {v[0], v[1], v[2]};
        }
        t.linear() = q.toRotationMatrix() * s.asDiagonal();
        t.translation() = tr;
        return t;
    }

    // ---- objects --------------------------------------------------------------------------
    void objects(const YAML::Node& n, const std::string& path) {
        if (!n.IsSequence() || n.size() == 0) fail(path, "expected a non-empty list of objects", n);
        for (std::size_t i = 0; i < n.size(); ++i) object(n[i], item(path, i));
    }

    fs::path resolve(const YAML::Node& n, const std::string& key) const {
        const fs::path p = string(n, key);
        const fs::path full = p.is_absolute() ? p : dir_ / p;
        std::error_code ec;
        if (!fs::is_regular_file(full, ec)) fail(key, "file not found: '" + full.string() + "'", n);
        return full;
    }

    // Runs a file reader; its errors get this object's key path in front.
    template <class F>
    auto with_context(const std::string& key, const YAML::Node& at, F&& f) const {
        try {
            return f();
        } catch (const Error& e) {
            // The inner message names its own file and line; the YAML line would only confuse.
            (void)at;
            std::string_view inner = e.what();
            if (inner.rfind("scene: ", 0) == 0) inner.remove_prefix(7);
            throw ConfigError("scene '" + file_ + "': " + key + ": " + std::string(inner));
        }
    }

    void object(const YAML::Node& n, const std::string& path) {
        require_map(n, path);
        if (!n["type"])
            fail(sub(path, "type"), "missing (mesh, plane, box, sphere or heightfield)", n);
        const std::string type = string(n["type"], sub(path, "type"));
        if (type == "mesh") {
            check_keys(n, path, {"type", "name", "material", "transform", "instances", "file"});
        } else if (type == "plane" || type == "box") {
            check_keys(n, path, {"type", "name", "material", "transform", "instances", "size"});
        } else if (type == "sphere") {
            check_keys(
                n, path,
                {"type", "name", "material", "transform", "instances", "radius", "subdivisions"});
        } else if (type == "heightfield") {
            check_keys(n, path,
                       {"type", "name", "material", "transform", "instances", "raster", "function",
                        "size", "cell_size", "z_scale", "z_offset"});
        } else {
            fail(sub(path, "type"),
                 "unknown type " + quote(type) + " (mesh, plane, box, sphere or heightfield)",
                 n["type"]);
        }
        if (!n["material"]) fail(sub(path, "material"), "missing", n);
        const std::string mat_name = string(n["material"], sub(path, "material"));
        auto mit = by_name_.by_name.find(mat_name);
        if (mit == by_name_.by_name.end()) {
            fail(sub(path, "material"), "unknown material " + quote(mat_name), n["material"]);
        }
        const std::uint32_t mat = mit->second;

        Mesh mesh;
        const std::uint64_t dropped_before = scene_.stats.degenerate_triangles_dropped;
        if (type == "mesh") {
            mesh = load_mesh(n, path, mat);
        } else if (type == "plane") {
            if (!n["size"]) fail(sub(path, "size"), "missing", n);
            const auto s = numbers(n["size"], sub(path, "size"), 2);
            check_positive(s, n["size"], sub(path, "size"));
            mesh = make_plane(s[0], s[1], mat);
        } else if (type == "box") {
            if (!n["size"]) fail(sub(path, "size"), "missing", n);
            const auto s = numbers(n["size"], sub(path, "size"), 3);
            check_positive(s, n["size"], sub(path, "size"));
            mesh = make_box({s[0], s[1], s[2]}, mat);
        } else if (type == "sphere") {
            if (!n["radius"]) fail(sub(path, "radius"), "missing", n);
            const double r = positive(n["radius"], sub(path, "radius"));
            int sd = 4;
            if (n["subdivisions"])
                sd = static_cast<int>(integer(n["subdivisions"], sub(path, "subdivisions"), 0, 8));
            mesh = make_icosphere(r, sd, mat);
        } else {
            mesh = heightfield(n, path, mat);
        }
        if (n["name"]) {
            mesh.name = string(n["name"], sub(path, "name"));
        } else if (type != "mesh") {
            mesh.name = type;
        }
        if (mesh.triangles.empty()) {
            fail(path,
                 "no triangles left (" +
                     std::to_string(scene_.stats.degenerate_triangles_dropped - dropped_before) +
                     " degenerate ones dropped)",
                 n);
        }

        Eigen::Affine3d t = Eigen::Affine3d::Identity();
        if (n["transform"]) t = transform(n["transform"], sub(path, "transform"));
        if (const YAML::Node& inst = n["instances"]) {
            const std::string ip = sub(path, "instances");
            if (!inst.IsSequence() || inst.size() == 0) {
                fail(ip, "expected a non-empty list of transforms", inst);
            }
            std::vector<Eigen::Affine3d> placements;
            for (std::size_t k = 0; k < inst.size(); ++k) {
                placements.push_back(t * transform(inst[k], item(ip, k)));
            }
            const std::uint32_t idx = scene_.add_mesh(std::move(mesh));
            for (const auto& p : placements) scene_.instances.push_back({idx, p});
        } else {
            if (!t.matrix().isIdentity(0)) transform_mesh(mesh, t);
            scene_.add_mesh(std::move(mesh));
        }
    }

    void check_positive(const std::vector<double>& v, const YAML::Node& n,
                        const std::string& path) const {
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (v[i] <= 0) fail(item(path, i), "must be positive", n[i]);
        }
    }

    Mesh load_mesh(const YAML::Node& n, const std::string& path, std::uint32_t mat) {
        const std::string key = sub(path, "file");
        if (!n["file"]) fail(key, "missing (an .obj or .ply file)", n);
        const fs::path file = resolve(n["file"], key);
        const std::string ext = lower_ext(file);
        MaterialBinding binding = by_name_;
        binding.fallback = mat;
        LoadStats& st = scene_.stats;
        Mesh m;
        if (ext == ".obj") {
            m = with_context(key, n["file"], [&] { return read_obj(file.string(), binding, st); });
        } else if (ext == ".ply") {
            m = with_context(key, n["file"], [&] { return read_ply(file.string(), binding, st); });
        } else {
            fail(key, "unsupported mesh format " + quote(ext) + " (use .obj or .ply)", n["file"]);
        }
        m.name = file.stem().string();
        return m;
    }

    Mesh heightfield(const YAML::Node& n, const std::string& path, std::uint32_t mat) {
        const bool raster = static_cast<bool>(n["raster"]);
        const bool function = static_cast<bool>(n["function"]);
        if (raster == function) {
            fail(path, "a heightfield needs exactly one of raster or function", n);
        }
        HeightGrid grid;
        if (raster) {
            const std::string key = sub(path, "raster");
            const fs::path file = resolve(n["raster"], key);
            const std::string ext = lower_ext(file);
            if (n["size"])
                fail(sub(path, "size"), "not used with raster (the raster gives the size)",
                     n["size"]);
            const double zs = n["z_scale"] ? number(n["z_scale"], sub(path, "z_scale")) : 1.0;
            const double zo = n["z_offset"] ? number(n["z_offset"], sub(path, "z_offset")) : 0.0;
            if (ext == ".asc") {
                if (n["cell_size"]) {
                    fail(sub(path, "cell_size"), "not used with .asc (the header gives cellsize)",
                         n["cell_size"]);
                }
                grid = with_context(key, n["raster"], [&] {
                    const std::string text = read_file_bytes(file.string(), "asc");
                    return parse_esri_ascii(text, file.string(), zs, zo);
                });
                // Header coordinates are in the scene CRS: move them into the local frame.
                const Eigen::Vector3d& a = scene_.georef.anchor();
                grid.x0_m -= a.x();
                grid.y0_m -= a.y();
                for (double& z : grid.z_m) z -= a.z();
            } else if (ext == ".pgm") {
                if (!n["cell_size"]) fail(sub(path, "cell_size"), "missing (needed for .pgm)", n);
                const double cell = positive(n["cell_size"], sub(path, "cell_size"));
                grid = with_context(key, n["raster"], [&] {
                    const std::string bytes = read_file_bytes(file.string(), "pgm");
                    return parse_pgm(bytes, file.string(), cell, zs, zo);
                });
            } else {
                fail(key, "unsupported raster format " + quote(ext) + " (use .asc or .pgm)",
                     n["raster"]);
            }
        } else {
            if (n["z_scale"]) fail(sub(path, "z_scale"), "only used with raster", n["z_scale"]);
            if (n["z_offset"]) fail(sub(path, "z_offset"), "only used with raster", n["z_offset"]);
            const HeightFunction f = height_function(n["function"], sub(path, "function"));
            if (!n["size"]) fail(sub(path, "size"), "missing (needed with function)", n);
            if (!n["cell_size"]) fail(sub(path, "cell_size"), "missing (needed with function)", n);
            const auto s = numbers(n["size"], sub(path, "size"), 2);
            check_positive(s, n["size"], sub(path, "size"));
            const double cell = positive(n["cell_size"], sub(path, "cell_size"));
            grid = with_context(sub(path, "size"), n["size"],
                                [&] { return grid_from_function(f, s[0], s[1], cell); });
        }
        return with_context(path, n, [&] { return mesh_from_grid(grid, mat); });
    }

    HeightFunction height_function(const YAML::Node& n, const std::string& path) const {
        require_map(n, path);
        if (!n["kind"]) fail(sub(path, "kind"), "missing (flat, ramp or sine_hills)", n);
        const std::string kind = string(n["kind"], sub(path, "kind"));
        HeightFunction f;
        if (kind == "flat") {
            check_keys(n, path, {"kind", "height"});
            f.kind = HeightFunction::Kind::Flat;
        } else if (kind == "ramp") {
            check_keys(n, path, {"kind", "height", "slope"});
            f.kind = HeightFunction::Kind::Ramp;
            if (!n["slope"]) fail(sub(path, "slope"), "missing ([dz/dx, dz/dy])", n);
            const auto s = numbers(n["slope"], sub(path, "slope"), 2);
            f.slope_x = s[0];
            f.slope_y = s[1];
        } else if (kind == "sine_hills") {
            check_keys(n, path, {"kind", "height", "amplitude", "wavelength"});
            f.kind = HeightFunction::Kind::SineHills;
            if (!n["amplitude"]) fail(sub(path, "amplitude"), "missing", n);
            if (!n["wavelength"]) fail(sub(path, "wavelength"), "missing", n);
            f.amplitude_m = number(n["amplitude"], sub(path, "amplitude"));
            f.wavelength_m = positive(n["wavelength"], sub(path, "wavelength"));
        } else {
            fail(sub(path, "kind"), "unknown kind " + quote(kind) + " (flat, ramp or sine_hills)",
                 n["kind"]);
        }
        if (n["height"]) f.height_m = number(n["height"], sub(path, "height"));
        return f;
    }

    std::string file_;
    fs::path dir_;
    Scene scene_;
    MaterialBinding by_name_;
};

}  // namespace

Scene load_scene(const std::string& path) {
    return SceneLoader(path, fs::path(path).parent_path()).run(nullptr);
}

Scene load_scene_text(const std::string& yaml, const std::string& name,
                      const std::filesystem::path& dir) {
    return SceneLoader(name, dir).run(&yaml);
}

Scene resolve_scene(const std::string& spec) {
    if (spec == "demo") return make_demo_town();
    if (spec.rfind("demo:", 0) == 0) {
        const std::string_view digits = std::string_view(spec).substr(5);
        std::uint64_t seed = 0;
        auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), seed);
        if (digits.empty() || ec != std::errc() || p != digits.data() + digits.size()) {
            throw ConfigError("scene '" + spec +
                              "': expected demo:<seed> with an unsigned integer seed");
        }
        DemoTownOptions opt;
        opt.seed = seed;
        return make_demo_town(opt);
    }
    return load_scene(spec);
}

}  // namespace mirage::scene
