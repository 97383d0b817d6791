// A run's robots.csv (docs/recording-format.md) read a tick at a time (or its readings.csv, whose rows are
// keyed the same way: tick, id, then numbers), for the replay (`swarm view RUN_DIR`).
// Opening reads the header, the first line and the file's tail: nothing else, whatever the file's size. A
// tick's rows are found by a binary search over byte offsets (the rows are in tick order: the format says
// so), about 2 * log2(size) short reads, and the next tick of the one just read costs nothing more: playing
// forward reads the file once, scrubbing reads ~60 lines a jump. Memory: one tick's rows.
//
// What is wrong is said, never fatal after opening: a row that cannot be read is skipped and counted
// (bad_rows(), with the first one's byte offset in first_problem()); a half-written last line (a run that
// stopped while writing) is not part of the data. Damage (damage()) is what a viewer must say: found at open
// (the file's tail: a half-written last line, a last tick short of robots) or when a tick is read (unreadable
// bytes after its rows, a tick short of robots, ticks lost in unreadable bytes); nothing is scanned for it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/types.hpp"

namespace swarmform::viewer {

struct RecordedRow {
  std::uint32_t id = 0;
  double x = 0, y = 0, theta = 0;
  bool alive = true;
  std::int32_t state = 0, label = -1, parent = -1;
  bool leader = false;
  double net_force = 0;
  std::array<Rgb, kLedCount> leds{};  // all off in a recording older than the `leds` column
  std::vector<double> extra;          // the behaviour's telemetry columns (extra_columns()), NaN where empty
};

struct RecordedTick {
  std::uint64_t tick = 0;
  std::vector<RecordedRow> rows;  // in file order (robot id order as written)
};

// Which file of the run directory: robots.csv, or readings.csv (only `tick` and `id` fixed, every other
// column a number or empty, in RecordedRow::extra: the sensors' readings, common/sensor_readings.hpp).
enum class RowsFile { Robots, Readings };

// Something wrong with the file that a viewer must say where it is: the timeline ticks it touches (a seek
// into [from_tick, to_tick] shows it), the byte where it is, and what.
struct Damage {
  std::uint64_t from_tick = 0, to_tick = 0;
  std::uint64_t offset = 0;
  bool at_open = false;  // found opening the file (its tail): said before anything is shown
  std::string what;      // without the file's name (file_name() says it)
};

class RobotsCsv {
 public:
  // Throws std::runtime_error naming the file and what is wrong (missing, no header, a fixed column missing,
  // no complete row). `max_rows`: the rows one tick may hold (the world's robot count); more are counted bad.
  // `every_tick_whole`: every tick must hold `max_rows` rows (robots.csv with world.json's robot count): a
  // tick with fewer is damage, and a last tick with fewer (a run that stopped while writing it) is left out.
  RobotsCsv(std::string path, std::size_t max_rows, RowsFile kind = RowsFile::Robots,
            bool every_tick_whole = false);
  ~RobotsCsv();
  RobotsCsv(const RobotsCsv&) = delete;
  RobotsCsv& operator=(const RobotsCsv&) = delete;

  std::uint64_t first_tick() const { return first_tick_; }
  std::uint64_t last_tick() const { return last_tick_; }
  std::uint64_t size_bytes() const { return data_end_; }
  const std::vector<std::string>& extra_columns() const { return extra_names_; }

  // The rows of the last recorded tick <= `tick` (the first recorded tick when `tick` is before it).
  const RecordedTick& read(std::uint64_t tick);

  // The damage found so far, in the order found; damage_at(t): the damage whose ticks hold t.
  const std::vector<Damage>& damage() const { return damage_; }
  std::vector<Damage> damage_at(std::uint64_t tick) const;
  const std::string& path() const { return path_; }

  std::uint64_t bad_rows() const { return bad_rows_; }
  const std::string& first_problem() const { return first_problem_; }
  // pread calls and bytes read so far (the tests: a jump reads a few lines, not the file).
  std::uint64_t reads() const { return reads_; }
  std::uint64_t bytes_read() const { return bytes_read_; }

 private:
  struct Line {
    std::uint64_t start = 0;
    std::uint64_t end = 0;  // one past its newline
    std::uint64_t tick = 0;
    bool ok = false;  // its tick could be read
  };
  Line line_from(std::uint64_t pos);              // the first whole line starting at or after pos
  Line line_before(std::uint64_t start);          // the line that ends at `start` (start > data_start_)
  std::uint64_t lower_bound(std::uint64_t tick);  // the first line start whose tick >= tick, or data_end_
  void load(std::uint64_t start);                 // the tick that starts at `start` into current_
  std::string pread_some(std::uint64_t at, std::size_t n);
  std::optional<std::uint64_t> newline_before(std::uint64_t at);  // the last '\n' in [data_start_, at)
  bool parse(const std::string& line, RecordedRow& row, std::uint64_t& tick) const;
  bool parse_tick(const std::string& line, std::uint64_t& tick) const;
  void problem(std::uint64_t offset, const std::string& what);
  void note_damage(Damage d);  // once per (tick, offset)
  void check_tail(std::uint64_t size);
  void note_load_damage(std::uint64_t start, std::uint64_t bad_lines, std::uint64_t bad_from,
                        std::uint64_t bad_to, const std::string& bad_first,
                        std::optional<std::uint64_t> next_tick, std::optional<std::uint64_t> too_long);

  std::string path_;
  int fd_ = -1;
  std::size_t max_rows_;
  RowsFile kind_;
  std::size_t columns_ = 0;
  // Index in a row of each fixed column (ROBOT_COLUMNS order: tick id x y theta alive state label parent
  // leader net_force), then of the extra ones.
  std::vector<std::size_t> fixed_;
  std::optional<std::size_t> leds_;  // the `leds` column, when the recording has it
  std::vector<std::size_t> extra_;
  std::vector<std::string> extra_names_;
  std::uint64_t data_start_ = 0;  // the first row's offset
  std::uint64_t data_end_ = 0;    // one past the last newline
  std::uint64_t first_tick_ = 0, last_tick_ = 0;

  RecordedTick current_;
  bool have_current_ = false;
  std::uint64_t current_start_ = 0;  // where current_'s rows start
  std::uint64_t next_start_ = 0;     // where the next tick's rows start (data_end_: none)

  bool every_tick_whole_ = false;
  bool opening_ = true;  // load() at open: the tail's check says what is short, not load()
  std::vector<Damage> damage_;

  std::uint64_t bad_rows_ = 0;
  std::string first_problem_;
  std::uint64_t reads_ = 0;
  std::uint64_t bytes_read_ = 0;
};

}  // namespace swarmform::viewer
