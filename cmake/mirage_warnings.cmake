# GCC 12 reports a false maybe-uninitialized inside its own AVX-512 intrinsics header whenever
# Eigen's AVX-512 code is inlined (_mm512_undefined_* self-initialise; GCC bug 105593, fixed in
# GCC 13). Where -march=native enables AVX-512 under GCC < 13 that warning is off; everywhere
# else it stays an error.
set(MIRAGE_GCC_AVX512_FALSE_WARNING OFF)
if(MIRAGE_NATIVE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU"
   AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  include(CheckCXXSourceCompiles)
  set(CMAKE_REQUIRED_FLAGS -march=native)
  check_cxx_source_compiles("#ifndef __AVX512F__\n#error no AVX-512\n#endif\nint main() {}"
                            MIRAGE_NATIVE_HAS_AVX512)
  unset(CMAKE_REQUIRED_FLAGS)
  set(MIRAGE_GCC_AVX512_FALSE_WARNING ${MIRAGE_NATIVE_HAS_AVX512})
endif()

# Warnings and sanitizers for Mirage's own targets only (never global flags).
function(mirage_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wconversion -Wimplicit-fallthrough)
  # Clang's -Wconversion includes -Wsign-conversion, which g++ leaves off for C++: one warning
  # set for both compilers.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    target_compile_options(${target} PRIVATE -Wno-sign-conversion)
  endif()
  # No code reads errno after a math call; without this, sqrt/floor/lround cannot be inlined
  # in the per-pulse loops. No code unmasks floating-point traps or reads the exception flags;
  # without -fno-trapping-math GCC will not compute both sides of a select, and a loop with one
  # (exp_poly's range checks) stays scalar. Neither changes a result.
  target_compile_options(${target} PRIVATE -fno-math-errno -fno-trapping-math)
  if(MIRAGE_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
  if(MIRAGE_GCC_AVX512_FALSE_WARNING)
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
  if(MIRAGE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(MIRAGE_FUZZ)
    # Coverage for libFuzzer in every Mirage target (libraries included), ASan + UBSan; a UB
    # report aborts so libFuzzer saves the input. Fuzz executables add -fsanitize=fuzzer. Line
    # tables are all the sanitizer reports need, and compile and link faster than full -g (CI).
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link,address,undefined
                                             -fno-sanitize-recover=undefined -fno-omit-frame-pointer
                                             -gline-tables-only)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
  if(MIRAGE_SANITIZE)
    # UBSan without its null and alignment checks: together they were about a third of g++'s
    # time on a heavy file; ASan reports a null dereference itself, and the fuzz build (Clang,
    # every parser of outside bytes) keeps both checks. docs/testing.md section 3.
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize=null,alignment
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# A Mirage library: mirage_<name> with alias mirage::<name>.
function(mirage_add_library name)
  add_library(mirage_${name} ${ARGN})
  add_library(mirage::${name} ALIAS mirage_${name})
  target_include_directories(mirage_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
  mirage_set_warnings(mirage_${name})
endfunction()

# A static library built again without -march=native and without sanitizers, for binaries that
# run elsewhere than the build host (the SocketCAN test binary boots under qemu's TCG CPU, which
# lacks the host's vector extensions). mirage_add_portable_library(<name> <sources...>)
function(mirage_add_portable_library name)
  add_library(mirage_${name}_portable STATIC ${ARGN})
  target_include_directories(mirage_${name}_portable PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_compile_options(mirage_${name}_portable PRIVATE -Wall -Wextra -Wconversion
                         -Wimplicit-fallthrough -fno-math-errno -fno-trapping-math)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    target_compile_options(mirage_${name}_portable PRIVATE -Wno-sign-conversion)
  endif()
  if(MIRAGE_WERROR)
    target_compile_options(mirage_${name}_portable PRIVATE -Werror)
  endif()
endfunction()
