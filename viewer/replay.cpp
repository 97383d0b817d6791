#include "viewer/replay.hpp"

#include <sys/stat.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "behaviour/known_columns.hpp"
#include "common/dds/behaviour_view.hpp"
#include "common/sensor_readings.hpp"
#include "viewer/foxglove.hpp"
#include "viewer/frame_json.hpp"
#include "viewer/page_flow.hpp"
#include "viewer/robots_csv.hpp"
#include "viewer/web_server.hpp"

namespace swarmform::viewer {

namespace {

using nlohmann::json;

constexpr int kPeriodMs = 20;
constexpr std::size_t kMaxRobots = 100000;  // the scenario format's limit (docs/recording-format.md)

// A file of the run directory as JSON: nullopt and `error` set (naming the file and what) when it is missing
// or not JSON.
std::optional<json> read_json_file(const std::string& path, std::string& error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    error = path + ": missing (is this a run directory?)";
    return std::nullopt;
  }
  std::ostringstream text;
  text << f.rdbuf();
  try {
    return json::parse(text.str());
  } catch (const json::parse_error& e) {
    error = path + ": not valid JSON (" + e.what() + ")";
    return std::nullopt;
  }
}

bool is_number(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number();
}

// What the page and Foxglove read of world.json, checked: "" when usable, else what is wrong.
std::string check_world(const json& w) {
  if (!w.is_object()) return "expected a JSON object";
  if (!w.contains("arena") || !w["arena"].is_object())
    return "missing 'arena' object {centre, width, height}";
  const json& a = w["arena"];
  if (!is_number(a, "width") || !is_number(a, "height") || a["width"].get<double>() <= 0 ||
      a["height"].get<double>() <= 0)
    return "arena: width and height must be positive numbers";
  if (!a.contains("centre") || !a["centre"].is_array() || a["centre"].size() != 2 ||
      !a["centre"][0].is_number() || !a["centre"][1].is_number())
    return "arena.centre: expected [x, y]";
  if (w.contains("robots") && !w["robots"].is_number_unsigned() && !w["robots"].is_array())
    return "robots: expected a count";
  if (w.contains("tick_rate") && (!w["tick_rate"].is_number() || w["tick_rate"].get<double>() <= 0))
    return "tick_rate: expected a positive number";
  return "";
}

// The recording's own description of its behaviour (world.json's behaviour_descriptor: the descriptor's
// states, docs/recording-format.md), in the form the live frames give it. Its telemetry columns are
// robots.csv's `columns` (with robot groups, every group's: a robot has its own group's values, the others'
// empty).
dds::BehaviourView behaviour_of(const json& world, const std::vector<std::string>& columns) {
  dds::BehaviourView v = dds::describe_behaviour("", nullptr);
  v.name = world.value("behaviour", std::string("?"));
  v.columns = columns;
  // The known columns (robots.csv's own label, parent, leader, net_force) a behaviour of the run declares.
  std::vector<json> descriptors = {world.value("behaviour_descriptor", json::object())};
  for (const json& g : world.value("groups", json::array()))
    if (g.is_object()) descriptors.push_back(g.value("behaviour_descriptor", json::object()));
  for (const std::string_view known : behaviour::kKnownColumns) {
    const auto declares = [&](const json& d) {
      if (!d.is_object() || !d.contains("telemetry") || !d["telemetry"].is_array()) return false;
      for (const json& t : d["telemetry"])
        if (t.is_object() && t.value("name", std::string()) == known) return true;
      return false;
    };
    if (std::any_of(descriptors.begin(), descriptors.end(), declares)) v.telemetry_fields.emplace_back(known);
  }
  v.telemetry_fields.insert(v.telemetry_fields.end(), columns.begin(), columns.end());
  const json d = world.value("behaviour_descriptor", json::object());
  if (!d.is_object()) return v;
  for (const auto& s : d.value("states", json::array())) {
    if (!s.is_object() || !s.contains("value") || !s["value"].is_number_integer()) continue;
    dds::StateStyleRow row;
    row.value = s["value"].get<std::int32_t>();
    row.name = s.contains("name") && s["name"].is_string() ? s["name"].get<std::string>()
                                                           : std::to_string(row.value);
    row.colour = s.contains("colour") && s["colour"].is_string() ? s["colour"].get<std::string>() : "#000000";
    v.states.push_back(std::move(row));
  }
  return v;
}

double r4(double v) {
  return std::isfinite(v) ? std::round(v * 1e4) / 1e4 : 0.0;
}

// The sensors whose columns readings.csv's header holds, in the layout's order
// (common/sensor_readings.hpp): nullopt when its columns are anything else.
std::optional<std::uint32_t> sensors_of(const std::vector<std::string>& columns) {
  std::uint32_t bits = 0;
  std::size_t at = 0;
  for (const SensorReadingsLayout& s : kSensorReadings) {
    const std::vector<std::string> want = sensor_reading_columns(s.bit);
    if (at + want.size() <= columns.size() && std::equal(want.begin(), want.end(), columns.begin() + at)) {
      bits |= s.bit;
      at += want.size();
    }
  }
  if (at != columns.size() || bits == 0) return std::nullopt;
  return bits;
}

class Session {
 public:
  Session(const ReplayOptions& o, json world, std::optional<json> summary, RobotsCsv& csv,
          RobotsCsv* readings, std::uint32_t sensors)
      : o_(o),
        world_(std::move(world)),
        csv_(csv),
        readings_(readings),
        sensors_(sensors),
        view_(behaviour_of(world_, csv.extra_columns())) {
    tick_rate_ = world_.value("tick_rate", 10.0);
    finished_ = summary.has_value();
    if (summary && summary->is_object()) {
      if (is_number(*summary, "formation_tick"))
        formation_tick_ = (*summary)["formation_tick"].get<std::int64_t>();
      if (is_number(*summary, "shape_error_at_formation"))
        shape_error_ = (*summary)["shape_error_at_formation"].get<double>();
      // The shape error of every tick from formation on ([[tick, error], ...]): Foxglove's /metrics plots it.
      for (const json& d : summary->value("distortion", json::array())) {
        if (d.is_array() && d.size() == 2 && d[0].is_number_unsigned() && d[1].is_number())
          distortion_[d[0].get<std::uint64_t>()] = d[1].get<double>();
      }
    }
    foxglove_.set_world(world_);
    foxglove_.set_recorded(true);
    // The run's wall time: world.json is written as the run starts; its ticks follow at tick / tick_rate.
    struct stat st {};
    if (::stat((o.run_dir + "/world.json").c_str(), &st) == 0)
      foxglove_.set_start_ns(static_cast<std::uint64_t>(st.st_mtim.tv_sec) * 1000000000U +
                             static_cast<std::uint64_t>(st.st_mtim.tv_nsec));
    tick_ = csv_.first_tick();
  }

