// Point-set readers (.xyz, .obj, .off) and the OBJ writer; see mesh_io.hpp.
//
// Every reader works line by line through LineReader, which keeps the
// 1-based number of the line just read, drops a trailing '\r' and anything
// from '#' on, and reports stream failures. Tokens are runs of non-blank
// characters; a number must be a whole token that std::from_chars accepts
// (after an optional '+', which from_chars does not take) and is finite.
// Invariant: a reader returns either points with no error, or an error and
// no points; it never throws past its own boundary (std::bad_alloc included,
// reported as an error).
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <hedra/hull/mesh_io.hpp>
#include <istream>
#include <limits>
#include <new>
#include <ostream>
#include <system_error>

namespace hedra::hull {

const char* to_string(PointFormat format) {
  switch (format) {
    case PointFormat::xyz:
      return "xyz";
    case PointFormat::obj:
      return "obj";
    case PointFormat::off:
      return "off";
  }
  return "unknown";
}

std::optional<PointFormat> format_from_path(std::string_view path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string lower;
  for (char c : extension) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".xyz") return PointFormat::xyz;
  if (lower == ".obj") return PointFormat::obj;
  if (lower == ".off") return PointFormat::off;
  return std::nullopt;
}

std::string IoError::message() const {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  text += ": ";
  text += what;
  return text;
}

namespace {

// Quotes a token for a message, shortening very long ones so that a line of
// binary garbage does not flood the terminal.
std::string quote_token(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string text = "'";
  if (token.size() <= kMaxShown) {
    text += token;
  } else {
    text += token.substr(0, kMaxShown);
    text += "...";
  }
  text += "'";
  return text;
}

class LineReader {
 public:
  explicit LineReader(std::istream& in) : in_(in) {}

  // Reads the next line into `content` (comment and '\r' removed); false at
  // the end of the stream or on a read error (see failed()).
  bool next(std::string_view& content) {
    if (!std::getline(in_, buffer_)) return false;
    ++line_;
    std::string_view view(buffer_);
    if (!view.empty() && view.back() == '\r') view.remove_suffix(1);
    const std::size_t hash = view.find('#');
    if (hash != std::string_view::npos) view = view.substr(0, hash);
    content = view;
    return true;
  }

  bool failed() const { return in_.bad(); }
  std::size_t line() const { return line_; }

 private:
  std::istream& in_;
  std::string buffer_;
  std::size_t line_ = 0;
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }

// Splits `text` into non-blank runs. Keeps at most `capacity` tokens in
// `tokens` and returns how many there are in all.
std::size_t split(std::string_view text, std::string_view* tokens, std::size_t capacity) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_blank(text[i])) ++i;
    if (i == text.size()) break;
    const std::size_t start = i;
    while (i < text.size() && !is_blank(text[i])) ++i;
    if (count < capacity) tokens[count] = text.substr(start, i - start);
    ++count;
  }
  return count;
}

// True when the decimal number in `token` (already known to be a valid
// from_chars number that came out of range) has magnitude below 1, i.e. it
// underflowed rather than overflowed. Looks at the position of the first
// non-zero digit and the exponent.
bool underflows(std::string_view token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '-' || token[i] == '+')) ++i;
  long long position = 0;  // decimal exponent of the first non-zero digit, before the 'e' part
  bool seen_nonzero = false;
  bool after_point = false;
  long long integer_digits = 0;
  long long leading_fraction_zeros = 0;
  for (; i < token.size(); ++i) {
    const char c = token[i];
    if (c == '.') {
      after_point = true;
    } else if (c >= '0' && c <= '9') {
      if (!after_point) {
        if (seen_nonzero || c != '0') ++integer_digits;
      } else if (!seen_nonzero && integer_digits == 0 && c == '0') {
        ++leading_fraction_zeros;
      }
      if (c != '0') seen_nonzero = true;
    } else {
      break;  // 'e' or 'E'
    }
  }
  position = integer_digits > 0 ? integer_digits - 1 : -(leading_fraction_zeros + 1);
  long long exponent = 0;
  if (i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
    ++i;
    bool negative = false;
    if (i < token.size() && (token[i] == '-' || token[i] == '+')) negative = token[i++] == '-';
    for (; i < token.size() && token[i] >= '0' && token[i] <= '9'; ++i) {
      // Saturate: any exponent past a million decides the matter by itself.
      if (exponent < 1000000) exponent = exponent * 10 + (token[i] - '0');
    }
    if (negative) exponent = -exponent;
  }
  return position + exponent < 0;
}

