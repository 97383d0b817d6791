#include "world_server/server.hpp"

#include <signal.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "common/id_ranges.hpp"
#include "common/process_state.hpp"
#include "world_server/observe_frame.hpp"
#include "world_server/run/run_end.hpp"
#include "world_server/wire_check.hpp"
#include "world_server/world/robot_groups.hpp"

namespace swarmform::server {

namespace {

dds_time_t seconds(double s) {
  return static_cast<dds_duration_t>(s * 1e9);
}
double to_s(dds_duration_t d) {
  return static_cast<double>(d) * 1e-9;
}

std::uint64_t fresh_nonce() {
  std::random_device rd;
  return (static_cast<std::uint64_t>(rd()) << 32) ^ rd() ^ static_cast<std::uint64_t>(dds_time());
}

ServerOptions with_run_nonce(ServerOptions o) {
  while (o.run_nonce == 0) o.run_nonce = fresh_nonce();
  return o;
}

// The calling thread's CPU time (ns) and involuntary context switches so far (0 where unsupported).
struct ThreadClock {
  dds_duration_t cpu = 0;
  std::uint64_t preempted = 0;
};
ThreadClock thread_clock() {
  ThreadClock c;
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0) c.cpu = DDS_SECS(ts.tv_sec) + ts.tv_nsec;
  rusage ru{};
  if (getrusage(RUSAGE_THREAD, &ru) == 0) c.preempted = static_cast<std::uint64_t>(ru.ru_nivcsw);
  return c;
}

GuardLimits guard_limits(const world::Scenario& scenario) {
  return scenario.mode == world::Mode::Realtime ? realtime_limits(scenario.tick_rate) : GuardLimits{};
}

// Observers get the world state at most this often (it is for viewers; agents never read it).
constexpr dds_duration_t kStatePeriod = DDS_MSECS(50);
// connect_agents, once every claim is in but a packet writer has not matched its reader yet.
constexpr dds_duration_t kMatchPoll = DDS_MSECS(5);

// Each robot group's telemetry limits (a robot is held to its own behaviour's states and columns).
std::vector<world::TelemetryLimits> group_telemetry_limits(const world::Scenario& scenario) {
  std::vector<world::TelemetryLimits> limits;
  for (std::size_t k = 0; k < world::group_count(scenario); ++k)
    limits.push_back(world::telemetry_limits(scenario, k));
  return limits;
}

}  // namespace

Server::Server(const world::Scenario& scenario, ServerOptions options, dds::SignalWatch& signals)
    : scenario_(scenario),
      options_(with_run_nonce(std::move(options))),
      signals_(signals),
      world_(scenario),
      session_(world_, world::RunOptions{options_.run_dir, std::string(world::to_string(scenario.mode)), 0.0,
                                         options_.record_every}),
      registry_(scenario.robots.size(), options_.open_rejoin  ? ClaimPolicy::Open
                                        : options_.run_secret ? ClaimPolicy::IssuedOnly
                                                              : ClaimPolicy::FirstClaimsOpen),
      link_(options_.dds, scenario.robots.size(), scenario.mode == world::Mode::Realtime, options_.run_nonce,
            receive_budget(guard_limits(scenario))),
      refusals_("world_server", std::cerr),
      robots_(scenario.robots.size()),
      guard_(guard_limits(scenario)),
      telemetry_limits_(group_telemetry_limits(scenario)),
      late_(scenario.robots.size()),
      schedule_(scenario),
      status_(options_.status_fd),
      faults_(
          scenario, world_, session_, [this](RobotId id) { return agent_pid(id); }, &status_) {
  // Each robot's messages are gathered and its ultrasonics read in publish_packets, just before its packet is
  // written, instead of for every robot in the step: robot i computes while the world senses for robot
  // i + 1, and the step (which every agent waits for) is shorter. The readings are the same
  // (World::defer_perceptions).
  world_.defer_perceptions(true);
  known_ = world::known_columns_by_robot(scenario);
  if (options_.viewer_token != 0) {
    viewer_ = std::make_unique<ViewerControl>(link_.participant, options_.run_nonce, options_.viewer_token,
                                              scenario.mode == world::Mode::Lockstep, options_.start_paused,
                                              describe_run(scenario));
    link_.waiter.attach(viewer_->condition());
  }
  signals_.notify(&link_.waiter);
}

Server::~Server() {
  signals_.notify(nullptr);
}

bool Server::stopping() const {
  return signals_.stop_requested();
}

int Server::run() {
  try {
    return run_inner();
  } catch (const world::RecordingError& e) {
    return fail(e.reason(), e.what(), kExitRecordingFailed);
  } catch (const std::exception& e) {
    return fail(world::EndReason::WorldFailed, e.what(), kExitWorldFailed);
  }
}

int Server::fail(world::EndReason reason, const std::string& what, int code) {
  // The agents are told first: they must not wait out their timeout for a world that has given up.
  try {
    announce_end();
  } catch (const std::exception& e) {
    std::cerr << "world_server: could not announce the end to the agents: " << e.what() << "\n";
  }
  session_.set_end_reason(reason);
  note_summary_fields();
  std::string summary;
  bool summary_ok = false;
  try {
    session_.finish(start_ ? to_s(dds_time() - start_) : 0.0);
    summary = session_.summary_written();
    summary_ok = true;
  } catch (const std::exception& e) {
    summary = std::string("summary.json not written: ") + e.what();
  }
  std::cerr << "world_server: run ended (" << world::to_string(reason) << ") at tick " << world_.tick()
            << ": " << what << "; " << summary << "\n";
  status_.emit("run_ended",
               {{"end_reason", world::to_string(reason)},
                {"tick", world_.tick()},
                {"what", what},
                {"summary", summary_ok ? nlohmann::ordered_json(options_.run_dir + "/summary.json")
                                       : nlohmann::ordered_json(nullptr)},
                {"summary_note", summary},
                {"summary_cut", summary_ok && session_.summary_cut()},
                {"exit_code", code}});
  return code;
}

