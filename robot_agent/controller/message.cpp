#include "robot_agent/controller/message.hpp"

#include <bit>
#include <cmath>

#include "common/little_endian.hpp"

namespace swarmform::controller {

namespace {

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { put(v, 2); }
  void u32(std::uint32_t v) { put(v, 4); }
  void i16(std::int16_t v) { put(static_cast<std::uint16_t>(v), 2); }
  void i64(std::int64_t v) { put(static_cast<std::uint64_t>(v), 8); }
  void u64(std::uint64_t v) { put(v, 8); }
  void f32(double v) { u32(std::bit_cast<std::uint32_t>(static_cast<float>(v))); }
  void bytes(const std::vector<std::uint8_t>& b, std::size_t n) {
    out_.insert(out_.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
  }

 private:
  void put(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> in) : p_(in.data()), end_(in.data() + in.size()) {}
  bool ok() const { return ok_; }
  bool at_end() const { return p_ == end_; }
  // True when `n` more bytes can be read; otherwise marks the input bad.
  bool has(std::size_t n) {
    if (ok_ && static_cast<std::size_t>(end_ - p_) >= n) return true;
    ok_ = false;
    return false;
  }
  std::uint8_t u8() { return get<std::uint8_t>(); }
  std::uint16_t u16() { return get<std::uint16_t>(); }
  // Unchecked reads: the caller has checked has() for them.
  template <class T>
  T take() {
    const T v = load_le<T>(p_);
    p_ += sizeof(T);
    return v;
  }
  // A non-finite number marks the input bad (checked by ok() at the end).
  double take_f32() {
    const float f = std::bit_cast<float>(take<std::uint32_t>());
    if (!std::isfinite(f)) ok_ = false;
    return static_cast<double>(f);
  }
  // A stigmergy entry; the caller has checked has(kEntryBytes).
  StigmergyEntry entry_unchecked() {
    StigmergyEntry e;
    e.key = load_le<std::uint32_t>(p_);
    e.value = load_le<std::int64_t>(p_ + 4);
    e.version = load_le<std::uint32_t>(p_ + 12);
    e.writer = load_le<std::uint32_t>(p_ + 16);
    p_ += kEntryBytes;
    return e;
  }
  // Past `n` bytes; the caller has checked has(n).
  void skip_unchecked(std::size_t n) { p_ += n; }
  void bytes(std::size_t n, std::vector<std::uint8_t>& out) {
    out.clear();
    if (!has(n)) return;
    out.assign(p_, p_ + n);
    p_ += n;
  }

  static constexpr std::size_t kEntryBytes = 20;

 private:
  template <class T>
  T get() {
    if (!has(sizeof(T))) return T{};
    const T v = load_le<T>(p_);
    p_ += sizeof(T);
    return v;
  }
  const std::uint8_t* p_;
  const std::uint8_t* end_;
  bool ok_ = true;
};

constexpr std::uint8_t kFlagHasOrigin = 0x01;
// magic, version, sender, state, label, pose, flags, origin, seed candidate, distance and age, table digest,
// free label count.
constexpr std::size_t kHeaderBytes = 49;
constexpr std::uint8_t kMaxStateValue = static_cast<std::uint8_t>(RobotState::Arrived);

}  // namespace

std::vector<std::uint8_t> encode_idle_beacon(RobotId self, const Pose2D& pose) {
  RobotMessage msg;
  msg.sender = self;
  msg.state = RobotState::Idle;
  msg.pose = pose;
  return encode_message(msg);
}

std::vector<std::uint8_t> encode_message(const RobotMessage& m) {
  std::vector<std::uint8_t> out;
  const std::size_t n_free = std::min(m.free_labels.size(), kMaxFreeLabels);
  const std::size_t n_entries = std::min(m.entries.size(), kMaxEntriesPerMessage);
  const std::size_t n_motion = std::min(m.motion.size(), kMaxMotionBytes);
  out.reserve(kMessageFixedBytes + 2 * n_free + 20 * n_entries + n_motion);
  Writer w(out);
  w.u8(kMessageMagic);
  w.u8(kMessageVersion);
  w.u32(m.sender);
  w.u8(static_cast<std::uint8_t>(m.state));
  w.i16(static_cast<std::int16_t>(m.label));
  w.f32(m.pose.x);
  w.f32(m.pose.y);
  w.f32(m.pose.theta);
  w.u8(m.has_origin ? kFlagHasOrigin : 0);
  w.f32(m.origin.x);
  w.f32(m.origin.y);
  w.u32(m.seed_candidate);
  w.f32(m.seed_distance);
  w.u8(m.seed_age);
  w.u64(m.table_digest);
  w.u8(static_cast<std::uint8_t>(n_free));
  for (std::size_t i = 0; i < n_free; ++i) w.i16(static_cast<std::int16_t>(m.free_labels[i]));
  w.u8(static_cast<std::uint8_t>(n_entries));
  for (std::size_t i = 0; i < n_entries; ++i) {
    const auto& e = m.entries[i];
    w.u32(e.key);
    w.i64(e.value);
    w.u32(e.version);
    w.u32(e.writer);
  }
  w.u16(static_cast<std::uint16_t>(n_motion));
  w.bytes(m.motion, n_motion);
  return out;
}

bool decode_message_into(std::span<const std::uint8_t> bytes, RobotMessage& m,
                         std::uint64_t skip_entries_digest) {
  m.entries.clear();
  return decode_message_into(bytes, static_cast<MessageBody&>(m), skip_entries_digest, m.entries);
}

bool decode_message_into(std::span<const std::uint8_t> bytes, MessageBody& m,
                         std::uint64_t skip_entries_digest, std::vector<StigmergyEntry>& entries) {
  // The fixed header is bounds-checked once, then read field by field without further checks.
  Reader r(bytes);
  if (!r.has(kHeaderBytes)) return false;
  if (r.take<std::uint8_t>() != kMessageMagic || r.take<std::uint8_t>() != kMessageVersion) return false;
  m.sender = r.take<std::uint32_t>();
  const std::uint8_t state = r.take<std::uint8_t>();
  if (state > kMaxStateValue) return false;
  m.state = static_cast<RobotState>(state);
  m.label = r.take<std::int16_t>();
  if (m.label < -1) return false;
  m.pose.x = r.take_f32();
  m.pose.y = r.take_f32();
  m.pose.theta = r.take_f32();
  const std::uint8_t flags = r.take<std::uint8_t>();
  if ((flags & ~kFlagHasOrigin) != 0) return false;
  m.has_origin = (flags & kFlagHasOrigin) != 0;
  m.origin.x = r.take_f32();
  m.origin.y = r.take_f32();
  m.seed_candidate = r.take<std::uint32_t>();
  m.seed_distance = r.take_f32();
  m.seed_age = r.take<std::uint8_t>();
  m.table_digest = r.take<std::uint64_t>();
  const std::size_t n_free = r.take<std::uint8_t>();
  if (n_free > kMaxFreeLabels || !r.has(2 * n_free) || !r.ok()) return false;
  m.free_labels.clear();  // clear + push_back: inlined, where resize is an out-of-line call
  // A vector that must grow takes the bound at once: a receiver decodes into each neighbour's own message,
  // and growing by doublings cost every newcomer up to six allocations (6 a step in a crowd, BENCHMARKS.md).
  if (m.free_labels.capacity() < n_free) m.free_labels.reserve(kMaxFreeLabels);
  for (std::size_t i = 0; i < n_free; ++i) {
    const int label = r.take<std::int16_t>();
    if (label < 0) return false;
    m.free_labels.push_back(label);
  }
  const std::size_t n_entries = r.u8();
  if (n_entries > kMaxEntriesPerMessage || !r.has(n_entries * Reader::kEntryBytes)) return false;
  if (skip_entries_digest != 0 && m.table_digest == skip_entries_digest) {
    r.skip_unchecked(n_entries * Reader::kEntryBytes);
  } else {
    // An empty vector that must grow takes the bound at once (see free_labels); one that already holds
    // entries (a buffer of many messages') grows as vectors do.
    if (entries.empty() && entries.capacity() < n_entries) entries.reserve(kMaxEntriesPerMessage);
    for (std::size_t i = 0; i < n_entries; ++i) entries.push_back(r.entry_unchecked());
  }
  const std::size_t n_motion = r.u16();
  if (n_motion > kMaxMotionBytes) return false;
  r.bytes(n_motion, m.motion);
  return r.ok() && r.at_end();
}

std::optional<RobotMessage> decode_message(std::span<const std::uint8_t> bytes) {
  RobotMessage m;
  if (!decode_message_into(bytes, m)) return std::nullopt;
  return m;
}

}  // namespace swarmform::controller
