# `cmake --install` puts the multiray binary and the balancing library under a prefix, the
# installed binary runs, and every example in EXAMPLES builds against the prefix alone
# (find_package(multiray), <multiray/balance.h>; no path into the source tree) and runs.
# Run by CTest: cmake -DBUILD=<build dir> -DPREFIX=<scratch dir> -DEXAMPLES=<examples dir>
# -P install_check.cmake
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${PREFIX}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}): ${err}")
endif()
if(NOT EXISTS "${PREFIX}/bin/multiray")
  message(FATAL_ERROR "no bin/multiray under ${PREFIX}")
endif()
file(GLOB_RECURSE lib "${PREFIX}/*/libmultiray_balance.a")
if(NOT lib)
  message(FATAL_ERROR "no libmultiray_balance.a under ${PREFIX}")
endif()
execute_process(COMMAND "${PREFIX}/bin/multiray" --version RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^multiray [0-9]+\\.[0-9]+\\.[0-9]+")
  message(FATAL_ERROR "the installed multiray --version gave ${rc}: ${out}")
endif()
foreach(example toy_renderer balancer_shootout)
  set(dir "${PREFIX}-build/${example}")
  file(REMOVE_RECURSE "${dir}")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${EXAMPLES}/${example}" -B "${dir}"
                          -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_BUILD_TYPE=Release
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "configuring ${example} against ${PREFIX} failed: ${out}${err}")
  endif()
  execute_process(COMMAND "${CMAKE_COMMAND}" --build "${dir}" RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "building ${example} against ${PREFIX} failed: ${out}${err}")
  endif()
  set(args)
  if(example STREQUAL "toy_renderer")
    set(args hybrid 3)
  endif()
  execute_process(COMMAND "${dir}/${example}" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${example}, built against ${PREFIX}, exited with ${rc}: ${err}")
  endif()
  file(REMOVE_RECURSE "${dir}")
endforeach()
file(REMOVE_RECURSE "${PREFIX}")