int Server::run_inner() {
  link_.mission.publish(mission_of(scenario_, options_.run_nonce));
  // The launcher starts the agents once it reads this line (docs/wire.md "Run nonce").
  char nonce[17];
  std::snprintf(nonce, sizeof nonce, "%016llx", static_cast<unsigned long long>(options_.run_nonce));
  status_.emit_and_print("ready", {{"domain", options_.dds.domain}, {"run_nonce", nonce}},
                         "world ready domain=" + std::to_string(options_.dds.domain) + " run_nonce=" + nonce);
  if (!connect_agents()) {
    announce_end();
    session_.set_end_reason(stopping() ? world::EndReason::Interrupted : world::EndReason::NoAgents);
    note_summary_fields();
    session_.finish(0.0);
    return stopping() ? kExitOk : kExitAgentsMissing;
  }
  start_ = last_progress_ = dds_time();
  if (options_.warmup_ticks == 0) steady_start_ = start_;
  registry_.start_run();
  run_rounds();
  const dds_time_t end = dds_time();
  const double wall = to_s(end - start_);
  schedule_.finish(session_);
  faults_.resume_all(&session_);  // a stalled agent must hear the end
  if (stalled_out_) return fail(world::EndReason::AgentsStalled, stalled_what_, kExitAgentsStalled);
  announce_end();
  progress(true);
  if (stopping()) session_.set_end_reason(world::EndReason::Interrupted);
  note_summary_fields();
  session_.finish(
      wall, world::SteadyWindow{options_.warmup_ticks, steady_start_ ? to_s(end - steady_start_) : 0.0});
  if (stopping())
    std::cerr << "world_server: stopped by signal " << signals_.signal() << ", summary written\n";
  if (profile_.rounds > 0) {
    const double r = static_cast<double>(profile_.rounds) * 1e3;  // ns -> us per round
    std::fprintf(
        stderr,
        "world_server: per round (us): publish %.1f (on CPU %.1f, preempted %.2f times), collect %.1f, step "
        "%.1f, record %.1f (%llu rounds)\n",
        static_cast<double>(profile_.publish) / r, static_cast<double>(profile_.publish_cpu) / r,
        static_cast<double>(profile_.publish_preempted) / static_cast<double>(profile_.rounds),
        static_cast<double>(profile_.collect) / r, static_cast<double>(profile_.step) / r,
        static_cast<double>(profile_.record) / r, static_cast<unsigned long long>(profile_.rounds));
    // The bare round's --readings/--message-bytes/--reply-bytes for the same bytes (scripts/bench-lockstep).
    const auto mean = [](std::uint64_t sum, std::uint64_t count) {
      return count == 0 ? 0.0 : static_cast<double>(sum) / static_cast<double>(count);
    };
    std::fprintf(stderr,
                 "world_server: wire per round: %.1f packets, %.2f messages a packet, %.1f bytes a message, "
                 "%.1f bytes a command's message\n",
                 mean(profile_.packets, profile_.rounds), mean(profile_.packet_messages, profile_.packets),
                 mean(profile_.packet_message_bytes, profile_.packet_messages),
                 mean(profile_.command_message_bytes, profile_.commands));
  }
  if (stalls_.own_stalls() > 0) {
    // The counts agree with what was recorded: a lost agent that came back and then turned out gone is a
    // death (in summary.json's deaths), not a comeback.
    std::fprintf(
        stderr,
        "world_server: the world itself stalled %llu time(s), %.1f s in all; %llu lost agent(s) came "
        "back within the grace and were not taken for dead; %llu were recorded dead (gone, or lost past "
        "the grace)\n",
        static_cast<unsigned long long>(stalls_.own_stalls()), stalls_.own_stalled_seconds(),
        static_cast<unsigned long long>(stalls_.suspicions_cleared()),
        static_cast<unsigned long long>(stalls_.suspects_died()));
  }
  if (stragglers_.total() > 0) {
    std::fprintf(stderr,
                 "world_server: lockstep waited for %zu agent(s) whose liveliness lapsed while their process "
                 "was there; %zu came back (not deaths)\n",
                 stragglers_.total(), stragglers_.came_back());
  }
  if (rounds_rewritten_ > 0) {
    std::fprintf(stderr,
                 "world_server: lockstep rounds waited long and wrote their packets again %llu time(s) (%llu "
                 "packets; events round_rewritten)\n",
                 static_cast<unsigned long long>(rounds_rewritten_),
                 static_cast<unsigned long long>(packets_rewritten_));
  }
  if (unjudged_lapses_ > 0) {
    std::fprintf(
        stderr,
        "world_server: agents' liveliness lapsed %llu time(s) before their first packet (not losses: "
        "an agent went away only if its writer did)\n",
        static_cast<unsigned long long>(unjudged_lapses_));
  }
  if (stale_samples_ > 0) {
    std::fprintf(
        stderr, "world_server: ignored %llu claim(s) and command(s) taken after their writer had gone away\n",
        static_cast<unsigned long long>(stale_samples_));
  }
  if (refusals_.total() > 0) {
    std::cerr << "world_server: refused " << refusals_.total()
              << " command sample(s) of another wire version or run in all\n";
  }
  if (missed_ticks_ > 0) {
    std::cerr << "world_server: " << missed_ticks_ << " missed ticks (see events)\n";
    std::cerr << "world_server: " << late_.summary() << "\n";  // its own line: scripts read the one above
  }
  status_.emit_and_print("done",
                         {{"ticks", world_.tick()},
                          {"run_dir", options_.run_dir},
                          {"summary", options_.run_dir + "/summary.json"}},
                         "done ticks=" + std::to_string(world_.tick()) + " run_dir=" + options_.run_dir);
  // Last: a run that used up max_ticks without its experiment's success says so (not after a stop by signal).
  const std::string why = stopping()
                              ? std::string()
                              : world::max_ticks_line(session_.verdict(), world_.tick(), scenario_.max_ticks);
  if (!why.empty()) std::cout << "world_server: " << why << std::endl;
  return kExitOk;
}

// ---- connecting -------------------------------------------------------------------------------------------

