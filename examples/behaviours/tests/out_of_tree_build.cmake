# cmake -DBUILD_DIR=<the product's build> -DEXAMPLES_DIR=<examples/behaviours> -DWORK_DIR=<scratch> -P this
# Installs the product into WORK_DIR/prefix and builds each example behaviour from a clean folder against it,
# as a user would; fails naming the step that failed. WORK_DIR is emptied first and removed on success.
foreach(v BUILD_DIR EXAMPLES_DIR WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "out_of_tree_build.cmake: -D${v}=... is required")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
endfunction()

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
foreach(name aggregation avoidance dispersion flocking foraging seek_light)
  # A copy of the example's folder alone: nothing of the product's tree is in reach.
  file(COPY ${EXAMPLES_DIR}/${name} DESTINATION ${WORK_DIR}/src)
  run("configure ${name}" ${CMAKE_COMMAND} -S ${WORK_DIR}/src/${name} -B ${WORK_DIR}/build-${name}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
  run("build ${name}" ${CMAKE_COMMAND} --build ${WORK_DIR}/build-${name})
  if(NOT EXISTS ${WORK_DIR}/build-${name}/lib${name}.so)
    message(FATAL_ERROR "build ${name}: no lib${name}.so in ${WORK_DIR}/build-${name}")
  endif()
  message(STATUS "${name}: built out of tree against ${WORK_DIR}/prefix")
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
