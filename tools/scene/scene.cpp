// Scene loading and validation (see scene.hpp). The reader walks the JSON
// document with the JSON path of the value in hand; the first problem throws
// a SceneError (internal to this file) carrying that path, and the public
// functions turn it into "<file>: <path>: <reason>". Nothing is built while
// reading: mesh files and hulls wait for build_shapes(), which builds only
// what the queries use.
#include "scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <hedra/hull/mesh_io.hpp>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "scene/timing.hpp"

namespace hedra::tool {

const char* to_string(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::sphere:
      return "sphere";
    case ShapeKind::box:
      return "box";
    case ShapeKind::capsule:
      return "capsule";
    case ShapeKind::cylinder:
      return "cylinder";
    case ShapeKind::cone:
      return "cone";
    case ShapeKind::hull:
      return "hull";
  }
  return "unknown";
}

const char* to_string(QueryType type) {
  switch (type) {
    case QueryType::intersect:
      return "intersect";
    case QueryType::distance:
      return "distance";
    case QueryType::penetration:
      return "penetration";
    case QueryType::contact:
      return "contact";
    case QueryType::raycast:
      return "raycast";
    case QueryType::cast:
      return "cast";
    case QueryType::toi:
      return "toi";
  }
  return "unknown";
}

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct SceneError {
  std::string path;  // JSON path; empty for the whole document
  std::string reason;
};

[[noreturn]] void fail(const std::string& path, const std::string& reason) { throw SceneError{path, reason}; }

std::string member(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

std::string format_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string type_name(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "a number";
    default:
      return "an unexpected value";
  }
}

const json& expect_object(const json& value, const std::string& path) {
  if (!value.is_object()) fail(path, "expected an object, got " + type_name(value));
  return value;
}

// Every key of `object` must be in `allowed`.
void check_keys(const json& object, const std::string& path, const std::vector<const char*>& allowed) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    bool known = false;
    for (const char* key : allowed) known = known || it.key() == key;
    if (known) continue;
    std::string list;
    for (const char* key : allowed) list += (list.empty() ? "" : ", ") + std::string(key);
    fail(member(path, it.key()), "unknown key (expected one of: " + list + ")");
  }
}

const json& require(const json& object, const std::string& path, const char* key) {
  auto it = object.find(key);
  if (it == object.end()) {
    fail(path.empty() ? key : path, path.empty() ? "missing" : std::string("missing required key '") + key + "'");
  }
  return *it;
}

