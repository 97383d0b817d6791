#include "world_server/run/recorder.hpp"

#include "common/led_text.hpp"
#include "common/sensor_readings.hpp"
#include "world_server/run/end_reason.hpp"
#include "world_server/run/recording_format.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace swarmform::world {

namespace {

constexpr std::size_t kStreamBuffer = 1 << 20;

// Shortest text that reads back to the same double (std::to_chars), so the recording is exact.
void append_double(std::string& out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, res.ptr);
}

template <typename Int>
void append_int(std::string& out, Int v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, res.ptr);
}

[[noreturn]] void fail(const std::string& run_dir, const char* what, int error) {
  throw RecordingError(run_dir + "/" + what + ": cannot write: " + std::strerror(error), error);
}

void write_all(std::FILE* f, const std::string& text, const std::string& run_dir, const char* what) {
  if (f == nullptr) return;
  if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) fail(run_dir, what, errno);
}

}  // namespace

std::FILE* RecordingWriter::open(const std::string& path, const char* mode, std::unique_ptr<char[]>& buffer) {
  std::FILE* f = std::fopen(path.c_str(), mode);
  if (f == nullptr) throw std::runtime_error(path + ": cannot open for writing: " + std::strerror(errno));
  buffer = std::make_unique_for_overwrite<char[]>(kStreamBuffer);
  std::setvbuf(f, buffer.get(), _IOFBF, kStreamBuffer);
  return f;
}

RecordingWriter::RecordingWriter(const std::string& run_dir, std::vector<std::string> extra_columns,
                                 std::uint32_t sensors, std::vector<std::vector<int>> column_of_robot,
                                 std::vector<behaviour::KnownColumns> known)
    : run_dir_(run_dir),
      sensors_(sensors),
      extra_columns_(extra_columns.size()),
      column_of_robot_(std::move(column_of_robot)),
      known_(std::move(known)) {
  std::error_code ec;
  std::filesystem::create_directories(run_dir_, ec);
  if (ec) throw std::runtime_error(run_dir_ + ": cannot create the run directory: " + ec.message());
  robots_ = open(run_dir_ + "/robots.csv", "w", robots_buffer_);
  events_ = open(run_dir_ + "/events.jsonl", "w", events_buffer_);
  log_ = open(run_dir_ + "/world.log", "w", log_buffer_);
  std::string header = std::string(kRobotsCsvHeader) + "," + kLedsColumn;
  for (const std::string& c : extra_columns) header += "," + c;
  write_all(robots_, header + "\n", run_dir_, "robots.csv");
  if (std::fflush(robots_) != 0) fail(run_dir_, "robots.csv", errno);
  if (sensors_ != 0) {
    readings_ = open(run_dir_ + "/readings.csv", "w", readings_buffer_);
    std::string names = kReadingsCsvHeader;
    for (const std::string& c : sensor_reading_columns(sensors_)) names += "," + c;
    write_all(readings_, names + "\n", run_dir_, "readings.csv");
    if (std::fflush(readings_) != 0) fail(run_dir_, "readings.csv", errno);
  }
  reserve_summary_room();
}

void RecordingWriter::reserve_summary_room() {
  const std::string tmp = run_dir_ + "/summary.json.tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return;  // said when the summary is written, if it still cannot be
  const int rc = ::posix_fallocate(fd, 0, static_cast<off_t>(kSummaryRoomBytes));
  ::close(fd);
  if (rc != 0) std::remove(tmp.c_str());  // a disk full already: nothing held back for nothing
}

void RecordingWriter::write_into_room(const std::string& name, const std::string& text) {
  const std::string path = run_dir_ + "/" + name;
  const std::string tmp = path + ".tmp";
  // No O_TRUNC: the blocks reserved at the start are written over, not freed and asked for again.
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) fail(run_dir_, (name + ".tmp").c_str(), errno);
  int error = 0;
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  if (error == 0 && ::ftruncate(fd, static_cast<off_t>(text.size())) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) fail(run_dir_, name.c_str(), error);  // the .tmp and its room stay for another try
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw RecordingError(path + ": cannot write: " + ec.message(), ec.value());
}

RecordingWriter::~RecordingWriter() {
  close_streams();
}

void RecordingWriter::close_streams() {
  for (std::FILE** f : {&robots_, &readings_, &events_, &log_}) {
    if (*f != nullptr) {
      std::fclose(*f);
      *f = nullptr;
    }
  }
}

void RecordingWriter::write_file_atomically(const std::string& name, const std::string& text) {
  const std::string path = run_dir_ + "/" + name;
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) fail(run_dir_, (name + ".tmp").c_str(), errno);
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0;
  const int error = errno;
  if (std::fclose(f) != 0 || !written) {
    std::remove(tmp.c_str());
    fail(run_dir_, name.c_str(), written ? errno : error);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw RecordingError(path + ": cannot write: " + ec.message(), ec.value());
}

void RecordingWriter::write_world(const nlohmann::ordered_json& world) {
  write_file_atomically("world.json", world.dump(2) + "\n");
}

