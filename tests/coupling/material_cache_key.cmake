# The material cache's key follows the calibrating code and nothing else (coupling/material_cache.h,
# cmake/write_source_version.cmake): on a copy of the tree's sources, the hash written into the
# generated header stays when the script runs again, when the FE solver's model or analyses, the
# pipeline or the app change and when git's state changes (the copy is no git tree); it moves when
# a DEM source, a calibration source, a material model, a module's CMakeLists.txt, the compiler or
# the flags change, and when a unit newly included on the calibration's path changes.
# Usage: cmake -DSOURCE_DIR=<tree> -DWORK=<scratch folder> -P material_cache_key.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/tree)
foreach(part util dem params fem coupling profile app CMakeLists.txt)
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

foreach(changed fem/model/snowpack_model.cpp fem/analysis/dynamic_pst.cpp coupling/pipeline.cpp app/main.cpp)
  file(APPEND ${WORK}/tree/${changed} "\n// a change off the calibration's path\n")
endforeach()
file(WRITE ${WORK}/tree/fem/model/new_solver_unit.cpp "// a new FE unit\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_fem)
expect("changes to the FE solver, the pipeline and the app" ${reference} ${after_fem} FALSE)

foreach(changed dem/CMakeLists.txt params/CMakeLists.txt util/CMakeLists.txt CMakeLists.txt
                coupling/calibrate.cpp coupling/material_handoff.cpp params/calibration.cpp
                fem/material/cohesive_cam_clay.cpp fem/material/material_file.cpp)
  file(READ ${WORK}/tree/${changed} original)
  file(APPEND ${WORK}/tree/${changed} "\n# a change\n")
  calibrating_code_hash("GNU 12.2.0" "Release: -O2" after)
  expect("a change to ${changed}" ${reference} ${after} TRUE)
  file(WRITE ${WORK}/tree/${changed} "${original}")
endforeach()

set(dem_source ${WORK}/tree/dem/core/system.cpp) # the engine's time loop
file(APPEND ${dem_source} "\n// a DEM change\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_dem)
expect("a DEM change" ${reference} ${after_dem} TRUE)
file(REMOVE ${dem_source})
calibrating_code_hash("GNU 12.2.0" "Release: -O2" after_removal)
expect("a DEM source removed" ${after_dem} ${after_removal} TRUE)

# A unit newly included on the calibration's path enters the key by the include alone.
file(WRITE ${WORK}/tree/params/new_law.h "#pragma once\n")
file(WRITE ${WORK}/tree/params/new_law.cpp "// a new law\n")
file(APPEND ${WORK}/tree/params/calibration.cpp "\n#include \"params/new_law.h\"\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" with_new_law)
file(APPEND ${WORK}/tree/params/new_law.cpp "// the law changed\n")
calibrating_code_hash("GNU 12.2.0" "Release: -O2" new_law_changed)
expect("a change to a unit newly on the calibration's path" ${with_new_law} ${new_law_changed} TRUE)

calibrating_code_hash("GNU 13.1.0" "Release: -O2" other_compiler)
expect("another compiler" ${new_law_changed} ${other_compiler} TRUE)
calibrating_code_hash("GNU 12.2.0" "Release: -O3" other_flags)
expect("other flags" ${new_law_changed} ${other_flags} TRUE)
file(REMOVE_RECURSE ${WORK})
message(STATUS "the material cache's key follows the calibrating code")
