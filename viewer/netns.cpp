#include "viewer/netns.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace swarmform::viewer {

void enter_network_namespace(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    throw std::invalid_argument("--netns " + name + ": want the name of a namespace of `ip netns list`");
  const std::string path = "/run/netns/" + name;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    throw std::runtime_error("--netns " + name + ": cannot open " + path + ": " + std::strerror(errno) +
                             " (is it in `ip netns list`?)");
  }
  const int rc = ::setns(fd, CLONE_NEWNET);
  const int err = errno;
  ::close(fd);
  if (rc != 0) {
    throw std::runtime_error("--netns " + name + ": cannot enter it: " + std::strerror(err) +
                             (err == EPERM ? " (needs root)" : ""));
  }
}

}  // namespace swarmform::viewer
