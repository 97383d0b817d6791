// The DDS domain of a test that talks over the network: SWARMFORM_TEST_DOMAIN_BASE (default 100) plus the
// test's own offset, below kTestDomainWindow. Two builds (say Release and the sanitizer build) run their
// tests side by side when their bases lie a window apart. Offsets in use (tests/README.md keeps the table):
//   0 tests/golden/test_golden.py (the multi-process golden runs), 1..15 multiprocess_test (11:
//   wire_endpoints_test), 16..20 paper_multiprocess_test, 21..22 bench_lockstep_smoke, 23..26
//   tests/scripts/test_launcher_e2e.py, 27 tests/bench/test_bench_script.py, 28
//   examples.installed_launcher, 29 example_run_tests' foraging run, 30
//   tests/scripts/test_groups_e2e.py, 36..37 wire_faults_test, 38..39
//   test_launcher_e2e.py's two concurrent runs (the launcher's free-domain picker, given
//   SWARM_DOMAINS=base+38-base+39). 40..43 the abuse tests (40 paper liar and deaf, 41 lockstep flood, 42
//   full disk + end reasons, 43 realtime flood). 44..46 faults_process_test, 47
//   tests/scripts/test_faults_e2e.py. 48..63 the plug-in, agent, hosts, faces, secure and viewer tests
//   (48..51 plug-ins, 52..55 external agents, 56..58 hosts, 59 faces_test (docs/wire.md "Faces"), 60..61
//   secure, 62..63 viewer: 62 tests/viewer/test_viewer_live.py, 63 tests/viewer/test_viewer_runs.py); each
//   area's README or test header says which it took (60..61: tests/scripts/test_secure_e2e.py).
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "common/dds/cyclone_config.hpp"

namespace swarmform::testing {

inline constexpr int kTestDomainWindow = 64;
inline constexpr int kDefaultTestDomainBase = 100;

// Throws (the test fails, naming the variable) when the base is not a number or its window passes kMaxDomain.
inline int test_domain(int offset) {
  int base = kDefaultTestDomainBase;
  if (const char* env = std::getenv("SWARMFORM_TEST_DOMAIN_BASE"); env != nullptr && *env != '\0') {
    std::size_t used = 0;
    try {
      base = std::stoi(env, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    const int highest = static_cast<int>(swarmform::dds::kMaxDomain) - kTestDomainWindow + 1;
    if (used != std::string(env).size() || base < 0 || base > highest) {
      throw std::invalid_argument("SWARMFORM_TEST_DOMAIN_BASE='" + std::string(env) +
                                  "': want an integer 0.." + std::to_string(highest) +
                                  " (each build's tests use " + std::to_string(kTestDomainWindow) +
                                  " domains from it)");
    }
  }
  if (offset < 0 || offset >= kTestDomainWindow)
    throw std::out_of_range("test domain offset out of the window");
  return base + offset;
}

}  // namespace swarmform::testing
