// swarm_viewer: the browser view of a swarmform run (viewer/README.md). Live: a DDS participant
// that reads the world's sf_observe frames and sends its viewer's sf_control samples, and serves the page
// (and Foxglove) on one port. Replay (--replay, replay.cpp): the same page and Foxglove over a run
// directory's recording.
//
// Exit codes: 0 the run ended (or SIGINT/SIGTERM); 1 a failure (DDS, the port); 2 bad flags.
#include <CLI/CLI.hpp>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/dds/observe_wire.hpp"
#include "viewer/foxglove.hpp"
#include "viewer/frame_json.hpp"
#include "viewer/netns.hpp"
#include "viewer/page_flow.hpp"
#include "viewer/replay.hpp"
#include "viewer/web_server.hpp"

namespace {

using swarmform::viewer::ClientId;
using swarmform::viewer::ClientKind;
using swarmform::viewer::Foxglove;
namespace dds = swarmform::dds;
using nlohmann::json;

constexpr int kPeriodMs = 20;
constexpr std::size_t kMaxEventsKept = 20000;  // the newest, for pages that open later
// HELLO binds the viewer and is its heartbeat: the world takes a viewer silent for 2 s for gone
// (world_server/viewer_control.hpp kSilence).
constexpr dds_duration_t kHelloEvery = DDS_MSECS(250);

// The page's files: an installed viewer's share/swarmform/web beside its bin/ (cmake --install), else the
// source tree's viewer/web it was built from.
std::string default_web_root() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "swarmform" / "web";
    if (std::filesystem::is_regular_file(installed / "index.html", ec)) return installed.string();
  }
  return SWARMFORM_VIEWER_WEB_ROOT;
}

struct Options {
  std::uint16_t port = 8765;
  std::string host = "127.0.0.1";
  std::string web_root = default_web_root();
  std::string run_dir;
  std::string replay;
  std::uint32_t domain = 0;
  std::string world_host = "127.0.0.1";
  std::string interface_address;  // the local interface's address for DDS (default: as robot_agent's)
  std::string netns;              // live: the network namespace of the DDS side (swarm run --hosts)
  std::string run_nonce;
  std::string token;
  std::string security_dir;  // --secure runs: the run's security directory (observer identity)
  double rate = 10.0;
  double linger_s = 2.0;
  double page_grace_s = 10.0;
  std::vector<std::string> control_origins;
  bool quiet = false;
};

std::uint64_t hex64(const std::string& flag, const std::string& text) {
  if (text.empty() || text.size() > 16 ||
      text.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
    throw std::invalid_argument(flag + " " + text + ": want 1 to 16 hex digits");
  }
  return std::stoull(text, nullptr, 16);
}

// New complete lines of the run's events.jsonl since the last call (the world appends and flushes them).
class EventTail {
 public:
  explicit EventTail(std::string path) : path_(std::move(path)) {}
  void read(std::vector<json>& out) {
    std::ifstream f(path_, std::ios::binary);
    if (!f) return;
    f.seekg(static_cast<std::streamoff>(offset_));
    std::string line;
    while (std::getline(f, line)) {
      if (f.eof()) break;  // no newline yet: a line still being written
      offset_ += line.size() + 1;
      json j = json::parse(line, nullptr, false);
      if (!j.is_discarded()) out.push_back(std::move(j));
    }
  }

 private:
  std::string path_;
  std::uint64_t offset_ = 0;
};

json read_json(const std::string& path) {
  std::ifstream f(path);
  return f ? json::parse(f, nullptr, false) : json();
}

