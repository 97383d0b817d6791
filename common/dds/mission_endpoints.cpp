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

void MissionWriter::publish(const MissionAnnouncement& a) {
  const Mission& m = a.mission;
  std::vector<sfdds_Param> params;
  params.reserve(m.params.size());
  for (const auto& [name, value] : m.params) {
    params.push_back(sfdds_Param{const_cast<char*>(name.c_str()), value});
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
    out = std::move(a);
  }
  return out;
}

}  // namespace swarmform::dds
