# millnet_add_module(<name> [SOURCES_GLOB <dir>] [PUBLIC_DEPS ...] [PRIVATE_DEPS ...] [INCLUDE_DIR <dir>])
#
# One library target per module, made in the same numbered steps for every module
# (after libigl's igl_add_library):
#   1. collect sources (the module's src/ folder, or an explicit list),
#   2. define the target and its alias millnet::<name>,
#   3. public include dir <module>/include, C++20,
#   4. strict warnings PRIVATE to our own code,
#   5. link dependencies (heavy ones PRIVATE).
# Sources are globbed with CONFIGURE_DEPENDS so that adding a .cpp to a module needs no CMake edit.
function(millnet_add_module name)
  cmake_parse_arguments(M "" "DIR;INCLUDE_DIR;SRC_DIR" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT M_DIR)
    set(M_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
  # 1. sources
  if(NOT M_SOURCES)
    if(NOT M_SRC_DIR)
      set(M_SRC_DIR ${M_DIR}/src)
    endif()
    file(GLOB M_SOURCES CONFIGURE_DEPENDS ${M_SRC_DIR}/*.cpp)
  endif()
  if(NOT M_INCLUDE_DIR)
    set(M_INCLUDE_DIR ${M_DIR}/include)
  endif()
  # 2. target (header-only while a module has no sources yet)
  if(NOT M_SOURCES)
    add_library(millnet_${name} INTERFACE)
    add_library(millnet::${name} ALIAS millnet_${name})
    target_include_directories(millnet_${name} INTERFACE ${M_INCLUDE_DIR})
    target_link_libraries(millnet_${name} INTERFACE ${M_PUBLIC_DEPS} ${M_PRIVATE_DEPS})
    return()
  endif()
  add_library(millnet_${name} STATIC ${M_SOURCES})
  add_library(millnet::${name} ALIAS millnet_${name})
  millnet_unity(millnet_${name})
  # 3. includes, standard
  target_include_directories(millnet_${name} PUBLIC ${M_INCLUDE_DIR})
  target_compile_features(millnet_${name} PUBLIC cxx_std_20)
  # 4. warnings
  millnet_warnings(millnet_${name})
  # 5. deps
  target_link_libraries(millnet_${name} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
endfunction()

# MILLNET_UNITY: the target's sources compiled in batches (CMakeLists.txt says why).
function(millnet_unity target)
  if(MILLNET_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 16)
  endif()
endfunction()

function(millnet_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wnon-virtual-dtor
    -Wold-style-cast -Wcast-align -Wdouble-promotion)
  if(MILLNET_NATIVE)
    # GCC 12 reports "'__Y' may be used uninitialized" inside its own avx512f/avx intrinsics headers
    # wherever Eigen reductions are inlined with -march=native: a known false positive.
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    # GCC 12 at -O2/-O3 reports "__builtin_memcpy … may overlap" for `"text" + std::string` once
    # inlined (GCC bug 105329, fixed in 13): a false positive in libstdc++'s own code.
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(MILLNET_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# millnet_add_test(<module>): one GoogleTest executable per module, test_<module>, built from
# tests/<module>/*.cpp and discovered by ctest. The working directory is the source root so that
# tests can read configs/ and datasets/ with relative paths.
function(millnet_add_test module)
  cmake_parse_arguments(T "" "LABELS" "DEPS" ${ARGN})
  file(GLOB T_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/${module}/*.cpp)
  if(NOT T_SOURCES)
    return()
  endif()
  add_executable(test_${module} ${T_SOURCES})
  millnet_warnings(test_${module})
  target_include_directories(test_${module} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_link_libraries(test_${module} PRIVATE ${T_DEPS} millnet_testing GTest::gtest GTest::gtest_main)
  target_compile_definitions(test_${module} PRIVATE
    MILLNET_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    MILLNET_BINARY_DIR="${PROJECT_BINARY_DIR}"
    MILLNET_EXE="$<TARGET_FILE:millnet>"
    MILLNET_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared")
  add_dependencies(test_${module} millnet)
  millnet_test_pch(test_${module} ${module})
  set(T_LABELS_PROP "")
  if(T_LABELS)
    set(T_LABELS_PROP LABELS ${T_LABELS})
  endif()
  gtest_discover_tests(test_${module}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "OMP_NUM_THREADS=2" ${T_LABELS_PROP})
endfunction()

# MILLNET_TEST_PCH: every test source starts from one precompiled header of what they nearly all
# include (GoogleTest, Eigen/Core: 97 and 68 of the 97 test sources; nlohmann/json and the standard
# headers), built once for test_core and reused by the other test executables. The tests build one
# source at a time (no unity batches: their file-scope helpers share names), so each parsed these
# headers itself: ~1 s of a source's 2–11 s with g++ -O2, ~1.2 s with clang's sanitizer build. One
# header per executable would cost as much as it saves (5–6 s each, measured); test_ingest defines
# MILLNET_HAVE_CAD, which clang's header check refuses to mix, and keeps its own parsing.
option(MILLNET_TEST_PCH "Precompile the headers the test sources share" ON)
function(millnet_test_pch target module)
  if(NOT MILLNET_TEST_PCH OR module STREQUAL "ingest")
    return()
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    # GCC 12 no longer sees libstdc++'s string code as a system header's once it comes from the
    # precompiled header, and reports its known false positives there (bug 105329's family).
    target_compile_options(${target} PRIVATE -Wno-array-bounds -Wno-stringop-overflow)
  endif()
  if(module STREQUAL "core")
    target_precompile_headers(${target} PRIVATE <gtest/gtest.h> <Eigen/Core> <nlohmann/json.hpp> <algorithm>
      <cmath> <filesystem> <fstream> <map> <sstream> <string> <vector>)
  else()
    target_precompile_headers(${target} REUSE_FROM test_core)
  endif()
endfunction()
