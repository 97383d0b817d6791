// The robot's broadcast: one message per tick, heard by every neighbour in range
// (world_server/world/medium.hpp). A compact, versioned, little-endian binary codec. decode() never trusts
// its input: any truncation, bad magic or version, count over its bound, non-finite number or trailing byte
// gives nullopt, never a crash.
//
// Wire layout, version 2 (all little-endian; f32 = IEEE-754 binary32):
//   u8  magic 0x53 ('S')         u8  version (1)
//   u32 sender id                u8  state (robot_agent/controller/robot_state.hpp)     i16 label (-1 none)
//   f32 x, f32 y, f32 heading    (the sender's own positioning sensor, arena frame: the paper's robots
//                                 exchange their coordinates)
//   u8  flags                    bit 0: has_origin
//   f32 origin x, f32 origin y   (the shape's origin, the place of label 0; meaningful with has_origin)
//   u32 seed candidate id        f32 seed candidate distance to the arena origin (flooded minimum)
//   u8  seed candidate age       (hops from the candidate's own report; a report that ages past the bound is
//                                 dropped, so a dead candidate's minimum dies out: allotment.hpp)
//   u64 stigmergy table digest   (Stigmergy::digest() of the sender's whole table when it composed this:
//                                 a receiver whose own table has the same digest skips the entries)
//   u8  free label count (<= 8)  then i16 each (free labels of the sender's 3x3 grid)
//   u8  stigmergy entry count (<= kMaxEntriesPerMessage) then per entry
//                                u32 key, i64 value, u32 version, u32 writer    (20 bytes)
//   u16 motion section length    then the bytes (the motion phases' own codec, opaque here)
// Size: 51 bytes + 2 per free label + 20 per entry + the motion section; with the bound of 24 entries and
// no motion section at most 546 bytes, well under the 1 KiB the world accepts.
// Version 2 added the table digest (a robot merging ~73 neighbours' entries every tick spent a third of
// its step on merges that changed nothing, BENCHMARKS.md). Version 3 added the seed candidate's age.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/types.hpp"
#include "robot_agent/controller/robot_state.hpp"

namespace swarmform::controller {

inline constexpr std::uint8_t kMessageMagic = 0x53;
inline constexpr std::uint8_t kMessageVersion = 3;
inline constexpr std::size_t kMaxFreeLabels = 8;          // a 3x3 grid has 8 cells around its centre
inline constexpr std::size_t kMaxEntriesPerMessage = 24;  // stigmergy entries carried per message
inline constexpr std::size_t kMaxMotionBytes = 1024;
inline constexpr std::size_t kMessageFixedBytes =
    51;  // everything but the free labels, entries and motion bytes

struct StigmergyEntry {
  std::uint32_t key = 0;
  std::int64_t value = 0;
  std::uint32_t version = 0;
  RobotId writer = 0;
  bool operator==(const StigmergyEntry&) const = default;
};

// Everything of a message but its stigmergy entries: what a receiver keeps of each neighbour
// (neighbours.hpp), whose entries go to the neighbour table's own buffer. A type of its own, so that code
// reading a stored neighbour's entries does not compile rather than reading an empty list.
struct MessageBody {
  RobotId sender = 0;
  RobotState state = RobotState::Idle;
  int label = -1;
  Pose2D pose;  // the sender's own pose (positioning sensor), arena frame
  bool has_origin = false;
  Vec2 origin;  // place of label 0, arena frame (valid with has_origin)
  RobotId seed_candidate = 0;
  double seed_distance = 0.0;      // m
  std::uint8_t seed_age = 0;       // hops from the candidate's own report (SeedElection)
  std::uint64_t table_digest = 0;  // Stigmergy::digest() of the sender's table
  std::vector<int> free_labels;
  std::vector<std::uint8_t> motion;  // opaque section for the motion phases
};

struct RobotMessage : MessageBody {
  std::vector<StigmergyEntry> entries;
};

// Encodes `m`. Counts over their bounds are truncated (free labels, entries, motion bytes): encode never
// produces what decode would refuse.
std::vector<std::uint8_t> encode_message(const RobotMessage& m);
// What a robot outside any formation says every tick (the built-in walkers): its id, Idle and its pose, so
// that it is heard and drawn among its neighbours.
std::vector<std::uint8_t> encode_idle_beacon(RobotId self, const Pose2D& pose);
std::optional<RobotMessage> decode_message(std::span<const std::uint8_t> bytes);
// The same into an existing message, reusing its vectors' capacity (no allocation once they have grown):
// true when `bytes` is a valid message; on false `m` holds garbage. When `skip_entries_digest` is not 0 and
// equals the message's table digest, the stigmergy entries are checked for length but not copied
// (`m.entries` is left empty): a receiver whose own table has that digest could learn nothing from them.
bool decode_message_into(std::span<const std::uint8_t> bytes, RobotMessage& m,
                         std::uint64_t skip_entries_digest = 0);
// The same with the entries appended to `entries` (on false, whatever was appended is garbage too).
bool decode_message_into(std::span<const std::uint8_t> bytes, MessageBody& m,
                         std::uint64_t skip_entries_digest, std::vector<StigmergyEntry>& entries);

}  // namespace swarmform::controller
