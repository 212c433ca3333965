# tricot_engine(NAME DEPS...): one library per engine from src/NAME/*.cpp, public headers in
# include/tricot/NAME. Dependencies given after PRIVATE stay private (STYLE.md §1).
function(tricot_engine name)
  cmake_parse_arguments(ARG "" "" "PUBLIC;PRIVATE" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(NOT sources)  # an engine whose first source has not landed yet
    set(sources ${CMAKE_CURRENT_BINARY_DIR}/empty.cpp)
    file(WRITE ${sources} "")
  endif()
  add_library(tricot_${name} STATIC ${sources})
  if(TRICOT_PYTHON)
    # The Python module (python/) is a shared object that links these libraries: position-independent
    # code (thread-locals included), with -fno-semantic-interposition so that GCC still inlines and
    # calls the libraries' own functions directly, as in the executables.
    set_target_properties(tricot_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(tricot_${name} PRIVATE -fno-semantic-interposition)
  endif()
  target_include_directories(tricot_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include
                                            PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(tricot_${name} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
endfunction()

# tricot_tests(ENGINE LIBS...): tests/ENGINE/*_test.cpp. Files ending in _slow_test.cpp get the ctest
# label `slow`, *_regression_test.cpp `regression`, all others `unit`. One executable per label.
function(tricot_tests engine)
  file(GLOB all CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cpp)
  foreach(label unit regression slow)
    set(files)
    foreach(f ${all})
      get_filename_component(n ${f} NAME)
      if(n MATCHES "_slow_test\\.cpp$")
        set(l slow)
      elseif(n MATCHES "_regression_test\\.cpp$")
        set(l regression)
      else()
        set(l unit)
      endif()
      if(l STREQUAL label)
        list(APPEND files ${f})
      endif()
    endforeach()
    if(files)
      set(exe ${engine}_${label}_tests)
      add_executable(${exe} ${files})
      target_link_libraries(${exe} PRIVATE ${ARGN} tricot_testing GTest::gtest GTest::gmock GTest::gtest_main)
      # ctest runs two test processes at once on CI's two cores: OpenMP threads that busy-wait between
      # parallel regions would then steal the other process's core (measured 2x slower), so they sleep.
      gtest_discover_tests(${exe} DISCOVERY_MODE PRE_TEST
                           PROPERTIES LABELS ${label} ENVIRONMENT OMP_WAIT_POLICY=passive
                           WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR} DISCOVERY_TIMEOUT 60)
    endif()
  endforeach()
endfunction()

# tricot_benchmark(NAME LIBS...): bench/NAME_benchmark.cpp, built by `make bench` only.
function(tricot_benchmark name)
  add_executable(${name}_benchmark EXCLUDE_FROM_ALL ${CMAKE_CURRENT_SOURCE_DIR}/${name}_benchmark.cpp)
  target_link_libraries(${name}_benchmark PRIVATE ${ARGN} benchmark::benchmark benchmark::benchmark_main)
  add_dependencies(benchmarks ${name}_benchmark)
endfunction()