bool Server::connect_agents() {
  const std::size_t n = scenario_.robots.size();
  const dds_time_t begin = dds_time();
  // The wait ends when the start-up stops moving, not at a fixed time: --connect-timeout counts from the last
  // claim or matched reader. 1024 agents starting on a host busy with other work took longer than any fixed
  // deadline fit for a quiet one (501 of 1024 claimed when the 55.6 s ran out, every one of them on its way);
  // slowness is not a missing agent. Each step restarts the count, so the wait is still bounded.
  const dds_duration_t patience = seconds(options_.connect_timeout_s);
  dds_time_t deadline = begin + patience;
  std::size_t progress = 0;  // claims, then matched readers once every id is claimed
  dds_time_t next_report = dds_time() + DDS_SECS(5);
  for (;;) {
    pump(false);
    // Every claim is accepted, but an accepted agent's packet reader may not be matched by its packet writer
    // yet (the claim comes on another topic, and the discovery of the reader can lag behind it while 256
    // agents connect): its first packets would go to nobody, the start-up misses of BENCHMARKS.md (P2). So
    // the run starts once every writer has its reader too; matching raises no event the waiter sees, so
    // this last stretch is polled.
    const bool claimed = registry_.connected_count() == n;
    const std::size_t unmatched = claimed ? unmatched_robots().size() : n;
    if (const std::size_t p = registry_.connected_count() + (n - unmatched); p > progress) {
      progress = p;
      deadline = dds_time() + patience;
    }
    if (claimed && unmatched == 0) {
      std::printf("connected agents=%zu seconds=%.2f\n", n, to_s(dds_time() - begin));
      std::fflush(stdout);
      status_.emit("connected", {{"agents", n}, {"seconds", to_s(dds_time() - begin)}});
      return true;
    }
    if (stopping()) return false;
    const dds_time_t now = dds_time();
    if (now >= deadline) {
      status_.emit("gave_up", {{"robots", n},
                               {"claimed", registry_.connected_count()},
                               {"timeout_s", options_.connect_timeout_s},
                               {"missing", claimed ? unmatched_robots() : registry_.missing()},
                               {"why", claimed ? "not_matched" : "not_claimed"}});
      if (claimed) {
        std::cerr << "world_server: every agent claimed its id, but these robots' packet writers matched no "
                     "reader, and none did in the last "
                  << options_.connect_timeout_s << " s: " << id_ranges_text(unmatched_robots()) << "\n";
      } else {
        std::cerr << "world_server: " << n - registry_.connected_count() << " of " << n
                  << " agents missing, and none claimed its id in the last " << options_.connect_timeout_s
                  << " s (" << to_s(now - begin)
                  << " s since the world was ready): " << id_ranges_text(registry_.missing())
                  << (link_.participant.secure()
                          ? " (DDS Security: only agents started with this run's --security-dir can connect)"
                          : "")
                  << "\n";
      }
      return false;
    }
    if (now >= next_report) {
      status_.emit_and_print(
          "connecting", {{"claimed", registry_.connected_count()}, {"matched", n - unmatched}, {"robots", n}},
          "connecting " + std::to_string(registry_.connected_count()) + "/" + std::to_string(n));
      next_report = now + DDS_SECS(5);
    }
    dds_time_t wake = std::min(deadline, next_report);
    if (claimed) wake = std::min(wake, now + kMatchPoll);
    wait_a_while(wake);
  }
}

std::vector<RobotId> Server::unmatched_robots() const {
  std::vector<RobotId> out;
  for (std::size_t i = 0; i < scenario_.robots.size(); ++i) {
    const auto id = static_cast<RobotId>(i);
    if (!link_.robots.reader_matched(id)) out.push_back(id);
  }
  return out;
}

// ---- the DDS side, whenever the server wakes --------------------------------------------------------------

void Server::wait_a_while(dds_time_t deadline) {
  link_.waiter.wait_until(std::min(deadline, stalls_.probe(dds_time())));
}

void Server::pump(bool running) {
  stalls_.observe(dds_time());  // first: a gap since the last wake-up was the world's own stall
  liveliness_.clear();
  link_.commands.take_liveliness_changes(liveliness_);
  if (scenario_.mode == world::Mode::Lockstep) link_.commands.set_window(world_.tick());
  report_budget_drops();
  // Commands before losses: a dying agent's last command for this round still counts.
  const std::size_t n = link_.commands.take(samples_);
  for (std::size_t i = 0; i < n; ++i) {
    const dds::CommandSample& s = samples_[i];
    // A sample from a suspect is proof of life, whatever the liveliness events said: when the agents' writers
    // all came back together after the world's own stall, one's regained event sometimes never arrived (2
    // runs in 13; not traced: Cyclone 0.10 calls the listener once per change, so it is not a merged status).
    // Not from a writer that went away: its samples may be taken after its going (stall_guard.hpp).
    if (stalls_.suspected(s.writer) || stragglers_.contains(s.writer)) on_regained(s.writer, running);
    if (!first_answer_due_.empty()) first_answer_due_.erase(s.writer);
    // An ALIVE sample has done its work on arrival (its writer's liveliness, in Cyclone): nothing to keep.
    if (s.kind == dds::CommandKind::Alive) continue;
    if (!admit(s, running)) continue;
    if (s.kind == dds::CommandKind::Claim) {
      on_claim(s, running);
    } else if (running) {
      on_command(s);
    }
  }
  for (const auto& change : liveliness_) {
    if (change.alive) {
      on_regained(change.writer, running);
    } else if (!change.gone && !judged(change.writer)) {
      // Before its first packet a lapse is not a loss: nothing is at stake yet, an agent waiting for the run
      // is quiet (docs/wire.md), and while 1024 agents start on 2 cores their leases lapsed thousands of
      // times anyway, so a world that dropped each lapsed owner never had all of them at once and never
      // started (bench/scale). An agent that died meanwhile goes away with its participant's lease; one
      // restarted meanwhile takes the id over (AgentRegistry::lapse).
      if (registry_.lapse(change.writer)) ++unjudged_lapses_;
    } else {
      on_lost(change.writer, running, change.gone);
    }
  }
  expired_.clear();
  stalls_.expired(expired_);
  for (auto it = first_answer_due_.begin(); it != first_answer_due_.end();) {
    if (stalls_.awake() < it->second) {
      ++it;
      continue;
    }
    // Silent since before its first packet: dead, unless lockstep sees its process there (a straggler, as
    // any owner whose liveliness is lost: 1024 agents starting on 2 cores missed the 2 s and 12 were
    // recorded dead at tick 0 of a run where nobody died).
    if (!straggles(it->first, running)) expired_.push_back(it->first);
    it = first_answer_due_.erase(it);
  }
  for (const dds::PublicationHandle w : expired_) on_dead(w, running);
  if (const auto g = mass_.close(stalls_.awake())) report_mass_loss(*g);
  if (!stragglers_.empty() && stragglers_.recheck_due(dds_time())) check_stragglers();
  if (viewer_) viewer_->poll(dds_time());
}

bool Server::judged(dds::PublicationHandle writer) const {
  const auto id = registry_.owner_of(writer);
  return !id || robots_[*id].judged;  // not an owner: on_lost finds nothing to lose
}

bool Server::admit(const dds::CommandSample& s, bool running) {
  const dds_time_t now = dds_time();
  if (s.kind == dds::CommandKind::Claim) {
    if (guard_.admit_claim(s.writer, now)) return true;
    report(s, Abuse::ClaimOverLimit, "claims_dropped",
           "dropped a claim of id " + std::to_string(s.robot_id) +
               ": over the limit of claims a second from one writer",
           true);
    return false;
  }
  if (!running) return true;  // pump ignores commands before the run
  const bool lockstep = scenario_.mode == world::Mode::Lockstep;
  const std::uint64_t window =
      lockstep ? world_.tick() : static_cast<std::uint64_t>(now / InputGuard::kSecond);
  if (guard_.admit_command(s.writer, window, now)) return true;
  report(s, Abuse::CommandOverLimit, "commands_dropped",
         "dropped a command for id " + std::to_string(s.robot_id) + ": over the limit of commands a " +
             (lockstep ? "tick" : "second") + " from one writer",
         false);
  return false;
}

