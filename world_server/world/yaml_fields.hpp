// Checked reading of YAML maps for the scenario loader: every value's type and range is checked, every key
// must be known, duplicates are refused, and every complaint is an InputError naming file:line and the
// field's path (e.g. `obstacles[2].radius`). yaml-cpp itself accepts unknown and duplicate keys silently;
// this is where that stops.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/types.hpp"

namespace swarmform::world::yaml {

// Where a node came from, for messages.
struct Source {
  std::string file;
};

int line_of(const YAML::Node& node);  // 1-based; 0 when unknown
[[noreturn]] void fail(const Source& src, const YAML::Node& at, const std::string& path,
                       const std::string& what);

// Scalar conversions with checks. `path` names the field in messages.
double to_number(const Source& src, const YAML::Node& n, const std::string& path);
std::int64_t to_integer(const Source& src, const YAML::Node& n, const std::string& path);
std::uint64_t to_unsigned(const Source& src, const YAML::Node& n, const std::string& path);
bool to_bool(const Source& src, const YAML::Node& n, const std::string& path);
std::string to_string(const Source& src, const YAML::Node& n, const std::string& path);
Vec2 to_vec2(const Source& src, const YAML::Node& n, const std::string& path);  // [x, y]

// Range checks: lo/hi inclusive unless stated; messages say the bound.
double check_range(const Source& src, const YAML::Node& n, const std::string& path, double v, double lo,
                   double hi);
double check_positive(const Source& src, const YAML::Node& n, const std::string& path, double v, double hi);

// A map whose keys are consumed one by one; finish() rejects whatever was not asked for.
class MapReader {
 public:
  MapReader(const Source& src, const YAML::Node& node, std::string path);

  // The value of `key`, or nothing when absent (null values count as given: the typed readers reject them).
  std::optional<YAML::Node> get(std::string_view key);
  bool has(std::string_view key) const;
  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }
  std::string field(std::string_view key) const;  // "path.key"

  // Typed readers: the value when present (checked), else `fallback`.
  double number(std::string_view key, double fallback, double lo, double hi);
  double positive(std::string_view key, double fallback, double hi);  // (0, hi]
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi);
  bool boolean(std::string_view key, bool fallback);

  // Every key not asked for is an error at its line, with the list of known keys.
  void finish(std::initializer_list<std::string_view> known) const;

 private:
  const Source& src_;
  YAML::Node node_;
  std::string path_;
  std::vector<std::string> used_;
};

}  // namespace swarmform::world::yaml
