# Run by `cmake --install` (SwarmformInstallLauncher.cmake sets the variables): bin/swarm from
# scripts/swarm-installed.in, naming the source tree's commit now (with -dirty when it has changes).
execute_process(COMMAND git -C ${SWARMFORM_ROOT} rev-parse --short=12 HEAD OUTPUT_VARIABLE SWARM_COMMIT
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE _git)
if(NOT _git EQUAL 0 OR SWARM_COMMIT STREQUAL "")
  set(SWARM_COMMIT "unknown")
else()
  execute_process(COMMAND git -C ${SWARMFORM_ROOT} status --porcelain --untracked-files=no
                  OUTPUT_VARIABLE _changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT _changes STREQUAL "")
    string(APPEND SWARM_COMMIT "-dirty")
  endif()
endif()
configure_file(${SWARMFORM_ROOT}/scripts/swarm-installed.in ${SWARM_WORK}/install-launcher/swarm @ONLY)
file(INSTALL ${SWARM_WORK}/install-launcher/swarm DESTINATION ${CMAKE_INSTALL_PREFIX}/${SWARM_BIN_REL}
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