const json* optional_member(const json& object, const char* key) {
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

double number(const json& value, const std::string& path) {
  if (!value.is_number()) fail(path, "expected a number, got " + type_name(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) fail(path, "expected a finite number");
  return x;
}

double non_negative(const json& value, const std::string& path) {
  const double x = number(value, path);
  if (x < 0.0) fail(path, "negative (" + format_number(x) + "), expected >= 0");
  if (x > collision::max_shape_size) fail(path, "too large (" + format_number(x) + "), expected at most " + "1e60");
  return x;
}

std::string string(const json& value, const std::string& path) {
  if (!value.is_string()) fail(path, "expected a string, got " + type_name(value));
  return value.get<std::string>();
}

// An array of exactly `n` finite numbers.
template <int N>
Eigen::Matrix<double, N, 1> numbers(const json& value, const std::string& path, const char* what) {
  if (!value.is_array() || value.size() != static_cast<std::size_t>(N)) {
    fail(path, "expected " + std::to_string(N) + " numbers" + what +
                   (value.is_array() ? ", got " + std::to_string(value.size()) : ", got " + type_name(value)));
  }
  Eigen::Matrix<double, N, 1> x;
  for (int i = 0; i < N; ++i)
    x[i] = number(value[static_cast<std::size_t>(i)], element(path, static_cast<std::size_t>(i)));
  return x;
}

Eigen::Vector3d vector3(const json& value, const std::string& path) { return numbers<3>(value, path, ""); }

// ---- shapes -----------------------------------------------------------------

ShapeSpec read_shape(const std::string& name, const json& value, const std::string& path, const fs::path& base) {
  expect_object(value, path);
  ShapeSpec shape;
  shape.name = name;
  const std::string type = string(require(value, path, "type"), member(path, "type"));
  if (const json* margin = optional_member(value, "margin"))
    shape.margin = non_negative(*margin, member(path, "margin"));

  auto radius = [&] { shape.radius = non_negative(require(value, path, "radius"), member(path, "radius")); };
  auto half_length = [&] {
    shape.half_length = non_negative(require(value, path, "half_length"), member(path, "half_length"));
  };
  if (type == "sphere") {
    shape.kind = ShapeKind::sphere;
    check_keys(value, path, {"type", "radius", "margin"});
    radius();
  } else if (type == "box") {
    shape.kind = ShapeKind::box;
    check_keys(value, path, {"type", "half_extents", "margin"});
    const std::string at = member(path, "half_extents");
    shape.half_extents = vector3(require(value, path, "half_extents"), at);
    for (int i = 0; i < 3; ++i)
      non_negative(value["half_extents"][static_cast<std::size_t>(i)], element(at, static_cast<std::size_t>(i)));
  } else if (type == "capsule" || type == "cylinder" || type == "cone") {
    shape.kind = type == "capsule" ? ShapeKind::capsule : type == "cylinder" ? ShapeKind::cylinder : ShapeKind::cone;
    check_keys(value, path, {"type", "radius", "half_length", "margin"});
    radius();
    half_length();
  } else if (type == "hull") {
    shape.kind = ShapeKind::hull;
    check_keys(value, path, {"type", "points", "file", "margin"});
    const json* points = optional_member(value, "points");
    const json* file = optional_member(value, "file");
    if (points && file) fail(path, "give either 'points' or 'file', not both");
    if (!points && !file) fail(path, "missing required key 'points' or 'file'");
    if (points) {
      const std::string at = member(path, "points");
      if (!points->is_array()) fail(at, "expected an array of [x, y, z] points, got " + type_name(*points));
      if (points->empty()) fail(at, "empty (a hull needs at least one point)");
      shape.points.reserve(points->size());
      for (std::size_t i = 0; i < points->size(); ++i) shape.points.push_back(vector3((*points)[i], element(at, i)));
    } else {
      const std::string at = member(path, "file");
      shape.file = string(*file, at);
      if (shape.file.empty()) fail(at, "empty file name");
      if (!hull::format_from_path(shape.file)) {
        fail(at, "unknown file extension in '" + shape.file + "' (expected .obj, .off or .xyz)");
      }
      const fs::path relative(shape.file);
      shape.resolved_file = relative.is_absolute() ? relative.string() : (base / relative).lexically_normal().string();
    }
  } else {
    fail(member(path, "type"),
         "unknown shape type '" + type + "' (expected sphere, box, capsule, cylinder, cone or hull)");
  }
  return shape;
}

// ---- bodies -----------------------------------------------------------------

// Edits (insert, delete, replace one character) from a to b: Levenshtein,
// two rows.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t replace = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, replace});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

// " (did you mean 'crate'?)" for the closest of `names` within a third of
// the name's length (at least 2 edits; case alone counts as close), or
// " (known: a, b, c)" for a short list, or nothing.
std::string did_you_mean(const std::vector<std::string>& names, const std::string& name) {
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::size_t limit = std::max<std::size_t>(2, name.size() / 3);
  std::size_t best = limit + 1;
  const std::string* closest = nullptr;
  for (const std::string& candidate : names) {
    const std::size_t d = lower(candidate) == lower(name) ? 0 : edit_distance(candidate, name);
    if (d < best) {
      best = d;
      closest = &candidate;
    }
  }
  if (closest) return " (did you mean '" + *closest + "'?)";
  if (names.empty() || names.size() > 8) return "";
  std::string list;
  for (const std::string& candidate : names) list += (list.empty() ? "" : ", ") + candidate;
  return " (known: " + list + ")";
}

std::size_t find_index(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

// A position: three finite numbers within collision::max_coordinate.
Eigen::Vector3d position(const json& value, const std::string& path) {
  const Eigen::Vector3d p = vector3(value, path);
  for (int k = 0; k < 3; ++k)
    if (std::abs(p[k]) > collision::max_coordinate)
      fail(element(path, static_cast<std::size_t>(k)),
           "too far from the origin (" + format_number(p[k]) + "), expected |x| <= " + "1e60");
  return p;
}

// A quaternion [w, x, y, z], normalised. Scaled first, so that neither tiny
// nor huge components under- or overflow the norm; a zero quaternion has no
// rotation.
Eigen::Quaterniond quaternion(const json& value, const std::string& path) {
  Eigen::Vector4d q = numbers<4>(value, path, " [w, x, y, z]");
  const double largest = q.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) fail(path, "zero quaternion (cannot be normalised)");
  q /= largest;
  q.normalize();
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

BodySpec read_body(const std::string& name, const json& value, const std::string& path,
                   const std::vector<std::string>& shape_names) {
  expect_object(value, path);
  check_keys(value, path, {"shape", "position", "orientation", "end_position", "end_orientation"});
  BodySpec body;
  body.name = name;
  const std::string shape = string(require(value, path, "shape"), member(path, "shape"));
  body.shape = find_index(shape_names, shape);
  if (body.shape == shape_names.size())
    fail(member(path, "shape"), "unknown shape '" + shape + "'" + did_you_mean(shape_names, shape));
  if (const json* p = optional_member(value, "position")) body.position = position(*p, member(path, "position"));
  if (const json* q = optional_member(value, "orientation"))
    body.orientation = quaternion(*q, member(path, "orientation"));
  body.end_position = body.position;
  body.end_orientation = body.orientation;
  if (const json* p = optional_member(value, "end_position"))
    body.end_position = position(*p, member(path, "end_position"));
  if (const json* q = optional_member(value, "end_orientation"))
    body.end_orientation = quaternion(*q, member(path, "end_orientation"));
  return body;
}

// ---- queries ----------------------------------------------------------------

QueryType read_query_type(const json& value, const std::string& path) {
  const std::string type = string(value, path);
  for (QueryType t : {QueryType::intersect, QueryType::distance, QueryType::penetration, QueryType::contact,
                      QueryType::raycast, QueryType::cast, QueryType::toi}) {
    if (type == to_string(t)) return t;
  }
  fail(path,
       "unknown query type '" + type + "' (expected intersect, distance, penetration, contact, raycast, cast or toi)");
}

// A continuous query's expectation: `hit` and `fraction`, `tolerance` on the
// fraction.
Expectation read_continuous_expectation(const json& value, const std::string& path, const std::string& type_word) {
  check_keys(
      value, path,
      {"hit", "fraction", "tolerance", "intersecting", "distance", "normal", "contact_count", "angle_tolerance"});
  for (const char* key : {"intersecting", "distance", "normal", "contact_count", "angle_tolerance"}) {
    if (optional_member(value, key)) {
      fail(member(path, key), type_word + " expects only 'hit' and 'fraction' (with 'tolerance'), not '" + key + "'");
    }
  }
  Expectation expect;
  if (const json* v = optional_member(value, "hit")) {
    if (!v->is_boolean()) fail(member(path, "hit"), "expected true or false, got " + type_name(*v));
    expect.hit = v->get<bool>();
  }
  if (const json* v = optional_member(value, "fraction")) {
    expect.fraction = non_negative(*v, member(path, "fraction"));
  }
  if (const json* v = optional_member(value, "tolerance")) {
    const std::string at = member(path, "tolerance");
    expect.tolerance = non_negative(*v, at);
    if (!expect.fraction) fail(at, "no 'fraction' expected to apply it to");
  }
  if (expect.empty()) fail(path, "empty (expect at least one of hit, fraction)");
  return expect;
}

Expectation read_expectation(const json& value, const std::string& path, QueryType type) {
  expect_object(value, path);
  Expectation expect;
  const std::string name = to_string(type);
  const std::string type_word = (name[0] == 'i' ? "an '" : "a '") + name + "' query";
  if (is_continuous(type)) return read_continuous_expectation(value, path, type_word);
  for (const char* key : {"hit", "fraction"}) {
    if (optional_member(value, key)) {
      fail(member(path, key), type_word + " has no '" + key + "' (only raycast, cast and toi queries do)");
    }
  }
  // The keys this type answers (the specific messages below name the
  // query that answers the others).
  std::vector<const char*> allowed = {"intersecting"};
  if (type != QueryType::intersect) {
    for (const char* key : {"distance", "normal", "tolerance", "angle_tolerance"}) allowed.push_back(key);
    if (type == QueryType::contact) allowed.push_back("contact_count");
  }
  std::vector<const char*> known = allowed;
  for (const char* key : {"distance", "normal", "contact_count", "tolerance", "angle_tolerance", "pair_count"})
    known.push_back(key);
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (std::any_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; })) continue;
    std::string list;
    for (const char* key : allowed) list += (list.empty() ? "" : ", ") + std::string(key);
    fail(member(path, it.key()), "unknown key (" + type_word + " may expect: " + list + ")");
  }
  if (const json* v = optional_member(value, "intersecting")) {
    if (!v->is_boolean()) fail(member(path, "intersecting"), "expected true or false, got " + type_name(*v));
    expect.intersecting = v->get<bool>();
  }
  if (const json* v = optional_member(value, "distance")) {
    const std::string at = member(path, "distance");
    if (type == QueryType::intersect) fail(at, type_word + " computes no distance (use 'distance' or 'penetration')");
    expect.distance = number(*v, at);
    if (type == QueryType::distance && *expect.distance < 0.0) {
      fail(at, "negative (" + format_number(*expect.distance) +
                   "): a 'distance' query answers >= 0; use 'penetration' for a signed distance");
    }
  }
  if (const json* v = optional_member(value, "normal")) {
    const std::string at = member(path, "normal");
    if (type == QueryType::intersect) fail(at, type_word + " computes no normal");
    Eigen::Vector3d n = vector3(*v, at);
    const double largest = n.cwiseAbs().maxCoeff();
    if (!(largest > 0.0)) fail(at, "zero vector (a normal needs a direction)");
    n /= largest;
    expect.normal = n.normalized();
  }
  if (optional_member(value, "pair_count"))
    fail(member(path, "pair_count"), "only a query over all pairs (\"pairs\": \"all\") counts pairs");
  if (const json* v = optional_member(value, "contact_count")) {
    const std::string at = member(path, "contact_count");
    if (type != QueryType::contact) fail(at, type_word + " computes no contacts (use 'contact')");
    if (!v->is_number_integer() || v->get<long long>() < 0 || v->get<long long>() > 4) {
      fail(at, "expected a whole number from 0 to 4, got " + v->dump());
    }
    expect.contact_count = v->get<int>();
  }
  if (const json* v = optional_member(value, "tolerance")) {
    const std::string at = member(path, "tolerance");
    expect.tolerance = non_negative(*v, at);
    if (!expect.distance) fail(at, "no 'distance' expected to apply it to");
  }
  if (const json* v = optional_member(value, "angle_tolerance")) {
    const std::string at = member(path, "angle_tolerance");
    expect.angle_tolerance = non_negative(*v, at);
    if (!expect.normal) fail(at, "no 'normal' expected to apply it to");
  }
  if (expect.empty()) fail(path, "empty (expect at least one of intersecting, distance, normal, contact_count)");
  return expect;
}

