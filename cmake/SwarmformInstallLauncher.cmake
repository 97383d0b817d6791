# The launcher in the installed package (docs/behaviour-api.md, "A plug-in in one file"): bin/swarm, the Python
# package under share/swarmform/python, and the data it reads: the exit-code table, the default scenario with
# its shapes, the viewer's page (viewer/CMakeLists.txt). A user with only the prefix and a plug-in runs,
# kills, sweeps, views, exports and judges as from the source tree.
set(_data ${CMAKE_INSTALL_DATADIR}/swarmform)
# bin/swarm names the commit it was installed from (a sweep records it): made at install time, not configure
# time, so that a build configured before the last commits still names the right one.
install(CODE "set(SWARMFORM_ROOT \"${SWARMFORM_ROOT}\")
set(SWARM_DATA_REL \"${_data}\")
set(SWARM_BIN_REL \"${CMAKE_INSTALL_BINDIR}\")
set(SWARM_WORK \"${CMAKE_BINARY_DIR}\")")
install(SCRIPT ${CMAKE_CURRENT_LIST_DIR}/install_swarm_wrapper.cmake)
install(DIRECTORY ${SWARMFORM_ROOT}/scripts/swarmform DESTINATION ${_data}/python
        FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
install(FILES ${SWARMFORM_ROOT}/common/exit_codes.json DESTINATION ${_data}/common)
install(FILES ${SWARMFORM_ROOT}/scenarios/paper.yaml ${SWARMFORM_ROOT}/scenarios/README.md
        DESTINATION ${_data}/scenarios)
install(DIRECTORY ${SWARMFORM_ROOT}/shapes DESTINATION ${_data})
# swarm export --mcap's writer (scripts/mcap/README.md): its @mcap/core is installed beside it by `npm ci` on first
# use (node_modules is not copied: it may hold a build machine's paths).
install(FILES ${SWARMFORM_ROOT}/scripts/mcap/package.json ${SWARMFORM_ROOT}/scripts/mcap/package-lock.json
              ${SWARMFORM_ROOT}/scripts/mcap/write.mjs ${SWARMFORM_ROOT}/scripts/mcap/read.mjs
              ${SWARMFORM_ROOT}/scripts/mcap/README.md
        DESTINATION ${_data}/scripts/mcap)
