#include "common/process_state.hpp"

#include <fstream>
#include <string>

namespace swarmform {

ProcessState process_state(pid_t pid) {
  if (pid <= 0) return ProcessState::Gone;
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!f || !std::getline(f, stat)) return ProcessState::Gone;
  // "pid (comm) S ...": the command name may hold spaces and parentheses, so the state follows the last ')'.
  const auto close = stat.rfind(')');
  if (close == std::string::npos || close + 2 >= stat.size()) return ProcessState::Gone;
  const char state = stat[close + 2];
  return state == 'Z' || state == 'X' || state == 'x' ? ProcessState::Gone : ProcessState::Present;
}

}  // namespace swarmform