  int run() {
    WebServer::Handlers h;
    h.opened = [this](ClientId c, ClientKind k) { opened(c, k); };
    h.closed = [this](ClientId c) {
      foxglove_.forget(c);
      selected_.erase(c);
      flow_.closed(c);
    };
    h.text = [this](ClientId c, ClientKind k, const std::string& text) { on_text(c, k, text); };
    // A Foxglove client's /control messages are the page's commands (play, pause, seek, speed), by the
    // page's rule on Origin.
    h.binary = [this](ClientId c, const std::string& bytes) {
      const auto got = foxglove_.on_binary(c, bytes);
      if (!got.status.empty()) {
        server_->send_text(c, got.status);
      } else if (!server_->may_drive(c)) {
        server_->send_text(
            c, Foxglove::status(2, "control refused: this connection's Origin is not this server's"));
      } else {
        on_text(c, ClientKind::Page, got.command);
      }
    };
    h.every = [this] { return every(); };
    WebServer server({o_.host, o_.port, o_.web_root, o_.run_dir, o_.control_origins}, h, kPeriodMs);
    server_ = &server;
    std::cout << "viewer http://" << o_.host << ":" << server.port() << "/ replay of " << o_.run_dir
              << " (ticks " << csv_.first_tick() << ".." << csv_.last_tick() << ", robots.csv "
              << csv_.size_bytes() << " bytes)" << std::endl;
    if (!finished_)
      std::cerr << "swarm_viewer: " << o_.run_dir
                << "/summary.json missing: the run did not finish (it was killed, or is still running)\n";
    show(tick_);
    server.run();
    server_ = nullptr;
    if (csv_.bad_rows() > 0)
      std::cerr << "swarm_viewer: " << csv_.bad_rows()
                << " row(s) of robots.csv skipped; the first: " << csv_.first_problem() << "\n";
    if (readings_ != nullptr && readings_->bad_rows() > 0)
      std::cerr << "swarm_viewer: " << readings_->bad_rows()
                << " row(s) of readings.csv skipped; the first: " << readings_->first_problem() << "\n";
    return 0;
  }

