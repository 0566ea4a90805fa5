# Sanitizer and fuzzing flags for every target; included before the first target is made.
#   MULTIRAY_SANITIZE  ASan + UBSan, plus -fsanitize=float-cast-overflow when the compiler
#                      has it (GCC's -fsanitize=undefined leaves that check out; clang's
#                      includes it).
#   MULTIRAY_FUZZ      clang only: libFuzzer coverage, ASan, UBSan and float-cast-overflow on
#                      everything, every UBSan report fatal, and the targets in fuzz/
#                      (fuzz/README.md).
include(CheckCXXCompilerFlag)

if(MULTIRAY_SANITIZE)
  set(_multiray_sanitizers address,undefined)
  set(CMAKE_REQUIRED_LINK_OPTIONS -fsanitize=float-cast-overflow)  # links libubsan too
  check_cxx_compiler_flag(-fsanitize=float-cast-overflow MULTIRAY_HAS_FLOAT_CAST_OVERFLOW)
  unset(CMAKE_REQUIRED_LINK_OPTIONS)
  if(MULTIRAY_HAS_FLOAT_CAST_OVERFLOW)
    string(APPEND _multiray_sanitizers ",float-cast-overflow")
  endif()
  add_compile_options(-fsanitize=${_multiray_sanitizers} -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${_multiray_sanitizers})
endif()

if(MULTIRAY_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "MULTIRAY_FUZZ=ON needs clang for libFuzzer: use the fuzz preset or "
                        "-DCMAKE_CXX_COMPILER=clang++-15 (fuzz/README.md)")
  endif()
  set(_multiray_fuzz_sanitizers address,undefined,float-cast-overflow)
  # fuzzer-no-link: coverage instrumentation only; the fuzz targets link libFuzzer itself.
  add_compile_options(-fsanitize=fuzzer-no-link,${_multiray_fuzz_sanitizers}
                      -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${_multiray_fuzz_sanitizers})
endif()
