#include "common/dds/world_state_endpoints.hpp"

#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/qos.hpp"
#include "common/dds/wire_version.hpp"

namespace swarmform::dds {

using internal::Loan;
using internal::make_condition;
using internal::make_reader;
using internal::make_writer;

struct WorldStateWriter::Impl {
  Entity writer;
  std::uint64_t run_nonce = 0;
  std::vector<sfdds_RobotPose> scratch;
};

WorldStateWriter::WorldStateWriter(const Participant& participant, std::uint64_t run_nonce)
    : impl_(std::make_unique<Impl>()) {
  impl_->run_nonce = run_nonce;
  impl_->writer = make_writer(participant.get(), participant.topics().world_state(), Channel::WorldState);
}
WorldStateWriter::~WorldStateWriter() = default;

void WorldStateWriter::publish(Tick tick, bool finished, std::uint32_t alive,
                               const std::vector<RobotPoseRow>& robots) {
  auto& scratch = impl_->scratch;
  scratch.resize(robots.size());
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotPoseRow& r = robots[i];
    scratch[i] = sfdds_RobotPose{r.id, r.pose.x, r.pose.y, r.pose.theta, r.alive, r.state, r.label};
  }
  sfdds_WorldState s{};
  s.wire_version = kWireVersion;
  s.run_nonce = impl_->run_nonce;
  s.tick = tick;
  s.finished = finished;
  s.alive = alive;
  s.robots._buffer = scratch.data();
  s.robots._length = s.robots._maximum = static_cast<std::uint32_t>(scratch.size());
  check(dds_write(impl_->writer.get(), &s), "dds_write(world state)");
}

WorldStateReader::WorldStateReader(const Participant& participant)
    : reader_(make_reader(participant.get(), participant.topics().world_state(), Channel::WorldState)),
      condition_(make_condition(reader_.get())) {}

std::optional<WorldStateHeader> WorldStateReader::take() {
  void* ptrs[4] = {};
  dds_sample_info_t infos[4];
  const int n = check(dds_take(reader_.get(), ptrs, infos, 4, 4), "dds_take(world state)");
  Loan loan(reader_.get(), ptrs, n);
  std::optional<WorldStateHeader> out;
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto& s = *static_cast<const sfdds_WorldState*>(ptrs[i]);
    if (s.wire_version != kWireVersion) continue;
    out = WorldStateHeader{s.run_nonce, s.tick, s.finished, s.alive};
  }
  return out;
}

}  // namespace swarmform::dds
