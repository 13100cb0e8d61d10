# Install rules and the CMake package of gdsmc.
#
#   cmake --install <build> --prefix <prefix>
# installs
#   <prefix>/bin/gdsmc                              the host
#   <prefix>/share/gdsmc/gdsmc_plot.py              the plotter that `gdsmc plot` runs
#   <prefix>/include/gdsmc/*.hpp                    the SDK headers
#   <prefix>/lib/gdsmc/plugins/gdsmc_*.so           the in-tree plugins (the host's default search path)
#   <prefix>/lib/cmake/gdsmc/gdsmcConfig.cmake      the package: gdsmc::sdk, gdsmc::gdsmc,
#   <prefix>/lib/cmake/gdsmc/gdsmcConfigVersion.cmake   gdsmc_add_plugin(), GDSMC_EXECUTABLE
#   <prefix>/lib/cmake/gdsmc/gdsmcTargets.cmake
#   <prefix>/lib/cmake/gdsmc/gdsmcPlugin.cmake
#   <prefix>/share/doc/gdsmc/*.md                   the documentation, side by side so that their
#                                                   relative links resolve: user-guide.md,
#                                                   output-format.md, references.md,
#                                                   plugin-author-guide.md, bgk-usf.md, cluster.md,
#                                                   scaling.md, validation/
#   <prefix>/share/doc/gdsmc/examples/              the SDK examples (one project per plugin kind)
# so that an out-of-tree project needs only
#   find_package(gdsmc CONFIG REQUIRED)
#   gdsmc_add_plugin(my_rule SOURCES my_rule.cpp)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(GDSMC_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/gdsmc)
# Fixed to lib/gdsmc/plugins: the host looks for <exe>/../lib/gdsmc/plugins (not lib64).
set(GDSMC_INSTALL_PLUGINDIR lib/gdsmc/plugins)

# The SDK ABI version, read from the header that defines it, for the package's variables.
file(STRINGS ${PROJECT_SOURCE_DIR}/sdk/include/gdsmc/version.hpp _gdsmc_abi REGEX "^#define GDSMC_SDK_ABI_(MAJOR|MINOR) ")
string(REGEX REPLACE ".*GDSMC_SDK_ABI_MAJOR ([0-9]+).*" "\\1" GDSMC_SDK_ABI_MAJOR "${_gdsmc_abi}")
string(REGEX REPLACE ".*GDSMC_SDK_ABI_MINOR ([0-9]+).*" "\\1" GDSMC_SDK_ABI_MINOR "${_gdsmc_abi}")

# SDK headers and the interface target gdsmc::sdk (include dir, C++20, BOOST_DLL_USE_STD_FS,
# Boost headers).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/include/gdsmc DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
set_target_properties(gdsmc_sdk PROPERTIES EXPORT_NAME sdk)
install(TARGETS gdsmc_sdk EXPORT gdsmcTargets)

# The host, exported as gdsmc::gdsmc (an imported executable) for `gdsmc conformance` tests.
install(TARGETS gdsmc EXPORT gdsmcTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The plotter of `gdsmc plot`, found by the host in <exe>/../share/gdsmc (not DATADIR-relocatable:
# the host looks exactly there).
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/gdsmc_plot.py DESTINATION share/gdsmc)

# In-tree plugins: every MODULE library made by gdsmc_add_plugin() under plugins/<kind>/<name>
# (test plugins under tests/test_plugins are not installed).
file(GLOB _gdsmc_plugin_dirs LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/plugins/*/*)
set(_gdsmc_plugin_targets "")
foreach(dir IN LISTS _gdsmc_plugin_dirs)
  if(EXISTS ${dir}/CMakeLists.txt)
    get_property(_targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(t IN LISTS _targets)
      get_target_property(_type ${t} TYPE)
      if(_type STREQUAL "MODULE_LIBRARY" AND t MATCHES "^gdsmc_plugin_")
        list(APPEND _gdsmc_plugin_targets ${t})
      endif()
    endforeach()
  endif()
endforeach()
if(_gdsmc_plugin_targets)
  install(TARGETS ${_gdsmc_plugin_targets} LIBRARY DESTINATION ${GDSMC_INSTALL_PLUGINDIR})
endif()

# The package.
install(EXPORT gdsmcTargets NAMESPACE gdsmc:: DESTINATION ${GDSMC_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/sdk/cmake/gdsmcConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/gdsmcConfig.cmake
                              INSTALL_DESTINATION ${GDSMC_INSTALL_CMAKEDIR}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR GDSMC_INSTALL_PLUGINDIR)
# ABI compatibility is carried by the SDK ABI version (checked when a plugin is loaded); the
# package version follows the gdsmc release: any 0.x (later x.y) with the same major is accepted.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gdsmcConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gdsmcConfig.cmake ${PROJECT_BINARY_DIR}/gdsmcConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/sdk/cmake/gdsmcPlugin.cmake
        DESTINATION ${GDSMC_INSTALL_CMAKEDIR})

# Documentation and examples, installed together in <prefix>/share/doc/gdsmc so that the links
# between them (plugin-author-guide.md -> user-guide.md, output-format.md, references.md; and
# references.md -> bgk-usf.md, validation/) resolve in the installed tree as in docs/. Every one is
# required: a missing document is a build-system error, not a silently incomplete installation.
# An installed document names only what is installed: a repository path (scripts/, configs/,
# tests/, docs/ not installed here, ...) says "in the source tree" in its paragraph, or the
# document says "every path named in this document is in the source tree" in its first paragraph
# (tests/framework/app/cli_help_test.cpp,
# InstalledDocumentation.NamesOnlyWhatIsInstalledOrSaysItIsInTheSourceTree).
set(GDSMC_INSTALLED_DOCS user-guide.md output-format.md references.md plugin-author-guide.md bgk-usf.md
                         cluster.md scaling.md)
foreach(doc IN LISTS GDSMC_INSTALLED_DOCS)
  if(NOT EXISTS ${PROJECT_SOURCE_DIR}/docs/${doc})
    message(FATAL_ERROR "docs/${doc} is missing: it is installed with gdsmc (cmake/gdsmcInstall.cmake)")
  endif()
  install(FILES ${PROJECT_SOURCE_DIR}/docs/${doc} DESTINATION ${CMAKE_INSTALL_DOCDIR})
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/validation/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/validation
        FILES_MATCHING PATTERN "*.md" PATTERN "*.png")  # the reports and the figures they embed
install(DIRECTORY ${PROJECT_SOURCE_DIR}/sdk/examples/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples
        PATTERN "build*" EXCLUDE)
