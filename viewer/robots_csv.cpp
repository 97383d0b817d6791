#include "viewer/robots_csv.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "common/led_text.hpp"

namespace swarmform::viewer {

namespace {

constexpr std::array<const char*, 11> kFixed = {"tick",  "id",    "x",      "y",      "theta",    "alive",
                                                "state", "label", "parent", "leader", "net_force"};
enum Fixed { kTick, kId, kX, kY, kTheta, kAlive, kState, kLabel, kParent, kLeader, kNetForce };
constexpr std::size_t kChunk = 512;                   // a probe's read: a row is ~60-200 bytes
constexpr std::size_t kBlock = std::size_t{1} << 16;  // a tick's rows are read in blocks of this
constexpr std::size_t kMaxLine = std::size_t{1} << 20;
constexpr int kMaxBadLinesSkipped = 10000;  // looking for a readable line near an offset
constexpr std::uint64_t kAfterAll = std::numeric_limits<std::uint64_t>::max();

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = line.find(',', from);
    out.push_back(
        trim(line.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from)));
    if (comma == std::string_view::npos) return out;
    from = comma + 1;
  }
}

template <typename T>
bool integer(std::string_view s, T& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

bool real(std::string_view s, double& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

bool flag(std::string_view s, bool& out) {
  if (s == "1" || s == "true" || s == "True") return out = true, true;
  if (s == "0" || s == "false" || s == "False") return out = false, true;
  return false;
}

// Damaged bytes as text a page and a terminal can show (the JSON of a frame must be UTF-8).
std::string printable(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  }
  return s;
}

}  // namespace

