#include "behaviour/descriptor_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "behaviour/descriptor_check.hpp"
#include "behaviour/params.hpp"
#include "common/input_error.hpp"

namespace swarmform::behaviour {
namespace {

using nlohmann::json;

constexpr std::string_view kExperimentRefused =
    "not supported: a behaviour described by a file has no experiment (its outcome is \"none\"; judge its "
    "runs with --expect)";

constexpr std::array<std::pair<std::string_view, std::uint32_t>, 5> kSensorBits = {{
    {"proximity", kProximity},
    {"light", kLight},
    {"ground", kGround},
    {"lidar", kLidar},
    {"battery", kBattery},
}};

// Reads one file's JSON, naming every problem as `file: key.path: what`.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& at, const std::string& what) const {
    throw InputError(file_, 0, at.empty() ? what : at + ": " + what);
  }

  // `j` is an object holding no key outside `known` (each listed in `required` present).
  void keys(const json& j, const std::string& at, std::initializer_list<std::string_view> known,
            std::initializer_list<std::string_view> required) const {
    if (!j.is_object()) fail(at, "expected an object, got " + std::string(j.type_name()));
    for (const auto& [key, value] : j.items()) {
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      if (at.empty() && key == "experiment") fail("experiment", std::string(kExperimentRefused));
      std::string list;
      for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      fail(join(at, key), "unknown key (known: " + list + ")");
    }
    for (std::string_view k : required) {
      if (!j.contains(k)) fail(join(at, std::string(k)), "missing");
    }
  }

  static std::string join(const std::string& at, const std::string& key) {
    return at.empty() ? key : at + "." + key;
  }

  std::string text(const json& j, const std::string& at) const {
    if (!j.is_string()) fail(at, "expected a string, got " + std::string(j.type_name()));
    return j.get<std::string>();
  }
  double number(const json& j, const std::string& at) const {
    if (!j.is_number()) fail(at, "expected a number, got " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(at, "expected a finite number");
    return v;
  }
  std::int64_t integer(const json& j, const std::string& at) const {
    if (!j.is_number_integer()) fail(at, "expected an integer, got " + std::string(j.type_name()));
    return j.get<std::int64_t>();
  }
  bool boolean(const json& j, const std::string& at) const {
    if (!j.is_boolean()) fail(at, "expected true or false, got " + std::string(j.type_name()));
    return j.get<bool>();
  }
  const json& array(const json& j, const std::string& at) const {
    if (!j.is_array()) fail(at, "expected an array, got " + std::string(j.type_name()));
    return j;
  }

 private:
  std::string file_;
};

std::string at_index(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::unique_ptr<const DescribedBehaviour> load_descriptor_file(const std::filesystem::path& path) {
  auto out = std::make_unique<DescribedBehaviour>();
  out->file_ = path.string();
  const Reader r(out->file_);
  std::ifstream in(path);
  if (!in) r.fail("", "cannot read the behaviour's descriptor file (no such file, or not readable)");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    std::string why = e.what();
    if (const auto close = why.find("] "); why.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      why.erase(0, close + 2);
    r.fail("", "not JSON: " + why);
  }
  r.keys(j, "", {"api_version", "name", "summary", "params", "states", "telemetry", "needs_goal", "sensors"},
         {"api_version", "name"});

  auto keep = [&](std::string s) -> std::string_view { return out->text_.emplace_back(std::move(s)); };
  Descriptor& d = out->descriptor_;

  const std::int64_t version = r.integer(j["api_version"], "api_version");
  if (version != kApiVersion) {
    r.fail("api_version", "the file declares behaviour API version " + std::to_string(version) +
                              ", this program has version " + std::to_string(kApiVersion) +
                              " (docs/behaviour-api.md lists what changed)");
  }
  const std::string name = r.text(j["name"], "name");
  if (!lower_case_name(name)) r.fail("name", "'" + name + "' is not a lower_case name (a-z, 0-9, _)");
  d.name = keep(name);
  if (j.contains("summary")) d.summary = keep(r.text(j["summary"], "summary"));
  if (j.contains("needs_goal")) d.needs_goal = r.boolean(j["needs_goal"], "needs_goal");

  if (j.contains("params")) {
    const json& list = r.array(j["params"], "params");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = at_index("params", i);
      r.keys(list[i], at, {"name", "default", "min", "max", "doc"}, {"name", "default", "min", "max", "doc"});
      const std::string pname = r.text(list[i]["name"], at + ".name");
      if (!lower_case_name(pname))
        r.fail(at + ".name", "'" + pname + "' is not a lower_case name (a-z, 0-9, _)");
      for (const ParamSpec& p : out->params_) {
        if (p.name == pname) r.fail(at + ".name", "'" + pname + "' is already a parameter");
      }
      ParamSpec p{};
      p.default_value = r.number(list[i]["default"], at + ".default");
      p.min_value = r.number(list[i]["min"], at + ".min");
      p.max_value = r.number(list[i]["max"], at + ".max");
      if (p.max_value < p.min_value)
        r.fail(at + ".max",
               "below min (" + number_text(p.max_value) + " < " + number_text(p.min_value) + ")");
      if (p.default_value < p.min_value || p.default_value > p.max_value) {
        r.fail(at + ".default", number_text(p.default_value) + " is outside [min, max] = [" +
                                    number_text(p.min_value) + ", " + number_text(p.max_value) + "]");
      }
      p.doc = keep(r.text(list[i]["doc"], at + ".doc"));
      p.name = keep(pname);
      out->params_.push_back(p);
    }
  }

  if (j.contains("states")) {
    const json& list = r.array(j["states"], "states");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = at_index("states", i);
      r.keys(list[i], at, {"value", "name", "colour"}, {"value", "name", "colour"});
      const std::int64_t value = r.integer(list[i]["value"], at + ".value");
      if (value < 0 || value > std::numeric_limits<std::int32_t>::max())
        r.fail(at + ".value", std::to_string(value) + " is outside 0..2147483647");
      const std::string sname = r.text(list[i]["name"], at + ".name");
      if (!lower_case_name(sname))
        r.fail(at + ".name", "'" + sname + "' is not a lower_case name (a-z, 0-9, _)");
      const std::string c = r.text(list[i]["colour"], at + ".colour");
      if (!colour_text(c)) r.fail(at + ".colour", "'" + c + "' is not a colour \"#rrggbb\"");
      for (const StateSpec& s : out->states_) {
        if (s.value == value)
          r.fail(at + ".value", std::to_string(value) + " is already state '" + std::string(s.name) + "'");
        if (s.name == sname) r.fail(at + ".name", "'" + sname + "' is already a state");
      }
      out->states_.push_back(StateSpec{static_cast<std::int32_t>(value), keep(sname), keep(c)});
    }
  }

