# The replay build of the fuzz targets (included by fuzz/CMakeLists.txt when MULTIRAY_FUZZ
# is off): each target's source with replay_main.cpp instead of libFuzzer, compiled like
# the rest of the tree (GCC, the build's flags and sanitizers), linked with Debian's shared
# tinygltf, tinyobjloader and stb as the renderer is (the fuzz build's thirdparty_*.cpp
# exist only to instrument those). ctest runs each one on its seed corpus:
#   FuzzReplay.seeds     fills <build>/fuzz/seeds/ with fuzz/seed-corpus.sh (the corpora the
#                        libFuzzer runs start from: fuzz/corpus/, assimp-testmodels and
#                        ../shared/data/ when installed or present); a fixture of the others
#   FuzzReplay.<target>  every input of seeds/<target>/ once; any finding fails it

add_library(multiray_fuzz_replay_main OBJECT replay_main.cpp)
# -O1 for the harnesses, as for the test files (tests/CMakeLists.txt): they are glue, and
# the code they drive keeps the library's own flags. Debug and sanitizer builds keep theirs.
set(_multiray_replay_flags $<$<CONFIG:Release>:-O1>)
target_compile_options(multiray_fuzz_replay_main PRIVATE ${_multiray_replay_flags})
target_compile_options(multiray_fuzz_support PRIVATE ${_multiray_replay_flags})

set(MULTIRAY_FUZZ_SEEDS ${CMAKE_CURRENT_BINARY_DIR}/seeds)
add_test(NAME FuzzReplay.seeds
         COMMAND sh -c "rm -rf \"$0\" && exec sh \"$1\" \"$0\"" ${MULTIRAY_FUZZ_SEEDS}
                 ${CMAKE_CURRENT_SOURCE_DIR}/seed-corpus.sh)
set_tests_properties(FuzzReplay.seeds PROPERTIES
  FIXTURES_SETUP multiray_fuzz_seeds
  ENVIRONMENT "MULTIRAY_SHARED_DATA_DIR=${MULTIRAY_SHARED_DATA_DIR};MULTIRAY_ASSIMP_MODELS_DIR=${MULTIRAY_ASSIMP_MODELS_DIR}")

# multiray_add_replay_test(NAME EXECUTABLE FLAGS...): FuzzReplay.NAME, EXECUTABLE on
# seeds/NAME/.
function(multiray_add_replay_test name executable)
  add_test(NAME FuzzReplay.${name} COMMAND ${executable} ${ARGN} ${MULTIRAY_FUZZ_SEEDS}/${name})
  set_tests_properties(FuzzReplay.${name} PROPERTIES
    FIXTURES_REQUIRED multiray_fuzz_seeds SKIP_RETURN_CODE 77)
endfunction()

# multiray_add_fuzzer(NAME SOURCE LIBS...): the executable fuzz_replay_NAME and its test.
function(multiray_add_fuzzer name source)
  add_executable(fuzz_replay_${name} ${source} $<TARGET_OBJECTS:multiray_fuzz_replay_main>)
  target_link_libraries(fuzz_replay_${name} PRIVATE multiray_fuzz_support ${ARGN})
  target_compile_options(fuzz_replay_${name} PRIVATE ${_multiray_replay_flags})
  multiray_add_replay_test(${name} fuzz_replay_${name})
endfunction()

# multiray_add_replay_loader(LIBS... FORMATS EXT...): the loader target built once,
# fuzz_replay_loader, and one test per format, given its extension as -ext=.EXT (the
# libFuzzer build makes one executable per format instead).
function(multiray_add_replay_loader)
  cmake_parse_arguments(ARG "" "" "FORMATS" ${ARGN})
  add_executable(fuzz_replay_loader fuzz_loader.cpp $<TARGET_OBJECTS:multiray_fuzz_replay_main>)
  target_link_libraries(fuzz_replay_loader PRIVATE multiray_fuzz_support
                        ${ARG_UNPARSED_ARGUMENTS})
  target_compile_options(fuzz_replay_loader PRIVATE ${_multiray_replay_flags})
  foreach(format ${ARG_FORMATS})
    multiray_add_replay_test(${format} fuzz_replay_loader -ext=.${format})
  endforeach()
endfunction()