RobotsCsv::RobotsCsv(std::string path, std::size_t max_rows, RowsFile kind, bool every_tick_whole)
    : path_(std::move(path)), max_rows_(max_rows), kind_(kind), every_tick_whole_(every_tick_whole) {
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(path_ + ": cannot open (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw std::runtime_error(path_ + ": not a regular file");
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  try {
    const std::string head = pread_some(0, kMaxLine);
    const std::size_t nl = head.find('\n');
    if (nl == std::string::npos)
      throw std::runtime_error(path_ + ":1: no header line (expected " + "tick,id,x,y,theta,...)");
    std::vector<std::string> names;
    for (std::string_view n : split(std::string_view(head).substr(0, nl))) names.emplace_back(n);
    columns_ = names.size();
    std::string missing;
    const std::size_t fixed_count = kind_ == RowsFile::Robots ? kFixed.size() : 2;  // tick, id
    for (std::size_t k = 0; k < fixed_count; ++k) {
      const char* f = kFixed[k];
      std::size_t i = 0;
      while (i < names.size() && names[i] != f) ++i;
      if (i == names.size()) missing += std::string(missing.empty() ? "" : ", ") + f;
      fixed_.push_back(i);
    }
    if (!missing.empty())
      throw std::runtime_error(path_ + ":1: the header lacks column(s) " + missing + "; got '" +
                               std::string(head.substr(0, std::min<std::size_t>(nl, 200))) + "'");
    for (std::size_t i = 0; i < names.size(); ++i) {
      bool is_fixed = false;
      for (std::size_t f : fixed_) is_fixed = is_fixed || f == i;
      if (is_fixed) continue;
      if (names[i] == "leds" && kind_ == RowsFile::Robots) {
        leds_ = i;
      } else {
        extra_.push_back(i);
        extra_names_.push_back(names[i]);
      }
    }
    data_start_ = nl + 1;
    // The data ends after the last newline: a half-written last line is not part of it.
    const auto end_nl = newline_before(size);
    data_end_ = end_nl ? *end_nl + 1 : data_start_;
    const Line first = line_from(data_start_);
    if (!first.ok) throw std::runtime_error(path_ + ":2: no complete row that can be read after the header");
    first_tick_ = first.tick;
    Line last = line_before(data_end_);
    for (int i = 0; !last.ok && last.start > data_start_ && i < kMaxBadLinesSkipped; ++i)
      last = line_before(last.start);
    last_tick_ = last.ok ? last.tick : first_tick_;
    if (last_tick_ < first_tick_)
      throw std::runtime_error(path_ + ": the last row's tick " + std::to_string(last_tick_) +
                               " is before the first's " + std::to_string(first_tick_) +
                               ": rows must be in tick order");
    check_tail(size);
    opening_ = false;
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

RobotsCsv::~RobotsCsv() {
  if (fd_ >= 0) ::close(fd_);
}

std::string RobotsCsv::pread_some(std::uint64_t at, std::size_t n) {
  std::string out(n, '\0');
  std::size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd_, out.data() + got, n - got, static_cast<off_t>(at + got));
    ++reads_;
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got += static_cast<std::size_t>(r);
    bytes_read_ += static_cast<std::uint64_t>(r);
  }
  out.resize(got);
  return out;
}

void RobotsCsv::check_tail(std::uint64_t size) {
  // A run that stopped while writing (killed, or the machine went down) leaves a half-written last line, or
  // a last tick short of robots: the recording is shown up to its last whole tick, and says it ends early.
  std::string what;
  if (data_end_ < size) {
    what = "a half-written last line at byte " + std::to_string(data_end_) + " (" +
           std::to_string(size - data_end_) + " bytes)";
  }
  std::uint64_t at = data_end_;
  if (every_tick_whole_ && last_tick_ > first_tick_) {
    at = lower_bound(last_tick_);
    load(at);
    if (have_current_ && current_.rows.size() < max_rows_) {
      const std::uint64_t cut = last_tick_;
      Line before = line_before(at);
      for (int i = 0; !before.ok && before.start > data_start_ && i < kMaxBadLinesSkipped; ++i)
        before = line_before(before.start);
      last_tick_ = before.ok ? before.tick : first_tick_;
      what += std::string(what.empty() ? "" : "; ") + "the last tick " + std::to_string(cut) + " has " +
              std::to_string(current_.rows.size()) + " of " + std::to_string(max_rows_) +
              " robots' rows (from byte " + std::to_string(at) + ")";
    } else {
      at = data_end_;
    }
    current_.rows.clear();
    have_current_ = false;
  }
  if (what.empty()) return;
  note_damage({last_tick_, last_tick_, std::min(at, data_end_), true,
               "ends early (the run stopped while writing): " + what + "; shown up to tick " +
                   std::to_string(last_tick_)});
}

void RobotsCsv::note_damage(Damage d) {
  for (const Damage& k : damage_) {
    if (k.from_tick == d.from_tick && k.offset == d.offset) return;
  }
  damage_.push_back(std::move(d));
}

std::vector<Damage> RobotsCsv::damage_at(std::uint64_t tick) const {
  std::vector<Damage> out;
  for (const Damage& d : damage_) {
    if (d.from_tick <= tick && tick <= d.to_tick) out.push_back(d);
  }
  return out;
}

void RobotsCsv::problem(std::uint64_t offset, const std::string& what) {
  if (++bad_rows_ == 1) first_problem_ = path_ + ": the row at byte " + std::to_string(offset) + ": " + what;
}

bool RobotsCsv::parse_tick(const std::string& line, std::uint64_t& tick) const {
  const std::vector<std::string_view> f = split(line);
  return f.size() == columns_ && integer(f[fixed_[kTick]], tick);
}

bool RobotsCsv::parse(const std::string& line, RecordedRow& row, std::uint64_t& tick) const {
  const std::vector<std::string_view> f = split(line);
  if (f.size() != columns_) return false;
  const auto at = [&](Fixed c) { return f[fixed_[c]]; };
  if (kind_ == RowsFile::Readings) {
    if (!integer(at(kTick), tick) || !integer(at(kId), row.id)) return false;
    row.extra.assign(extra_.size(), std::nan(""));
    for (std::size_t k = 0; k < extra_.size(); ++k) {
      // Empty: a dead robot's (docs/recording-format.md); anything else must be a number.
      if (!f[extra_[k]].empty() && !real(f[extra_[k]], row.extra[k])) return false;
    }
    return true;
  }
  if (!integer(at(kTick), tick) || !integer(at(kId), row.id) || !real(at(kX), row.x) ||
      !real(at(kY), row.y) || !real(at(kTheta), row.theta) || !flag(at(kAlive), row.alive) ||
      !integer(at(kState), row.state) || !integer(at(kLabel), row.label) ||
      !integer(at(kParent), row.parent) || !flag(at(kLeader), row.leader) ||
      !real(at(kNetForce), row.net_force)) {
    return false;
  }
  row.leds = {};
  if (leds_) {
    const auto leds = parse_led_text(f[*leds_]);
    if (!leds) return false;
    row.leds = *leds;
  }
  row.extra.assign(extra_.size(), std::nan(""));
  for (std::size_t k = 0; k < extra_.size(); ++k) {
    double v = 0;
    if (real(f[extra_[k]], v)) row.extra[k] = v;  // empty: not reported yet (docs/recording-format.md)
  }
  return true;
}

RobotsCsv::Line RobotsCsv::line_from(std::uint64_t pos) {
  std::uint64_t start = data_start_;
  if (pos > data_start_) {
    // The first line starting at or after pos: after the first newline at or after pos - 1.
    std::uint64_t at = pos - 1;
    start = data_end_;
    while (at < data_end_) {
      const std::string chunk =
          pread_some(at, static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, data_end_ - at)));
      if (chunk.empty()) break;
      const std::size_t nl = chunk.find('\n');
      if (nl != std::string::npos) {
        start = at + nl + 1;
        break;
      }
      at += chunk.size();
    }
  }
  for (int skipped = 0; start < data_end_ && skipped < kMaxBadLinesSkipped; ++skipped) {
    Line l;
    l.start = start;
    std::string text;
    std::uint64_t at = start;
    std::size_t nl = std::string::npos;
    while (nl == std::string::npos && at < data_end_ && text.size() < kMaxLine) {
      text += pread_some(at, static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, data_end_ - at)));
      at = start + text.size();
      nl = text.find('\n');
    }
    if (nl == std::string::npos) break;  // a line longer than kMaxLine: nothing readable here
    text.resize(nl);
    l.end = start + nl + 1;
    l.ok = parse_tick(text, l.tick);
    if (l.ok) return l;
    start = l.end;  // unreadable: the next one decides
  }
  return Line{data_end_, data_end_, kAfterAll, false};
}

