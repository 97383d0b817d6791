#include "world_server/world/yaml_fields.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "common/input_error.hpp"

namespace swarmform::world::yaml {
namespace {

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Scalar:
      return "'" + n.Scalar() + "'";
    default:
      return "an undefined value";
  }
}

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

int line_of(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const YAML::Mark m = node.Mark();
  return m.is_null() ? 0 : m.line + 1;
}

void fail(const Source& src, const YAML::Node& at, const std::string& path, const std::string& what) {
  throw InputError(src.file, line_of(at), path.empty() ? what : path + ": " + what);
}

double to_number(const Source& src, const YAML::Node& n, const std::string& path) {
  if (!n.IsScalar()) fail(src, n, path, "expected a number, got " + describe(n));
  const std::string& s = n.Scalar();
  // YAML's own spellings of the specials: refused (a scenario has no use for them).
  if (s == ".nan" || s == ".NaN" || s == ".NAN" || s == ".inf" || s == ".Inf" || s == "-.inf" ||
      s == "+.inf" || s == "-.Inf") {
    fail(src, n, path, "expected a finite number, got '" + s + "'");
  }
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) {
    fail(src, n, path, "expected a finite number, got '" + s + "'");
  }
  return v;
}

std::int64_t to_integer(const Source& src, const YAML::Node& n, const std::string& path) {
  if (!n.IsScalar()) fail(src, n, path, "expected an integer, got " + describe(n));
  const std::string& s = n.Scalar();
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE) {
    fail(src, n, path, "expected an integer, got '" + s + "'");
  }
  return v;
}

std::uint64_t to_unsigned(const Source& src, const YAML::Node& n, const std::string& path) {
  if (!n.IsScalar()) fail(src, n, path, "expected a non-negative integer, got " + describe(n));
  const std::string& s = n.Scalar();
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (s.empty() || s[0] == '-' || s[0] == '+' || end != s.c_str() + s.size() || errno == ERANGE) {
    fail(src, n, path, "expected a non-negative integer, got '" + s + "'");
  }
  return v;
}

bool to_bool(const Source& src, const YAML::Node& n, const std::string& path) {
  if (n.IsScalar()) {
    const std::string& s = n.Scalar();
    if (s == "true" || s == "on" || s == "yes") return true;
    if (s == "false" || s == "off" || s == "no") return false;
  }
  fail(src, n, path, "expected true or false, got " + describe(n));
}

std::string to_string(const Source& src, const YAML::Node& n, const std::string& path) {
  if (!n.IsScalar()) fail(src, n, path, "expected a string, got " + describe(n));
  return n.Scalar();
}

Vec2 to_vec2(const Source& src, const YAML::Node& n, const std::string& path) {
  if (!n.IsSequence() || n.size() != 2) fail(src, n, path, "expected [x, y], got " + describe(n));
  return Vec2{to_number(src, n[0], path + "[0]"), to_number(src, n[1], path + "[1]")};
}

double check_range(const Source& src, const YAML::Node& n, const std::string& path, double v, double lo,
                   double hi) {
  if (v < lo || v > hi) {
    fail(src, n, path,
         "must be in [" + format_number(lo) + ", " + format_number(hi) + "], got " + format_number(v));
  }
  return v;
}

double check_positive(const Source& src, const YAML::Node& n, const std::string& path, double v, double hi) {
  if (!(v > 0.0) || v > hi) {
    fail(src, n, path, "must be > 0 and <= " + format_number(hi) + ", got " + format_number(v));
  }
  return v;
}

MapReader::MapReader(const Source& src, const YAML::Node& node, std::string path)
    : src_(src), node_(node), path_(std::move(path)) {
  if (!node_.IsMap()) fail(src_, node_, path_, "expected a map of key: value, got " + describe(node_));
  std::vector<std::string> seen;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) fail(src_, kv.first, path_, "keys must be plain names");
    const std::string& k = kv.first.Scalar();
    if (std::find(seen.begin(), seen.end(), k) != seen.end()) {
      fail(src_, kv.first, field(k), "duplicate key");
    }
    seen.push_back(k);
  }
}

std::string MapReader::field(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

bool MapReader::has(std::string_view key) const {
  for (const auto& kv : node_) {
    if (kv.first.Scalar() == key) return true;
  }
  return false;
}

std::optional<YAML::Node> MapReader::get(std::string_view key) {
  for (const auto& kv : node_) {
    if (kv.first.Scalar() == key) {
      used_.emplace_back(key);
      return kv.second;
    }
  }
  return std::nullopt;
}

double MapReader::number(std::string_view key, double fallback, double lo, double hi) {
  auto n = get(key);
  if (!n) return fallback;
  return check_range(src_, *n, field(key), to_number(src_, *n, field(key)), lo, hi);
}

double MapReader::positive(std::string_view key, double fallback, double hi) {
  auto n = get(key);
  if (!n) return fallback;
  return check_positive(src_, *n, field(key), to_number(src_, *n, field(key)), hi);
}

std::int64_t MapReader::integer(std::string_view key, std::int64_t fallback, std::int64_t lo,
                                std::int64_t hi) {
  auto n = get(key);
  if (!n) return fallback;
  const std::int64_t v = to_integer(src_, *n, field(key));
  if (v < lo || v > hi) {
    fail(src_, *n, field(key),
         "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
             std::to_string(v));
  }
  return v;
}

bool MapReader::boolean(std::string_view key, bool fallback) {
  auto n = get(key);
  if (!n) return fallback;
  return to_bool(src_, *n, field(key));
}

void MapReader::finish(std::initializer_list<std::string_view> known) const {
  for (const auto& kv : node_) {
    const std::string& k = kv.first.Scalar();
    if (std::find(used_.begin(), used_.end(), k) != used_.end()) continue;
    std::string list;
    for (std::string_view name : known) list += (list.empty() ? "" : ", ") + std::string(name);
    const bool is_known = std::find(known.begin(), known.end(), k) != known.end();
    fail(src_, kv.first, field(k), is_known ? "not allowed here" : "unknown key (known here: " + list + ")");
  }
}

}  // namespace swarmform::world::yaml