  if (j.contains("telemetry")) {
    const json& list = r.array(j["telemetry"], "telemetry");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = at_index("telemetry", i);
      r.keys(list[i], at, {"name", "doc"}, {"name", "doc"});
      const std::string tname = r.text(list[i]["name"], at + ".name");
      if (!lower_case_name(tname))
        r.fail(at + ".name", "'" + tname + "' is not a lower_case name (a-z, 0-9, _)");
      for (const TelemetryColumn& t : out->telemetry_) {
        if (t.name == tname) r.fail(at + ".name", "'" + tname + "' is already a column");
      }
      const std::string doc = r.text(list[i]["doc"], at + ".doc");
      out->telemetry_.push_back(TelemetryColumn{keep(tname), keep(doc)});
    }
  }

  if (j.contains("sensors")) {
    const json& list = r.array(j["sensors"], "sensors");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = at_index("sensors", i);
      const std::string sensor = r.text(list[i], at);
      const auto it = std::find_if(kSensorBits.begin(), kSensorBits.end(),
                                   [&](const auto& kv) { return kv.first == sensor; });
      if (it == kSensorBits.end())
        r.fail(at, "unknown sensor '" + sensor + "' (known: proximity, light, ground, lidar, battery)");
      if ((d.sensors & it->second) != 0) r.fail(at, "'" + sensor + "' is already listed");
      d.sensors |= it->second;
    }
  }

  d.params = out->params_;
  d.states = out->states_;
  d.telemetry = out->telemetry_;
  d.make = nullptr;  // its controller is the --exec program
  // The registry's checks of every descriptor, as for a plug-in.
  for (const std::string& why : {check_shape_rules(d), check_experiment(d), check_sensors(d)}) {
    if (!why.empty()) r.fail("", why);
  }
  return out;
}

}  // namespace swarmform::behaviour
