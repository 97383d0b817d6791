#include "common/dds/command_reader.hpp"

#include <algorithm>
#include <mutex>
#include <string>
#include <unordered_map>

#include "common/dds/internal/endpoint_kit.hpp"
#include "common/dds/internal/idl.hpp"
#include "common/dds/internal/topics.hpp"
#include "common/dds/qos.hpp"

namespace swarmform::dds {

using internal::assign_octets;
using internal::Loan;
using internal::make_condition;
using internal::make_partitioned;
using internal::make_reader;
using internal::pace_of;
using internal::str;

namespace {
constexpr std::uint32_t kTakeBatch = 64;  // samples a dds_take (on the stack) in CommandReader::take
}  // namespace

struct CommandReader::Impl {
  Waiter* waiter = nullptr;
  std::mutex mutex;
  std::vector<LivelinessChange> changes;  // guarded by mutex
  dds_entity_t topic = 0;                 // with the filter set on it (0: none)
  std::unique_ptr<ReceiveBudget> budget;  // with the filter
  bool secure = false;
  std::uint32_t face = 0;  // stamped on every sample taken (CommandSample::face)
  Entity subscriber;       // secure: partition robot/* (every robot's own)
  Entity reader, condition;
  std::unordered_map<PublicationHandle, std::optional<RobotId>> authenticated;  // per writer, looked up once

  // Runs on Cyclone's receive thread for every sample, before the sample is stored, and on its info alone:
  // Cyclone decodes a sample for a filter that asks for it (a filter on the sample decoded every sample of a
  // flood, 1 KB message and event strings, and stored all of those for ids inside the run: the world then
  // decoded them again, queued behind the flood, and the honest robots' commands with them).
  static bool accept(const dds_sample_info_t* info, void* arg) {
    // The world's clock, not the sample's source timestamp: that is the writer's to say.
    return static_cast<Impl*>(arg)->budget->admit(info->publication_handle, info->instance_handle,
                                                  dds_time());
  }

  static void on_data_available(dds_entity_t, void* arg) {
    try {
      static_cast<Impl*>(arg)->waiter->arrived();
    } catch (const DdsError&) {
      // Only possible while tearing down; nobody is waiting then.
    }
  }

