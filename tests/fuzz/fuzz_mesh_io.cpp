// Fuzz target: the point readers of hull/mesh_io (.xyz, .obj, .off).
//
// The first byte picks the format; the rest is the file's text. Checked: the
// reader returns either at least one point, every coordinate finite, or an
// error whose message names the stream and (when it concerns a line) a line
// that exists in the input. Never a crash, an exception or a hang.
#include <cmath>
#include <cstdint>
#include <hedra/hull/mesh_io.hpp>
#include <sstream>
#include <string>

#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const hedra::hull::PointFormat formats[] = {hedra::hull::PointFormat::xyz, hedra::hull::PointFormat::obj,
                                              hedra::hull::PointFormat::off};
  const hedra::hull::PointFormat format = formats[data[0] % 3];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::istringstream in(text);
  const hedra::hull::ReadPointsResult r = hedra::hull::read_points(in, format, "fuzz");
  if (r.ok()) {
    HEDRA_FUZZ_CHECK(!r.points.empty(), "ok with no points");
    for (const Eigen::Vector3d& p : r.points) HEDRA_FUZZ_CHECK(p.allFinite(), "non-finite point accepted");
  } else {
    HEDRA_FUZZ_CHECK(r.points.empty(), "error with %zu points", r.points.size());
    const hedra::hull::IoError& e = *r.error;
    HEDRA_FUZZ_CHECK(!e.what.empty(), "empty error message");
    HEDRA_FUZZ_CHECK(e.message().rfind("fuzz", 0) == 0, "message does not name the stream: %s", e.message().c_str());
    std::size_t lines = 1;
    for (char c : text) lines += c == '\n';
    HEDRA_FUZZ_CHECK(e.line <= lines, "error on line %zu of %zu: %s", e.line, lines, e.message().c_str());
  }
  return 0;
}
