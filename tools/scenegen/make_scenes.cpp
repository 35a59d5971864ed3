// Writes the regression scenes (scenes/<family>/*.json, scenes/meshes/*.obj)
// from tools/scenegen/scene_catalog.cpp, with `expect` values from the
// exact reference, in the format of docs/scene-format.md. JSON goes through nlohmann-json: numbers in its shortest
// round-trip form, so `hedra check` reads back the very doubles used here.
//
// Usage:
//   hedra_make_scenes --out DIR     write every scene and mesh under DIR;
//                                   hedra's disagreements go to stderr
//   hedra_make_scenes --check DIR   regenerate into a temporary directory and
//                                   compare with DIR: meshes byte for byte,
//                                   scenes as JSON (numbers within 1e-12
//                                   relative, 1e-15 absolute, so that a last-
//                                   bit difference of sin/cos or qhull on
//                                   another machine does not count); files of
//                                   the generated families that the generator
//                                   no longer writes count as differences.
//                                   Exit 1 on any difference.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "scenegen/scene_catalog.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using hedra::scenes::Expectation;
using hedra::scenes::Mesh;
using hedra::scenes::SceneSpec;

namespace {

// x + 0.0 turns -0.0 into 0.0 (nothing else changes): no "-0.0" in the files.
double clean(double x) { return x + 0.0; }
json vec(const Eigen::Vector3d& v) { return json::array({clean(v.x()), clean(v.y()), clean(v.z())}); }

// One line per value, with a space after ':' and ','.
std::string inline_dump(const json& j) {
  if (j.is_object()) {
    std::string s = "{";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      s += (first ? "" : ", ") + json(it.key()).dump() + ": " + inline_dump(it.value());
      first = false;
    }
    return s + "}";
  }
  if (j.is_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < j.size(); ++i) s += (i ? ", " : "") + inline_dump(j[i]);
    return s + "]";
  }
  return j.dump();
}

struct Counts {
  int queries = 0;
  int disagreements = 0;
};

