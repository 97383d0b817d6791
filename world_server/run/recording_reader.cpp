#include "world_server/run/recording_reader.hpp"

#include <algorithm>

#include <charconv>
#include <fstream>
#include <sstream>

#include "common/input_error.hpp"
#include "common/led_text.hpp"
#include "world_server/run/recorder.hpp"

namespace swarmform::world {

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Splits into lines; reports whether the text ended with a newline.
std::vector<std::string_view> split_lines(const std::string& text, bool& complete) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const auto end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.emplace_back(text.data() + start, text.size() - start);
      complete = false;
      return lines;
    }
    lines.emplace_back(text.data() + start, end - start);
    start = end + 1;
  }
  complete = true;
  return lines;
}

template <typename T>
T parse_field(std::string_view field, const std::string& path, int line, const char* name) {
  T value{};
  const auto res = std::from_chars(field.data(), field.data() + field.size(), value);
  if (res.ec != std::errc() || res.ptr != field.data() + field.size()) {
    throw InputError(path, line, std::string("bad ") + name + " '" + std::string(field) + "'");
  }
  return value;
}

bool parse_flag(std::string_view field, const std::string& path, int line, const char* name) {
  if (field == "0") return false;
  if (field == "1") return true;
  throw InputError(path, line, std::string("bad ") + name + " '" + std::string(field) + "' (want 0 or 1)");
}

}  // namespace

std::vector<RecordedRow> read_robots_csv(const std::string& path, bool allow_truncated_tail) {
  const std::string text = slurp(path);
  bool complete = true;
  auto lines = split_lines(text, complete);
  // The fixed columns, then the behaviour's own (its telemetry), if any.
  const std::string fixed = kRobotsCsvHeader;
  if (lines.empty() || (lines[0] != fixed && lines[0].rfind(fixed + ",", 0) != 0)) {
    throw InputError(path, 1, std::string("expected the header '") + kRobotsCsvHeader + "'");
  }
  const std::size_t fields = 1 + static_cast<std::size_t>(std::count(lines[0].begin(), lines[0].end(), ','));
  // The LEDs' column follows the fixed ones in a recording that has it (a telemetry column is never named
  // so).
  const std::string with_leds = fixed + "," + kLedsColumn;
  const bool has_leds = lines[0] == with_leds || lines[0].rfind(with_leds + ",", 0) == 0;
  if (!complete) {
    if (!allow_truncated_tail) {
      throw InputError(path, static_cast<int>(lines.size()), "last line cut off (truncated recording)");
    }
    lines.pop_back();
  }
  std::vector<RecordedRow> rows;
  rows.reserve(lines.size() - 1);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const int line = static_cast<int>(i + 1);
    std::vector<std::string_view> f;
    std::string_view rest = lines[i];
    while (true) {
      const auto comma = rest.find(',');
      f.push_back(rest.substr(0, comma));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    if (f.size() != fields) {
      throw InputError(path, line,
                       "expected " + std::to_string(fields) + " fields, found " + std::to_string(f.size()));
    }
    RecordedRow r;
    r.tick = parse_field<Tick>(f[0], path, line, "tick");
    r.id = parse_field<RobotId>(f[1], path, line, "id");
    r.pose.x = parse_field<double>(f[2], path, line, "x");
    r.pose.y = parse_field<double>(f[3], path, line, "y");
    r.pose.theta = parse_field<double>(f[4], path, line, "theta");
    r.alive = parse_flag(f[5], path, line, "alive");
    r.state = parse_field<std::int32_t>(f[6], path, line, "state");
    r.label = parse_field<std::int32_t>(f[7], path, line, "label");
    r.parent = parse_field<std::int32_t>(f[8], path, line, "parent");
    r.leader = parse_flag(f[9], path, line, "leader");
    r.net_force = parse_field<double>(f[10], path, line, "net_force");
    if (has_leds) {
      const auto leds = parse_led_text(f[11]);
      if (!leds) {
        throw InputError(path, line,
                         "bad leds '" + std::string(f[11]) + "' (want empty or '#rrggbb #rrggbb #rrggbb')");
      }
      r.leds = *leds;
    }
    rows.push_back(r);
  }
  return rows;
}

std::vector<nlohmann::json> read_events_jsonl(const std::string& path) {
  const std::string text = slurp(path);
  bool complete = true;
  const auto lines = split_lines(text, complete);
  if (!complete)
    throw InputError(path, static_cast<int>(lines.size()), "last line cut off (truncated recording)");
  std::vector<nlohmann::json> events;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int line = static_cast<int>(i + 1);
    nlohmann::json e = nlohmann::json::parse(lines[i], nullptr, /*allow_exceptions=*/false);
    if (e.is_discarded() || !e.is_object()) throw InputError(path, line, "not a JSON object");
    if (!e.contains("tick") || !e["tick"].is_number_integer() || !e.contains("kind") ||
        !e["kind"].is_string() || !e.contains("id") || !e["id"].is_number_integer()) {
      throw InputError(path, line, "an event needs an integer tick, a string kind and an integer id");
    }
    events.push_back(std::move(e));
  }
  return events;
}

nlohmann::json read_json_file(const std::string& path) {
  const std::string text = slurp(path);
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw InputError(path, 0, "not valid JSON (truncated?)");
  return j;
}

}  // namespace swarmform::world