std::optional<std::uint64_t> RobotsCsv::newline_before(std::uint64_t at) {
  // Backwards a chunk at a time from `at` (exclusive) down to the data's start.
  while (at > data_start_) {
    const std::uint64_t from = at > data_start_ + kChunk ? at - kChunk : data_start_;
    const std::string chunk = pread_some(from, static_cast<std::size_t>(at - from));
    if (const std::size_t nl = chunk.rfind('\n'); nl != std::string::npos) return from + nl;
    at = from;
  }
  return std::nullopt;
}

RobotsCsv::Line RobotsCsv::line_before(std::uint64_t end) {
  // The newline at end - 1 closes the line; its start is after the newline before that (or the data's start).
  const auto nl = newline_before(end - 1);
  const std::uint64_t start = nl ? *nl + 1 : data_start_;
  Line l;
  l.start = start;
  l.end = end;
  const std::string text =
      pread_some(start, static_cast<std::size_t>(std::min<std::uint64_t>(end - 1 - start, kMaxLine)));
  l.ok = parse_tick(text, l.tick);
  return l;
}

std::uint64_t RobotsCsv::lower_bound(std::uint64_t tick) {
  // The smallest offset whose next readable line has a tick >= `tick` (ticks never decrease along the file).
  std::uint64_t lo = data_start_, hi = data_end_;
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (line_from(mid).tick >= tick) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return line_from(lo).start;
}

void RobotsCsv::load(std::uint64_t start) {
  current_.rows.clear();
  have_current_ = false;
  std::string buf;
  std::uint64_t buf_at = start;  // file offset of buf[0]
  std::uint64_t read_to = start;
  bool first = true;
  std::uint64_t pos = start;
  // What load() finds wrong on its way (damage, said by the caller's viewer): unreadable lines after the
  // tick's first row, and the tick of the next readable one.
  std::uint64_t bad_lines = 0, bad_from = 0, bad_to = 0;
  std::string bad_first;
  std::optional<std::uint64_t> next_tick;
  bool too_long = false;
  while (pos < data_end_) {
    std::size_t in_buf = static_cast<std::size_t>(pos - buf_at);
    std::size_t nl = buf.find('\n', in_buf);
    if (nl == std::string::npos) {
      buf.erase(0, in_buf);
      buf_at = pos;
      if (buf.size() > kMaxLine) too_long = true;
      if (read_to >= data_end_ || buf.size() > kMaxLine) break;
      const std::string more =
          pread_some(read_to, static_cast<std::size_t>(std::min<std::uint64_t>(kBlock, data_end_ - read_to)));
      if (more.empty()) break;
      buf += more;
      read_to += more.size();
      continue;
    }
    const std::string line = buf.substr(in_buf, nl - in_buf);
    RecordedRow row;
    std::uint64_t tick = 0;
    if (!parse(line, row, tick)) {
      problem(pos, "cannot be read: '" + line.substr(0, 80) + "'");
      if (bad_lines++ == 0) {
        bad_from = pos;
        bad_first = printable(line.substr(0, 60));
      }
      pos = buf_at + nl + 1;
      bad_to = pos;
      continue;
    }
    if (first) {
      current_.tick = tick;
      first = false;
    } else if (tick != current_.tick) {
      next_tick = tick;
      break;
    }
    if (current_.rows.size() < max_rows_) {
      current_.rows.push_back(std::move(row));
    } else {
      problem(pos, "tick " + std::to_string(tick) + " has more than " + std::to_string(max_rows_) +
                       " rows (world.json's robot count)");
    }
    pos = buf_at + nl + 1;
  }
  have_current_ = !first;
  current_start_ = start;
  next_start_ = pos < data_end_ ? pos : data_end_;
  if (have_current_ && !opening_)
    note_load_damage(start, bad_lines, bad_from, bad_to, bad_first, next_tick,
                     too_long ? std::optional<std::uint64_t>(pos) : std::nullopt);
}

