# swarmform_discover_process_tests(<target> LABEL <label>): the GoogleTest cases of <target>, which start
# world_server and robot_agent processes, registered with ctest in two kinds:
#
# - Cases whose verdict rests on the wall clock (realtime runs, stalls and stops measured against leases and
#   timeouts, a death seen within a second, floods counted per second, the host-load test that brings its own
#   spinners): RUN_SERIAL, alone on the host, and label wallclock (the Release stage runs them).
# - The others (lockstep runs, whose verdict is the host's load's to change in no way: docs/wire.md): one at a
#   time among themselves (RESOURCE_LOCK sf_processes: two worlds' rounds would share the host's CPU at once)
#   but beside a unit or sim test. Alone, a lockstep test leaves most of 2 cores idle while it waits on sockets
#   and clocks; the sanitizer stage spent ~520 of its ~800 s in such serial tests (tests/README.md).
#
# The wall-clock set is chosen by name (gtest filter patterns below): a new test whose verdict needs the host
# to itself says so in its name (Realtime, Stall, Stopped, Timeout, WithinOneSecond) or joins the list.
set(SWARMFORM_WALL_CLOCK_TESTS
    "*Realtime*:*Stall*:*Stopped*:*Timeout*:*WithinOneSecond*:*Spinners*:Abuse.*")

function(swarmform_discover_process_tests target)
  # One label: gtest_discover_tests splits its properties again, and LABELS "a;b" became LABELS a and a
  # property named b (the example runs lost their integration label, timeout and serial run that way). A
  # folder that needs a second label on every test sets the folder's LABELS property.
  cmake_parse_arguments(ARG "" "LABEL" "" ${ARGN})
  # Label wallclock, not LABEL: the sanitizer stage (labels unit, sim, integration) leaves them out, as it leaves
  # out every wall-clock verdict: under the sanitizers each process runs ~3x slower (tests/README.md).
  gtest_discover_tests(${target} TEST_FILTER "${SWARMFORM_WALL_CLOCK_TESTS}"
                       PROPERTIES LABELS wallclock RUN_SERIAL TRUE TIMEOUT 180 DISCOVERY_TIMEOUT 30)
  gtest_discover_tests(${target} TEST_FILTER "*-${SWARMFORM_WALL_CLOCK_TESTS}"
                       PROPERTIES LABELS ${ARG_LABEL} RESOURCE_LOCK sf_processes TIMEOUT 180
                                  DISCOVERY_TIMEOUT 30)
endfunction()
