# gdsmc_add_plugin(<name> SOURCES <files...> [LINK_LIBRARIES <libs...>]
#                  [CONFORMANCE_ARGS <args...>] [CONFORMANCE_PARAMS <files.yaml...>]
#                  [NO_CONFORMANCE_TEST] [NO_INSTALL] [NO_DEFAULT_OPTIMIZATION])
#
# Builds a gdsmc plugin: a MODULE library named gdsmc_<name>.so, compiled against the gdsmc SDK
# (C++20, hidden visibility), written to GDSMC_PLUGIN_OUTPUT_DIR (default: <build>/plugins) so that
# `gdsmc --plugin-path <dir>` or GDSMC_PLUGIN_PATH=<dir> finds it. Sets GDSMC_LAST_PLUGIN_TARGET
# (the target is gdsmc_plugin_<name>) in the caller's scope.
#
# Optimisation: the SDK compiles the whole per-cell DSMC loop into the plugin, so a plugin built
# without optimisation runs several times slower than the same physics in tree. When the project
# sets no build type (CMAKE_BUILD_TYPE empty, a single-configuration generator) and no -O flag in
# CMAKE_CXX_FLAGS, the plugin gets the flags of the in-tree Release build: -O3 -DNDEBUG. The
# author's own CMAKE_BUILD_TYPE (Debug, RelWithDebInfo, ...) or -O flag always wins; turn the
# default off for one plugin with NO_DEFAULT_OPTIMIZATION, or for all with
# -DGDSMC_PLUGIN_DEFAULT_OPTIMIZATION=OFF. (Multi-configuration generators: choose --config.)
#
# Out of tree (after find_package(gdsmc CONFIG REQUIRED)) it also
#   - adds a CTest test gdsmc_conformance_<name> running `gdsmc conformance <plugin>
#     <CONFORMANCE_ARGS...>` (with enable_testing(); skip it with NO_CONFORMANCE_TEST), and one
#     more, gdsmc_conformance_<name>_<stem>, for each parameter set <stem>.yaml of
#     CONFORMANCE_PARAMS (a YAML mapping name: value, relative to the current source directory),
#     running the same command with `--params <file>`, and
#   - installs the plugin into <prefix>/lib/gdsmc/plugins (GDSMC_PLUGIN_INSTALL_SUBDIR), where the
#     gdsmc host installed in the same prefix finds it (skip with NO_INSTALL).
option(GDSMC_PLUGIN_DEFAULT_OPTIMIZATION
       "gdsmc_add_plugin: build plugins with -O3 -DNDEBUG when the project sets no build type" ON)

function(gdsmc_add_plugin name)
  cmake_parse_arguments(ARG "NO_CONFORMANCE_TEST;NO_INSTALL;NO_DEFAULT_OPTIMIZATION" ""
                        "SOURCES;LINK_LIBRARIES;CONFORMANCE_ARGS;CONFORMANCE_PARAMS" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "gdsmc_add_plugin(${name}): no SOURCES given")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(WARNING "gdsmc_add_plugin(${name}): ignoring unknown arguments: ${ARG_UNPARSED_ARGUMENTS}")
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
  # The in-tree Release flags when the author chose nothing (see the header).
  get_property(multi_config GLOBAL PROPERTY GENERATOR_IS_MULTI_CONFIG)
  if(GDSMC_PLUGIN_DEFAULT_OPTIMIZATION AND NOT ARG_NO_DEFAULT_OPTIMIZATION AND NOT multi_config
     AND NOT CMAKE_BUILD_TYPE AND NOT " ${CMAKE_CXX_FLAGS} " MATCHES " -O")
    target_compile_options(${target} PRIVATE -O3)
    target_compile_definitions(${target} PRIVATE NDEBUG)
  endif()
  if(GDSMC_CONFORMANCE_EXECUTABLE AND NOT ARG_NO_CONFORMANCE_TEST)
    add_test(NAME gdsmc_conformance_${name}
             COMMAND ${GDSMC_CONFORMANCE_EXECUTABLE} conformance $<TARGET_FILE:${target}> ${ARG_CONFORMANCE_ARGS})
    foreach(params IN LISTS ARG_CONFORMANCE_PARAMS)
      get_filename_component(params_file ${params} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
      get_filename_component(stem ${params} NAME_WE)
      add_test(NAME gdsmc_conformance_${name}_${stem}
               COMMAND ${GDSMC_CONFORMANCE_EXECUTABLE} conformance $<TARGET_FILE:${target}> ${ARG_CONFORMANCE_ARGS}
                       --params ${params_file})
    endforeach()
  endif()
  if(GDSMC_CONFORMANCE_EXECUTABLE AND NOT ARG_NO_INSTALL)
    if(NOT GDSMC_PLUGIN_INSTALL_SUBDIR)
      set(GDSMC_PLUGIN_INSTALL_SUBDIR lib/gdsmc/plugins)
    endif()
    install(TARGETS ${target} LIBRARY DESTINATION ${GDSMC_PLUGIN_INSTALL_SUBDIR})
  endif()
  set(GDSMC_LAST_PLUGIN_TARGET ${target} PARENT_SCOPE)
endfunction()