std::size_t read_body_name(const json& value, const std::string& path, const char* key,
                           const std::vector<std::string>& body_names) {
  const std::string at = member(path, key);
  const std::string name = string(require(value, path, key), at);
  const std::size_t index = find_index(body_names, name);
  if (index == body_names.size()) fail(at, "unknown body '" + name + "'" + did_you_mean(body_names, name));
  return index;
}

// raycast: "body", "origin", "direction" (not zero), "max_fraction" (>= 0).
void read_ray(const json& value, const std::string& path, const std::vector<std::string>& body_names,
              QuerySpec& query) {
  check_keys(value, path, {"type", "body", "origin", "direction", "max_fraction", "expect"});
  query.a = query.b = read_body_name(value, path, "body", body_names);
  query.origin = position(require(value, path, "origin"), member(path, "origin"));
  const std::string at = member(path, "direction");
  query.direction = vector3(require(value, path, "direction"), at);
  if (!(query.direction.cwiseAbs().maxCoeff() > 0.0)) fail(at, "zero vector (a ray needs a direction)");
  for (int k = 0; k < 3; ++k)
    if (std::abs(query.direction[k]) > collision::max_coordinate)
      fail(element(at, static_cast<std::size_t>(k)),
           "too large (" + format_number(query.direction[k]) + "), expected |x| <= " + "1e60");
  if (const json* v = optional_member(value, "max_fraction"))
    query.max_fraction = non_negative(*v, member(path, "max_fraction"));
}

