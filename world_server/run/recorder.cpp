#include "world_server/run/recorder.hpp"

#include "world_server/run/recording_format.hpp"

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

void write_all(std::FILE* f, const std::string& text, const char* what) {
  if (f == nullptr) return;
  if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) {
    throw std::runtime_error(std::string("recording: cannot write ") + what + ": " + std::strerror(errno));
  }
}

}  // namespace

std::FILE* RecordingWriter::open(const std::string& path, const char* mode) {
  std::FILE* f = std::fopen(path.c_str(), mode);
  if (f == nullptr) throw std::runtime_error(path + ": cannot open for writing: " + std::strerror(errno));
  std::setvbuf(f, nullptr, _IOFBF, kStreamBuffer);
  return f;
}

RecordingWriter::RecordingWriter(const std::string& run_dir) : run_dir_(run_dir) {
  std::error_code ec;
  std::filesystem::create_directories(run_dir_, ec);
  if (ec) throw std::runtime_error(run_dir_ + ": cannot create the run directory: " + ec.message());
  robots_ = open(run_dir_ + "/robots.csv", "w");
  events_ = open(run_dir_ + "/events.jsonl", "w");
  log_ = open(run_dir_ + "/world.log", "w");
  write_all(robots_, std::string(kRobotsCsvHeader) + "\n", "robots.csv");
  std::fflush(robots_);
}

RecordingWriter::~RecordingWriter() {
  close_streams();
}

void RecordingWriter::close_streams() {
  for (std::FILE** f : {&robots_, &events_, &log_}) {
    if (*f != nullptr) {
      std::fclose(*f);
      *f = nullptr;
    }
  }
}

void RecordingWriter::write_file_atomically(const std::string& name, const std::string& text) {
  const std::string path = run_dir_ + "/" + name;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error(tmp + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}

void RecordingWriter::write_world(const nlohmann::ordered_json& world) {
  write_file_atomically("world.json", world.dump(2) + "\n");
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
    append_int(row_buffer_, r.telemetry.label);
    row_buffer_.push_back(',');
    append_int(row_buffer_, r.telemetry.parent);
    row_buffer_.append(r.telemetry.leader ? ",1," : ",0,");
    append_double(row_buffer_, r.telemetry.net_force);
    row_buffer_.push_back('\n');
  }
  write_all(robots_, row_buffer_, "robots.csv");
  if (++ticks_since_flush_ >= kFlushEveryTicks) flush();
}

void RecordingWriter::write_event(const nlohmann::ordered_json& event) {
  write_all(events_, event.dump() + "\n", "events.jsonl");
}

void RecordingWriter::log(Tick tick, const std::string& text) {
  write_all(log_, "tick " + std::to_string(tick) + ": " + text + "\n", "world.log");
}

void RecordingWriter::flush() {
  for (std::FILE* f : {robots_, events_, log_}) {
    if (f != nullptr) std::fflush(f);
  }
  ticks_since_flush_ = 0;
}

void RecordingWriter::write_summary(const nlohmann::ordered_json& summary) {
  flush();
  close_streams();
  write_file_atomically("summary.json", summary_text(summary));
}

}  // namespace swarmform::world