// Parses `token` as a finite double. On failure returns false and says why
// in `why` (without location).
bool parse_number(std::string_view token, double& value, std::string& why) {
  std::string_view digits = token;
  // from_chars takes no '+'; accept one, but not "+-1" or "++1".
  if (!digits.empty() && digits.front() == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && (digits.front() == '+' || digits.front() == '-')) digits = token;
  }
  const char* first = digits.data();
  const char* last = digits.data() + digits.size();
  double parsed = 0.0;
  const std::from_chars_result result = std::from_chars(first, last, parsed, std::chars_format::general);
  if (result.ptr != last || (result.ec != std::errc() && result.ec != std::errc::result_out_of_range)) {
    why = quote_token(token) + " is not a number";
    return false;
  }
  if (result.ec == std::errc::result_out_of_range) {
    if (!underflows(digits)) {
      why = "number " + quote_token(token) + " is too large for a double (not finite)";
      return false;
    }
    parsed = digits.front() == '-' ? -0.0 : 0.0;
  }
  if (!std::isfinite(parsed)) {
    why = "non-finite number " + quote_token(token);
    return false;
  }
  value = parsed;
  return true;
}

// Parses a non-negative integer count (for OFF headers).
bool parse_count(std::string_view token, std::size_t& value) {
  const char* last = token.data() + token.size();
  unsigned long long parsed = 0;
  const std::from_chars_result result = std::from_chars(token.data(), last, parsed);
  if (result.ec != std::errc() || result.ptr != last) return false;
  if (parsed > std::numeric_limits<std::size_t>::max()) return false;
  value = static_cast<std::size_t>(parsed);
  return true;
}

// Shared state of one read: the name for messages, the result being built.
struct Reader {
  std::string_view name;
  ReadPointsResult result;

  ReadPointsResult fail(std::size_t line, std::string what) {
    result.points.clear();
    result.points.shrink_to_fit();
    result.error = IoError{std::string(name), line, std::move(what)};
    return std::move(result);
  }

  // Parses tokens[0..2] as a point; on failure sets `why`.
  bool add_point(const std::string_view* tokens, std::string& why) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) {
      if (!parse_number(tokens[k], p[k], why)) return false;
    }
    result.points.push_back(p);
    return true;
  }

  // Parses optional extra tokens (OBJ's w or colours) only to check them.
  static bool check_numbers(const std::string_view* tokens, std::size_t count, std::string& why) {
    double ignored = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      if (!parse_number(tokens[k], ignored, why)) return false;
    }
    return true;
  }

  ReadPointsResult finish(const LineReader& lines) {
    if (lines.failed()) return fail(0, "read error after line " + std::to_string(lines.line()));
    if (result.points.empty()) return fail(0, "no points found");
    return std::move(result);
  }
};

ReadPointsResult read_xyz(std::istream& in, std::string_view name) {
  Reader reader{name, {}};
  LineReader lines(in);
  std::string_view content;
  std::string_view tokens[4];
  std::string why;
  while (lines.next(content)) {
    const std::size_t count = split(content, tokens, 4);
    if (count == 0) continue;
    if (count != 3) {
      return reader.fail(lines.line(), "expected 3 numbers (x y z), found " + std::to_string(count) + " fields");
    }
    if (!reader.add_point(tokens, why)) return reader.fail(lines.line(), why);
  }
  return reader.finish(lines);
}

ReadPointsResult read_obj(std::istream& in, std::string_view name) {
  Reader reader{name, {}};
  LineReader lines(in);
  std::string_view content;
  std::string_view tokens[8];
  std::string why;
  while (lines.next(content)) {
    const std::size_t count = split(content, tokens, 8);
    if (count == 0 || tokens[0] != "v") continue;  // vt, vn, f, o, g, usemtl, ...: not points
    const std::size_t numbers = count - 1;
    // x y z, x y z w, or the widespread colour extension x y z r g b.
    if (numbers != 3 && numbers != 4 && numbers != 6) {
      return reader.fail(lines.line(),
                         "expected 3 numbers after 'v' (x y z, optionally w), found " + std::to_string(numbers));
    }
    if (!reader.add_point(tokens + 1, why)) return reader.fail(lines.line(), why);
    if (!Reader::check_numbers(tokens + 4, numbers - 3, why)) return reader.fail(lines.line(), why);
  }
  return reader.finish(lines);
}