std::string scene_text(const SceneSpec& scene, Counts& counts, bool verify) {
  json shapes = json::object();
  for (const auto& s : scene.shapes) {
    json j = {{"type", s.type}};
    if (s.type == "sphere") j["radius"] = s.radius;
    if (s.type == "box") j["half_extents"] = vec(s.half_extents);
    if (s.type == "capsule" || s.type == "cylinder" || s.type == "cone") {
      j["radius"] = s.radius;
      j["half_length"] = s.half_length;
    }
    if (s.type == "hull") {
      if (!s.mesh.empty()) {
        j["file"] = "../meshes/" + s.mesh + ".obj";
      } else {
        json points = json::array();
        for (const auto& p : s.points) points.push_back(vec(p));
        j["points"] = points;
      }
    }
    if (s.margin > 0) j["margin"] = s.margin;
    shapes[s.name] = j;
  }
  json bodies = json::object();
  for (const auto& b : scene.bodies) {
    json j = {{"shape", b.shape}, {"position", vec(b.position)}};
    if (b.orientation != Eigen::Vector4d(1, 0, 0, 0))
      j["orientation"] = json::array({b.orientation[0], b.orientation[1], b.orientation[2], b.orientation[3]});
    if (b.end_position) j["end_position"] = vec(*b.end_position);
    if (b.end_orientation) {
      const Eigen::Vector4d& q = *b.end_orientation;
      j["end_orientation"] = json::array({q[0], q[1], q[2], q[3]});
    }
    bodies[b.name] = j;
  }
  std::vector<json> queries;
  for (const auto& q : scene.queries) {
    const Expectation e = hedra::scenes::expect(scene, q);
    if (!e.exact.ok) throw std::runtime_error(scene.name + ": " + q.a + "-" + q.b + ": " + e.exact.reason);
    json ex = json::object();
    if (q.continuous()) {
      ex["hit"] = *e.hit;
      ex["fraction"] = clean(*e.fraction);
      ex["tolerance"] = e.tolerance;
      json j;
      if (q.type == "raycast") {
        j = {{"type", q.type}, {"body", q.a}, {"origin", vec(q.origin)}, {"direction", vec(q.direction)}};
        if (q.max_fraction != 1.0) j["max_fraction"] = q.max_fraction;
      } else {
        j = {{"a", q.a}, {"b", q.b}, {"type", q.type}};
        if (q.target_distance != 0.0) j["target_distance"] = q.target_distance;
      }
      j["expect"] = ex;
      queries.push_back(j);
    }
    if (q.continuous()) {
      ++counts.queries;
      if (verify) {
        const std::string problems = hedra::scenes::check_hedra(scene, q, e);
        if (!problems.empty()) {
          ++counts.disagreements;
          std::cerr << "hedra disagrees: " << scene.family << "/" << scene.name << ".json " << q.a << "-" << q.b << " "
                    << q.type << ": " << problems << "\n";
        }
      }
      continue;
    }
    if (e.intersecting) ex["intersecting"] = *e.intersecting;
    if (e.distance) ex["distance"] = clean(*e.distance);
    if (e.normal) ex["normal"] = vec(*e.normal);
    if (e.contact_count) ex["contact_count"] = *e.contact_count;
    if (e.distance) ex["tolerance"] = e.tolerance;
    if (e.normal) ex["angle_tolerance"] = e.angle_tolerance;
    queries.push_back({{"a", q.a}, {"b", q.b}, {"type", q.type}, {"expect", ex}});
    ++counts.queries;
    if (verify) {
      const std::string problems = hedra::scenes::check_hedra(scene, q, e);
      if (!problems.empty()) {
        ++counts.disagreements;
        std::cerr << "hedra disagrees: " << scene.family << "/" << scene.name << ".json " << q.a << "-" << q.b << " "
                  << q.type << ": " << problems << "\n";
      }
    }
  }
  std::string text = "{\n";
  text += "  \"hedra_scene\": 1,\n";
  text += "  \"name\": " + json(scene.name).dump() + ",\n";
  text += "  \"description\": " + json(scene.description).dump() + ",\n";
  text += "  \"shapes\": {\n";
  bool first = true;
  for (auto it = shapes.begin(); it != shapes.end(); ++it, first = false)
    text += std::string(first ? "" : ",\n") + "    " + json(it.key()).dump() + ": " + inline_dump(it.value());
  text += "\n  },\n  \"bodies\": {\n";
  first = true;
  for (auto it = bodies.begin(); it != bodies.end(); ++it, first = false)
    text += std::string(first ? "" : ",\n") + "    " + json(it.key()).dump() + ": " + inline_dump(it.value());
  text += "\n  },\n  \"queries\": [\n";
  for (std::size_t i = 0; i < queries.size(); ++i)
    text += (i ? ",\n" : "") + std::string("    ") + inline_dump(queries[i]);
  text += "\n  ]\n}\n";
  return text;
}

bool write_file(const fs::path& path, const std::string& text) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) {
    std::cerr << path.string() << ": cannot write\n";
    return false;
  }
  return true;
}

// Writes everything under `dir`; returns the relative paths written.
bool generate(const fs::path& dir, bool verify, std::set<std::string>& written, std::set<std::string>& families) {
  const std::vector<Mesh> meshes = hedra::scenes::make_meshes();
  const std::vector<SceneSpec> scenes = hedra::scenes::make_scenes(meshes);
  for (const Mesh& m : meshes) {
    const std::string rel = "meshes/" + m.name + ".obj";
    if (!write_file(dir / rel, m.text)) return false;
    written.insert(rel);
  }
  families.insert("meshes");
  Counts counts;
  for (const SceneSpec& s : scenes) {
    const std::string rel = s.family + "/" + s.name + ".json";
    if (written.count(rel)) throw std::runtime_error("two scenes named " + rel);
    if (!write_file(dir / rel, scene_text(s, counts, verify))) return false;
    written.insert(rel);
    families.insert(s.family);
  }
  std::cerr << "hedra_make_scenes: " << scenes.size() << " scenes, " << counts.queries << " queries, " << meshes.size()
            << " meshes";
  if (verify) std::cerr << "; hedra disagrees on " << counts.disagreements << " queries";
  std::cerr << "\n";
  return true;
}

