#include "common/dds/mission_endpoints.hpp"

#include <string>
#include <utility>
#include <vector>

#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/refusal_log.hpp"
#include "common/dds/wire_version.hpp"
#include "common/input_error.hpp"
#include "common/mission_check.hpp"

namespace swarmform::dds {

using internal::Loan;
using internal::make_condition;
using internal::make_reader;
using internal::make_writer;
using internal::nonce_text;
using internal::str;
using internal::version_text;

MissionWriter::MissionWriter(const Participant& participant)
    : writer_(make_writer(participant.get(), participant.topics().mission(), Channel::Mission)) {}

namespace {

std::vector<sfdds_Param> wire_params(const Mission& m) {
  std::vector<sfdds_Param> params;
  params.reserve(m.params.size());
  for (const auto& [name, value] : m.params) {
    params.push_back(sfdds_Param{const_cast<char*>(name.c_str()), value});
  }
  return params;
}

// At most this many groups in a mission: more is a malformed (or hostile) sample, never a scenario.
constexpr std::uint32_t kMaxGroups = 4096;

}  // namespace

void take_own_group(MissionAnnouncement& a, RobotId id) {
  if (a.groups.empty()) return;
  for (MissionGroup& g : a.groups) {
    if (id >= g.first_id && id - g.first_id < g.count) {
      a.mission = g.mission;
      return;
    }
  }
  // No group holds it: the groups cover every robot of the run (take checks it), so the id is not of this
  // run, which the agent refuses by the robot count.
}

void MissionWriter::publish(const MissionAnnouncement& a) {
  const Mission& m = a.mission;
  std::vector<sfdds_Param> params = wire_params(m);
  // The groups' own parts; each group's params stay alive in group_params while the sample is written.
  std::vector<std::vector<sfdds_Param>> group_params;
  std::vector<sfdds_MissionGroup> groups;
  group_params.reserve(a.groups.size());
  for (const MissionGroup& g : a.groups) {
    group_params.push_back(wire_params(g.mission));
    sfdds_MissionGroup w{};
    w.first_id = g.first_id;
    w.count = g.count;
    w.behaviour = const_cast<char*>(g.mission.behaviour.c_str());
    w.plugin = const_cast<char*>(g.mission.plugin.c_str());
    w.descriptor = const_cast<char*>(g.mission.descriptor.c_str());
    w.params._buffer = group_params.back().data();
    w.params._length = w.params._maximum = static_cast<std::uint32_t>(group_params.back().size());
    groups.push_back(w);
  }
  std::vector<std::int32_t> cells(m.shape.cells.begin(), m.shape.cells.end());
  sfdds_Mission s{};
  s.wire_version = kWireVersion;
  s.run_nonce = a.run_nonce;
  s.robots = a.robots;
  s.behaviour = const_cast<char*>(m.behaviour.c_str());
  s.plugin = const_cast<char*>(m.plugin.c_str());
  s.descriptor = const_cast<char*>(m.descriptor.c_str());
  s.rows = m.shape.rows;
  s.cols = m.shape.cols;
  s.cells._buffer = cells.data();
  s.cells._length = s.cells._maximum = static_cast<std::uint32_t>(cells.size());
  s.grid_spacing = m.grid_spacing;
  s.has_goal = m.has_goal;
  s.goal_x = m.goal.x;
  s.goal_y = m.goal.y;
  s.goal_radius = m.goal_radius;
  s.max_speed = m.max_speed;
  s.tick_rate = m.tick_rate;
  s.comm_range = m.comm_range;
  s.max_message_bytes = m.max_message_bytes;
  s.seed = m.seed;
  s.params._buffer = params.data();
  s.params._length = s.params._maximum = static_cast<std::uint32_t>(params.size());
  s.realtime = a.realtime;
  s.groups._buffer = groups.data();
  s.groups._length = s.groups._maximum = static_cast<std::uint32_t>(groups.size());
  check(dds_write(writer_.get(), &s), "dds_write(mission)");
}

MissionReader::MissionReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().mission(), Channel::Mission)),
      condition_(make_condition(reader_.get())) {}