ReadPointsResult read_off(std::istream& in, std::string_view name) {
  Reader reader{name, {}};
  LineReader lines(in);
  std::string_view content;
  std::string_view tokens[5];
  std::string why;

  // Header: "OFF", possibly followed by the counts on the same line.
  std::size_t count = 0;
  while (lines.next(content)) {
    count = split(content, tokens, 5);
    if (count > 0) break;
  }
  if (count == 0) return reader.finish(lines);  // read error or no content at all
  if (tokens[0] != "OFF") {
    const std::string_view head = tokens[0];
    if (head.size() > 3 && head.substr(head.size() - 3) == "OFF") {
      return reader.fail(lines.line(), "unsupported OFF variant " + quote_token(head) + " (only plain 'OFF' is read)");
    }
    return reader.fail(lines.line(), "expected the header 'OFF', found " + quote_token(head));
  }
  std::string_view* counts = tokens + 1;
  count -= 1;
  if (count == 0) {
    while (lines.next(content)) {
      count = split(content, tokens, 5);
      if (count > 0) break;
    }
    if (count == 0) {
      if (lines.failed()) return reader.finish(lines);
      return reader.fail(lines.line(), "unexpected end of file: expected the counts line 'vertices faces edges'");
    }
    counts = tokens;
  }
  std::size_t vertex_count = 0;
  std::size_t face_count = 0;
  std::size_t edge_count = 0;
  if (count != 3 || !parse_count(counts[0], vertex_count) || !parse_count(counts[1], face_count) ||
      !parse_count(counts[2], edge_count)) {
    return reader.fail(lines.line(), "expected the counts 'vertices faces edges' as 3 non-negative integers");
  }
  if (vertex_count == 0) return reader.fail(lines.line(), "no points: the vertex count is 0");
  // The count is untrusted: reserve a bounded amount and let the vector grow.
  reader.result.points.reserve(std::min<std::size_t>(vertex_count, std::size_t{1} << 16));

  while (reader.result.points.size() < vertex_count) {
    if (!lines.next(content)) {
      if (lines.failed()) return reader.finish(lines);
      return reader.fail(lines.line(), "unexpected end of file: read " + std::to_string(reader.result.points.size()) +
                                           " of " + std::to_string(vertex_count) + " vertices");
    }
    const std::size_t fields = split(content, tokens, 5);
    if (fields == 0) continue;
    if (fields != 3) {
      return reader.fail(lines.line(),
                         "expected 3 numbers (x y z) for vertex " + std::to_string(reader.result.points.size() + 1) +
                             " of " + std::to_string(vertex_count) + ", found " + std::to_string(fields) + " fields");
    }
    if (!reader.add_point(tokens, why)) return reader.fail(lines.line(), why);
  }
  // The faces that follow are not needed for a point set.
  return reader.finish(lines);
}

}  // namespace

ReadPointsResult read_points(std::istream& in, PointFormat format, std::string_view name) {
  try {
    switch (format) {
      case PointFormat::xyz:
        return read_xyz(in, name);
      case PointFormat::obj:
        return read_obj(in, name);
      case PointFormat::off:
        return read_off(in, name);
    }
    ReadPointsResult result;
    result.error = IoError{std::string(name), 0, "unknown point format"};
    return result;
  } catch (const std::bad_alloc&) {
    ReadPointsResult result;
    result.error = IoError{std::string(name), 0, "out of memory while reading points"};
    return result;
  }
}

ReadPointsResult read_points(const std::string& path) {
  ReadPointsResult result;
  const std::optional<PointFormat> format = format_from_path(path);
  if (!format) {
    const std::string extension = std::filesystem::path(path).extension().string();
    result.error = IoError{
        path, 0,
        (extension.empty() ? std::string("no file extension") : "unknown file extension " + quote_token(extension)) +
            " (expected .xyz, .obj or .off)"};
    return result;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    result.error = IoError{path, 0, "cannot read: is a directory"};
    return result;
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;
    result.error =
        IoError{path, 0, std::string("cannot open: ") + (error != 0 ? std::strerror(error) : "unknown error")};
    return result;
  }
  return read_points(in, *format, path);
}

namespace {

// Appends `value` with 17 significant digits, as printf's %.17g would, but
// independent of the locale.
void append_number(std::string& line, double value) {
  char buffer[32];
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 17);
  line.append(buffer, result.ptr);
}

}  // namespace

void write_obj(const HalfEdgeMesh& mesh, std::ostream& out, bool triangulate) {
  const std::vector<std::vector<Index>> polygons = mesh.polygons();
  std::size_t written_faces = 0;
  for (const std::vector<Index>& polygon : polygons) {
    written_faces += triangulate ? (polygon.size() >= 3 ? polygon.size() - 2 : 0) : 1;
  }
  out << "# hedra convex hull: " << mesh.vertex_count() << " vertices, " << written_faces
      << (triangulate ? " triangles\n" : " faces\n");

  std::string line;
  for (const Vertex& vertex : mesh.vertices) {
    line = "v";
    for (int k = 0; k < 3; ++k) {
      line += ' ';
      append_number(line, vertex.position[k]);
    }
    line += '\n';
    out << line;
  }
  for (const std::vector<Index>& polygon : polygons) {
    if (!triangulate) {
      line = "f";
      for (Index v : polygon) {
        line += ' ';
        line += std::to_string(std::size_t{v} + 1);
      }
      line += '\n';
      out << line;
      continue;
    }
    // Faces are convex, so a fan from the first vertex covers each exactly.
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      out << "f " << std::size_t{polygon[0]} + 1 << ' ' << std::size_t{polygon[k]} + 1 << ' '
          << std::size_t{polygon[k + 1]} + 1 << '\n';
    }
  }
}

}  // namespace hedra::hull