// "pairs": "all" (scene-format.md, "All pairs"): no bodies named,
// "max_distance" >= 0 (default 0), `expect` holds only "pair_count".
void read_all_pairs(const json& value, const std::string& path, QuerySpec& query) {
  const std::string at = member(path, "pairs");
  const json& pairs = require(value, path, "pairs");
  if (!pairs.is_string() || pairs.get<std::string>() != "all")
    fail(at, "expected \"all\" (every pair of bodies), got " + pairs.dump());
  if (is_continuous(query.type))
    fail(member(path, "type"), std::string("a '") + to_string(query.type) +
                                   "' query has no all-pairs form (intersect, distance, penetration or contact)");
  for (const char* key : {"a", "b", "body"})
    if (optional_member(value, key))
      fail(member(path, key), "a query over all pairs names no bodies (remove it, or remove \"pairs\")");
  if (optional_member(value, "contact_distance"))
    fail(member(path, "contact_distance"), "a query over all pairs takes 'max_distance' (also the contact distance)");
  check_keys(value, path, {"type", "pairs", "max_distance", "expect"});
  query.all_pairs = true;
  if (const json* v = optional_member(value, "max_distance"))
    query.max_distance = non_negative(*v, member(path, "max_distance"));
  query.contact_distance = query.max_distance;
  if (const json* expect = optional_member(value, "expect")) {
    const std::string where = member(path, "expect");
    expect_object(*expect, where);
    check_keys(*expect, where, {"pair_count"});
    const json& count = require(*expect, where, "pair_count");
    if (!count.is_number_integer() || count.get<long long>() < 0)
      fail(member(where, "pair_count"), "expected a whole number >= 0, got " + count.dump());
    Expectation e;
    e.pair_count = count.get<long long>();
    query.expect = e;
  }
}