std::optional<MissionAnnouncement> MissionReader::take(std::optional<std::uint64_t> want_nonce,
                                                       RefusalLog& refusals) {
  void* ptrs[8] = {};
  dds_sample_info_t infos[8];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 8, 8), "dds_take(mission)");
  Loan loan(reader_.get(), ptrs, n);
  std::optional<MissionAnnouncement> out;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_Mission*>(ptrs[i]);
    const auto key = writer_participant(reader_.get(), infos[i].publication_handle);
    const std::string writer = "the world of participant " + (key ? to_string(*key) : std::string("?"));
    if (s.wire_version != kWireVersion) {
      refusals.refuse(infos[i].publication_handle, writer, "mission", version_text(s.wire_version),
                      dds_time());
      continue;
    }
    if (want_nonce && s.run_nonce != *want_nonce) {
      refusals.refuse(infos[i].publication_handle, writer, "mission",
                      "another run's (" + nonce_text(s.run_nonce, *want_nonce) + ")", dds_time());
      continue;
    }
    if (!key) continue;  // its writer is gone already: a world that left
    MissionAnnouncement a;
    a.world = *key;
    a.run_nonce = s.run_nonce;
    a.robots = s.robots;
    a.realtime = s.realtime;
    Mission& m = a.mission;
    m.behaviour = str(s.behaviour);
    m.plugin = str(s.plugin);
    m.descriptor = str(s.descriptor);
    m.shape.rows = s.rows;
    m.shape.cols = s.cols;
    m.shape.cells.assign(s.cells._buffer, s.cells._buffer + s.cells._length);
    m.grid_spacing = s.grid_spacing;
    m.has_goal = s.has_goal;
    m.goal = Vec2{s.goal_x, s.goal_y};
    m.goal_radius = s.goal_radius;
    m.max_speed = s.max_speed;
    m.tick_rate = s.tick_rate;
    m.comm_range = s.comm_range;
    m.max_message_bytes = s.max_message_bytes;
    m.seed = s.seed;
    for (std::uint32_t k = 0; k < s.params._length; ++k) {
      m.params[str(s.params._buffer[k].name)] = s.params._buffer[k].value;
    }
    check_mission(m,
                  "<mission>");  // common/mission_check.hpp: a malformed mission never reaches a controller
    // Robot groups: contiguous from id 0 and covering every robot, each a checked mission of its own.
    if (s.groups._length > kMaxGroups) {
      throw InputError(
          "<mission>", 0,
          std::to_string(s.groups._length) + " robot groups, more than " + std::to_string(kMaxGroups));
    }
    std::uint64_t next = 0;
    for (std::uint32_t k = 0; k < s.groups._length; ++k) {
      const sfdds_MissionGroup& w = s.groups._buffer[k];
      if (w.first_id != next || w.count == 0) {
        throw InputError("<mission>", 0,
                         "robot group " + std::to_string(k) + " starts at id " + std::to_string(w.first_id) +
                             " with " + std::to_string(w.count) + " robots; expected id " +
                             std::to_string(next) + " and at least one");
      }
      next += w.count;
      MissionGroup g;
      g.first_id = w.first_id;
      g.count = w.count;
      g.mission = m;
      g.mission.behaviour = str(w.behaviour);
      g.mission.plugin = str(w.plugin);
      g.mission.descriptor = str(w.descriptor);
      g.mission.params.clear();
      for (std::uint32_t p = 0; p < w.params._length; ++p) {
        g.mission.params[str(w.params._buffer[p].name)] = w.params._buffer[p].value;
      }
      check_mission(g.mission, "<mission>");
      a.groups.push_back(std::move(g));
    }
    if (s.groups._length > 0 && next != s.robots) {
      throw InputError(
          "<mission>", 0,
          "the robot groups hold " + std::to_string(next) + " robots, the run " + std::to_string(s.robots));
    }
    out = std::move(a);
  }
  return out;
}

}  // namespace swarmform::dds
