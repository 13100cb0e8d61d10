# gdsmc_add_plugin(<name> SOURCES <files...> [LINK_LIBRARIES <libs...>])
#
# Builds a gdsmc plugin: a MODULE library named gdsmc_<name>.so, compiled against the gdsmc SDK
# with hidden visibility, written to GDSMC_PLUGIN_OUTPUT_DIR (default: <build>/plugins) so that
# `gdsmc --plugin-path <dir>` or GDSMC_PLUGIN_PATH=<dir> finds it.
function(gdsmc_add_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LINK_LIBRARIES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "gdsmc_add_plugin(${name}): no SOURCES given")
  endif()
  set(target gdsmc_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  if(TARGET gdsmc::sdk)
    target_link_libraries(${target} PRIVATE gdsmc::sdk ${ARG_LINK_LIBRARIES})
  else()
    message(FATAL_ERROR "gdsmc_add_plugin: the gdsmc::sdk target is missing; call find_package(gdsmc CONFIG REQUIRED) first")
  endif()
  if(NOT GDSMC_PLUGIN_OUTPUT_DIR)
    set(GDSMC_PLUGIN_OUTPUT_DIR ${CMAKE_BINARY_DIR}/plugins)
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME gdsmc_${name}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY ${GDSMC_PLUGIN_OUTPUT_DIR})
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  set(GDSMC_LAST_PLUGIN_TARGET ${target} PARENT_SCOPE)
endfunction()