 private:
  void opened(ClientId c, ClientKind k) {
    if (k == ClientKind::Foxglove) {
      for (const std::string& m : foxglove_.hello()) server_->send_text(c, m);
      for (const Damage& d : csv_.damage()) server_->send_text(c, foxglove_status(csv_, d));
      return;
    }
    json fields = view_.telemetry_fields;
    json states = json::array();
    for (const auto& s : view_.states)
      states.push_back({{"value", s.value}, {"name", s.name}, {"colour", s.colour}});
    const json hello = {{"type", "hello"},
                        {"mode", "replay"},
                        {"behaviour", view_.name},
                        {"states", states},
                        {"telemetry_fields", fields},
                        {"first_tick", csv_.first_tick()},
                        {"last_tick", csv_.last_tick()},
                        {"tick_rate", tick_rate_},
                        {"finished", finished_},
                        {"damage", damage_json(false, 0)}};
    server_->send_text(c, hello.dump());
    flow_.opened(c, !last_page_frame_.empty());
    if (!last_page_frame_.empty()) server_->send_text(c, last_page_frame_);
  }

  void on_text(ClientId c, ClientKind k, const std::string& text) {
    if (k == ClientKind::Foxglove) {
      const std::string answer = foxglove_.on_text(c, text);
      if (!answer.empty()) server_->send_text(c, answer);
      // A new subscriber gets the frame shown now at once (a paused replay would send nothing else).
      for (auto& [client, bytes] : foxglove_.messages(frame_, c)) server_->send_binary(client, bytes);
      return;
    }
    const json m = json::parse(text, nullptr, false);
    const std::string cmd = m.is_object() ? m.value("cmd", std::string()) : std::string();
    const bool has_value = m.is_object() && m.contains("value") && m["value"].is_number();
    const double value = has_value ? m["value"].get<double>() : 0.0;
    if (cmd == "drawn") {
      // The page drew a frame: the newest goes now if one waited for it (page_flow.hpp).
      bool jump = false;
      if (flow_.drawn(c, jump) && !last_page_frame_.empty())
        server_->send_text(c, jump && played_frame_ ? as_jump() : last_page_frame_);
      return;
    }
    if (cmd == "seek" && has_value && std::isfinite(value)) {
      const double t =
          std::clamp(value, static_cast<double>(csv_.first_tick()), static_cast<double>(csv_.last_tick()));
      carry_ = 0;
      show(static_cast<std::uint64_t>(t));
    } else if (cmd == "play") {
      if (tick_ >= csv_.last_tick()) show(csv_.first_tick());  // at the end: from the start again
      playing_ = true;
      last_ = std::chrono::steady_clock::now();
      carry_ = 0;
      show(tick_);
    } else if (cmd == "pause") {
      playing_ = false;
      show(tick_);
    } else if (cmd == "speed" && has_value && value > 0 && value <= 1000) {
      speed_ = value;
    } else if (cmd == "select" && has_value) {
      // The robot whose panel the page shows (-1: none): its readings go into the frames from now on.
      if (value >= 0 && value < 4294967296.0) {
        selected_[c] = static_cast<std::uint32_t>(value);
      } else {
        selected_.erase(c);
      }
      show(tick_);
    } else if (++bad_messages_ == 1 || bad_messages_ % 1000 == 0) {
      std::cerr << "swarm_viewer: ignored " << bad_messages_ << " page message(s) it does not know, e.g. "
                << text.substr(0, 80) << "\n";
    }
  }