QuerySpec read_query(const json& value, const std::string& path, const std::vector<std::string>& body_names) {
  expect_object(value, path);
  QuerySpec query;
  query.type = read_query_type(require(value, path, "type"), member(path, "type"));
  if (optional_member(value, "pairs")) {
    read_all_pairs(value, path, query);
    return query;
  }
  if (optional_member(value, "max_distance"))
    fail(member(path, "max_distance"), "only a query over all pairs (\"pairs\": \"all\") takes 'max_distance'");
  if (query.type == QueryType::raycast) {
    read_ray(value, path, body_names, query);
  } else {
    if (query.type == QueryType::cast || query.type == QueryType::toi) {
      check_keys(value, path, {"a", "b", "type", "target_distance", "expect"});
      if (const json* v = optional_member(value, "target_distance"))
        query.target_distance = non_negative(*v, member(path, "target_distance"));
    } else if (query.type == QueryType::contact) {
      check_keys(value, path, {"a", "b", "type", "contact_distance", "expect"});
      if (const json* v = optional_member(value, "contact_distance"))
        query.contact_distance = non_negative(*v, member(path, "contact_distance"));
    } else {
      check_keys(value, path, {"a", "b", "type", "expect"});
    }
    query.a = read_body_name(value, path, "a", body_names);
    query.b = read_body_name(value, path, "b", body_names);
    if (query.a == query.b) {
      fail(member(path, "b"), "the same body as 'a' ('" + body_names[query.a] +
                                  "'): a body is not queried against itself (it would answer its own size, "
                                  "negated, as a depth)");
    }
  }
  if (const json* expect = optional_member(value, "expect")) {
    query.expect = read_expectation(*expect, member(path, "expect"), query.type);
  }
  return query;
}

// ---- the document -----------------------------------------------------------