  static void on_liveliness(dds_entity_t, const dds_liveliness_changed_status_t status, void* arg) {
    auto* self = static_cast<Impl*>(arg);
    // alive_count falls when a writer loses liveliness (not_alive rises) or goes away (deleted, unmatched),
    // and rises when a writer appears or its liveliness comes back; not_alive alone falls when a writer
    // that had lost its liveliness goes away.
    const int a = status.alive_count_change;
    const int na = status.not_alive_count_change;
    const bool alive = a > 0;
    const bool lapsed = a < 0 && na > 0;
    const bool gone = (a < 0 && na <= 0) || (a == 0 && na < 0);
    if (!alive && !lapsed && !gone) return;
    {
      std::lock_guard lock(self->mutex);
      self->changes.push_back(LivelinessChange{status.last_publication_handle, alive, gone});
    }
    try {
      self->waiter->wake();
    } catch (const DdsError&) {
      // Only possible while tearing down; nobody is waiting then.
    }
  }
};

CommandReader::CommandReader(const Participant& participant, Waiter& waiter, bool realtime,
                             std::uint32_t accept_ids, std::uint32_t face, bool count_arrivals,
                             std::uint32_t samples_per_window)
    : impl_(std::make_unique<Impl>()) {
  impl_->waiter = &waiter;
  impl_->face = face;
  if (accept_ids > 0 || samples_per_window > 0) {
    // Set before the reader exists (Cyclone's rule for topic filters); only the world reads this topic in
    // its participant.
    impl_->topic = participant.topics().command();
    impl_->budget = std::make_unique<ReceiveBudget>(samples_per_window, accept_ids);
    dds_topic_filter filter{};
    filter.mode = DDS_TOPIC_FILTER_SAMPLEINFO_ARG;
    filter.f.sampleinfo_arg = &Impl::accept;
    filter.arg = impl_.get();
    check(dds_set_topic_filter_extended(impl_->topic, &filter), "dds_set_topic_filter_extended(command)");
  }
  dds_entity_t parent = participant.get();
  if (participant.secure()) {
    // Every robot's commands come in its own partition (CommandWriter); a wildcard reads them all.
    impl_->secure = true;
    impl_->subscriber = make_partitioned(participant.get(), "robot/*", false);
    parent = impl_->subscriber.get();
  }
  dds_listener_t* listener = dds_create_listener(impl_.get());
  dds_lset_liveliness_changed(listener, &Impl::on_liveliness);
  // Set with the reader, so that no sample is ever stored uncounted (Cyclone calls it once per stored
  // sample).
  if (count_arrivals) dds_lset_data_available(listener, &Impl::on_data_available);
  try {
    impl_->reader =
        make_reader(parent, participant.topics().command(), Channel::Command, listener, pace_of(realtime));
  } catch (...) {
    dds_delete_listener(listener);
    throw;
  }
  dds_delete_listener(listener);
  impl_->condition = make_condition(impl_->reader.get());
}

CommandReader::~CommandReader() {
  if (impl_) {
    impl_->condition.reset();
    impl_->reader.reset();
    if (impl_->topic != 0) {  // the filter's argument dies with impl_
      dds_topic_filter none{};
      none.mode = DDS_TOPIC_FILTER_NONE;
      (void)dds_set_topic_filter_extended(impl_->topic, &none);
    }
  }
}

std::uint64_t CommandReader::filtered() const {
  return impl_->budget ? impl_->budget->out_of_range() : 0;
}

void CommandReader::set_window(std::uint64_t window) {
  if (impl_->budget) impl_->budget->set_window(window);
}

void CommandReader::take_budget_drops(std::vector<ReceiveBudget::Drops>& out) {
  if (impl_->budget) impl_->budget->take_drops(out);
}

std::uint64_t CommandReader::over_budget() const {
  return impl_->budget ? impl_->budget->over_budget() : 0;
}

std::optional<RobotId> CommandReader::authenticated_robot(PublicationHandle writer) {
  if (!impl_->secure) return std::nullopt;
  if (auto it = impl_->authenticated.find(writer); it != impl_->authenticated.end()) return it->second;
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(impl_->reader.get(), writer);
  if (e == nullptr) return std::nullopt;  // gone already: asked again if it writes again
  std::optional<RobotId> robot;
  std::uint32_t n = 0;
  char** names = nullptr;
  if (dds_qget_partition(e->qos, &n, &names) && n == 1) {
    const std::string name = names[0];
    const std::string prefix = "robot/";
    if (name.size() > prefix.size() && name.size() <= prefix.size() + 10 && name.rfind(prefix, 0) == 0 &&
        name.find_first_not_of("0123456789", prefix.size()) == std::string::npos) {
      const unsigned long long id = std::stoull(name.substr(prefix.size()));
      if (id <= 0xffffffffULL && robot_partition(static_cast<RobotId>(id)) == name) {
        robot = static_cast<RobotId>(id);
      }
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) dds_free(names[i]);
  dds_free(names);
  dds_builtintopic_free_endpoint(e);
  // Bounded: one entry per matched writer, and only matched (authenticated, permitted) writers get here.
  impl_->authenticated.emplace(writer, robot);
  return robot;
}

bool CommandReader::matched(PublicationHandle writer) const {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(impl_->reader.get(), writer);
  if (e == nullptr) return false;
  dds_builtintopic_free_endpoint(e);
  return true;
}

std::optional<RemoteWriter> CommandReader::remote(PublicationHandle writer) const {
  return remote_writer(impl_->reader.get(), writer);
}

dds_entity_t CommandReader::condition() const {
  return impl_->condition.get();
}

void CommandReader::take_liveliness_changes(std::vector<LivelinessChange>& out) {
  std::lock_guard lock(impl_->mutex);
  out.insert(out.end(), impl_->changes.begin(), impl_->changes.end());
  impl_->changes.clear();
}

std::size_t CommandReader::take(std::vector<CommandSample>& buf, std::size_t max_samples, std::size_t first) {
  std::size_t count = first;
  max_samples += first;
  while (count < max_samples) {
    void* ptrs[kTakeBatch] = {};
    dds_sample_info_t infos[kTakeBatch];
    const auto batch = static_cast<std::uint32_t>(std::min<std::size_t>(kTakeBatch, max_samples - count));
    const int n = check(dds_take(impl_->reader.get(), ptrs, infos, batch, batch), "dds_take(command)");
    Loan loan(impl_->reader.get(), ptrs, n);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto& s = *static_cast<const sfdds_Command*>(ptrs[i]);
      if (impl_->budget &&
          !impl_->budget->taken(infos[i].publication_handle, infos[i].instance_handle, s.robot_id)) {
        continue;  // an id outside the run: its writer's unknown instances are dropped from now on
      }
      if (count == buf.size()) buf.emplace_back();
      CommandSample& c = buf[count++];
      c.wire_version = s.wire_version;
      c.run_nonce = s.run_nonce;
      c.robot_id = s.robot_id;
      c.kind = s.kind == sfdds_COMMAND_CLAIM   ? CommandKind::Claim
               : s.kind == sfdds_COMMAND_ALIVE ? CommandKind::Alive
                                               : CommandKind::Step;
      c.tick = s.tick;
      c.nonce = s.nonce;
      c.pid = s.pid;
      c.writer = infos[i].publication_handle;
      c.sent_at = infos[i].source_timestamp;
      c.face = impl_->face;
      c.command.left_speed = s.left_speed;
      c.command.right_speed = s.right_speed;
      assign_octets(c.command.message, s.message);
      for (std::size_t k = 0; k < kLedCount; ++k)
        c.command.leds[k] = {s.leds[3 * k], s.leds[3 * k + 1], s.leds[3 * k + 2]};
      Telemetry& t = c.command.telemetry;
      t.state = s.state;
      t.events.resize(s.events._length);
      for (std::uint32_t k = 0; k < s.events._length; ++k) t.events[k] = str(s.events._buffer[k]);
      t.extra.assign(s.extra._buffer, s.extra._buffer + s.extra._length);
    }
    if (n < static_cast<int>(batch)) break;
  }
  return count - first;
}

}  // namespace swarmform::dds
