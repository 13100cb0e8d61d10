# gdsmc_add_plugin(<name> SOURCES <files...> [LINK_LIBRARIES <libs...>]
#                  [CONFORMANCE_ARGS <args...>] [NO_CONFORMANCE_TEST] [NO_INSTALL])
#
# Builds a gdsmc plugin: a MODULE library named gdsmc_<name>.so, compiled against the gdsmc SDK
# (C++20, hidden visibility), written to GDSMC_PLUGIN_OUTPUT_DIR (default: <build>/plugins) so that
# `gdsmc --plugin-path <dir>` or GDSMC_PLUGIN_PATH=<dir> finds it. Sets GDSMC_LAST_PLUGIN_TARGET
# (the target is gdsmc_plugin_<name>) in the caller's scope.
#
# Out of tree (after find_package(gdsmc CONFIG REQUIRED)) it also
#   - adds a CTest test gdsmc_conformance_<name> running `gdsmc conformance <plugin>
#     <CONFORMANCE_ARGS...>` (with enable_testing(); skip it with NO_CONFORMANCE_TEST), and
#   - installs the plugin into <prefix>/lib/gdsmc/plugins (GDSMC_PLUGIN_INSTALL_SUBDIR), where the
#     gdsmc host installed in the same prefix finds it (skip with NO_INSTALL).
function(gdsmc_add_plugin name)
  cmake_parse_arguments(ARG "NO_CONFORMANCE_TEST;NO_INSTALL" "" "SOURCES;LINK_LIBRARIES;CONFORMANCE_ARGS" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "gdsmc_add_plugin(${name}): no SOURCES given")
  endif()
  if(NOT TARGET gdsmc::sdk)
    message(FATAL_ERROR "gdsmc_add_plugin: the gdsmc::sdk target is missing; call find_package(gdsmc CONFIG REQUIRED) first")
  endif()
  set(target gdsmc_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE gdsmc::sdk ${ARG_LINK_LIBRARIES})
  target_compile_features(${target} PRIVATE cxx_std_20)
  if(NOT GDSMC_PLUGIN_OUTPUT_DIR)
    set(GDSMC_PLUGIN_OUTPUT_DIR ${CMAKE_BINARY_DIR}/plugins)
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME gdsmc_${name}
    SUFFIX ".so"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY ${GDSMC_PLUGIN_OUTPUT_DIR})
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(GDSMC_CONFORMANCE_EXECUTABLE AND NOT ARG_NO_CONFORMANCE_TEST)
    add_test(NAME gdsmc_conformance_${name}
             COMMAND ${GDSMC_CONFORMANCE_EXECUTABLE} conformance $<TARGET_FILE:${target}> ${ARG_CONFORMANCE_ARGS})
  endif()
  if(GDSMC_CONFORMANCE_EXECUTABLE AND NOT ARG_NO_INSTALL)
    if(NOT GDSMC_PLUGIN_INSTALL_SUBDIR)
      set(GDSMC_PLUGIN_INSTALL_SUBDIR lib/gdsmc/plugins)
    endif()
    install(TARGETS ${target} LIBRARY DESTINATION ${GDSMC_PLUGIN_INSTALL_SUBDIR})
  endif()
  set(GDSMC_LAST_PLUGIN_TARGET ${target} PARENT_SCOPE)
endfunction()