  bool every() {
    if (!playing_) return true;
    const auto now = std::chrono::steady_clock::now();
    carry_ += std::chrono::duration<double>(now - last_).count() * tick_rate_ * speed_;
    last_ = now;
    const auto step = static_cast<std::uint64_t>(carry_);
    if (step == 0) return true;
    carry_ -= static_cast<double>(step);
    std::uint64_t next = tick_ + step;
    if (next >= csv_.last_tick()) {
      next = csv_.last_tick();
      playing_ = false;
    }
    played_ = true;
    show(next);
    played_ = false;
    return true;
  }

  // The damage of robots.csv and readings.csv (robots_csv.hpp Damage) as the page's JSON: all of it, or
  // (`at_tick`) what touches timeline tick `tick`.
  json damage_json(bool at_tick, std::uint64_t tick) const {
    json out = json::array();
    const std::array<const RobotsCsv*, 2> files = {&csv_, readings_};
    for (const RobotsCsv* f : files) {
      if (f == nullptr) continue;
      const std::string name = f == &csv_ ? "robots.csv" : "readings.csv";
      for (const Damage& d : at_tick ? f->damage_at(tick) : f->damage()) {
        out.push_back({{"file", name},
                       {"offset", d.offset},
                       {"from_tick", d.from_tick},
                       {"to_tick", d.to_tick},
                       {"at_open", d.at_open},
                       {"what", d.what}});
      }
    }
    return out;
  }

  // Damage as a Foxglove status (a warning in its problems panel): Foxglove's users are told too.
  static std::string foxglove_status(const RobotsCsv& f, const Damage& d) {
    const std::string ticks = d.from_tick == d.to_tick
                                  ? "tick " + std::to_string(d.from_tick)
                                  : "ticks " + std::to_string(d.from_tick) + ".." + std::to_string(d.to_tick);
    return json{{"op", "status"},
                {"level", 1},
                {"id", "damage-" + std::to_string(d.offset)},
                {"message", "damaged recording: " + f.path() + " byte " + std::to_string(d.offset) + " (" +
                                ticks + "): " + d.what}}
        .dump();
  }

  // Damage found since the last call, on stderr at once (`swarm view` shows the viewer's stderr; a viewer
  // stopped by a signal has said it already).
  void say_new_damage() {
    const std::array<const RobotsCsv*, 2> files = {&csv_, readings_};
    for (const RobotsCsv* f : files) {
      if (f == nullptr) continue;
      std::size_t& said = f == &csv_ ? said_robots_ : said_readings_;
      for (; said < f->damage().size(); ++said) {
        const Damage& d = f->damage()[said];
        std::cerr << "swarm_viewer: " << f->path() << " byte " << d.offset << " (tick " << d.from_tick
                  << (d.to_tick != d.from_tick ? ".." + std::to_string(d.to_tick) : std::string())
                  << "): " << d.what << std::endl;
        if (server_ != nullptr) server_->broadcast_text(ClientKind::Foxglove, foxglove_status(*f, d));
      }
    }
  }

