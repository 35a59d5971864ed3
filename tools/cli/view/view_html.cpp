// The HTML page of `hedra view` (see view_html.hpp). The page is assembled
// from text embedded at build time (embed_text.cmake): three.js, its
// OrbitControls, viewer.css and viewer.js; only the JSON block depends on
// the model.
#include "cli/view/view_html.hpp"

#include <nlohmann/json.hpp>
#include <string_view>

#include "cli/view/embedded_text.hpp"

namespace hedra::tool::view {

namespace {

using Json = nlohmann::ordered_json;

Json vector_json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

template <class T>
Json optional_json(const std::optional<T>& value) {
  if (!value) return nullptr;
  if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
    return vector_json(*value);
  } else {
    return *value;
  }
}

Json points_json(const std::vector<Eigen::Vector3d>& points) {
  Json out = Json::array();
  for (const Eigen::Vector3d& p : points) out.push_back(vector_json(p));
  return out;
}

Json mesh_json(const PolygonMesh& mesh) {
  Json edges = Json::array();
  for (const auto& edge : mesh.edges) edges.push_back({edge[0], edge[1]});
  return {{"vertices", points_json(mesh.vertices)}, {"faces", mesh.faces}, {"edges", std::move(edges)}};
}

Json model_json(const ViewModel& model) {
  Json document;
  document["title"] = model.title;
  document["description"] = model.description;
  document["notes"] = model.notes;
  Json bodies = Json::array();
  for (const ViewBody& body : model.bodies) {
    Json b;
    b["name"] = body.name;
    b["shape"] = body.shape;
    b["margin"] = body.margin;
    b["mesh"] = mesh_json(body.mesh);
    b["core"] = body.core.vertices.empty() ? Json(nullptr) : mesh_json(body.core);
    bodies.push_back(std::move(b));
  }
  document["bodies"] = std::move(bodies);
  Json queries = Json::array();
  for (const ViewQuery& query : model.queries) {
    Json q;
    q["a"] = query.a;
    q["b"] = query.b;
    q["type"] = query.type;
    q["status"] = query.status;
    q["intersecting"] = optional_json(query.intersecting);
    q["distance"] = optional_json(query.distance);
    q["point_a"] = optional_json(query.point_a);
    q["point_b"] = optional_json(query.point_b);
    q["normal"] = optional_json(query.normal);
    Json contacts = Json::array();
    for (const ViewContact& contact : query.contacts) {
      contacts.push_back({{"point", vector_json(contact.point)}, {"depth", contact.depth}});
    }
    q["contacts"] = std::move(contacts);
    q["hit"] = optional_json(query.hit);
    q["fraction"] = optional_json(query.fraction);
    q["initially_overlapping"] = optional_json(query.initially_overlapping);
    Json sweeps = Json::array();
    for (const ViewSweep& sweep : query.sweeps) {
      sweeps.push_back({{"body", sweep.body},
                        {"start", mesh_json(sweep.start)},
                        {"end", mesh_json(sweep.end)},
                        {"at_fraction", mesh_json(sweep.at_fraction)}});
    }
    q["sweeps"] = std::move(sweeps);
    if (query.ray) {
      q["ray"] = {{"origin", vector_json(query.ray->origin)},
                  {"end", vector_json(query.ray->end)},
                  {"hit_point", optional_json(query.ray->hit_point)}};
    } else {
      q["ray"] = nullptr;
    }
    queries.push_back(std::move(q));
  }
  document["queries"] = std::move(queries);
  if (model.hull) {
    const ViewHull& hull = *model.hull;
    Json h;
    h["input"] = hull.input;
    h["input_count"] = hull.input_count;
    h["input_points"] = points_json(hull.input_points);
    h["vertices"] = points_json(hull.vertices);
    h["faces"] = hull.faces;
    Json half_edges = Json::array();
    for (const ViewHalfEdge& e : hull.half_edges) half_edges.push_back({e.origin, e.twin, e.next, e.face});
    h["half_edges"] = std::move(half_edges);  // [origin, twin, next, face] each
    h["face_half_edges"] = hull.face_half_edges;
    h["edge_count"] = hull.edge_count;
    h["dimension"] = hull.dimension;
    h["volume"] = hull.volume;
    h["area"] = hull.area;
    h["max_outside_distance"] = hull.max_outside_distance;
    document["hull"] = std::move(h);
  } else {
    document["hull"] = nullptr;
  }
  return document;
}

// Text for an HTML element's content (the <title>).
std::string escape_html(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// JSON safe inside <script>: '<' only occurs inside JSON strings, where
// \u003c means the same character, so "</script>" and "<!--" cannot appear.
std::string json_for_script(const Json& document) {
  // Invalid UTF-8 in a name becomes U+FFFD instead of throwing.
  const std::string text = document.dump(-1, ' ', false, Json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size() + 64);
  for (char c : text) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

// Installed before any other script, so errors thrown while three.js or the
// viewer load are recorded too.
constexpr std::string_view kErrorCapture = R"js(
window.hedraViewReady = false;
window.hedraViewErrors = [];
(function () {
  function record(message) {
    window.hedraViewErrors.push(String(message));
    document.documentElement.setAttribute('data-hedra-errors', String(window.hedraViewErrors.length));
    var log = document.getElementById('hedra-error-log');
    if (log) { log.textContent += String(message) + '\n'; log.hidden = false; }
  }
  window.hedraRecordError = record;
  document.documentElement.setAttribute('data-hedra-errors', '0');
  window.addEventListener('error', function (e) {
    record('error: ' + e.message + (e.filename ? ' (' + e.filename + ':' + e.lineno + ')' : ''));
  });
  window.addEventListener('unhandledrejection', function (e) { record('unhandled rejection: ' + e.reason); });
  var consoleError = console.error;
  console.error = function () {
    record('console.error: ' + Array.prototype.slice.call(arguments).join(' '));
    return consoleError.apply(console, arguments);
  };
})();
)js";

}  // namespace

bool three_js_available() { return !embedded_three_js().empty(); }

const char* three_js_missing_message() {
  return "this hedra was built without three.js (Debian package libjs-three: apt-get install libjs-three, then "
         "reconfigure and rebuild)";
}

std::string render_view_html(const ViewModel& model) {
  if (!three_js_available()) return std::string();
  const std::string data = json_for_script(model_json(model));
  std::string html;
  html.reserve(embedded_three_js().size() + embedded_orbit_controls_js().size() + embedded_viewer_js().size() +
               data.size() + 4096);
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<meta name=\"generator\" content=\"hedra view\">\n";
  html += "<title>hedra view: " + escape_html(model.title) + "</title>\n";
  html += "<style>\n";
  html += embedded_viewer_css();
  html += "</style>\n<script>";
  html += kErrorCapture;
  html += "</script>\n</head>\n<body>\n";
  html += "<div id=\"hedra-viewport\"></div>\n<div id=\"hedra-labels\"></div>\n<aside id=\"hedra-panel\"></aside>\n";
  html += "<pre id=\"hedra-error-log\" hidden></pre>\n";
  html += "<script type=\"application/json\" id=\"hedra-data\">";
  html += data;
  html += "</script>\n<script>\n";
  html += embedded_three_js();
  html += "\n</script>\n<script>\n";
  html += embedded_orbit_controls_js();
  html += "\n</script>\n<script>\n";
  html += embedded_viewer_js();
  html += "\n</script>\n</body>\n</html>\n";
  return html;
}

}  // namespace hedra::tool::view
