// Every Cyclone call's result is checked at once: a negative dds_return_t becomes a DdsError naming the call
// and Cyclone's own reason. Front ends catch it, print it and exit non-zero (never abort, as the examples
// do).
#pragma once

#include <dds/dds.h>

#include <stdexcept>
#include <string>

namespace swarmform::dds {

class DdsError : public std::runtime_error {
 public:
  DdsError(const std::string& call, dds_return_t rc)
      : std::runtime_error(call + ": " + dds_strretcode(rc)), rc_(rc) {}
  dds_return_t code() const { return rc_; }

 private:
  dds_return_t rc_;
};

// Returns `rc` when it is not an error (entities are positive handles, plain calls return DDS_RETCODE_OK).
inline dds_return_t check(dds_return_t rc, const char* call) {
  if (rc < 0) throw DdsError(call, rc);
  return rc;
}

}  // namespace swarmform::dds