  // Tick `t` (the last recorded tick <= t) to every page and every Foxglove subscriber.
  void show(std::uint64_t t) {
    const RecordedTick& rec = csv_.read(t);
    tick_ = std::min(std::max(t, rec.tick), csv_.last_tick());
    frame_ = dds::ObserveFrameData{};
    frame_.tick = rec.tick;
    frame_.paused = !playing_;
    frame_.behaviour = view_.name;
    frame_.states = view_.states;
    frame_.telemetry_fields = view_.telemetry_fields;
    frame_.columns = view_.columns;
    const bool formed = formation_tick_ >= 0 && static_cast<std::uint64_t>(formation_tick_) <= rec.tick;
    frame_.formation_tick = formed ? formation_tick_ : -1;
    frame_.shape_error = formed ? shape_error_ : -1.0;
    if (const auto d = distortion_.find(rec.tick); d != distortion_.end()) frame_.shape_error = d->second;
    json robots = json::array();
    const std::vector<std::string>& extra = csv_.extra_columns();
    // The tick's readings (readings.csv has the rows of robots.csv's ticks) of the robots the pages show in
    // their panels: nothing read while no page has one selected.
    const RecordedTick* sensed = nullptr;
    if (readings_ != nullptr && !selected_.empty()) {
      sensed = &readings_->read(rec.tick);
      if (sensed->tick != rec.tick) sensed = nullptr;
    }
    for (std::size_t row = 0; row < rec.rows.size(); ++row) {
      const RecordedRow& r = rec.rows[row];
      dds::ObservedRobotRow o;
      o.id = r.id;
      o.pose = {r.x, r.y, r.theta};
      o.alive = r.alive;
      o.state = r.state;
      o.label = r.label;
      o.parent = r.parent;
      o.leader = r.leader;
      o.net_force = r.net_force;
      o.leds = r.leds;
      o.extra = r.extra;
      if (sensed != nullptr && is_selected(r.id)) readings_of(*sensed, row, r.id, o);
      frame_.alive += r.alive ? 1 : 0;
      // The page's robot: what robots.csv and readings.csv hold (no ultrasonics, neighbours heard or command:
      // not recorded).
      json j = {{"id", r.id},         {"x", r4(r.x)},
                {"y", r4(r.y)},       {"theta", r4(r.theta)},
                {"alive", r.alive},   {"state", r.state},
                {"label", r.label},   {"parent", r.parent},
                {"leader", r.leader}, {"net_force", r4(r.net_force)}};
      if (json leds = leds_json(r.leds); !leds.is_null()) j["leds"] = std::move(leds);
      for (std::size_t k = 0; k < extra.size() && k < r.extra.size(); ++k) {
        if (std::isfinite(r.extra[k])) j[extra[k]] = r.extra[k];
      }
      add_readings(o.equipped, o.readings, j);  // the live frames' code: the panel draws them the same
      frame_.robots.push_back(std::move(o));
      robots.push_back(std::move(j));
    }
    json states = json::array();
    for (const auto& s : frame_.states)
      states.push_back({{"value", s.value}, {"name", s.name}, {"colour", s.colour}});
    page_ = {{"type", "frame"},
             {"tick", rec.tick},
             {"at", tick_},
             {"damage", damage_json(true, tick_)},
             {"finished", false},
             {"paused", !playing_},
             {"controllable", false},
             {"speed_cap", 0.0},
             {"replay_speed", speed_},
             {"played", played_},
             {"alive", frame_.alive},
             {"formation_tick", frame_.formation_tick},
             {"shape_error", frame_.shape_error},
             {"behaviour", frame_.behaviour},
             {"states", states},
             {"telemetry_fields", frame_.telemetry_fields},
             {"robots", robots}};
    last_page_frame_ = page_.dump();
    played_frame_ = played_;
    say_new_damage();
    if (server_ == nullptr) return;
    // Paced as live: a page still drawing gets the newest frame when it has drawn (page_flow.hpp), so a
    // replay played faster than a page draws shows the timeline's tick, not a backlog in the socket.
    for (const PageFlow::Send& to : flow_.offer(!played_)) server_->send_text(to.client, last_page_frame_);
    for (auto& [client, bytes] : foxglove_.messages(frame_)) server_->send_binary(client, bytes);
  }