void Server::report_budget_drops() {
  budget_drops_.clear();
  link_.commands.take_budget_drops(budget_drops_);
  for (const dds::ReceiveBudget::Drops& d : budget_drops_) {
    stalls_.flooded();
    const auto n = guard_.report(d.writer, Abuse::CommandOverLimit, dds_time(), 0, d.count);
    if (!n) continue;
    char b[64];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(d.writer));
    session_.record_event(-1, "commands_dropped",
                          "dropped " + std::to_string(*n) + " sample(s) of writer " + b +
                              " over its budget of " +
                              std::to_string(receive_budget(guard_limits(scenario_))) + " a second" +
                              (scenario_.mode == world::Mode::Lockstep ? " or tick" : "") +
                              ", before decoding them (logged once a second a writer)");
  }
}

void Server::report(const dds::CommandSample& s, Abuse what, const std::string& kind,
                    const std::string& detail, bool to_stderr) {
  stalls_.flooded();
  const auto n = guard_.report(s.writer, what, dds_time());
  if (!n) return;
  std::string text = detail + " (pid " + std::to_string(s.pid) + ")";
  if (*n > 1) text += "; x" + std::to_string(*n) + " from this writer (logged once a second a writer)";
  session_.record_event(s.robot_id, kind, text);
  if (to_stderr) std::cerr << "world_server: " << text << "\n";
}

void Server::check_telemetry_of(RobotId id) {
  const world::TelemetryDrops d =
      world::check_telemetry(robots_[id].latest.telemetry, world_.robots()[id].telemetry,
                             telemetry_limits_[world::group_of(world_.scenario(), id)]);
  if (!d.any()) return;
  telemetry_fields_dropped_ += d.fields;
  telemetry_events_dropped_ += d.events;
  const auto n = guard_.report(robots_[id].latest_writer, Abuse::BadTelemetry, dds_time());
  if (!n) return;
  std::string text = "telemetry of robot " + std::to_string(id) + " out of range, dropped: " + d.first;
  if (*n > 1) text += "; x" + std::to_string(*n) + " commands (logged once a second a writer)";
  session_.record_event(id, "telemetry_dropped", text);
  std::cerr << "world_server: " << text << "\n";
}

void Server::note_summary_fields() {
  note_input_dropped();
  // A group still open at the end is closed now: its window cannot take more deaths.
  if (const auto g = mass_.close(std::numeric_limits<dds_time_t>::max())) report_mass_loss(*g);
  nlohmann::ordered_json losses = nlohmann::ordered_json::array();
  for (const MassLoss::Group& g : mass_.groups()) {
    losses.push_back({{"tick", g.tick},
                      {"robots", g.robots},
                      {"within_ms", static_cast<double>(g.last - g.first) / 1e6},
                      {"processes_present", g.processes_present}});
  }
  session_.set_summary_field("mass_losses", std::move(losses));
}

void Server::report_mass_loss(const MassLoss::Group& g) {
  std::string ids;
  for (const RobotId id : g.robots) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
  char within[32];
  std::snprintf(within, sizeof within, "%.0f", static_cast<double>(g.last - g.first) / 1e6);
  const std::string n = std::to_string(g.robots.size());
  const std::string detail = n + " robots (" + ids + ") lost their liveliness within " + within +
                             " ms of each other from tick " + std::to_string(g.tick) + ", " +
                             std::to_string(g.processes_present) + " of their processes still there: " +
                             "one event of the host (load, a stopped group of processes, a suspended "
                             "machine, a cut link) rather than " +
                             n + " independent deaths";
  session_.record_event(-1, "mass_loss", detail);
  std::cout << "mass_loss robots=" << n << " tick=" << g.tick << " processes_present=" << g.processes_present
            << std::endl;
}

void Server::note_input_dropped() {
  nlohmann::ordered_json j;
  bool any = false;
  for (std::size_t k = 0; k < static_cast<std::size_t>(Abuse::Count); ++k) {
    const auto what = static_cast<Abuse>(k);
    j[std::string(to_string(what))] = guard_.total(what);
    any = any || guard_.total(what) > 0;
  }
  j["out_of_range_ids"] = link_.commands.filtered();  // dropped by the reader's id filter (wire.hpp)
  j["telemetry_fields"] = telemetry_fields_dropped_;
  j["telemetry_events"] = telemetry_events_dropped_;
  session_.set_summary_field("input_dropped", j);
  if (any) std::cerr << "world_server: input dropped and counted: " << j.dump() << "\n";
}

