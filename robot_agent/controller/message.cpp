#include "robot_agent/controller/message.hpp"

#include <bit>
#include <cmath>
#include <cstring>

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
  explicit Reader(std::span<const std::uint8_t> in) : in_(in) {}
  bool ok() const { return ok_; }
  bool at_end() const { return pos_ == in_.size(); }
  std::uint8_t u8() { return static_cast<std::uint8_t>(get(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(get(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(get(4)); }
  std::int16_t i16() { return static_cast<std::int16_t>(static_cast<std::uint16_t>(get(2))); }
  std::int64_t i64() { return static_cast<std::int64_t>(get(8)); }
  double f32() {
    const float f = std::bit_cast<float>(u32());
    if (!std::isfinite(f)) ok_ = false;
    return ok_ ? static_cast<double>(f) : 0.0;
  }
  std::vector<std::uint8_t> bytes(std::size_t n) {
    if (!ok_ || in_.size() - pos_ < n) {
      ok_ = false;
      return {};
    }
    std::vector<std::uint8_t> b(in_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                in_.begin() + static_cast<std::ptrdiff_t>(pos_ + n));
    pos_ += n;
    return b;
  }

 private:
  std::uint64_t get(std::size_t n) {
    if (!ok_ || in_.size() - pos_ < n) {
      ok_ = false;
      return 0;
    }
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(in_[pos_ + i]) << (8 * i);
    pos_ += n;
    return v;
  }
  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

constexpr std::uint8_t kFlagHasOrigin = 0x01;
constexpr std::uint8_t kMaxStateValue = static_cast<std::uint8_t>(RobotState::Arrived);

}  // namespace

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

std::optional<RobotMessage> decode_message(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  if (r.u8() != kMessageMagic || r.u8() != kMessageVersion || !r.ok()) return std::nullopt;
  RobotMessage m;
  m.sender = r.u32();
  const std::uint8_t state = r.u8();
  if (state > kMaxStateValue) return std::nullopt;
  m.state = static_cast<RobotState>(state);
  m.label = r.i16();
  if (m.label < -1) return std::nullopt;
  m.pose.x = r.f32();
  m.pose.y = r.f32();
  m.pose.theta = r.f32();
  const std::uint8_t flags = r.u8();
  if ((flags & ~kFlagHasOrigin) != 0) return std::nullopt;
  m.has_origin = (flags & kFlagHasOrigin) != 0;
  m.origin.x = r.f32();
  m.origin.y = r.f32();
  m.seed_candidate = r.u32();
  m.seed_distance = r.f32();
  const std::size_t n_free = r.u8();
  if (n_free > kMaxFreeLabels) return std::nullopt;
  m.free_labels.reserve(n_free);  // one allocation, not one per doubling (decoding is the hottest path)
  for (std::size_t i = 0; i < n_free && r.ok(); ++i) {
    const int label = r.i16();
    if (label < 0) return std::nullopt;
    m.free_labels.push_back(label);
  }
  const std::size_t n_entries = r.u8();
  if (n_entries > kMaxEntriesPerMessage) return std::nullopt;
  m.entries.reserve(n_entries);
  for (std::size_t i = 0; i < n_entries && r.ok(); ++i) {
    StigmergyEntry e;
    e.key = r.u32();
    e.value = r.i64();
    e.version = r.u32();
    e.writer = r.u32();
    m.entries.push_back(e);
  }
  const std::size_t n_motion = r.u16();
  if (n_motion > kMaxMotionBytes) return std::nullopt;
  m.motion = r.bytes(n_motion);
  if (!r.ok() || !r.at_end()) return std::nullopt;
  return m;
}

}  // namespace swarmform::controller