 public:
  // `swarm export`: every recorded tick's Foxglove messages, as the live server sends them, on `out` for
  // scripts/mcap/write.mjs: serverInfo and advertise (a line each), a line {"op": "range", ...}, then a line
  // per message: CHANNEL LOG_TIME_NS TICK PAYLOAD. Damage is said on stderr as the replay says it.
  int export_lines(std::ostream& out) {
    // A pipe's writes in 1 MiB blocks, not stdio's 4 KiB: the writer at the other end wakes less often (3x
    // faster end to end).
    static std::vector<char> buffer(1 << 20);
    std::setvbuf(stdout, buffer.data(), _IOFBF, buffer.size());
    for (const std::string& m : foxglove_.hello()) out << m << '\n';
    out << json{{"op", "range"},
                {"first_tick", csv_.first_tick()},
                {"last_tick", csv_.last_tick()},
                {"tick_rate", tick_rate_},
                {"start_ns", foxglove_.log_ns(0)}}
               .dump()
        << '\n';
    json subs = json::array();
    for (std::uint32_t c = Foxglove::kScene; c <= Foxglove::kChannels; ++c)
      subs.push_back({{"id", c}, {"channelId", c}});  // subscription id = channel id
    foxglove_.on_text(1, json{{"op", "subscribe"}, {"subscriptions", subs}}.dump());
    std::optional<std::uint64_t> last;
    for (std::uint64_t t = csv_.first_tick();; ++t) {
      show(t);
      if (!last || frame_.tick != *last) {  // a recording that skips ticks: each recorded tick once
        last = frame_.tick;
        for (const auto& [client, bytes] : foxglove_.messages(frame_)) {
          std::uint32_t sub = 0;
          std::uint64_t stamp = 0;
          for (int i = 0; i < 4; ++i)
            sub |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[1 + i])) << (8 * i);
          for (int i = 0; i < 8; ++i)
            stamp |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[5 + i])) << (8 * i);
          out << sub << ' ' << stamp << ' ' << frame_.tick << ' ';
          out.write(bytes.data() + 13, static_cast<std::streamsize>(bytes.size() - 13));
          out << '\n';
        }
      }
      if (t >= csv_.last_tick()) break;
    }
    out.flush();
    if (!out) {
      std::cerr << "swarm_viewer: --export-frames: writing stdout failed\n";
      return 1;
    }
    if (csv_.bad_rows() > 0)
      std::cerr << "swarm_viewer: " << csv_.bad_rows()
                << " row(s) of robots.csv skipped; the first: " << csv_.first_problem() << "\n";
    return 0;
  }

 private:
  // The newest frame, made by the timeline playing on, as a jump: to a page that skipped a jump's frame.
  std::string as_jump() {
    page_["played"] = false;
    std::string text = page_.dump();
    page_["played"] = true;
    return text;
  }

  bool is_selected(std::uint32_t id) const {
    for (const auto& [client, robot] : selected_) {
      if (robot == id) return true;
    }
    return false;
  }

  // Robot `id`'s readings from `sensed` (its row at `hint` when the rows are in id order) into `o`: none when
  // it has no row, or an empty value (a dead robot's).
  void readings_of(const RecordedTick& sensed, std::size_t hint, std::uint32_t id, dds::ObservedRobotRow& o) {
    const RecordedRow* s =
        hint < sensed.rows.size() && sensed.rows[hint].id == id ? &sensed.rows[hint] : nullptr;
    for (std::size_t k = 0; s == nullptr && k < sensed.rows.size(); ++k) {
      if (sensed.rows[k].id == id) s = &sensed.rows[k];
    }
    if (s == nullptr || s->extra.size() != sensor_readings_count(sensors_)) return;
    for (const double v : s->extra) {
      if (std::isnan(v)) return;
    }
    o.equipped = sensors_;
    o.readings = s->extra;
  }

  const ReplayOptions& o_;
  json world_;
  RobotsCsv& csv_;
  RobotsCsv* readings_;    // null: the recording has no readings.csv (no sensors declared, or older)
  std::uint32_t sensors_;  // readings.csv's sensors (behaviour::Sensor bits)
  std::map<ClientId, std::uint32_t> selected_;  // each page's selected robot, whose readings its frames carry
  dds::BehaviourView view_;
  Foxglove foxglove_;
  WebServer* server_ = nullptr;
  double tick_rate_ = 10.0;
  std::int64_t formation_tick_ = -1;
  double shape_error_ = -1.0;
  std::map<std::uint64_t, double> distortion_;  // summary.json's per tick shape error from formation on

  std::uint64_t tick_ = 0;  // the timeline's position (the tick shown is the last recorded one <= it)
  bool playing_ = false;
  double speed_ = 1.0;  // recorded seconds a second
  double carry_ = 0.0;  // ticks due but not yet shown
  // The frame being sent is the timeline playing on (every()), not a seek, a play or a selection: the page
  // measures ticks/s over these only (a jump is not a rate).
  bool played_ = false;
  std::chrono::steady_clock::time_point last_;
  dds::ObserveFrameData frame_;
  json page_;  // the newest page frame, and its text:
  std::string last_page_frame_;
  bool played_frame_ = false;  // it was made by the timeline playing on
  PageFlow flow_;
  std::uint64_t bad_messages_ = 0;
  bool finished_ = false;  // summary.json is there: the run ended (else it was killed, or still runs)
  std::size_t said_robots_ = 0, said_readings_ = 0;  // damage said on stderr
};

}  // namespace

