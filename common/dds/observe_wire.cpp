#include "common/dds/observe_wire.hpp"

#include <cstddef>

#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/matching.hpp"
#include "common/dds/qos.hpp"
#include "common/sensor_readings.hpp"

namespace swarmform::dds {

using internal::Loan;
using internal::make_condition;
using internal::make_reader;
using internal::make_writer;
using internal::str;

const std::vector<std::string>& ObserveFrameData::columns_of(RobotId id) const {
  for (const auto& g : groups) {
    if (id >= g.first_id && id - g.first_id < g.count) return g.columns;
  }
  return columns;
}

struct ObserveWriter::Impl {
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::vector<sfdds_ObservedRobot> robots;
  std::vector<sfdds_StateStyle> states;
  std::vector<char*> fields;
  std::vector<char*> columns;
  std::vector<sfdds_ObservedGroup> groups;
  std::vector<std::vector<sfdds_StateStyle>> group_states;
  std::vector<std::vector<char*>> group_columns;
};

namespace {

// Sequences that point into the frame's own vectors (not owned: Cyclone serialises them during dds_write).
void style_rows(const std::vector<StateStyleRow>& rows, std::vector<sfdds_StateStyle>& out) {
  out.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    out[i] = sfdds_StateStyle{rows[i].value, const_cast<char*>(rows[i].name.c_str()),
                              const_cast<char*>(rows[i].colour.c_str())};
}

void name_rows(const std::vector<std::string>& names, std::vector<char*>& out) {
  out.resize(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) out[i] = const_cast<char*>(names[i].c_str());
}

template <typename Seq, typename T>
void point_at(Seq& seq, std::vector<T>& rows) {
  seq._buffer = rows.data();
  seq._length = seq._maximum = static_cast<std::uint32_t>(rows.size());
  seq._release = false;
}

std::vector<StateStyleRow> styles_of(const dds_sequence_sfdds_StateStyle& seq) {
  std::vector<StateStyleRow> out(seq._length);
  for (std::uint32_t i = 0; i < seq._length; ++i) {
    const sfdds_StateStyle& st = seq._buffer[i];
    out[i] = StateStyleRow{st.value, str(st.name), str(st.colour)};
  }
  return out;
}

std::vector<std::string> names_of(const dds_sequence_string& seq) {
  std::vector<std::string> out(seq._length);
  for (std::uint32_t i = 0; i < seq._length; ++i) out[i] = str(seq._buffer[i]);
  return out;
}

}  // namespace

ObserveWriter::ObserveWriter(const Participant& participant, std::uint64_t run_nonce)
    : impl_(std::make_unique<Impl>()) {
  impl_->run_nonce = run_nonce;
  impl_->writer = make_writer(participant.get(), participant.topics().observe(), Channel::Observe);
}
ObserveWriter::~ObserveWriter() = default;

void ObserveWriter::publish(const ObserveFrameData& f) {
  auto& robots = impl_->robots;
  robots.resize(f.robots.size());
  for (std::size_t i = 0; i < f.robots.size(); ++i) {
    const ObservedRobotRow& r = f.robots[i];
    sfdds_ObservedRobot& o = robots[i];
    o = sfdds_ObservedRobot{};
    o.id = r.id;
    o.x = r.pose.x;
    o.y = r.pose.y;
    o.theta = r.pose.theta;
    o.alive = r.alive;
    o.state = r.state;
    o.label = r.label;
    o.parent = r.parent;
    o.leader = r.leader;
    o.net_force = r.net_force;
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) o.ultrasonic[k] = r.ultrasonic[k];
    o.heard._buffer = const_cast<std::uint32_t*>(r.heard.data());
    o.heard._length = o.heard._maximum = static_cast<std::uint32_t>(r.heard.size());
    o.heard._release = false;
    o.left_speed = r.left_speed;
    o.right_speed = r.right_speed;
    o.message_bytes = r.message_bytes;
    for (std::size_t k = 0; k < kLedCount; ++k) {
      o.leds[3 * k] = r.leds[k].r;
      o.leds[3 * k + 1] = r.leds[k].g;
      o.leds[3 * k + 2] = r.leds[k].b;
    }
    o.equipped = r.equipped;
    o.readings._buffer = const_cast<double*>(r.readings.data());
    o.readings._length = o.readings._maximum = static_cast<std::uint32_t>(r.readings.size());
    o.readings._release = false;
    o.extra._buffer = const_cast<double*>(r.extra.data());
    o.extra._length = o.extra._maximum = static_cast<std::uint32_t>(r.extra.size());
    o.extra._release = false;
  }
  Impl& m = *impl_;
  style_rows(f.states, m.states);
  name_rows(f.telemetry_fields, m.fields);
  name_rows(f.columns, m.columns);
  m.groups.resize(f.groups.size());
  m.group_states.resize(f.groups.size());
  m.group_columns.resize(f.groups.size());
  for (std::size_t i = 0; i < f.groups.size(); ++i) {
    const ObservedGroupRow& g = f.groups[i];
    style_rows(g.states, m.group_states[i]);
    name_rows(g.columns, m.group_columns[i]);
    sfdds_ObservedGroup& o = m.groups[i];
    o = sfdds_ObservedGroup{};
    o.first_id = g.first_id;
    o.count = g.count;
    o.behaviour = const_cast<char*>(g.behaviour.c_str());
    point_at(o.states, m.group_states[i]);
    point_at(o.columns, m.group_columns[i]);
  }
  sfdds_ObserveFrame s{};
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.tick = f.tick;
  s.finished = f.finished;
  s.paused = f.paused;
  s.controllable = f.controllable;
  s.speed_cap = f.speed_cap;
  s.alive = f.alive;
  s.formation_tick = f.formation_tick;
  s.shape_error = f.shape_error;
  s.behaviour = const_cast<char*>(f.behaviour.c_str());
  point_at(s.states, m.states);
  point_at(s.telemetry_fields, m.fields);
  point_at(s.columns, m.columns);
  point_at(s.groups, m.groups);
  s.robots._buffer = robots.data();
  s.robots._length = s.robots._maximum = static_cast<std::uint32_t>(robots.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(observe)");
}

ObserveReader::ObserveReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().observe(), Channel::Observe)),
      condition_(make_condition(reader_.get())) {}