void Server::on_claim(const dds::CommandSample& s, bool running) {
  if (const std::string why = wire_refusal(s, options_.run_nonce); !why.empty()) {
    // Answered (the claimant learns why and exits 4) only if it speaks this version; said once a second.
    if (s.wire_version == dds::kWireVersion) {
      link_.robots.reply_claim(dds::ClaimAnswer{s.robot_id, s.nonce, false, why});
    }
    refusals_.refuse(s.writer, writer_text(s), "claim", why, dds_time());
    return;
  }
  if (const std::uint32_t face = link_.robots.face(s.robot_id); s.face != face) {
    // Robot K's packets go out on face face(K) only (docs/wire.md "Faces"): an agent that claims K on another
    // face would never hear its packets. (It does not hear this answer either: the world says it here.)
    const std::string why = "robot " + std::to_string(s.robot_id) +
                            "'s agent must peer with the world's face " + std::to_string(face) +
                            " (UDP port " +
                            std::to_string(dds::face_discovery_port(options_.dds.domain, face)) +
                            "), not face " + std::to_string(s.face);
    link_.robots.reply_claim(dds::ClaimAnswer{s.robot_id, s.nonce, false, why});
    report(s, Abuse::RefusedClaim, "claim_refused",
           "refused a claim of id " + std::to_string(s.robot_id) + ": " + why, true);
    return;
  }
  if (link_.participant.secure()) {
    // Under --secure an id goes only to the participant authenticated as that robot: its claim must come
    // from a writer in partition robot/K, which DDS Security lets only robot K's certificate write.
    const auto who = link_.commands.authenticated_robot(s.face, s.writer);
    if (who != s.robot_id) {
      const std::string why = who ? "the claimant is authenticated as robot " + std::to_string(*who) +
                                        ", not robot " + std::to_string(s.robot_id)
                                  : "the claimant's writer is not in partition " +
                                        dds::robot_partition(s.robot_id) + " (under --secure only robot " +
                                        std::to_string(s.robot_id) + "'s certificate may claim it)";
      link_.robots.reply_claim(dds::ClaimAnswer{s.robot_id, s.nonce, false, why});
      report(s, Abuse::RefusedClaim, "claim_refused",
             "refused a claim of id " + std::to_string(s.robot_id) + ": " + why, true);
      return;
    }
  }
  if (!link_.commands.matched(s.face, s.writer)) {
    // Written before its agent went away, taken after (stall_guard.hpp): binding the id to a writer that
    // is gone would keep its robot alive, without an agent, to the end of the run.
    ++stale_samples_;
    return;
  }
  // Who the claimant is, as DDS discovery knows it (not what its sample says), and whether the run's starter
  // issued its claim: under --secure its certificate says so (checked above), otherwise its proof.
  const std::optional<dds::RemoteWriter> remote = link_.commands.remote(s.face, s.writer);
  ClaimCredentials credentials;
  if (remote) credentials.guid = remote->guid;
  credentials.issued =
      link_.participant.secure() || (options_.run_secret && remote &&
                                     dds::proof_valid(*options_.run_secret, options_.run_nonce, s.robot_id,
                                                      s.nonce, remote->guid, s.command.message));
  const ClaimResult r = registry_.claim(s.robot_id, s.writer, s.pid, s.nonce, credentials);
  const bool accepted = r.outcome == ClaimOutcome::Accepted || r.outcome == ClaimOutcome::Repeated ||
                        r.outcome == ClaimOutcome::Rebound || r.outcome == ClaimOutcome::TakenOver;
  link_.robots.reply_claim(dds::ClaimAnswer{s.robot_id, s.nonce, accepted, r.reason});
  if (r.outcome == ClaimOutcome::Unproven) {
    report(s, Abuse::UnprovenClaim, "claim_unproven",
           "refused a claim of id " + std::to_string(s.robot_id) + " from " + claimant_text(s, remote) +
               ": " + r.reason,
           true);
    return;
  }
  if (!accepted) {
    report(s, Abuse::RefusedClaim, "claim_refused",
           "refused a claim of id " + std::to_string(s.robot_id) + ": " + r.reason, true);
    return;
  }
  if (r.outcome == ClaimOutcome::Repeated) return;
  if (r.outcome == ClaimOutcome::Rebound) {
    session_.record_event(
        s.robot_id, "agent_rebound",
        "pid " + std::to_string(s.pid) + ": its re-sent claim came through a new writer handle");
    return;
  }
  const std::string who = claimant_text(s, remote) + (credentials.issued ? "" : ", unissued");
  session_.record_event(s.robot_id, "agent_connected", who);
  std::cerr << "world_server: id " << s.robot_id << " claimed by " << who << "\n";
  status_.emit("claimed", {{"id", s.robot_id}, {"pid", s.pid}});
  // The new owner's claim nonce goes on its perceptions: a previous owner that comes back learns from it
  // that it lost the id (docs/wire.md "Identity and the claim protocol").
  RobotSlot& slot = robots_[s.robot_id];
  slot.owner_nonce = s.nonce;
  slot.judged = false;  // a new owner: quiet until its first packet
  link_.robots.set_owner(s.robot_id, s.nonce, slot.generation);
  if (r.outcome == ClaimOutcome::TakenOver && running && !world_.alive(s.robot_id)) revive(s.robot_id);
  if (running && slot.waiting && scenario_.mode == world::Mode::Lockstep) {
    // The round awaits this robot, and its packet went out with the previous owner's nonce, which the new
    // owner skips as stale: it gets the round's packet again, as its own, or the round would wait for an
    // answer nobody is going to give (a take-over before the run's first round).
    link_.robots.write_packet(s.robot_id, dds::PacketStatus::Run, world_.perception(s.robot_id));
  }
}

void Server::revive(RobotId id) {
  RobotSlot& r = robots_[id];
  world_.revive(id);
  ++r.generation;
  link_.robots.set_owner(id, r.owner_nonce, r.generation);
  session_.record_rejoin(id);
  r.fresh = false;
  std::cout << "rejoin id=" << id << " tick=" << world_.tick() << std::endl;
}

void Server::on_command(const dds::CommandSample& s) {
  if (const std::string why = wire_refusal(s, options_.run_nonce); !why.empty()) {
    refusals_.refuse(s.writer, writer_text(s), "command", why, dds_time());
    return;
  }
  if (!registry_.owns(s.robot_id, s.writer)) {
    if (!link_.commands.matched(s.face, s.writer)) {
      ++stale_samples_;  // a dead owner's last words, taken after its going: not a spoof
      return;
    }
    report(s, Abuse::SpoofedCommand, "spoofed_command",
           "dropped a command for id " + std::to_string(s.robot_id) + " from a writer that does not own it",
           false);
    return;
  }
  const RobotId id = s.robot_id;
  RobotSlot& r = robots_[id];
  const Tick now = world_.tick();
  if (scenario_.mode == world::Mode::Realtime && s.tick < now) {
    if (const auto late = late_.arrived(id, s.tick, s.sent_at, dds_time())) {
      char detail[256];
      std::snprintf(
          detail, sizeof detail,
          "tick %llu: packet written %.1f ms into the round, answered %.1f ms after it, transit %.1f "
          "ms; received %.1f ms after the deadline",
          static_cast<unsigned long long>(s.tick), late->written_ms, late->answered_ms, late->transit_ms,
          late->late_ms);
      session_.record_event(id, "late_command", detail);
    }
  }
  // Lockstep takes only this round's command; realtime takes the newest, however old (a slow agent acts on
  // stale data, as a real robot would).
  const bool usable = scenario_.mode == world::Mode::Lockstep ? s.tick == now : s.tick <= now;
  if (!usable || (r.fresh && s.tick < r.latest_tick)) return;
  r.latest = s.command;  // copy-assign: reuses the message buffer's capacity
  r.latest_writer = s.writer;
  r.latest_tick = s.tick;
  r.fresh = true;
  if (s.tick == now && r.waiting) {
    r.waiting = false;
    --waiting_count_;
    ++profile_.commands;
    profile_.command_message_bytes += s.command.message.size();
  }
}

void Server::on_lost(dds::PublicationHandle writer, bool running, bool gone) {
  if (gone) {
    stragglers_.remove(writer);  // its writer went away with its participant: judged as below
  } else if (straggles(writer, running)) {
    return;
  }
  // Right after the world's own stall a loss is only suspected (stall_guard.hpp): the agent keeps its robot
  // and its packets until the grace is over or its liveliness is back (never, if its writer went away).
  if (running && registry_.owner_of(writer) && stalls_.suspect(writer, gone)) return;
  on_dead(writer, running);
}

