# trocar_target_warnings(target): the project's warning set; errors when TROCAR_WERROR is on.
function(trocar_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion $<$<BOOL:${TROCAR_WERROR}>:-Werror>)
  # g++ 12 warns -Wrestrict inside std::string's operator+ at -O2/-O3, a known false positive
  # (GCC bug 105651, fixed in g++ 13); it would fail -Werror builds on correct code.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
endfunction()

# trocar_add_module(name SOURCES... DEPS...): one library per folder under src/trocar/,
# exported as trocar::name, headers installed under include/trocar/name.
function(trocar_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(trocar_${name} ${M_SOURCES})
  add_library(trocar::${name} ALIAS trocar_${name})
  set_target_properties(trocar_${name} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(trocar_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(trocar_${name} PUBLIC cxx_std_20)
  target_link_libraries(trocar_${name} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  trocar_target_warnings(trocar_${name})
  install(TARGETS trocar_${name} EXPORT trocarTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/trocar/${name}
    FILES_MATCHING PATTERN "*.h")
endfunction()

# trocar_add_test(name [SHARED_DATA] SOURCES... DEPS...): a GoogleTest binary registered with
# ctest. SHARED_DATA: some of its tests read ../shared/data/meshes through
# tests/support/shared_data.h and skip when it is absent; they carry the ctest label
# `shared_data`, which .ci/run runs once more with the folder hidden (the fresh-clone check).
# REAL_TIME: its tests run real-time threads (the runtime, the viewer); ctest runs them alone
# (RUN_SERIAL), as two such tests side by side on a 2-core machine starve each other. They count
# ticks and steps (a manual clock, frame scripts); rates are the benchmarks'.
function(trocar_add_test name)
  cmake_parse_arguments(T "SHARED_DATA;REAL_TIME" "" "SOURCES;DEPS" ${ARGN})
  if(NOT T_SOURCES)
    return()
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_DEPS} trocar_test_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(${name} PRIVATE
    TROCAR_SHARED_MESHES_DEFAULT="${PROJECT_SOURCE_DIR}/../shared/data/meshes")
  trocar_target_warnings(${name})
  set(labels unit)
  if(T_SHARED_DATA)
    set(labels shared_data)
  endif()
  set(serial FALSE)
  if(T_REAL_TIME)
    set(serial TRUE)
    list(APPEND labels real_time)
  endif()
  # Each test logs its skip for the check_skips test (tests/CMakeLists.txt), which runs after them.
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 TEST_PREFIX "${name}."
    PROPERTIES ENVIRONMENT "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp"
               ENVIRONMENT_MODIFICATION "TROCAR_SKIP_LOG=set:${TROCAR_SKIP_LOG}"
               FIXTURES_REQUIRED trocar_skip_log
               LABELS "${labels}" RUN_SERIAL ${serial})
endfunction()