void RecordingWriter::copy_in(const std::string& source, const std::string& name) {
  const std::string path = run_dir_ + "/" + name;
  std::error_code ec;
  std::filesystem::copy_file(source, path + ".tmp", std::filesystem::copy_options::overwrite_existing, ec);
  if (!ec) std::filesystem::rename(path + ".tmp", path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(path + ".tmp", ignored);
    throw RecordingError(path + ": cannot copy " + source + " there: " + ec.message(), ec.value());
  }
}

void RecordingWriter::write_rows(Tick tick, const std::vector<RobotTruth>& robots) {
  row_buffer_.clear();
  for (const auto& r : robots) {
    append_int(row_buffer_, tick);
    row_buffer_.push_back(',');
    append_int(row_buffer_, r.id);
    row_buffer_.push_back(',');
    append_double(row_buffer_, r.pose.x);
    row_buffer_.push_back(',');
    append_double(row_buffer_, r.pose.y);
    row_buffer_.push_back(',');
    append_double(row_buffer_, r.pose.theta);
    row_buffer_.append(r.alive ? ",1," : ",0,");
    append_int(row_buffer_, r.telemetry.state);
    row_buffer_.push_back(',');
    const behaviour::KnownColumns known = r.id < known_.size() ? known_[r.id] : behaviour::KnownColumns{};
    append_int(row_buffer_, known.label_of(r.telemetry));
    row_buffer_.push_back(',');
    append_int(row_buffer_, known.parent_of(r.telemetry));
    row_buffer_.append(known.leader_of(r.telemetry) ? ",1," : ",0,");
    append_double(row_buffer_, known.net_force_of(r.telemetry));
    row_buffer_.push_back(',');
    append_led_text(row_buffer_, r.leds);
    // The behaviour's columns: its values, or empty fields before it has said any (telemetry_check.hpp
    // lets through exactly extra_columns_ values or none).
    const auto& extra = r.telemetry.extra;
    if (r.id < column_of_robot_.size()) {  // robot groups: its own behaviour's columns, the others empty
      for (const int at : column_of_robot_[r.id]) {
        row_buffer_.push_back(',');
        if (at >= 0 && static_cast<std::size_t>(at) < extra.size())
          append_double(row_buffer_, extra[static_cast<std::size_t>(at)]);
      }
    } else {
      for (std::size_t k = 0; k < extra_columns_; ++k) {
        row_buffer_.push_back(',');
        if (k < extra.size()) append_double(row_buffer_, extra[k]);
      }
    }
    row_buffer_.push_back('\n');
  }
  write_all(robots_, row_buffer_, run_dir_, "robots.csv");
  if (++ticks_since_flush_ >= kFlushEveryTicks) flush();
}

void RecordingWriter::write_readings(Tick tick, const World& world) {
  if (readings_ == nullptr) return;
  row_buffer_.clear();
  const std::size_t values = sensor_readings_count(sensors_);
  for (const auto& r : world.robots()) {
    append_int(row_buffer_, tick);
    row_buffer_.push_back(',');
    append_int(row_buffer_, r.id);
    // A dead robot senses nothing: its perception keeps its last readings, which are not this tick's.
    if (r.alive) pack_sensor_readings(world.optional_sensors(r.id), equipped_, sensor_values_);
    const bool whole = r.alive && equipped_ == sensors_;
    for (std::size_t k = 0; k < values; ++k) {
      row_buffer_.push_back(',');
      if (whole) append_double(row_buffer_, sensor_values_[k]);
    }
    row_buffer_.push_back('\n');
  }
  write_all(readings_, row_buffer_, run_dir_, "readings.csv");
}

void RecordingWriter::write_event(const nlohmann::ordered_json& event) {
  write_all(events_, event.dump() + "\n", run_dir_, "events.jsonl");
}

void RecordingWriter::log(Tick tick, const std::string& text) {
  write_all(log_, "tick " + std::to_string(tick) + ": " + text + "\n", run_dir_, "world.log");
}

void RecordingWriter::flush() {
  ticks_since_flush_ = 0;
  const std::pair<std::FILE*, const char*> streams[] = {
      {robots_, "robots.csv"}, {readings_, "readings.csv"}, {events_, "events.jsonl"}, {log_, "world.log"}};
  for (const auto& [f, name] : streams) {
    if (f != nullptr && std::fflush(f) != 0) fail(run_dir_, name, errno);
  }
}

bool RecordingWriter::write_summary(const nlohmann::ordered_json& summary) {
  // The streams' failures were reported when they happened (or are now, by flush): the summary is still
  // written if it can be, so that a run whose robots.csv hit a full disk says so in summary.json.
  try {
    flush();
  } catch (const RecordingError&) {
  }
  close_streams();
  try {
    write_into_room("summary.json", summary_text(summary));
    return false;
  } catch (const RecordingError& e) {
    if (!e.disk_full()) throw;
  }
  // Larger than its room on a full disk (a long run's distortion series, many deaths): the outcome alone,
  // which always fits.
  try {
    write_into_room("summary.json", summary_text(summary_outcome(summary)));
  } catch (const RecordingError&) {
    std::remove((run_dir_ + "/summary.json.tmp").c_str());
    throw;
  }
  return true;
}

}  // namespace swarmform::world