void RobotsCsv::note_load_damage(std::uint64_t start, std::uint64_t bad_lines, std::uint64_t bad_from,
                                 std::uint64_t bad_to, const std::string& bad_first,
                                 std::optional<std::uint64_t> next_tick,
                                 std::optional<std::uint64_t> too_long) {
  const std::uint64_t t = current_.tick;
  const bool short_of_robots = every_tick_whole_ && current_.rows.size() < max_rows_;
  if (bad_lines == 0 && !short_of_robots && !too_long) return;
  Damage d;
  d.from_tick = d.to_tick = t;
  d.offset = bad_lines > 0 ? bad_from : too_long ? *too_long : start;
  std::string what;
  if (bad_lines > 0) {
    what = "bytes " + std::to_string(bad_from) + ".." + std::to_string(bad_to) + " cannot be read (" +
           std::to_string(bad_lines) + " line(s), the first '" + bad_first + "')";
    // The ticks between this one and the next readable one are lost in them (in a thinned recording some of
    // those were never written): a seek there shows this tick, and this.
    if (next_tick && *next_tick > t + 1) {
      d.to_tick = *next_tick - 1;
      what +=
          "; no tick after " + std::to_string(t) + " can be read before tick " + std::to_string(*next_tick);
    }
  }
  if (too_long) {
    what += std::string(what.empty() ? "" : "; ") + "a line longer than " + std::to_string(kMaxLine) +
            " bytes at byte " + std::to_string(*too_long) + ": nothing after it is read";
  }
  if (short_of_robots) {
    std::vector<char> seen(max_rows_, 0);
    for (const RecordedRow& r : current_.rows) {
      if (r.id < max_rows_) seen[r.id] = 1;
    }
    std::string missing;
    int listed = 0;
    for (std::size_t id = 0; id < max_rows_ && listed < 10; ++id) {
      if (seen[id]) continue;
      if (listed++ > 0) missing += ' ';
      missing += std::to_string(id);
    }
    if (max_rows_ - current_.rows.size() > 10) missing += " ...";
    what += std::string(what.empty() ? "" : "; ") + "tick " + std::to_string(t) + " has " +
            std::to_string(current_.rows.size()) + " of " + std::to_string(max_rows_) +
            " robots' rows (missing: " + missing + ")";
  }
  note_damage({d.from_tick, d.to_tick, d.offset, false, what});
}

const RecordedTick& RobotsCsv::read(std::uint64_t tick) {
  tick = std::min(tick, last_tick_);  // a last tick left out at open (check_tail) is never shown
  if (have_current_ && tick == current_.tick) return current_;
  if (have_current_ && tick > current_.tick) {
    // Playing forward: the next tick starts where this one ended.
    if (next_start_ >= data_end_) return current_;
    const Line next = line_from(next_start_);
    if (next.ok && next.tick > tick) return current_;
    if (next.ok && next.tick == tick) {
      load(next.start);
      return current_;
    }
  }
  const std::uint64_t at = lower_bound(tick);
  if (at < data_end_) {
    const Line l = line_from(at);
    if (l.ok && l.tick == tick) {
      load(at);
      return current_;
    }
  }
  if (at <= data_start_ || tick < first_tick_) {
    load(data_start_);  // before the recording: its first tick
    return current_;
  }
  // No rows at `tick` (a recording that skips ticks, or past the end): the last tick before it.
  Line before = line_before(at);
  for (int i = 0; !before.ok && before.start > data_start_ && i < kMaxBadLinesSkipped; ++i)
    before = line_before(before.start);
  load(before.ok ? lower_bound(before.tick) : data_start_);
  return current_;
}

}  // namespace swarmform::viewer
