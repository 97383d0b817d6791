#include "common/dds/command_writer.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "common/dds/identity.hpp"
#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/qos.hpp"

namespace swarmform::dds {

using internal::keep_instance;
using internal::make_partitioned;
using internal::make_writer;
using internal::octets;
using internal::pace_of;

struct CommandWriter::Impl {
  Entity publisher;  // secure: the robot's own partition
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::uint16_t wire_version = kWireVersion;
  std::vector<char*> events;          // reused: points into the command's strings during dds_write
  dds_time_t alive_at = 0;            // the last write or assertion (each renews the liveliness lease)
  std::optional<RobotId> registered;  // the id whose instance is kept (keep_instance), from the first claim
};

CommandWriter::CommandWriter(const Participant& participant, bool realtime, std::optional<RobotId> robot)
    : impl_(std::make_unique<Impl>()) {
  dds_entity_t parent = participant.get();
  if (participant.secure() && !robot) {
    throw std::logic_error("CommandWriter on a secure participant needs its robot id");
  }
  if (robot) {
    impl_->publisher = make_partitioned(participant.get(), robot_partition(*robot), true);
    parent = impl_->publisher.get();
  }
  impl_->writer = make_writer(parent, participant.topics().command(), Channel::Command, pace_of(realtime));
}
CommandWriter::~CommandWriter() = default;
dds_entity_t CommandWriter::get() const {
  return impl_->writer.get();
}

namespace {
sfdds_Command command_key(RobotId id) {
  sfdds_Command key{};
  key.robot_id = id;
  return key;
}

// A command of `kind` for `id` stamped with the writer's run and version; its telemetry says nothing (no
// columns) until a step fills it.
sfdds_Command stamped_command(RobotId id, std::uint8_t kind, std::uint64_t run_nonce,
                              std::uint16_t wire_version) {
  sfdds_Command s{};
  s.robot_id = id;
  s.wire_version = wire_version;
  s.run_nonce = run_nonce;
  s.kind = kind;
  return s;
}
}  // namespace

void CommandWriter::set_stamp(std::uint64_t run_nonce, std::uint16_t wire_version) {
  impl_->run_nonce = run_nonce;
  impl_->wire_version = wire_version;
}

void CommandWriter::claim(RobotId id, std::uint64_t nonce, std::uint32_t pid,
                          std::span<const std::uint8_t> proof) {
  if (impl_->registered != id) {
    const sfdds_Command key = command_key(id);
    keep_instance(impl_->writer.get(), &key);
    impl_->registered = id;
  }
  sfdds_Command s = stamped_command(id, sfdds_COMMAND_CLAIM, impl_->run_nonce, impl_->wire_version);
  s.nonce = nonce;
  s.pid = pid;
  s.message._buffer = const_cast<std::uint8_t*>(proof.data());
  s.message._length = s.message._maximum = static_cast<std::uint32_t>(proof.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(claim)");
  impl_->alive_at = dds_time();
}

WriterGuid CommandWriter::guid() const {
  dds_guid_t g{};
  check(dds_get_guid(impl_->writer.get(), &g), "dds_get_guid(command writer)");
  WriterGuid out{};
  static_assert(sizeof(g.v) == std::tuple_size_v<WriterGuid>);
  std::memcpy(out.data(), g.v, out.size());
  return out;
}

dds_time_t CommandWriter::keep_alive(dds_time_t now, bool by_sample) {
  if (now - impl_->alive_at >= kLivelinessAssertPeriod) {
    if (by_sample && impl_->registered) {
      const sfdds_Command s =
          stamped_command(*impl_->registered, sfdds_COMMAND_ALIVE, impl_->run_nonce, impl_->wire_version);
      check(dds_write(impl_->writer.get(), &s), "dds_write(alive)");
    } else {
      check(dds_assert_liveliness(impl_->writer.get()), "dds_assert_liveliness(command writer)");
    }
    impl_->alive_at = now;
  }
  return impl_->alive_at + kLivelinessAssertPeriod;
}

bool CommandWriter::holds_instance(RobotId id) const {
  const sfdds_Command key = command_key(id);
  return dds_lookup_instance(impl_->writer.get(), &key) != DDS_HANDLE_NIL;
}

void CommandWriter::step(RobotId id, Tick tick, const Command& c) {
  sfdds_Command s = stamped_command(id, sfdds_COMMAND_STEP, impl_->run_nonce, impl_->wire_version);
  s.tick = tick;
  s.left_speed = c.left_speed;
  s.right_speed = c.right_speed;
  s.message = octets(c.message);
  for (std::size_t k = 0; k < kLedCount; ++k) {
    s.leds[3 * k] = c.leds[k].r;
    s.leds[3 * k + 1] = c.leds[k].g;
    s.leds[3 * k + 2] = c.leds[k].b;
  }
  s.state = c.telemetry.state;
  auto& events = impl_->events;
  events.clear();
  for (const std::string& e : c.telemetry.events) events.push_back(const_cast<char*>(e.c_str()));
  s.events._buffer = events.data();
  s.events._length = s.events._maximum = static_cast<std::uint32_t>(events.size());
  s.extra._buffer = const_cast<double*>(c.telemetry.extra.data());
  s.extra._length = s.extra._maximum = static_cast<std::uint32_t>(c.telemetry.extra.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(command)");
  impl_->alive_at = dds_time();
}

}  // namespace swarmform::dds
