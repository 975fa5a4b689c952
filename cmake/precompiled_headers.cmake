# Precompiled headers: the standard library (and GoogleTest for the tests)
# compiled once per build instead of once per file. They are about a third of
# a test file's compile time and a quarter of a library file's; CI builds the
# tree three times (release, asan, tsan) from a clean clone.
#
# Three anchor targets each compile one header; every other target reuses one
# of them (REUSE_FROM), so the header is built three times, not once per
# target. The anchors match the flags of their users, or the compiler ignores
# the header: the library one is PIC (an OBJECT library), the executable ones
# are executables (-fPIE).
#
# PRIVATE to each target: installed headers and a project built against them
# never see these includes. Builds through a compiler launcher (ccache on a
# developer's machine) leave them off, as ccache does not cache compilations
# that use a GCC precompiled header; those builds also catch a missing
# #include that a precompiled header would hide.
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(plc_pch_default OFF)
else()
  set(plc_pch_default ON)
endif()
option(PLC_PCH "Precompiled headers (default: on unless a compiler launcher such as ccache is set)"
       ${plc_pch_default})

set(PLC_PCH_STD_HEADERS <algorithm> <array> <atomic> <chrono> <cstdint> <cstdio> <cstring>
                        <filesystem> <fstream> <functional> <map> <memory> <mutex> <optional>
                        <span> <sstream> <string> <string_view> <thread> <vector>)

# plc_precompile_headers(): gives every C++ target below the project's
# folders its precompiled header. Call once, after every add_subdirectory.
function(plc_precompile_headers)
  if(NOT PLC_PCH)
    return()
  endif()
  # GCC 12 inlines std::string differently when <string> comes from a
  # precompiled header and then warns falsely inside libstdc++
  # (-Wstringop-overflow, -overread, -Warray-bounds on char_traits::copy; GCC bugs
  # 105329, 105651; fixed in 13). The same files compile without a warning
  # without the header, and builds without it (ccache) keep both warnings.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    set(plc_pch_options -Wno-stringop-overflow -Wno-stringop-overread -Wno-array-bounds)
  endif()
  set(anchor ${PROJECT_SOURCE_DIR}/cmake/pch/anchor.cpp)
  add_library(plc_pch_lib OBJECT ${anchor})
  target_precompile_headers(plc_pch_lib PRIVATE ${PLC_PCH_STD_HEADERS})
  add_executable(plc_pch_exe EXCLUDE_FROM_ALL ${anchor})
  target_precompile_headers(plc_pch_exe PRIVATE ${PLC_PCH_STD_HEADERS})
  add_executable(plc_pch_test EXCLUDE_FROM_ALL ${anchor})
  target_link_libraries(plc_pch_test PRIVATE GTest::gtest)
  target_precompile_headers(plc_pch_test PRIVATE <gtest/gtest.h> ${PLC_PCH_STD_HEADERS})
  # The header is only used with the options it was built with (clang
  # refuses an -O1 header in an -O0 file: __OPTIMIZE__).
  target_compile_options(plc_pch_test PRIVATE ${PLC_GTEST_COMPILE_OPTIONS})

  set(dirs ${PROJECT_SOURCE_DIR})
  while(dirs)
    list(POP_FRONT dirs dir)
    get_property(sub DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
    list(APPEND dirs ${sub})
    get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(t ${targets})
      get_target_property(type ${t} TYPE)
      get_target_property(sources ${t} SOURCES)
      if(t MATCHES "^plc_pch_" OR NOT sources OR NOT sources MATCHES "\\.cpp")
        continue()
      endif()
      if(NOT type MATCHES "^(STATIC|SHARED|MODULE|OBJECT)_LIBRARY$|^EXECUTABLE$")
        continue()
      endif()
      target_compile_options(${t} PRIVATE ${plc_pch_options})
      if(type MATCHES "LIBRARY$")
        target_precompile_headers(${t} REUSE_FROM plc_pch_lib)
      elseif(type STREQUAL "EXECUTABLE")
        get_target_property(libs ${t} LINK_LIBRARIES)
        if(libs MATCHES "GTest::gtest")
          target_precompile_headers(${t} REUSE_FROM plc_pch_test)
        else()
          target_precompile_headers(${t} REUSE_FROM plc_pch_exe)
        endif()
      endif()
    endforeach()
  endwhile()
endfunction()