bool ObserveReader::take(std::uint64_t run_nonce, ObserveFrameData& out) {
  void* ptrs[4] = {};
  dds_sample_info_t infos[4];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 4, 4), "dds_take(observe)");
  Loan loan(reader_.get(), ptrs, n);
  const sfdds_ObserveFrame* newest = nullptr;
  std::int64_t sent_at = 0;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_ObserveFrame*>(ptrs[i]);
    if (s.wire_version != kWireVersion || s.run_nonce != run_nonce) {
      ++refused_;
      continue;
    }
    newest = &s;
    sent_at = infos[i].source_timestamp;
  }
  if (newest == nullptr) return false;
  const sfdds_ObserveFrame& s = *newest;
  out.run_nonce = s.run_nonce;
  out.tick = s.tick;
  out.sent_at = sent_at;
  out.finished = s.finished;
  out.paused = s.paused;
  out.controllable = s.controllable;
  out.speed_cap = s.speed_cap;
  out.alive = s.alive;
  out.formation_tick = s.formation_tick;
  out.shape_error = s.shape_error;
  out.behaviour = str(s.behaviour);
  out.states = styles_of(s.states);
  out.telemetry_fields = names_of(s.telemetry_fields);
  out.columns = names_of(s.columns);
  out.groups.resize(s.groups._length);
  for (std::uint32_t i = 0; i < s.groups._length; ++i) {
    const sfdds_ObservedGroup& g = s.groups._buffer[i];
    out.groups[i] =
        ObservedGroupRow{g.first_id, g.count, str(g.behaviour), styles_of(g.states), names_of(g.columns)};
  }
  out.robots.resize(s.robots._length);
  for (std::uint32_t i = 0; i < s.robots._length; ++i) {
    const sfdds_ObservedRobot& o = s.robots._buffer[i];
    ObservedRobotRow& r = out.robots[i];
    r.id = o.id;
    r.pose = Pose2D{o.x, o.y, o.theta};
    r.alive = o.alive;
    r.state = o.state;
    r.label = o.label;
    r.parent = o.parent;
    r.leader = o.leader;
    r.net_force = o.net_force;
    for (std::size_t k = 0; k < kUltrasonicCount; ++k) r.ultrasonic[k] = o.ultrasonic[k];
    r.heard.assign(o.heard._buffer, o.heard._buffer + o.heard._length);
    r.left_speed = o.left_speed;
    r.right_speed = o.right_speed;
    r.message_bytes = o.message_bytes;
    for (std::size_t k = 0; k < kLedCount; ++k)
      r.leds[k] = {o.leds[3 * k], o.leds[3 * k + 1], o.leds[3 * k + 2]};
    // Readings that do not add up to what `equipped` says are left out rather than misread.
    const bool whole = sensor_readings_count(o.equipped) == o.readings._length;
    r.equipped = whole ? o.equipped : 0;
    r.readings.assign(o.readings._buffer, o.readings._buffer + (whole ? o.readings._length : 0));
    r.extra.assign(o.extra._buffer, o.extra._buffer + o.extra._length);
  }
  return true;
}

ControlWriter::ControlWriter(const Participant& participant)
    : writer_(make_writer(participant.get(), participant.topics().control(), Channel::Control)) {}

void ControlWriter::send(const ControlSample& c) {
  sfdds_Control s{};
  s.wire_version = c.wire_version;
  s.run_nonce = c.run_nonce;
  s.token = c.token;
  s.seq = c.seq;
  s.kind = c.kind;
  s.count = c.count;
  s.value = c.value;
  check(dds_write(writer_.get(), &s), "dds_write(control)");
}

bool ControlWriter::matched() const {
  return writer_matched(writer_.get());
}

ControlReader::ControlReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().control(), Channel::Control)),
      condition_(make_condition(reader_.get())) {}

void ControlReader::take(std::vector<ControlSample>& out) {
  constexpr int kBatch = 64;
  void* ptrs[kBatch] = {};
  dds_sample_info_t infos[kBatch];
  const int n = check(dds_take(reader_.get(), ptrs, infos, kBatch, kBatch), "dds_take(control)");
  Loan loan(reader_.get(), ptrs, n);
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_Control*>(ptrs[i]);
    out.push_back(ControlSample{s.wire_version, s.run_nonce, s.token, s.seq, s.kind, s.count, s.value,
                                infos[i].publication_handle});
  }
}

bool ControlReader::writer_alive(PublicationHandle writer) const {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader_.get(), writer);
  if (e == nullptr) return false;
  dds_builtintopic_free_endpoint(e);
  return true;
}

}  // namespace swarmform::dds