// Sections are read in key order (nlohmann::json sorts object keys), so
// shapes and bodies are numbered by name; queries keep the file's order.
Scene read_scene(const json& document, const std::string& file) {
  Scene scene;
  scene.file = file;
  if (!document.is_object()) fail("", "expected a JSON object at the top level, got " + type_name(document));
  // The version first: a newer file's unknown keys would only confuse.
  const json& version = require(document, "", "hedra_scene");
  if (!version.is_number() || version.get<double>() != 1.0) {
    fail("hedra_scene", "unsupported version " + version.dump() + " (this hedra reads version 1)");
  }
  check_keys(document, "", {"hedra_scene", "name", "description", "shapes", "bodies", "queries"});
  scene.name = fs::path(file).stem().string();
  if (const json* name = optional_member(document, "name")) scene.name = string(*name, "name");
  if (const json* description = optional_member(document, "description")) {
    scene.description = string(*description, "description");
  }

  const fs::path base = fs::path(file).parent_path();
  const json& shapes = expect_object(require(document, "", "shapes"), "shapes");
  std::vector<std::string> shape_names;
  for (auto it = shapes.begin(); it != shapes.end(); ++it) {
    scene.shapes.push_back(read_shape(it.key(), it.value(), member("shapes", it.key()), base));
    shape_names.push_back(it.key());
  }

  const json& bodies = expect_object(require(document, "", "bodies"), "bodies");
  std::vector<std::string> body_names;
  for (auto it = bodies.begin(); it != bodies.end(); ++it) {
    scene.bodies.push_back(read_body(it.key(), it.value(), member("bodies", it.key()), shape_names));
    body_names.push_back(it.key());
  }

  const json& queries = require(document, "", "queries");
  if (!queries.is_array()) fail("queries", "expected an array, got " + type_name(queries));
  if (queries.empty()) fail("queries", "empty (a scene asks at least one query)");
  for (std::size_t i = 0; i < queries.size(); ++i) {
    scene.queries.push_back(read_query(queries[i], element("queries", i), body_names));
  }
  return scene;
}

// Finds the first key repeated within one object (nlohmann keeps the last
// silently, which would hide a typo'd copy) and its JSON path.
class DuplicateKeyFinder {
 public:
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        frames_.push_back({true, {}, {}, 0});
        break;
      case json::parse_event_t::array_start:
        frames_.push_back({false, {}, {}, 0});
        break;
      case json::parse_event_t::key:
        if (!frames_.empty()) {
          Frame& top = frames_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second && duplicate.empty()) duplicate = path();
        }
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!frames_.empty()) frames_.pop_back();
        next_element();
        break;
      case json::parse_event_t::value:
        next_element();
        break;
    }
    return true;
  }

  std::string duplicate;  // path of the first repeated key; empty if none

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;
    std::size_t index;
  };
  void next_element() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  std::string path() const {
    std::string p;
    for (const Frame& frame : frames_) p = frame.object ? member(p, frame.key) : element(p, frame.index);
    return p;
  }
  std::vector<Frame> frames_;
};

// "line:column" (1-based) of byte `offset` (1-based, as parse_error::byte).
std::string line_column(const std::string& text, std::size_t offset) {
  const std::size_t end = std::min(offset == 0 ? 0 : offset - 1, text.size());
  std::size_t line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return std::to_string(line) + ":" + std::to_string(end - line_start + 1);
}

// nlohmann's message without its "[json.exception...] parse error at line
// L, column C: " prefix (the location is computed above).
std::string parse_reason(const char* what) {
  std::string message = what;
  if (message.rfind("[json.exception.", 0) == 0) {
    const std::size_t close = message.find("] ");
    if (close != std::string::npos) message = message.substr(close + 2);
  }
  if (message.rfind("parse error", 0) == 0) {
    const std::size_t colon = message.find(": ");
    if (colon != std::string::npos) message = message.substr(colon + 2);
  }
  return message;
}

}  // namespace

LoadSceneResult parse_scene(const std::string& text, const std::string& file) {
  LoadSceneResult result;
  json document;
  DuplicateKeyFinder duplicates;
  try {
    document = json::parse(text, std::ref(duplicates));
  } catch (const json::parse_error& error) {
    result.error = file + ":" + line_column(text, error.byte) + ": malformed JSON: " + parse_reason(error.what());
    return result;
  } catch (const json::out_of_range& error) {
    // A number too large for a double ("number overflow parsing '1e999'"):
    // nlohmann gives no position, so locate the token it quotes.
    const std::string message = error.what();
    const std::size_t open = message.find('\'');
    const std::size_t close = open == std::string::npos ? open : message.find('\'', open + 1);
    const std::size_t at = close == std::string::npos ? close : text.find(message.substr(open + 1, close - open - 1));
    result.error = file + (at == std::string::npos ? "" : ":" + line_column(text, at + 1)) +
                   ": malformed JSON: " + parse_reason(error.what()) + " (not a finite double)";
    return result;
  } catch (const json::exception& error) {
    result.error = file + ": malformed JSON: " + error.what();
    return result;
  }
  if (!duplicates.duplicate.empty()) {
    result.error = file + ": " + duplicates.duplicate + ": duplicate key";
    return result;
  }
  try {
    result.scene = read_scene(document, file);
  } catch (const SceneError& error) {
    result.error = file + ": " + (error.path.empty() ? "" : error.path + ": ") + error.reason;
  } catch (const json::exception& error) {
    // A type mismatch the reader did not foresee: still bad input.
    result.error = file + ": " + error.what();
  }
  return result;
}