bool Server::straggles(dds::PublicationHandle writer, bool running) {
  if (!running || scenario_.mode != world::Mode::Lockstep) return false;
  if (stragglers_.contains(writer)) return true;
  const auto id = registry_.owner_of(writer);
  if (!id || !world_.alive(*id)) return false;
  // Only a process seen gone is a death at once; without a pid the world cannot look, and a loss is judged as
  // before (stall_guard.hpp).
  const auto pid = agent_pid(*id);
  if (!pid || faults_.stopped(*pid) || process_state(*pid) != ProcessState::Present) return false;
  stragglers_.add(writer, *id);
  session_.record_event(*id, "agent_stalled",
                        "liveliness lost at tick " + std::to_string(world_.tick()) +
                            " while its process (pid " + std::to_string(*pid) +
                            ") is still there: slow, not dead; the world waits for it");
  session_.flush();  // the world records nothing else while it waits: the reason is in events.jsonl now
  return true;
}

void Server::check_stragglers() {
  std::vector<dds::PublicationHandle> gone;
  stragglers_.for_each([&](dds::PublicationHandle writer, RobotId id) {
    const auto pid = agent_pid(id);
    if (!pid || process_state(*pid) == ProcessState::Gone) gone.push_back(writer);
  });
  for (const dds::PublicationHandle w : gone) {
    stragglers_.remove(w);
    // An agent that exits while it is waited for (killed, or gave up on a world it could not hear: a host
    // cut off past the agent's --world-timeout) is dead now.
    on_dead(w, true, "its process exited while the world waited for it");
  }
}

void Server::on_dead(dds::PublicationHandle writer, bool running, const char* why) {
  // A suspect whose grace ran out went when it was suspected (MassLoss groups it by that).
  const dds_time_t lost_at = stalls_.take_lost_at(writer).value_or(stalls_.awake());
  static_assert(StallGuard::kGrace <= MassLoss::kLate);
  stragglers_.remove(writer);
  guard_.forget(writer);
  const auto id = registry_.lose(writer);
  if (!id) return;  // not an owner (a refused claimant, a spoofer, a test program)
  if (!running) {
    session_.record_event(*id, "agent_lost", "before the run started");
    return;
  }
  if (robots_[*id].waiting) {
    robots_[*id].waiting = false;
    --waiting_count_;
  }
  if (!world_.alive(*id)) return;
  world_.kill(*id);
  session_.record_death(*id);
  stalls_.died(writer);
  std::string detail =
      std::string(why ? why : "liveliness lost") + " at tick " + std::to_string(world_.tick());
  if (const auto ms = faults_.take_kill_delay_ms(*id)) {
    detail += "; detected " + std::to_string(*ms) + " ms after SIGKILL";
  }
  session_.record_event(*id, "death_detected", detail);
  std::cout << "death id=" << *id << " tick=" << world_.tick() << std::endl;
  if (!why) {  // its liveliness lapsed (not an exit the world saw): it may be one of many lost together
    const auto pid = agent_pid(*id);
    const bool present = pid && process_state(*pid) == ProcessState::Present;
    if (const auto g = mass_.died(*id, world_.tick(), lost_at, present)) report_mass_loss(*g);
  }
}

void Server::on_regained(dds::PublicationHandle writer, bool running) {
  first_answer_due_.erase(writer);
  if (const auto id = stragglers_.remove(writer)) {
    stragglers_.note_came_back();
    (void)registry_.regain(writer);  // one that lapsed before its first packet is no longer lapsed
    session_.record_event(*id, "liveliness_regained",
                          "the owner's writer is alive again after a stall of its own: not a death");
    return;
  }
  // An owner declared dead whose writer turns out alive was stalled (starved of CPU past the lease), not
  // dead: its robot comes back as on a rejoin, rather than leaving a live agent without packets until the
  // end.
  if (stalls_.clear(writer)) {
    if (const auto id = registry_.owner_of(writer)) {
      session_.record_event(*id, "liveliness_regained",
                            "the owner's writer is alive again after the world's own stall: not a death");
    }
    return;
  }
  const auto id = registry_.regain(writer);
  if (!id) return;  // a new writer, or one whose id was taken over meanwhile
  session_.record_event(*id, "liveliness_regained", "the owner's writer is alive again");
  if (running && !world_.alive(*id)) revive(*id);
}

std::optional<pid_t> Server::agent_pid(RobotId id) {
  if (const auto it = options_.agent_pids.find(id); it != options_.agent_pids.end()) return it->second;
  if (options_.agent_pids_file.empty()) return std::nullopt;
  // The launcher writes the file after it started the agents (after the world); read it when needed.
  std::ifstream f(options_.agent_pids_file);
  const nlohmann::json j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) {
    std::cerr << "world_server: --agent-pids " << options_.agent_pids_file
              << ": not a JSON object of id -> pid (yet)\n";
    return std::nullopt;
  }
  for (const auto& [key, value] : j.items()) {
    const std::string& k = key;
    if (k.empty() || k.size() > 9 || k.find_first_not_of("0123456789") != std::string::npos) continue;
    if (!value.is_number_unsigned() || value.get<std::uint64_t>() == 0 ||
        value.get<std::uint64_t>() > 4194304)
      continue;
    options_.agent_pids[static_cast<RobotId>(std::stoul(k))] = static_cast<pid_t>(value.get<std::uint64_t>());
  }
  if (const auto it = options_.agent_pids.find(id); it != options_.agent_pids.end()) return it->second;
  return std::nullopt;
}

// ---- the round --------------------------------------------------------------------------------------------

// The run's rounds until it is complete or a stop is asked: each line is one stage, in the order they run.
// Two overlaps are stages of their own (README.md "A round"): each robot's perception is made in
// publish_packets just before its packet goes out, and the previous tick's record runs after this round's
// packets are out, while the agents compute.
void Server::run_rounds() {
  const bool lockstep = scenario_.mode == world::Mode::Lockstep;
  if (!lockstep) round_due_ = dds_time() + seconds(1.0 / scenario_.tick_rate);  // the first period's end
  for (;;) {
    if (lockstep && viewer_ && !hold_for_viewer()) return;
    begin_publish();  // the profile's publish time: from here to end_publish
    kills_and_faults();
    publish_packets();
    offer_viewer_frame();
    end_publish();
    record_deferred_tick();
    if (!collect()) return;  // a stop was asked: the round in flight is not stepped
    apply_commands();
    step_world();
    if (record_or_defer()) return;  // the run is complete
    if (lockstep && viewer_) viewer_->ticked();
  }
}

bool Server::hold_for_viewer() {
  const dds_time_t earliest = viewer_->next_round_at(round_start_);
  for (;;) {
    const dds_time_t now = dds_time();
    if (!viewer_->holding(now) && now >= earliest) return true;
    // A kill asked while paused is done now, as the round would do it first thing (kills_and_faults): its
    // death is seen and recorded at this tick, the tick the round about to run would record it at, and the
    // page shows it without a step.
    if (viewer_->holding(now)) {
      for (const RobotId id : viewer_->take_kills()) {
        if (id < robots_.size()) faults_.kill(id);
      }
    }
    // The page sees the pause at once, and keeps seeing frames (a pause changes nothing it draws).
    offer_frame(now, false);
    wait_a_while(viewer_->holding(now) ? now + DDS_MSECS(100) : earliest);
    pump(true);
    if (stopping()) return false;
  }
}

