# podid_configure_target(<target>): warnings and sanitizers for podid's own code.
function(podid_configure_target target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(PODID_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
      # GCC 12 at -O3 (the release preset) flags libstdc++'s own string
      # operator+ with a false -Wrestrict (GCC bug 105329): keep it a warning.
      target_compile_options(${target} PRIVATE -Wno-error=restrict)
    endif()
  endif()
endfunction()

if(PODID_SANITIZE)
  # Applied globally so that every object, test and benchmark is instrumented.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# podid_add_module(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates podid_<name> with alias podid::<name>, headers under <dir>/include.
function(podid_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT ARG_SOURCES)
    message(STATUS "podid: module ${name} has no sources; not built")
    return()
  endif()
  add_library(podid_${name} STATIC ${ARG_SOURCES})
  add_library(podid::${name} ALIAS podid_${name})
  set_target_properties(podid_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(podid_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(podid_${name} PUBLIC cxx_std_20)
  target_link_libraries(podid_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  podid_configure_target(podid_${name})
  set_property(GLOBAL APPEND PROPERTY PODID_MODULES podid_${name})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
include(GNUInstallDirs)