int replay(const ReplayOptions& o) {
  std::string error;
  const std::optional<json> world = read_json_file(o.run_dir + "/world.json", error);
  if (!world) {
    std::cerr << "swarm_viewer: " << error << "\n";
    return 2;
  }
  if (const std::string bad = check_world(*world); !bad.empty()) {
    std::cerr << "swarm_viewer: " << o.run_dir << "/world.json: " << bad << "\n";
    return 2;
  }
  std::string summary_error;
  std::optional<json> summary = read_json_file(o.run_dir + "/summary.json", summary_error);
  if (!summary) summary = std::nullopt;  // a run that did not finish has none: no formation marks
  const json& n = world->value("robots", json(0));
  const std::uint64_t robots = n.is_array() ? n.size() : n.get<std::uint64_t>();
  std::unique_ptr<RobotsCsv> csv;
  try {
    // With world.json's robot count, every tick must hold a row of each robot: a tick short of one is damage.
    const bool counted = robots > 0 && robots <= kMaxRobots;
    csv = std::make_unique<RobotsCsv>(o.run_dir + "/robots.csv", counted ? robots : kMaxRobots,
                                      RowsFile::Robots, counted);
  } catch (const std::runtime_error& e) {
    std::cerr << "swarm_viewer: " << e.what() << "\n";
    return 2;
  }
  // readings.csv, when the behaviour declared sensors: a file that cannot be used is said and left out, the
  // replay goes on without readings.
  std::unique_ptr<RobotsCsv> readings;
  std::uint32_t sensors = 0;
  const std::string readings_path = o.run_dir + "/readings.csv";
  if (std::ifstream(readings_path).good()) {
    try {
      readings = std::make_unique<RobotsCsv>(
          readings_path, robots > 0 && robots <= kMaxRobots ? robots : kMaxRobots, RowsFile::Readings);
      if (const auto bits = sensors_of(readings->extra_columns())) {
        sensors = *bits;
      } else {
        std::cerr << "swarm_viewer: " << readings_path
                  << ":1: the columns are not a sensor's (docs/recording-format.md): readings left out\n";
        readings.reset();
      }
    } catch (const std::runtime_error& e) {
      std::cerr << "swarm_viewer: " << e.what() << ": readings left out\n";
    }
  }
  Session session(o, *world, std::move(summary), *csv, readings.get(), sensors);
  return o.export_lines ? session.export_lines(std::cout) : session.run();
}

}  // namespace swarmform::viewer