void Server::begin_publish() {
  const ThreadClock c = thread_clock();
  profile_.cpu_at_start = c.cpu;
  profile_.preempted_at_start = c.preempted;
  profile_.stage_start = round_start_ = dds_time();
}

void Server::kills_and_faults() {
  const Tick t = world_.tick();
  if (viewer_) {
    for (const RobotId id : viewer_->take_kills()) {
      if (id < robots_.size()) schedule_.add_kill(t, id);  // the path of --kill, this tick
    }
  }
  schedule_.at_round(t, session_, faults_);
}

void Server::publish_packets() {
  const bool realtime = scenario_.mode == world::Mode::Realtime;
  waiting_count_ = 0;
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const auto id = static_cast<RobotId>(i);
    RobotSlot& r = robots_[i];
    const bool live = world_.alive(id) && registry_.connected(id) && !schedule_.held(id);
    r.waiting = live;
    waiting_count_ += r.waiting ? 1 : 0;
    if (!live) continue;
    if (!r.judged) {
      r.judged = true;
      if (const auto w = registry_.lapsed_writer(id))
        first_answer_due_[*w] = stalls_.awake() + kFirstAnswerGrace;
    }
    const Perception& packet = world_.perception(id);
    ++profile_.packets;
    profile_.packet_messages += packet.messages.size();
    for (const RabReading& m : packet.messages) profile_.packet_message_bytes += m.data.size();
    link_.robots.write_packet(id, dds::PacketStatus::Run, packet);
    if (realtime) r.written_at = dds_time();  // for late_commands; lockstep has no deadline to miss
  }
}

void Server::offer_viewer_frame() {
  // While the agents compute this round: the frame is off the round's critical path in lockstep. Its slot
  // (frame_schedule.hpp) is judged at the round's start, the tick's time (on the clock in realtime), not now:
  // the round's packets went out in between, 20-120 ms for 256 robots on a busy host, and that wobble made
  // frames look early or late to the schedule.
  if (viewer_) offer_frame(round_start_, false);
}

void Server::end_publish() {
  profile_.publish += dds_time() - profile_.stage_start;
  const ThreadClock c = thread_clock();
  profile_.publish_cpu += c.cpu - profile_.cpu_at_start;
  profile_.publish_preempted += c.preempted - profile_.preempted_at_start;
}

void Server::record_deferred_tick() {
  if (!record_pending_) return;
  record_pending_ = false;
  record_tick();
  publish_observers();
}

bool Server::collect() {
  return scenario_.mode == world::Mode::Lockstep ? collect_lockstep() : collect_realtime();
}

bool Server::collect_lockstep() {
  const dds_time_t collect_start = dds_time();
  // In the world's awake time (stall_guard.hpp): the world's own pause makes no agent late.
  stalls_.observe(collect_start);
  // In lockstep a live agent is never stepped without (world_server/README.md "In lockstep slowness is never
  // death"): the round waits for every awaited command however long the host makes it take, and only a wait
  // longer than lockstep_deadline ends the run (agents_stalled). Stepping on without a late agent made the
  // trajectory a function of the host's load (a host cut off for 4 s: its 3 robots stepped without when the
  // old 2 s deadline ran out before their lease did).
  const dds_duration_t allowed = seconds(scenario_.lockstep_deadline_s);
  dds_time_t waited_since = stalls_.awake();
  dds_time_t next_report = waited_since + kWaitReport;
  const dds_duration_t rewrite = std::min(kRoundRewrite, allowed / 2);
  dds_time_t next_rewrite = round_start_ + rewrite;  // wall time: the agents wait in theirs
  std::size_t came_back = stragglers_.came_back();
  for (;;) {
    pump(true);
    if (waiting_count_ == 0 || stopping()) break;
    const dds_time_t now = dds_time();
    if (now >= next_rewrite) {
      rewrite_round();
      next_rewrite = now + rewrite;
      continue;  // pump again: an answer to it may be in already
    }
    const dds_time_t awake = stalls_.awake();
    if (stragglers_.came_back() != came_back) {
      // A straggler heard again has the whole wait from now on: the packet it missed comes again first.
      came_back = stragglers_.came_back();
      waited_since = awake;
    }
    if (awake - waited_since >= allowed) {
      stalled_out_ = true;
      break;
    }
    if (awake >= next_report) {
      std::cerr << "world_server: tick " << world_.tick() << ": waiting for " << awaited_text() << " ("
                << to_s(awake - waited_since) << " s of lockstep_deadline " << scenario_.lockstep_deadline_s
                << " s)\n";
      next_report = awake + kWaitReport;
    }
    // Sleep until as many samples are in as commands are awaited (each awaited agent sends one), not at each
    // arrival: a round at N = 64 took the commands 8.9 times (dds::Waiter, "Counted arrivals").
    link_.waiter.need(waiting_count_);
    wait_a_while(std::min(now + std::min(waited_since + allowed, next_report) - awake, next_rewrite));
  }
  link_.waiter.need(1);  // elsewhere every sample wakes the world
  profile_.collect += dds_time() - collect_start;
  if (stalled_out_) {
    std::ostringstream what;
    what << awaited_text() << " gave no command for tick " << world_.tick() << " in "
         << scenario_.lockstep_deadline_s << " s (lockstep_deadline) of the world's awake time; "
         << stragglers_.size() << " of them with their liveliness lost while their process was there";
    stalled_what_ = what.str();
    for (std::size_t i = 0; i < robots_.size(); ++i) {
      if (robots_[i].waiting)
        session_.record_event(static_cast<RobotId>(i), "command_waited_out",
                              "no command for tick " + std::to_string(world_.tick()) +
                                  " within lockstep_deadline; the run ends (agents_stalled)");
    }
    return false;
  }
  return !stopping();
}

void Server::rewrite_round() {
  // A round that waits long may wait for a packet that never arrived: a reliable sample written while its
  // reader was not matched (a participant dropped after its lease on a starved host, and matched again) is
  // never delivered, and the round waited for an answer to it until the agent gave up; or for an answer
  // that was lost. The awaited robots' packets again serve both: an agent answers a tick it answered already
  // with the same command (robot_agent/answer_memory.hpp), so the run is as if nothing happened. Only the
  // awaited: at 1024 agents on a starved host every robot's packet again cost as many answers each period.
  ++rounds_rewritten_;
  std::size_t written = 0;
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (!robots_[i].waiting) continue;  // awaited: live and connected (publish_packets, on_dead)
    const auto id = static_cast<RobotId>(i);
    link_.robots.write_packet(id, dds::PacketStatus::Run, world_.perception(id));
    ++written;
  }
  packets_rewritten_ += written;
  session_.record_event(-1, "round_rewritten",
                        "tick " + std::to_string(world_.tick()) + ": waiting for " + awaited_text() + "; " +
                            std::to_string(written) + " packet(s) written again");
}

