# `cmake --install` puts the multiray binary and the balancing library under a prefix, and
# the installed binary runs. Run by CTest: cmake -DBUILD=<build dir> -DPREFIX=<scratch dir>
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
file(REMOVE_RECURSE "${PREFIX}")
