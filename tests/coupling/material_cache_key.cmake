# The material cache's key follows the calibrating code and nothing else (coupling/material_cache.h,
# cmake/write_source_version.cmake): on a copy of the tree's util/, dem/, params/ and fem/ sources,
# the hash written into the generated header stays when the script runs again, when an FE source
# changes and when git's state changes (the copy is no git tree), and moves when a DEM source, a
# calibration source, a module's CMakeLists.txt, the compiler or the flags change.
# Usage: cmake -DSOURCE_DIR=<tree> -DWORK=<scratch folder> -P material_cache_key.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/tree)
foreach(part util dem params fem CMakeLists.txt)
  file(COPY ${SOURCE_DIR}/${part} DESTINATION ${WORK}/tree)
endforeach()

function(calibrating_code_hash compiler flags result)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${WORK}/tree -DOUTPUT=${WORK}/header.h
                          "-DCOMPILER=${compiler}" "-DFLAGS=${flags}"
                          -P ${SOURCE_DIR}/cmake/write_source_version.cmake
                  RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "write_source_version.cmake failed: ${status}")
  endif()
  file(STRINGS ${WORK}/header.h line REGEX "ANTICRACK_CALIBRATION_CODE_SHA256")
  string(REGEX MATCH "\"([0-9a-f]+)\"" _ "${line}")
  string(LENGTH "${CMAKE_MATCH_1}" length)
  if(NOT length EQUAL 64)
    message(FATAL_ERROR "no SHA-256 in the generated header: '${line}'")
  endif()
  set(${result} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

function(expect what before after should_change)
  if(should_change AND before STREQUAL after)
    message(FATAL_ERROR "${what}: the calibrating code's hash did not change (${after})")
  elseif(NOT should_change AND NOT before STREQUAL after)
    message(FATAL_ERROR "${what}: the calibrating code's hash changed (${before} -> ${after})")
  endif()
endfunction()

calibrating_code_hash("GNU 12.2.0" "Release: -O2" reference)
calibrating_code_hash("GNU 12.2.0" "Release: -O2" again)
expect("the same tree again" ${reference} ${again} FALSE)

file(APPEND ${WORK}/tree/fem/CMakeLists.txt "\n# an FE change\n")
file(WRITE ${WORK}/tree/fem/new_solver_unit.cpp "// a new FE unit\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_fem)
expect("an FE change" ${reference} ${after_fem} FALSE)

foreach(changed dem/CMakeLists.txt params/CMakeLists.txt util/CMakeLists.txt CMakeLists.txt)
  file(READ ${WORK}/tree/${changed} original)
  file(APPEND ${WORK}/tree/${changed} "\n# a change\n")
  calibrating_code_hash("GNU 12.2.0" "Release: -O2" after)
  expect("a change to ${changed}" ${reference} ${after} TRUE)
  file(WRITE ${WORK}/tree/${changed} "${original}")
endforeach()

file(GLOB_RECURSE dem_sources ${WORK}/tree/dem/*.cpp)
list(SORT dem_sources)
list(GET dem_sources 0 dem_source)
file(APPEND ${dem_source} "\n// a DEM change\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_dem)
expect("a DEM change" ${reference} ${after_dem} TRUE)
file(REMOVE ${dem_source})
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_removal)
expect("a DEM source removed" ${after_dem} ${after_removal} TRUE)

calibrating_code_hash("GNU 13.1.0" "Release: -O2" other_compiler)
expect("another compiler" ${after_removal} ${other_compiler} TRUE)
calibrating_code_hash("GNU 12.2.0" "Release: -O3" other_flags)
expect("other flags" ${after_removal} ${other_flags} TRUE)
file(REMOVE_RECURSE ${WORK})
message(STATUS "the material cache's key follows the calibrating code")