std::string Server::awaited_text() const {
  std::string ids;
  std::size_t n = 0;
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (!robots_[i].waiting) continue;
    if (++n <= 16) ids += (ids.empty() ? "" : ", ") + std::to_string(i);
  }
  if (n > 16) ids += ", ... (" + std::to_string(n) + " in all)";
  return (n == 1 ? "robot " : "robots ") + ids;
}

bool Server::collect_realtime() {
  const dds_duration_t period = seconds(1.0 / scenario_.tick_rate);
  dds_time_t now = 0;
  for (;;) {
    pump(true);
    if (stopping()) return false;
    now = dds_time();
    if (now >= round_due_) break;
    wait_a_while(round_due_);
  }
  // A missed tick: a live agent's command for tick t not in before tick t+1.
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (!robots_[i].waiting) continue;
    ++missed_ticks_;
    late_.missed(static_cast<RobotId>(i), world_.tick(), round_start_, robots_[i].written_at, round_due_);
    session_.record_event(static_cast<RobotId>(i), "missed_tick",
                          "no command for tick " + std::to_string(world_.tick()) + " before the next tick");
  }
  round_due_ += period;
  if (round_due_ < now) round_due_ = now + period;  // fell behind by more than a period: no catching up
  return true;
}

void Server::apply_commands() {
  profile_.stage_start = dds_time();
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    RobotSlot& r = robots_[i];
    if (!r.fresh) continue;
    r.fresh = false;
    const auto id = static_cast<RobotId>(i);
    if (!world_.alive(id)) continue;
    check_telemetry_of(id);
    const world::CommandVerdict v = world_.apply_command(id, r.latest);
    if (v != world::CommandVerdict::Ok) {
      // Counted every time; written as an event once a second per robot and verdict (an owner sending NaN
      // every tick wrote a line a tick: ~800 a second in lockstep).
      const auto logged =
          guard_.report(r.latest_writer, Abuse::BadCommand, dds_time(), static_cast<std::size_t>(v));
      session_.record_command_verdict(id, v, logged.value_or(0));
    }
  }
}

void Server::step_world() {
  world_.step();
  const dds_time_t now = dds_time();
  if (world_.tick() == options_.warmup_ticks) steady_start_ = now;
  profile_.step += now - profile_.stage_start;  // apply + step
  ++profile_.rounds;
}

bool Server::record_or_defer() {
  // Decided before the new tick is recorded: the record can set the experiment's done, which ends the run
  // only kTicksAfterDone ticks later, so the answer is the same as after it.
  static_assert(world::kTicksAfterDone > 0);
  const bool complete = world::run_complete(session_, world_.tick(), scenario_.max_ticks);
  // Every agent waits for the step and the packets after it: the new tick's record (events, metrics, the
  // recording's rows) waits until the next round's packets are out when that round's start does not depend
  // on it, and runs while the agents compute. The last tick is recorded at once.
  record_pending_ = !complete && record_can_follow_packets();
  if (!record_pending_) {
    record_tick();
    publish_observers();
  }
  return complete;
}

void Server::record_tick() {
  profile_.stage_start = dds_time();
  session_.record_tick();
}

void Server::publish_observers() {
  const dds_time_t now = dds_time();
  if (now - last_state_ >= kStatePeriod) {
    pose_rows(world_, known_, rows_);
    std::uint32_t alive = 0;
    for (const auto& r : rows_) alive += r.alive ? 1 : 0;
    link_.state.publish(world_.tick(), false, alive, rows_);
    last_state_ = now;
  }
  progress(false);
  profile_.record += dds_time() - profile_.stage_start;  // record_tick + observers
}

bool Server::record_can_follow_packets() const {
  return !viewer_ && schedule_.quiet_at(world_.tick());
}

void Server::offer_frame(dds_time_t now, bool finished) {
  viewer_->offer_frame(
      world_, [this](RobotId id) -> const Command& { return robots_[id].latest; }, session_.formation(), now,
      finished);
}

bool Server::may_hear_the_end(RobotId id) {
  if (registry_.connected(id)) return true;
  // Its owner was taken for dead (or never answered) and nobody took the id over: its agent may still be
  // there, stopped or starved past its lease, and resume after the run. Its END waits for it in its own
  // socket (the packet instance still names its claim nonce), so it exits on its own, saying why. Not to a
  // process seen gone: its reader, still matched until its participant's lease ends, would hold the
  // acknowledgement wait below for nothing.
  if (robots_[id].owner_nonce == 0) return false;
  const auto pid = agent_pid(id);
  return !pid || process_state(*pid) == ProcessState::Present;
}

void Server::announce_end() {
  // Every agent that holds an id hears the end, and so does every agent that held one and may still be
  // there (may_hear_the_end); refused ones left already.
  Perception end;
  end.tick = world_.tick();
  for (std::size_t i = 0; i < scenario_.robots.size(); ++i) {
    const auto id = static_cast<RobotId>(i);
    if (may_hear_the_end(id)) link_.robots.write_packet(id, dds::PacketStatus::End, end);
  }
  pose_rows(world_, known_, rows_);
  std::uint32_t alive = 0;
  for (const auto& r : rows_) alive += r.alive ? 1 : 0;
  link_.state.publish(world_.tick(), true, alive, rows_);
  if (viewer_) offer_frame(dds_time(), true);
  link_.robots.wait_for_acks(DDS_SECS(2));
}

void Server::progress(bool force) {
  const dds_time_t now = dds_time();
  if (!force && now - last_progress_ < DDS_SECS(1)) return;
  const double dt = to_s(now - last_progress_);
  const double tps = dt > 0 ? static_cast<double>(world_.tick() - last_progress_tick_) / dt : 0.0;
  std::size_t alive = 0;
  for (const auto& r : world_.robots()) alive += r.alive ? 1 : 0;
  char line[128];
  std::snprintf(line, sizeof line, "progress tick=%llu alive=%zu/%zu tps=%.1f",
                static_cast<unsigned long long>(world_.tick()), alive, world_.robots().size(), tps);
  status_.emit_and_print(
      "progress",
      {{"tick", world_.tick()}, {"alive", alive}, {"robots", world_.robots().size()}, {"tps", tps}}, line);
  last_progress_ = now;
  last_progress_tick_ = world_.tick();
}

}  // namespace swarmform::server
