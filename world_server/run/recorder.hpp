// Writes a run directory (docs/recording-format.md): world.json at the start, robots.csv, readings.csv and
// events.jsonl as the run goes (flushed every kFlushEveryTicks recorded ticks, so a crashed run keeps what it
// had), a human-readable world.log, and summary.json at the end. Plain file output only; what to write is
// decided by RunSession.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "behaviour/known_columns.hpp"
#include "world_server/world/world.hpp"

namespace swarmform::world {

// robots.csv's eleven fixed columns (docs/recording-format.md), in every version of the format; a recording
// then has `leds` (kLedsColumn, since the LEDs were recorded: older ones lack it), then the behaviour's
// telemetry columns.
inline constexpr const char* kRobotsCsvHeader = "tick,id,x,y,theta,alive,state,label,parent,leader,net_force";
inline constexpr const char* kLedsColumn = "leds";
// readings.csv's first columns; then common/sensor_readings.hpp sensor_reading_columns.
inline constexpr const char* kReadingsCsvHeader = "tick,id";
inline constexpr Tick kFlushEveryTicks = 10;
// Room reserved for summary.json when the run directory is made (summary.json.tmp, allocated at once), so
// that a disk that fills during the run still takes the run's outcome: the summary is written into that
// room, and cut to its outcome (summary_outcome, recording_format.hpp) when the whole of it does not fit.
inline constexpr std::size_t kSummaryRoomBytes = 64 * 1024;

class RecordingWriter {
 public:
  // Creates `run_dir` (and parents) and opens the files; throws std::runtime_error naming the path on
  // failure.
  // `extra_columns`: the behaviour's telemetry columns (its descriptor's), written after the fixed ones.
  // `sensors`: the optional sensors the behaviour declares (behaviour::Sensor bits): readings.csv records
  // them; 0: no readings.csv.
  // `column_of_robot` (telemetry_columns.hpp): for robot id, the index into its telemetry.extra of each
  // extra column, -1 for none (left empty); empty: column k is extra[k] for every robot.
  // `known` (by robot id): where its behaviour's known columns are (behaviour/known_columns.hpp), recorded in
  // robots.csv's label, parent, leader and net_force; a robot without: -1, -1, 0, 0.
  explicit RecordingWriter(const std::string& run_dir, std::vector<std::string> extra_columns = {},
                           std::uint32_t sensors = 0, std::vector<std::vector<int>> column_of_robot = {},
                           std::vector<behaviour::KnownColumns> known = {});
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  const std::string& run_dir() const { return run_dir_; }

  void write_world(const nlohmann::ordered_json& world);  // world.json, written whole at once
  // A copy of `source` in the run folder as `name` (the floor image); throws RecordingError naming both.
  void copy_in(const std::string& source, const std::string& name);
  // One row per robot (in id order) for this tick; flushes every kFlushEveryTicks ticks.
  void write_rows(Tick tick, const std::vector<RobotTruth>& robots);
  // readings.csv's rows of this tick: each robot's optional sensors (World::optional_sensors), empty values
  // for a dead robot. Nothing without sensors. Flushed with robots.csv.
  void write_readings(Tick tick, const World& world);
  void write_event(const nlohmann::ordered_json& event);  // one line of events.jsonl
  void log(Tick tick, const std::string& text);           // one line of world.log
  void flush();
  // summary.json, into its reserved room; closes the streams first. On a full disk the summary cut to its
  // outcome is written instead (returns true then); throws RecordingError when not even that can be.
  bool write_summary(const nlohmann::ordered_json& summary);

 private:
  // Opens `path` with `buffer` (allocated here) as its stdio buffer.
  static std::FILE* open(const std::string& path, const char* mode, std::unique_ptr<char[]>& buffer);
  void close_streams();
  void write_file_atomically(const std::string& name, const std::string& text);
  // Allocates summary.json.tmp's room (best effort: without it the summary is written as any file).
  void reserve_summary_room();
  // Writes `text` over `name`.tmp from its start (into the room already allocated there), cuts the file to
  // it and renames it to `name`.
  void write_into_room(const std::string& name, const std::string& text);

  std::string run_dir_;
  std::FILE* robots_ = nullptr;
  std::FILE* readings_ = nullptr;  // null: the behaviour declares no optional sensor
  std::FILE* events_ = nullptr;
  std::FILE* log_ = nullptr;
  // The streams' buffers: glibc's setvbuf ignores the size it is given with no buffer and keeps 4 KiB,
  // which wrote robots.csv in 4 KiB pieces, a system call a tick at N = 64, on the lockstep round's path.
  std::unique_ptr<char[]> robots_buffer_, readings_buffer_, events_buffer_, log_buffer_;
  std::string row_buffer_;
  std::uint32_t sensors_ = 0;
  std::uint32_t equipped_ = 0;  // write_readings' scratch: one robot's sensors and values
  std::vector<double> sensor_values_;
  std::size_t extra_columns_ = 0;
  std::vector<std::vector<int>> column_of_robot_;
  std::vector<behaviour::KnownColumns> known_;
  Tick ticks_since_flush_ = 0;
};

}  // namespace swarmform::world
