# The package test (ctest label `package`): what a user of the installed
# package does, with this build.
#   1. cmake --install CAMDYN_BUILD_DIR --prefix WORK_DIR/prefix (copies only;
#      the build is already up to date when ctest runs);
#   2. configures examples/cpp with only that prefix to find camdyn in
#      (find_package(camdyn 0.2 REQUIRED); no package registry), and checks
#      it found the installed camdynConfig.cmake, not the build tree;
#   3. builds it (one small source) and runs it on studies/quickstart.json;
#   4. checks its output: the version and the metrics it prints.
# The prefix and the consumer's build are removed when the test passes.
#
#   cmake -DCAMDYN_BUILD_DIR=... -DCAMDYN_SOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=...
#         -DCXX_COMPILER=... -DBUILD_TYPE=... -DEXPECTED_VERSION=... -P consume_installed.cmake
cmake_minimum_required(VERSION 3.25)

foreach(var CAMDYN_BUILD_DIR CAMDYN_SOURCE_DIR WORK_DIR GENERATOR CXX_COMPILER EXPECTED_VERSION)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "consume_installed: ${var} is not set")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
set(consumer ${WORK_DIR}/consumer)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# step NAME COMMAND...: runs COMMAND; on failure prints its output and stops.
function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "consume_installed: ${name} failed (${code}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("install" ${CMAKE_COMMAND} --install ${CAMDYN_BUILD_DIR} --prefix ${prefix})

step("configure examples/cpp" ${CMAKE_COMMAND} -S ${CAMDYN_SOURCE_DIR}/examples/cpp -B ${consumer}
  -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS ${consumer}/CMakeCache.txt camdyn_dir REGEX "^camdyn_DIR:")
string(REGEX REPLACE "^camdyn_DIR:[A-Z]+=" "" camdyn_dir "${camdyn_dir}")
cmake_path(IS_PREFIX prefix "${camdyn_dir}" NORMALIZE found_installed)
if(NOT found_installed)
  message(FATAL_ERROR "consume_installed: found camdyn in '${camdyn_dir}', not under the prefix ${prefix}")
endif()

step("build examples/cpp" ${CMAKE_COMMAND} --build ${consumer})

# Run from the source tree, where the study's relative profile path resolves.
execute_process(COMMAND ${consumer}/app ${CAMDYN_SOURCE_DIR}/studies/quickstart.json
  WORKING_DIRECTORY ${CAMDYN_SOURCE_DIR} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "consume_installed: examples/cpp app failed (${code}):\n${out}\n${err}")
endif()
foreach(expected
    "camdyn ${EXPECTED_VERSION}"
    "quickstart at 1300 rpm: converged"
    "rigid-model jump speed [0-9.]+ rpm"
    "separation_fraction [0-9.e+-]+"
    "peak_contact_force [0-9.e+-]+ N"
    "impacts [0-9]+"
    "[0-9]+ contact events")
  if(NOT out MATCHES "${expected}")
    message(FATAL_ERROR "consume_installed: the app's output lacks '${expected}':\n${out}")
  endif()
endforeach()
message(STATUS "consume_installed: the installed package works:\n${out}")
file(REMOVE_RECURSE ${WORK_DIR})
