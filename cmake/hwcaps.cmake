# libnsf_runtime.so once more, built for x86-64-v3 (AVX2, FMA: most x86-64 CPUs since 2015), in
# glibc-hwcaps/x86-64-v3/ beside the baseline copy, in the build tree and where it is installed.
# The ROM's step runs in Eigen, whose vector width is fixed when it is compiled, so the baseline
# copy runs it with SSE alone; glibc's loader (2.33 and later) loads this copy instead on a CPU
# that has x86-64-v3, for every host that finds the library through a search path (its run path,
# LD_LIBRARY_PATH or the system's directories). Same sources, soname and symbols: only -march
# differs. Built from the layers the runtime links (core, mpm, data; nn's torch-free half and rom),
# each target taking the baseline one's properties.
set(NSF_HWCAPS_ARCH x86-64-v3)
set(NSF_HWCAPS_DIR glibc-hwcaps/${NSF_HWCAPS_ARCH})
file(GLOB_RECURSE NSF_HWCAPS_LIB_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/core/*.cpp
     ${CMAKE_SOURCE_DIR}/src/mpm/*.cpp ${CMAKE_SOURCE_DIR}/src/data/*.cpp)
add_library(nsf_hwcaps STATIC ${NSF_HWCAPS_LIB_SOURCES})
add_library(nsf_rom_hwcaps STATIC ${NSF_ROM_SOURCES})
add_library(nsf_runtime_hwcaps SHARED ${NSF_RUNTIME_SOURCES})
foreach(t nsf nsf_rom nsf_runtime)
  foreach(p INCLUDE_DIRECTORIES INTERFACE_INCLUDE_DIRECTORIES COMPILE_DEFINITIONS COMPILE_FEATURES
            INTERFACE_COMPILE_DEFINITIONS INTERFACE_COMPILE_FEATURES LINK_OPTIONS
            CXX_VISIBILITY_PRESET VISIBILITY_INLINES_HIDDEN POSITION_INDEPENDENT_CODE VERSION
            SOVERSION INSTALL_RPATH_USE_LINK_PATH LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
    get_target_property(value ${t} ${p})
    if(NOT value STREQUAL "value-NOTFOUND")
      # The layers below are this copy's: nsf_rom -> nsf_rom_hwcaps, $<LINK_ONLY:nsf> -> ...
      list(TRANSFORM value REPLACE "^(nsf|nsf_rom)$" "\\1_hwcaps")
      list(TRANSFORM value REPLACE "^([$]<LINK_ONLY:)(nsf|nsf_rom)>$" "\\1\\2_hwcaps>")
      list(FILTER value EXCLUDE REGEX "^NSF_BUILD_ARCH=")
      set_property(TARGET ${t}_hwcaps PROPERTY ${p} "${value}")
    endif()
  endforeach()
  get_target_property(options ${t} COMPILE_OPTIONS)
  list(TRANSFORM options REPLACE "^-march=.*" "-march=${NSF_HWCAPS_ARCH}")
  set_property(TARGET ${t}_hwcaps PROPERTY COMPILE_OPTIONS "${options}")
endforeach()
target_compile_definitions(nsf_runtime_hwcaps PRIVATE NSF_BUILD_ARCH="${NSF_HWCAPS_ARCH}")
set_target_properties(nsf_runtime_hwcaps PROPERTIES OUTPUT_NAME nsf_runtime
                      LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/${NSF_HWCAPS_DIR})
# Built with the baseline copy, so that every host linked in the build tree meets both.
add_dependencies(nsf_runtime nsf_runtime_hwcaps)
install(TARGETS nsf_runtime_hwcaps LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/${NSF_HWCAPS_DIR}
        NAMELINK_SKIP)
