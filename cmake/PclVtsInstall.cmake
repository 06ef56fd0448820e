# `cmake --install build --prefix P`: headers, the module libraries, the tools, the
# CMake package (find_package(pcl_vts [COMPONENTS <module>...])) and one pkg-config file
# per module. Everything is found relative to P: the package by @PACKAGE_INIT@ and the
# exported targets' _IMPORT_PREFIX, the .pc files by ${pcfiledir}, the libraries by
# $ORIGIN. Nothing here names a module: every target made by pcl_vts_add_module
# (cmake/PclVtsModule.cmake) is installed, exported and described, and what its users
# must find is read from its link interface (pcl_vts_describe_link_item below).
include(CMakePackageConfigHelpers)

set(PCL_VTS_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/pcl_vts)
get_property(PCL_VTS_MODULES GLOBAL PROPERTY PCL_VTS_MODULES)

# Two install components, as a distribution splits them: Runtime (the versioned
# shared libraries, pcd_to_mesh) and Development (headers, the .so links, static
# libraries, CMake and pkg-config files): `cmake --install build --component Runtime`.
# `make package` puts both in one .deb.
install(TARGETS ${PCL_VTS_MODULES} EXPORT pcl_vtsTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Runtime
          NAMELINK_COMPONENT Development
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Development)
# The public headers (private ones live beside their sources in src/) and the
# generated export headers.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/pcl_vts ${PROJECT_BINARY_DIR}/include/pcl_vts
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT Development)
# The user tools, named: pcd_to_mesh and, when MPI was found, pcd_to_mesh_mpi (the
# README's list). Other executables (docs_pictures, compare_methods, benchmarks,
# tests) are never installed.
foreach(tool pcd_to_mesh pcd_to_mesh_mpi)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime)
  endif()
endforeach()
install(EXPORT pcl_vtsTargets NAMESPACE pcl_vts:: FILE pcl_vtsTargets.cmake
        DESTINATION ${PCL_VTS_CMAKE_INSTALL_DIR} COMPONENT Development)

# ---- What one item of a module's INTERFACE_LINK_LIBRARIES asks of its users ------------
# Sets, in the caller:
#   item_private  ON for $<LINK_ONLY:x> (a static library's private dependency)
#   item_module   the export name of a pcl_vts module, or empty
#   item_package  the package to find_dependency() (PCL, Boost, Threads, GDAL, ...)
#   item_component  its component, if any (PCL's io, Boost's program_options)
#   item_pc       the pkg-config module that provides it, or empty
#   item_libs     link flags where no pkg-config module does (-pthread, -lm)
function(pcl_vts_describe_link_item item)
  set(private OFF)
  set(module "")
  set(package "")
  set(component "")
  set(pc "")
  set(libs "")
  if(item MATCHES "^\\$<LINK_ONLY:(.*)>$")
    set(private ON)
    set(item "${CMAKE_MATCH_1}")
  endif()
  if(item MATCHES "^\\$<INSTALL_INTERFACE:(.*)>$")
    set(item "${CMAKE_MATCH_1}")
  endif()
  if(TARGET "${item}")
    get_target_property(aliased ${item} ALIASED_TARGET)
    if(aliased)
      set(item ${aliased}) # pcl_vts::io -> pcl_vts_io
    endif()
  endif()
  if(item MATCHES "^\\$<BUILD_INTERFACE:" OR item STREQUAL "")
    # Not part of the installed interface.
  elseif(item MATCHES "^\\$<")
    message(WARNING "pcl_vts install: cannot describe the link item '${item}' to users "
                    "of the package; find it in cmake/PclVtsInstall.cmake")
  elseif(TARGET ${item} AND item IN_LIST PCL_VTS_MODULES)
    get_target_property(module ${item} EXPORT_NAME)
    get_target_property(pc ${item} OUTPUT_NAME)
    if(NOT pc)
      set(pc ${item})
    endif()
  elseif(item MATCHES "^pcl_(.+)$")
    # PCL's components are imported targets without a namespace; Debian names their
    # pkg-config files pcl_<component>.pc.
    set(package PCL)
    set(component ${CMAKE_MATCH_1})
    set(pc ${item})
  elseif(item STREQUAL "Threads::Threads")
    set(package Threads)
    set(libs -pthread)
  elseif(item MATCHES "^Boost::(.+)$")
    set(package Boost)
    if(NOT CMAKE_MATCH_1 MATCHES "^(headers|boost|diagnostic_definitions|disable_autolinking|dynamic_linking)$")
      set(component ${CMAKE_MATCH_1})
      set(libs -lboost_${CMAKE_MATCH_1})
    endif()
  elseif(item MATCHES "^PkgConfig::")
    message(WARNING "pcl_vts install: '${item}' (pkg_check_modules) cannot be found "
                    "again by the CMake package; link a find_package() target instead")
  elseif(item MATCHES "^([A-Za-z0-9_]+)::")
    # Namespace = package for CMake's own and most config packages (GDAL::GDAL,
    # ZLIB::ZLIB, Eigen3::Eigen, TBB::tbb); the pkg-config name is its lower case.
    set(package ${CMAKE_MATCH_1})
    string(TOLOWER ${CMAKE_MATCH_1} pc)
  elseif(TARGET ${item})
    message(WARNING "pcl_vts install: a module links the target '${item}', which is "
                    "neither a pcl_vts module nor a namespaced imported target")
  elseif(item MATCHES "^-" OR IS_ABSOLUTE "${item}")
    set(libs "${item}")
  else()
    set(libs "-l${item}")
  endif()
  foreach(var private module package component pc libs)
    set(item_${var} "${${var}}" PARENT_SCOPE)
  endforeach()