LoadSceneResult load_scene(const std::string& path) {
  LoadSceneResult result;
  std::error_code code;
  if (fs::is_directory(path, code)) {
    result.error = path + ": is a directory, expected a scene file";
    return result;
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    // The reason, as the point-file reader gives it (errno of the failed open).
    const int error = errno;
    result.error = path + ": cannot open: " + (error != 0 ? std::strerror(error) : "unknown error");
    return result;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) {
    result.error = path + ": cannot read";
    return result;
  }
  return parse_scene(buffer.str(), path);
}

// ---- building ---------------------------------------------------------------

double pair_size(const collision::Shape& a, const collision::Pose& pose_a, const collision::Shape& b,
                 const collision::Pose& pose_b) {
  auto centre = [](const collision::Shape& s, const collision::Pose& pose) {
    const auto* polyhedron = std::get_if<collision::Polyhedron>(&s);
    return pose.apply(polyhedron ? polyhedron->hull->offset() : Eigen::Vector3d::Zero());
  };
  const Eigen::Vector3d centre_a = centre(a, pose_a);
  const Eigen::Vector3d centre_b = centre(b, pose_b);
  const double half_gap = 0.5 * (centre_b - centre_a).norm();
  return half_gap + std::max(collision::bounding_radius(a), collision::bounding_radius(b));
}

namespace {

// The largest distance of a shape's points from its local origin (a
// polyhedron's core sits at its offset from that origin).
double reach(const collision::Shape& shape) {
  const auto* polyhedron = std::get_if<collision::Polyhedron>(&shape);
  const double offset = polyhedron ? polyhedron->hull->offset().norm() : 0.0;
  return offset + collision::bounding_radius(shape);
}

}  // namespace

double default_fraction_tolerance(const BuiltScene& built, std::size_t index) {
  const Scene& scene = *built.scene;
  const QuerySpec& query = scene.queries[index];
  const collision::Shape& a = *built.shapes[scene.bodies[query.a].shape];
  const collision::Shape& b = *built.shapes[scene.bodies[query.b].shape];
  const collision::Pose& pa = built.poses[query.a];
  const collision::Pose& pb = built.poses[query.b];
  const BodySpec& body_a = scene.bodies[query.a];
  const BodySpec& body_b = scene.bodies[query.b];
  double size = 0.0;
  double speed = 0.0;
  double far = 0.0;  // the coordinates' magnitude: their rounding is the floor
  if (query.type == QueryType::raycast) {
    size = collision::bounding_radius(a);
    speed = query.direction.norm();
    far = std::max(query.origin.cwiseAbs().maxCoeff(), body_a.position.cwiseAbs().maxCoeff());
  } else {
    size = pair_size(a, pa, b, pb);
    speed = ((body_b.end_position - body_b.position) - (body_a.end_position - body_a.position)).norm();
    if (query.type == QueryType::toi) {
      speed += body_a.orientation.angularDistance(body_a.end_orientation) * reach(a) +
               body_b.orientation.angularDistance(body_b.end_orientation) * reach(b);
    }
    far = std::max(body_a.position.cwiseAbs().maxCoeff(), body_b.position.cwiseAbs().maxCoeff());
  }
  const double distance = kDefaultRelativeTolerance * size + 64.0 * std::numeric_limits<double>::epsilon() * far;
  return speed > 0.0 ? distance / speed : kDefaultRelativeTolerance;
}

