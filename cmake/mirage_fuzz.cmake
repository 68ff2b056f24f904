# libFuzzer targets and their seed corpora (docs: scripts/run-fuzz).
#
# mirage_add_fuzz(<name> SOURCES <files...> LIBS <targets...> CORPUS <dir> [MAX_LEN <bytes>]
#                 [INCLUDES <dirs...>])
# registers one LLVMFuzzerTestOneInput entry point and its committed corpus of valid inputs.
#  - MIRAGE_FUZZ=ON (Clang): <name> is a libFuzzer executable; the target `mirage_fuzz` builds
#    them all (and only the libraries they link), and <build>/fuzz-targets.tsv lists name,
#    executable, corpus and -max_len for scripts/run-fuzz.
#  - otherwise: <name>_seeds replays the corpus through the entry point once, a ctest test
#    labelled unit, so every build (and `make asan`) runs the seeds and keeps the target compiling.
if(MIRAGE_FUZZ)
  add_custom_target(mirage_fuzz)
endif()

function(mirage_add_fuzz name)
  cmake_parse_arguments(F "" "CORPUS;MAX_LEN" "SOURCES;LIBS;INCLUDES" ${ARGN})
  if(NOT F_SOURCES OR NOT F_CORPUS)
    message(FATAL_ERROR "mirage_add_fuzz(${name}): SOURCES and CORPUS are required")
  endif()
  if(NOT F_MAX_LEN)
    set(F_MAX_LEN 4096)
  endif()
  cmake_path(ABSOLUTE_PATH F_CORPUS NORMALIZE)
  file(GLOB seeds ${F_CORPUS}/*)
  if(NOT seeds)
    message(FATAL_ERROR "mirage_add_fuzz(${name}): no seeds in ${F_CORPUS} (committed?)")
  endif()
  if(MIRAGE_FUZZ)
    set(exe ${name})
    add_executable(${exe} ${F_SOURCES})
    target_link_options(${exe} PRIVATE -fsanitize=fuzzer)
    add_dependencies(mirage_fuzz ${exe})
    set_property(GLOBAL APPEND PROPERTY MIRAGE_FUZZ_LIST
                 "${name}\t${CMAKE_CURRENT_BINARY_DIR}/${exe}\t${F_CORPUS}\t${F_MAX_LEN}")
  else()
    set(exe ${name}_seeds)
    add_executable(${exe} ${F_SOURCES} ${PROJECT_SOURCE_DIR}/tests/testing/fuzz_replay_main.cpp)
    add_test(NAME ${exe} COMMAND ${exe} ${F_CORPUS})
    set_tests_properties(${exe} PROPERTIES LABELS unit)
  endif()
  target_link_libraries(${exe} PRIVATE ${F_LIBS})
  target_include_directories(${exe} PRIVATE ${PROJECT_SOURCE_DIR}/tests/testing ${F_INCLUDES})
  target_compile_definitions(${exe} PRIVATE MIRAGE_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  mirage_set_warnings(${exe})
endfunction()

# Writes <build>/fuzz-targets.tsv (call once, after every mirage_add_fuzz).
function(mirage_write_fuzz_list)
  get_property(entries GLOBAL PROPERTY MIRAGE_FUZZ_LIST)
  list(JOIN entries "\n" text)
  file(WRITE ${CMAKE_BINARY_DIR}/fuzz-targets.tsv "${text}\n")
endfunction()
