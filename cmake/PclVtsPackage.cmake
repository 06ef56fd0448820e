# CPack: one Debian package, pcl-vts_<version>_<arch>.deb (`make package` builds it in
# build-package/, configured with CMAKE_INSTALL_PREFIX=/usr so that the libraries land
# in /usr/lib/<multiarch>). It holds what `cmake --install` installs: the libraries,
# pcd_to_mesh, the headers, the CMake package and the pkg-config files.
#
# Depends: the shared libraries it links, as dpkg-shlibdeps finds them (libpcl-*1.13,
# libgdal32, libboost-program-options1.74.0 for pcd_to_mesh, libstdc++6, ...), and libpcl-dev: the headers include PCL's, and the CMake
# package calls find_dependency(PCL), which needs PCL's CMake files and the -dev
# packages they look for (Boost, Eigen, FLANN, VTK). One package rather than a
# runtime/-dev pair: pcl_vts is used from C++ code, and pcd_to_mesh rides along.
set(CPACK_PACKAGE_NAME pcl-vts)
set(CPACK_PACKAGE_VENDOR "pcl_vts developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Exact Delaunay triangulation of elevation point clouds for PCL (VTS method)")
set(CPACK_PACKAGE_DESCRIPTION
    "pcl::VTSGridTriangulation turns an elevation point cloud (LiDAR ground, DEM) into
the exact Delaunay triangulation of its XY projection, with outward-triangle removal
and hole filling; pcd_to_mesh runs the pipeline from the command line.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_FILE_NAME "${CPACK_PACKAGE_NAME}-${PROJECT_VERSION}")
set(CPACK_RESOURCE_FILE_README ${PROJECT_SOURCE_DIR}/README.md)
set(CPACK_STRIP_FILES ON)

set(CPACK_GENERATOR DEB)
set(PCL_VTS_PACKAGE_MAINTAINER "pcl_vts developers <pcl-vts@users.noreply.github.com>"
    CACHE STRING "Maintainer field of the .deb")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${PCL_VTS_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT) # pcl-vts_0.1.0_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Our own libraries are in the package: dpkg-shlibdeps must look for them there.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "")
foreach(target IN LISTS PCL_VTS_MODULES)
  get_target_property(dir ${target} BINARY_DIR)
  list(APPEND CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${dir})
endforeach()
# A shlibs file and the ldconfig trigger for the libraries in /usr/lib/<multiarch>.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libpcl-dev (>= ${PCL_VERSION_MAJOR}.${PCL_VERSION_MINOR})")

include(CPack)