endfunction()

# ---- The package config: one table of the modules, then cmake/pcl_vtsConfig.cmake.in ----
# For each module <m>: the modules it links (its users need them imported and their
# dependencies found), the packages its users must find (public dependencies; for a
# static library also the private ones, which link into the user's program) and their
# components. A shared library's private dependencies are its own business.
set(PCL_VTS_CONFIG_TABLE "")
set(PCL_VTS_EXPORT_NAMES "")
foreach(target IN LISTS PCL_VTS_MODULES)
  get_target_property(name ${target} EXPORT_NAME)
  list(APPEND PCL_VTS_EXPORT_NAMES ${name})
  get_target_property(items ${target} INTERFACE_LINK_LIBRARIES)
  if(NOT items)
    set(items "")
  endif()
  set(modules "")
  set(packages "")
  set(component_lines "")
  foreach(item IN LISTS items)
    pcl_vts_describe_link_item("${item}")
    if(item_module)
      list(APPEND modules ${item_module})
    elseif(item_package)
      list(APPEND packages ${item_package})
      if(item_component)
        string(APPEND component_lines
               "list(APPEND _pcl_vts_${name}_${item_package}_components ${item_component})\n")
      endif()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES modules)
  list(REMOVE_DUPLICATES packages)
  string(APPEND PCL_VTS_CONFIG_TABLE
    "set(_pcl_vts_${name}_modules ${modules})\n"
    "set(_pcl_vts_${name}_packages ${packages})\n"
    "${component_lines}")
endforeach()
string(PREPEND PCL_VTS_CONFIG_TABLE "set(_pcl_vts_modules ${PCL_VTS_EXPORT_NAMES})\n")
set(PCL_VTS_PCL_VERSION ${PCL_VERSION_MAJOR}.${PCL_VERSION_MINOR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pcl_vtsConfig.cmake.in
  ${PROJECT_BINARY_DIR}/pcl_vtsConfig.cmake
  INSTALL_DESTINATION ${PCL_VTS_CMAKE_INSTALL_DIR})
# 0.x: SameMinorVersion, since the API may change with every minor release before 1.0
# (the libraries' SOVERSION is major.minor too): a request for 0.1 takes 0.1.z only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pcl_vtsConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pcl_vtsConfig.cmake
              ${PROJECT_BINARY_DIR}/pcl_vtsConfigVersion.cmake
        DESTINATION ${PCL_VTS_CMAKE_INSTALL_DIR} COMPONENT Development)

# ---- pkg-config: <target>.pc per module (pcl_vts_core.pc, ..., pcl_vts.pc) --------------
file(RELATIVE_PATH PCL_VTS_PC_TO_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig
     ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" PCL_VTS_PC_TO_PREFIX "${PCL_VTS_PC_TO_PREFIX}")
foreach(target IN LISTS PCL_VTS_MODULES)
  get_target_property(PC_NAME ${target} OUTPUT_NAME)
  if(NOT PC_NAME)
    set(PC_NAME ${target})
  endif()
  get_target_property(name ${target} EXPORT_NAME)
  set(PC_DESCRIPTION "pcl_vts module ${name} (CMake: pcl_vts::${name})")
  set(PC_REQUIRES "")
  set(PC_REQUIRES_PRIVATE "")
  set(PC_LIBS "-l${PC_NAME}")
  set(PC_LIBS_PRIVATE "")
  set(PC_CFLAGS "")
  get_target_property(items ${target} INTERFACE_LINK_LIBRARIES)
  if(NOT items)
    set(items "")
  endif()
  foreach(item IN LISTS items)
    pcl_vts_describe_link_item("${item}")
    if(item_private)
      set(suffix _PRIVATE)
    else()
      set(suffix "")
    endif()
    if(item_pc)
      list(APPEND PC_REQUIRES${suffix} ${item_pc})
    endif()
    if(item_libs)
      list(APPEND PC_LIBS${suffix} ${item_libs})
    endif()
  endforeach()
  get_target_property(definitions ${target} INTERFACE_COMPILE_DEFINITIONS)
  foreach(definition IN LISTS definitions)
    if(definition)
      string(APPEND PC_CFLAGS " -D${definition}")
    endif()
  endforeach()
  foreach(var PC_REQUIRES PC_REQUIRES_PRIVATE PC_LIBS PC_LIBS_PRIVATE)
    list(REMOVE_DUPLICATES ${var})
    string(REPLACE ";" " " ${var} "${${var}}")
  endforeach()
  configure_file(${PROJECT_SOURCE_DIR}/cmake/pcl_vts.pc.in
                 ${PROJECT_BINARY_DIR}/pkgconfig/${PC_NAME}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/${PC_NAME}.pc
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
          COMPONENT Development)
endforeach()
