// The one exception type for bad input (a file, a flag, a field): it names where (file:line) and what is
// wrong, so every front end can print it as `file:line: message` and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace swarmform {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, const std::string& what)
      : std::runtime_error(format(file, line, what)), file_(std::move(file)), line_(line) {}

  const std::string& file() const { return file_; }
  int line() const {
    return line_;
  }  // 1-based; 0 when the problem is the whole file (e.g. it cannot be read)

 private:
  static std::string format(const std::string& file, int line, const std::string& what) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + what : file + ": " + what;
  }
  std::string file_;
  int line_;
};

}  // namespace swarmform