int live(const Options& o) {
  const std::uint64_t nonce = hex64("--run-nonce", o.run_nonce);
  const std::uint64_t token = hex64("--token", o.token);
  dds::DdsSettings settings;
  settings.domain = o.domain;
  settings.role = dds::Role::Agent;
  settings.world_host = o.world_host;
  if (!o.security_dir.empty())
    settings.security = dds::security_files(o.security_dir, dds::observer_identity());
  settings.interface_address = o.interface_address;
  // Made once the page's socket listens (below): under --netns the participant lives in another namespace.
  std::optional<dds::Participant> participant;
  std::optional<dds::ObserveReader> frames;
  std::optional<dds::ControlWriter> control;

  std::uint64_t seq = 0;
  bool got_frame = false;
  // A page's command before the world has bound this viewer would go to a reader not matched yet (sf_control
  // is volatile) and be lost: it waits here until the first frame shows the binding.
  std::vector<dds::ControlSample> pending;
  auto send = [&](dds::ControlKind kind, std::uint64_t count, double value) {
    dds::ControlSample c;
    c.run_nonce = nonce;
    c.token = token;
    c.kind = static_cast<std::uint8_t>(kind);
    c.count = count;
    c.value = value;
    if (!got_frame && kind != dds::ControlKind::Hello) {
      if (pending.size() < 1000) pending.push_back(c);
      return;
    }
    c.seq = ++seq;
    control->send(c);
  };

  swarmform::viewer::WebServer* server_ptr = nullptr;
  std::string last_frame;
  std::string last_end;  // the "end" message, for a page that opens after it
  std::deque<json> events;
  EventTail tail(o.run_dir + "/events.jsonl");
  double rate = o.rate;
  dds_time_t last_hello = 0;
  std::optional<dds_time_t> finished_at;
  std::uint64_t bad_page_messages = 0;
  dds::ObserveFrameData frame;
  std::vector<json> fresh;
  // The run's end as the page shows it: summary.json's end_reason (the world writes it as it ends), sent
  // once.
  bool said_end = false;
  dds_time_t last_summary_check = 0;
  auto say_end = [&]() {
    if (said_end || server_ptr == nullptr) return;
    const json s = read_json(o.run_dir + "/summary.json");
    if (!s.is_object() || !s.contains("end_reason") || !s["end_reason"].is_string()) return;
    said_end = true;
    json end = {{"type", "end"}, {"end_reason", s["end_reason"]}};
    end["tick"] = s.contains("ticks") && s["ticks"].is_number_unsigned() ? s["ticks"] : json(frame.tick);
    server_ptr->broadcast_text(ClientKind::Page, end.dump());
    last_end = end.dump();
  };
  // The last page closed while the run was paused: after --page-grace seconds with no page, the run resumes
  // (a run never waits for ever for a page nobody looks at).
  bool seen_page = false;
  std::optional<dds_time_t> alone_since;
  const auto grace = static_cast<dds_duration_t>(o.page_grace_s * 1e9);

  const json hello = {{"type", "hello"}, {"mode", "live"}};
  swarmform::viewer::Foxglove foxglove;
  auto read_world = [&] {
    if (foxglove.has_world()) return;
    const json w = read_json(o.run_dir + "/world.json");
    if (w.is_object()) foxglove.set_world(w);
  };
  // Each page's frames in flight: the newest frame when it drew the last (page_flow.hpp).
  swarmform::viewer::PageFlow pages;
  auto frame_to_pages = [&] {
    for (const auto& to : pages.offer(false)) server_ptr->send_text(to.client, last_frame);
  };
  swarmform::viewer::WebServer::Handlers h;
  h.closed = [&](ClientId c) {
    foxglove.forget(c);
    pages.closed(c);
  };
  h.opened = [&](ClientId c, ClientKind k) {
    if (k == ClientKind::Foxglove) {
      read_world();
      for (const std::string& m : foxglove.hello()) server_ptr->send_text(c, m);
      return;
    }
    server_ptr->send_text(c, hello.dump());
    if (!events.empty()) {
      json all = json::array();
      for (const json& e : events) all.push_back(e);
      server_ptr->send_text(c, json{{"type", "events"}, {"events", all}}.dump());
    }
    pages.opened(c, !last_frame.empty());
    if (!last_frame.empty()) server_ptr->send_text(c, last_frame);
    if (!last_end.empty()) server_ptr->send_text(c, last_end);
  };
  // A page's command, or a Foxglove client's on /control (the same commands, the same path): "" when sent,
  // else why not.
  auto command = [&](const std::string& text) -> std::string {
    const json m = json::parse(text, nullptr, false);
    const std::string cmd = m.is_object() ? m.value("cmd", std::string()) : std::string();
    const double value =
        m.is_object() && m.contains("value") && m["value"].is_number() ? m["value"].get<double>() : 0;
    const std::uint64_t n = value > 0 && value < 1e15 ? static_cast<std::uint64_t>(value) : 0;
    const bool timeline = cmd == "pause" || cmd == "resume" || cmd == "step" || cmd == "speed";
    if (timeline && got_frame && frame.finished) return "the run has ended";
    if (timeline && got_frame && !frame.controllable)
      return "a realtime run: its ticks follow the clock, " + cmd + " does nothing (kill still acts)";
    if (cmd == "pause") {
      send(dds::ControlKind::Pause, 0, 0);
    } else if (cmd == "resume") {
      send(dds::ControlKind::Resume, 0, 0);
    } else if (cmd == "step" && n > 0) {
      send(dds::ControlKind::Step, n, 0);
    } else if (cmd == "speed") {
      send(dds::ControlKind::Speed, 0, value);
    } else if (cmd == "kill" && m.contains("value") && m["value"].is_number_unsigned()) {
      send(dds::ControlKind::Kill, m["value"].get<std::uint64_t>(), 0);
    } else if (cmd == "rate" && value > 0) {
      rate = value;
      send(dds::ControlKind::Hello, 0, rate);
    } else {
      if (++bad_page_messages == 1 || bad_page_messages % 1000 == 0) {
        std::cerr << "swarm_viewer: ignored " << bad_page_messages
                  << " page message(s) it does not know, e.g. " << text.substr(0, 80) << "\n";
      }
      return "not a command: " + text.substr(0, 80) +
             " (want {\"cmd\": \"pause\" | \"resume\" | \"step\" | \"speed\" | \"kill\", \"value\": N})";
    }
    return "";
  };
  h.text = [&](ClientId client, ClientKind k, const std::string& text) {
    if (k == ClientKind::Foxglove) {
      const std::string answer = foxglove.on_text(client, text);
      if (!answer.empty()) server_ptr->send_text(client, answer);
      return;
    }
    // The page drew a frame: the next may go, the newest if one waited (a page's own flow, not a command).
    if (text.find("\"drawn\"") != std::string::npos) {
      const json m = json::parse(text, nullptr, false);
      if (m.is_object() && m.value("cmd", std::string()) == "drawn") {
        bool jump = false;
        if (pages.drawn(client, jump) && !last_frame.empty()) server_ptr->send_text(client, last_frame);
        return;
      }
    }
    command(text);
  };
  h.binary = [&](ClientId client, const std::string& bytes) {
    const auto got = foxglove.on_binary(client, bytes);
    std::string problem = got.status;
    if (problem.empty() && !server_ptr->may_drive(client)) {
      problem = Foxglove::status(2,
                                 "control refused: this connection's Origin is not this server's (read only; "
                                 "Foxglove's desktop app, which sends none, may control)");
    } else if (problem.empty()) {
      const std::string why = command(got.command);
      if (!why.empty()) problem = Foxglove::status(1, why);
    }
    if (!problem.empty()) server_ptr->send_text(client, problem);
  };
  h.every = [&]() -> bool {
    const dds_time_t now = dds_time();
    // Hello until bound (the world may have come up after us, or the first sample went before the reader
    // matched), and then as a heartbeat.
    if (now - last_hello >= kHelloEvery) {
      send(dds::ControlKind::Hello, 0, rate);
      last_hello = now;
    }
    fresh.clear();
    tail.read(fresh);
    if (!fresh.empty()) {
      for (const json& e : fresh) {
        events.push_back(e);
        if (events.size() > kMaxEventsKept) events.pop_front();
      }
      server_ptr->broadcast_text(ClientKind::Page, json{{"type", "events"}, {"events", fresh}}.dump());
    }
    if (frames->take(nonce, frame)) {
      if (!got_frame) {
        got_frame = true;
        for (dds::ControlSample& c : pending) {
          c.seq = ++seq;
          control->send(c);
        }
        pending.clear();
      }
      last_frame = swarmform::viewer::frame_json(frame).dump();
      frame_to_pages();
      read_world();
      // Log time: the wall time the frame arrived (the tick is in each message).
      const auto wall = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
      for (auto& [client, bytes] : foxglove.messages(frame, 0, static_cast<std::uint64_t>(wall)))
        server_ptr->send_binary(client, bytes);
      if (frame.finished && !finished_at) finished_at = now;
    }
    if (got_frame && !said_end && now - last_summary_check >= DDS_MSECS(200)) {
      last_summary_check = now;
      say_end();
    }
    if (server_ptr->clients(ClientKind::Page) > 0) {
      seen_page = true;
      alone_since.reset();
    } else if (seen_page && got_frame && frame.paused && frame.controllable && !frame.finished) {
      if (!alone_since) {
        alone_since = now;
        std::cerr << "swarm_viewer: the last page closed while the run is paused at tick " << frame.tick
                  << "; it resumes in " << o.page_grace_s << " s unless a page opens (--page-grace)"
                  << std::endl;
      } else if (now - *alone_since >= grace) {
        // count: the grace in ms, which the world prints (a Resume from the page has count 0).
        send(dds::ControlKind::Resume,
             std::max<std::uint64_t>(1, static_cast<std::uint64_t>(o.page_grace_s * 1e3)), 0);
        std::cerr << "swarm_viewer: no page for " << o.page_grace_s << " s while paused: the run resumes"
                  << std::endl;
        alone_since.reset();
        seen_page = false;
      }
    } else {
      alone_since.reset();
    }
    // The viewer ends with the run (after a moment, so pages get the last frame and events).
    return !finished_at || now - *finished_at < static_cast<dds_duration_t>(o.linger_s * 1e9);
  };
  h.stopping = [&] { say_end(); };  // stopped by the launcher as the world exits: the end, if written
  swarmform::viewer::WebServer server({o.host, o.port, o.web_root, o.run_dir, o.control_origins}, h,
                                      kPeriodMs);
  server_ptr = &server;
  if (!o.netns.empty()) swarmform::viewer::enter_network_namespace(o.netns);
  participant.emplace(settings);
  frames.emplace(*participant);
  control.emplace(*participant);
  std::cout << "viewer http://" << o.host << ":" << server.port() << "/" << std::endl;
  server.run();
  if (pages.skipped() > 0) {
    std::cerr << "swarm_viewer: " << pages.skipped()
              << " frame(s) not sent to a page still drawing an earlier one (it got the newest)" << std::endl;
  }
  if (finished_at) std::cout << "viewer: the run ended" << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "swarm_viewer: the browser view of a swarmform run (live over DDS, or --replay a run directory)"};
  app.add_option("--port", o.port, "TCP port of the page and the WebSocket (default 8765; 0: any free one)");
  app.add_option("--host", o.host, "address to listen on (default 127.0.0.1: this machine only)");
  app.add_option(
      "--web-root", o.web_root,
      "folder of the page's files (default: share/swarmform/web beside an installed viewer's bin/, else "
      "viewer/web of the source tree)");
  app.add_option("--run-dir", o.run_dir,
                 "live: the run directory (the page loads world.json, events from it)");
  app.add_option("--replay", o.replay, "RUN_DIR: serve the page over this recording (no DDS)");
  app.add_option("--control-origin", o.control_origins,
                 "ORIGIN (repeatable): a Foxglove client from this browser origin may control the run over "
                 "/control too, e.g. https://app.foxglove.dev (default: none; clients with no Origin or this "
                 "server's may)");
  std::string export_dir;
  app.add_option("--export-frames", export_dir,
                 "RUN_DIR: write every recorded tick's Foxglove messages on stdout, one a line (swarm export "
                 "--mcap reads them), and exit");
  app.add_option("--domain", o.domain, "live: the run's DDS domain id")->check(CLI::Range(0u, 232u));
  app.add_option("--world-host", o.world_host, "live: the world's address (default 127.0.0.1)");
  app.add_option("--interface", o.interface_address,
                 "live: local interface address for DDS (default: loopback when the world is on loopback)");
  app.add_option(
      "--netns", o.netns,
      "live: the network namespace (`ip netns list`) of the DDS side; the page still listens where "
      "the viewer starts (swarm run --hosts --view: the world's host; needs root)");
  app.add_option("--run-nonce", o.run_nonce,
                 "live: the run's nonce, 16 hex digits (the world's `world ready` line)");
  app.add_option(
      "--security-dir", o.security_dir,
      "live, DDS Security: the run's security directory (`swarm run --secure`); the viewer "
      "authenticates as the run's observer, whose permissions read sf_observe and write sf_control");
  app.add_option("--token", o.token, "live: the viewer token the world was given (--viewer-token)");
  app.add_option("--rate", o.rate, "live: frames a second asked of the world (default 10, 1..60)")
      ->check(CLI::Range(1.0, 60.0));
  app.add_option("--linger", o.linger_s,
                 "live: seconds to keep serving after the run's last frame (default 2)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--page-grace", o.page_grace_s,
                 "live: seconds a paused run waits once its last page closed, then it resumes (default 10)")
      ->check(CLI::Range(0.0, 86400.0));
  app.footer("Exit codes: 0 the run ended or a signal; 1 a failure (DDS, the port); 2 bad flags.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (!export_dir.empty())
      return swarmform::viewer::replay({export_dir, o.host, o.port, o.web_root, {}, true});
    if (!o.replay.empty())
      return swarmform::viewer::replay({o.replay, o.host, o.port, o.web_root, o.control_origins});
    if (o.run_dir.empty() || o.run_nonce.empty() || o.token.empty()) {
      std::cerr
          << "swarm_viewer: a live view needs --run-dir, --run-nonce and --token (or --replay RUN_DIR)\n";
      return 2;
    }
    return live(o);
  } catch (const std::invalid_argument& e) {
    std::cerr << "swarm_viewer: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "swarm_viewer: " << e.what() << "\n";
    return 1;
  }
}