std::string read_text(const fs::path& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Structural comparison; numbers within 1e-12 relative or 1e-15 absolute.
bool same_json(const json& a, const json& b, const std::string& at, std::string& where) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    if (x == y || std::abs(x - y) <= 1e-12 * std::max(std::abs(x), std::abs(y)) || std::abs(x - y) <= 1e-15)
      return true;
    where = at + ": " + a.dump() + " vs " + b.dump();
    return false;
  }
  if (a.type() != b.type()) {
    where = at + ": different types";
    return false;
  }
  if (a.is_object()) {
    if (a.size() != b.size()) {
      where = at + ": different keys";
      return false;
    }
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key())) {
        where = at + "." + it.key() + ": missing";
        return false;
      }
      if (!same_json(it.value(), b.at(it.key()), at + "." + it.key(), where)) return false;
    }
    return true;
  }
  if (a.is_array()) {
    if (a.size() != b.size()) {
      where = at + ": different lengths";
      return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same_json(a[i], b[i], at + "[" + std::to_string(i) + "]", where)) return false;
    return true;
  }
  if (a != b) {
    where = at + ": " + a.dump() + " vs " + b.dump();
    return false;
  }
  return true;
}

int check(const fs::path& committed) {
  char pattern[] = "/tmp/hedra_scenes_XXXXXX";
  const char* made = mkdtemp(pattern);
  if (!made) {
    std::cerr << "hedra_make_scenes: cannot create a temporary directory\n";
    return 2;
  }
  const fs::path temp(made);
  std::set<std::string> written, families;
  int differences = 0;
  try {
    if (!generate(temp, false, written, families)) differences = -1;
  } catch (const std::exception& e) {
    std::cerr << "hedra_make_scenes: " << e.what() << "\n";
    differences = -1;
  }
  if (differences == 0) {
    for (const std::string& rel : written) {
      bool ok_new = false, ok_old = false;
      const std::string fresh = read_text(temp / rel, ok_new);
      const std::string old = read_text(committed / rel, ok_old);
      if (!ok_old) {
        std::cerr << (committed / rel).string() << ": missing (the generator writes it)\n";
        ++differences;
        continue;
      }
      if (fresh == old) continue;
      std::string where = "bytes differ";
      bool same = false;
      if (rel.size() > 5 && rel.compare(rel.size() - 5, 5, ".json") == 0) {
        const json a = json::parse(fresh, nullptr, false), b = json::parse(old, nullptr, false);
        same = !a.is_discarded() && !b.is_discarded() && same_json(a, b, "", where);
      }
      if (!same) {
        std::cerr << (committed / rel).string() << ": differs from what hedra_make_scenes generates (" << where
                  << "); regenerate with hedra_make_scenes --out scenes\n";
        ++differences;
      }
    }
    for (const std::string& family : families) {
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(committed / family, ec)) {
        const std::string rel = family + "/" + entry.path().filename().string();
        if (!written.count(rel)) {
          std::cerr << entry.path().string() << ": not generated any more; remove it or regenerate\n";
          ++differences;
        }
      }
    }
  }
  std::error_code ec;
  fs::remove_all(temp, ec);
  if (differences < 0) return 2;
  return differences == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--check") == 0) return check(argv[2]);
  if (argc == 3 && std::strcmp(argv[1], "--out") == 0) {
    std::set<std::string> written, families;
    try {
      return generate(argv[2], true, written, families) ? 0 : 2;
    } catch (const std::exception& e) {
      std::cerr << "hedra_make_scenes: " << e.what() << "\n";
      return 2;
    }
  }
  std::cerr << "usage: hedra_make_scenes --out DIR | --check DIR\n";
  return 2;
}