BuildShapesResult build_shapes(const Scene& scene, bool all_shapes) {
  BuildShapesResult result;
  BuiltScene built;
  built.scene = &scene;
  built.shapes.resize(scene.shapes.size());
  for (const BodySpec& body : scene.bodies) {
    built.poses.push_back(body.pose());
    built.end_poses.push_back(body.end_pose());
  }

  std::vector<bool> needed(scene.shapes.size(), all_shapes);
  for (const QuerySpec& query : scene.queries) {
    if (query.all_pairs) {
      std::fill(needed.begin(), needed.end(), true);  // every body takes part
      continue;
    }
    needed[scene.bodies[query.a].shape] = true;
    needed[scene.bodies[query.b].shape] = true;
  }

  const Clock::time_point start = Clock::now();
  for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
    if (!needed[i]) continue;
    const ShapeSpec& spec = scene.shapes[i];
    const std::string where = scene.file + ": shapes." + spec.name;
    collision::Shape shape;
    switch (spec.kind) {
      case ShapeKind::sphere: {
        collision::Sphere s;
        s.radius = spec.radius;
        s.margin = spec.margin;
        shape = s;
        break;
      }
      case ShapeKind::box: {
        collision::Box s;
        s.half_extents = spec.half_extents;
        s.margin = spec.margin;
        shape = s;
        break;
      }
      case ShapeKind::capsule: {
        collision::Capsule s;
        s.radius = spec.radius;
        s.half_length = spec.half_length;
        s.margin = spec.margin;
        shape = s;
        break;
      }
      case ShapeKind::cylinder: {
        collision::Cylinder s;
        s.radius = spec.radius;
        s.half_length = spec.half_length;
        s.margin = spec.margin;
        shape = s;
        break;
      }
      case ShapeKind::cone: {
        collision::Cone s;
        s.radius = spec.radius;
        s.half_length = spec.half_length;
        s.margin = spec.margin;
        shape = s;
        break;
      }
      case ShapeKind::hull: {
        const std::vector<Eigen::Vector3d>* points = &spec.points;
        hull::ReadPointsResult read;
        if (!spec.file.empty()) {
          read = hull::read_points(spec.resolved_file);
          if (!read.ok()) {
            result.error = where + ".file: " + read.error->message();
            return result;
          }
          ++built.mesh_files_read;
          points = &read.points;
        }
        collision::ConvexPolyhedron::BuildResult hull = collision::ConvexPolyhedron::build(*points);
        if (!hull.ok()) {
          result.error = where + ": cannot build the hull (" + collision::to_string(hull.error) + "): " + hull.message;
          return result;
        }
        ++built.hulls_built;
        collision::Polyhedron s;
        s.hull = std::move(hull.polyhedron);
        s.margin = spec.margin;
        shape = s;
        break;
      }
    }
    // The reader checked every parameter already; this guards the
    // conversion (and any rule the library adds later).
    const collision::ShapeValidation valid = collision::validate(shape);
    if (!valid.ok()) {
      result.error = where + ": " + valid.message;
      return result;
    }
    built.shapes[i] = std::move(shape);
    ++built.shapes_built;
  }
  // Pairs the queries refuse (query.hpp, min_pair_extent) are bad input
  // here, named like every other: all of them answered invalid_input
  // otherwise, with exit code 0.
  for (std::size_t i = 0; i < scene.queries.size(); ++i) {
    const QuerySpec& query = scene.queries[i];
    if (query.type == QueryType::raycast) continue;  // one body: any size answers
    if (query.all_pairs) continue;                   // such pairs answer invalid_input, reported per pair
    const BodySpec& a = scene.bodies[query.a];
    const BodySpec& b = scene.bodies[query.b];
    if (!collision::pair_in_range(*built.shapes[a.shape], built.poses[query.a], *built.shapes[b.shape],
                                  built.poses[query.b])) {
      result.error = scene.file + ": queries[" + std::to_string(i) + "]: bodies '" + a.name + "' and '" + b.name +
                     "' fit within 1e-60 (their bounding radii and the distance between them are all "
                     "below 1e-60, not all zero): too small for double arithmetic, whose squares underflow";
      return result;
    }
  }
  built.build_ns = elapsed_ns(start, Clock::now());
  result.built = std::move(built);
  return result;
}

}  // namespace hedra::tool
