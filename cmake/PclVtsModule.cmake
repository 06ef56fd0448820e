# pcl_vts_add_module(<target> EXPORT_NAME <name> SOURCES <files...>)
#
# One library per module folder (src/<module>/), exported as pcl_vts::<name> and
# usable in-tree under the same name (ALIAS). Shared by default (BUILD_SHARED_LIBS, as
# PCL): symbols are hidden unless a header marks them with the module's export macro,
# generated here as <pcl_vts/<module>/export.h> (PCL_VTS_<MODULE>_EXPORT; for the PCL
# adapters <pcl_vts/export.h> and PCL_VTS_EXPORT). A static build defines
# PCL_VTS_<MODULE>_STATIC_DEFINE for itself and its users, so the macros are empty.
# The target is recorded in the global property PCL_VTS_MODULES: that list is what
# cmake/PclVtsInstall.cmake installs, exports as a package component and describes in
# a pkg-config file, with the dependencies read from its link interface. A new module
# needs nothing more than this call and its target_link_libraries.
function(pcl_vts_add_module target)
  cmake_parse_arguments(ARG "" "EXPORT_NAME" "SOURCES" ${ARGN})
  add_library(${target} ${ARG_SOURCES})
  add_library(pcl_vts::${ARG_EXPORT_NAME} ALIAS ${target})

  if(ARG_EXPORT_NAME STREQUAL "pcl_vts")
    set(base_name PCL_VTS)
    set(export_header pcl_vts/export.h)
  else()
    string(TOUPPER "PCL_VTS_${ARG_EXPORT_NAME}" base_name)
    set(export_header pcl_vts/${ARG_EXPORT_NAME}/export.h)
  endif()
  generate_export_header(${target} BASE_NAME ${base_name}
    EXPORT_FILE_NAME ${PROJECT_BINARY_DIR}/include/${export_header})
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "STATIC_LIBRARY")
    target_compile_definitions(${target} PUBLIC ${base_name}_STATIC_DEFINE)
  endif()

  set_target_properties(${target} PROPERTIES
    EXPORT_NAME ${ARG_EXPORT_NAME}
    VERSION ${PROJECT_VERSION}
    # ABI changes with every minor release before 1.0 (PCL: libpcl_common.so.1.13).
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    POSITION_INDEPENDENT_CODE ON
    # An installed library finds its sibling modules beside itself.
    INSTALL_RPATH "${PCL_VTS_LIB_RPATH}")
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  # The libraries are -Wconversion clean (narrowing by explicit casts where the value
  # is known to fit); tools and tests are not held to it yet.
  target_compile_options(${target} PRIVATE ${PCL_VTS_WARNINGS} -Wconversion)
  set_property(GLOBAL APPEND PROPERTY PCL_VTS_MODULES ${target})
endfunction()
