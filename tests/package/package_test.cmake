# The installed package and the subproject, tried the way users try them (ctest runs
# this with cmake -P; tests/CMakeLists.txt). Every step that fails stops the test.
#   -DMODE=install         cmake --install BUILD_DIR into WORK/staged, then moved to
#                          WORK/prefix (fixture): what follows proves it relocatable
#   -DMODE=find_package    examples/ and consumer/ built against WORK/prefix with only
#                          CMAKE_PREFIX_PATH; the version file; pkg-config; run and
#                          check the programs and where they load pcl_vts from
#   -DMODE=add_subdirectory  parent/ add_subdirectory()s the source tree with GTest,
#                          CGAL hidden, builds the examples from it
#                          (no build type: the cheapest compile)
# Other variables: SOURCE_DIR, BUILD_DIR, WORK, SAMPLE (a .pcd), VERSION, JOBS.
cmake_minimum_required(VERSION 3.21)
foreach(var MODE SOURCE_DIR BUILD_DIR WORK SAMPLE VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "package_test.cmake: -D${var}=... missing")
  endif()
endforeach()
if(NOT DEFINED JOBS)
  set(JOBS 2)
endif()
set(PREFIX ${WORK}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${command}\n${out}")
  endif()
  set(RUN_OUTPUT "${out}" PARENT_SCOPE)
endfunction()

# A command that must fail, saying what matches `expected`.
function(run_must_fail expected)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  string(REPLACE ";" " " command "${ARGN}")
  if(rc EQUAL 0)
    message(FATAL_ERROR "succeeded but must fail: ${command}\n${out}")
  endif()
  if(NOT out MATCHES "${expected}")
    message(FATAL_ERROR "failed without '${expected}': ${command}\n${out}")
  endif()
endfunction()

# The libraries a program loads, transitively, those matching `regex` in out_var; a
# library it cannot find fails the test.
function(loaded_libraries program regex out_var)
  file(GET_RUNTIME_DEPENDENCIES EXECUTABLES ${program}
       RESOLVED_DEPENDENCIES_VAR resolved UNRESOLVED_DEPENDENCIES_VAR unresolved)
  if(unresolved)
    message(FATAL_ERROR "${program}: unresolved libraries: ${unresolved}")
  endif()
  list(FILTER resolved INCLUDE REGEX "${regex}")
  set(${out_var} ${resolved} PARENT_SCOPE)
endfunction()

# The pcl_vts libraries a program loads come from the installed prefix, and it loads
# at least one (else the check is void).
function(check_loads_pcl_vts_from_prefix program)
  if(NOT PCL_VTS_SHARED)
    return()
  endif()
  loaded_libraries(${program} "/libpcl_vts[^/]*$" resolved)
  if(NOT resolved)
    message(FATAL_ERROR "${program} loads no pcl_vts library")
  endif()
  file(REAL_PATH ${PREFIX} prefix)
  foreach(library IN LISTS resolved)
    file(REAL_PATH ${library} library)
    string(FIND "${library}" "${prefix}/" at)
    if(NOT at EQUAL 0)
      message(FATAL_ERROR "${program} loads ${library}, not the one in ${PREFIX}")
    endif()
  endforeach()
endfunction()

# A program loads none of the libraries matching `forbidden`, and one matching
# `must_load` (else the check is void).
function(check_loads_none program forbidden must_load)
  loaded_libraries(${program} "${forbidden}" loaded)
  if(loaded)
    message(FATAL_ERROR "${program} loads ${loaded}")
  endif()
  loaded_libraries(${program} "${must_load}" loaded)
  if(NOT loaded)
    message(FATAL_ERROR "${program} does not load ${must_load}: the check is void")
  endif()
endfunction()

# The number after `label` in text, or a failure naming what is missing.
function(number_after label text out_var)
  if(NOT text MATCHES "${label} +([0-9]+)")
    message(FATAL_ERROR "no '${label} N' in:\n${text}")
  endif()
  set(${out_var} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

# triangulate_pcd's (or read_and_triangulate's) mesh: exactly the Delaunay triangulation of the hull of the
# distinct points, 2n - h - 2 triangles, and not empty.
function(check_example_output text out_triangles)
  number_after("distinct points" "${text}" n)
  number_after("hull vertices" "${text}" h)
  number_after("triangles" "${text}" t)
  math(EXPR expected "2 * ${n} - ${h} - 2")
  if(t EQUAL 0 OR NOT t EQUAL expected)
    message(FATAL_ERROR "triangulate_pcd: ${t} triangles, 2n - h - 2 = ${expected}")
  endif()
  set(${out_triangles} ${t} PARENT_SCOPE)
endfunction()

if(MODE STREQUAL "install")
  set(staged ${WORK}/staged)
  file(REMOVE_RECURSE ${PREFIX} ${staged})
  run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${staged})
  # Relocatable: everything after this uses the prefix where it was moved to.
  file(RENAME ${staged} ${PREFIX})
  # No installed text names the place it was installed to, built in or built from
  # (BUILD_DIR and the stage lie under SOURCE_DIR in make test's tree; checked apart
  # for builds elsewhere).
  file(GLOB_RECURSE texts ${PREFIX}/*.cmake ${PREFIX}/*.pc ${PREFIX}/include/*)
  if(NOT texts)
    message(FATAL_ERROR "nothing installed under ${PREFIX}")
  endif()
  foreach(text IN LISTS texts)
    file(READ ${text} content)
    foreach(path ${SOURCE_DIR} ${BUILD_DIR})
      string(FIND "${content}" "${path}" at)
      if(at GREATER -1)
        message(FATAL_ERROR "${text} names ${path}: not relocatable")
      endif()
    endforeach()
  endforeach()
  # The package: config, version file, one pkg-config file per library, the tool.
  file(GLOB config ${PREFIX}/lib*/cmake/pcl_vts/pcl_vtsConfig.cmake
                   ${PREFIX}/lib/*/cmake/pcl_vts/pcl_vtsConfig.cmake)
  file(GLOB version ${PREFIX}/lib*/cmake/pcl_vts/pcl_vtsConfigVersion.cmake
                    ${PREFIX}/lib/*/cmake/pcl_vts/pcl_vtsConfigVersion.cmake)
  if(NOT config OR NOT version OR NOT EXISTS ${PREFIX}/bin/pcd_to_mesh
     OR NOT EXISTS ${PREFIX}/include/pcl_vts/vts_grid_triangulation.h
     OR NOT EXISTS ${PREFIX}/include/pcl_vts/export.h)
    message(FATAL_ERROR "incomplete install in ${PREFIX}: config '${config}', "
                        "version file '${version}', bin/pcd_to_mesh, headers")
  endif()
  file(GLOB_RECURSE libraries ${PREFIX}/libpcl_vts*.so ${PREFIX}/libpcl_vts*.a)
  if(NOT libraries)
    message(FATAL_ERROR "no libpcl_vts* installed under ${PREFIX}")
  endif()
  foreach(library IN LISTS libraries)
    get_filename_component(dir ${library} DIRECTORY)
    get_filename_component(name ${library} NAME_WE)
    string(REGEX REPLACE "^lib" "" name ${name})
    if(NOT EXISTS ${dir}/pkgconfig/${name}.pc)
      message(FATAL_ERROR "${library} has no ${dir}/pkgconfig/${name}.pc")
    endif()
  endforeach()

elseif(MODE STREQUAL "find_package")
  # A static install (BUILD_SHARED_LIBS=OFF) links pcl_vts into the programs: the
  # checks of what they load from the prefix are then moot.
  file(GLOB_RECURSE PCL_VTS_SHARED ${PREFIX}/libpcl_vts*.so)
  set(adapters_library "libpcl_vts\\.so")
  set(core_library "libpcl_vts_core\\.so")
  if(NOT PCL_VTS_SHARED)
    set(adapters_library "libpcl_common")
    set(core_library "libstdc\\+\\+")
  endif()
  set(examples ${WORK}/examples)
  set(core ${WORK}/core_only)
  file(REMOVE_RECURSE ${examples} ${core} ${WORK}/adapters_only ${WORK}/io_only
                    ${WORK}/refused)
  # Only CMAKE_PREFIX_PATH: the package finds its dependencies itself.
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${examples}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX})
  run(${CMAKE_COMMAND} --build ${examples} -j ${JOBS})

  run(${examples}/triangulate_pcd ${SAMPLE} ${examples}/mesh.ply)
  check_example_output("${RUN_OUTPUT}" example_triangles)
  if(NOT EXISTS ${examples}/mesh.ply)
    message(FATAL_ERROR "triangulate_pcd wrote no mesh.ply")
  endif()
  check_loads_pcl_vts_from_prefix(${examples}/triangulate_pcd)
  # The installed pcd_to_mesh runs (relative RPATH) and finds the same triangulation.
  run(${PREFIX}/bin/pcd_to_mesh ${SAMPLE} ${examples}/pcd_to_mesh.ply --no-trim
      --no-fill)
  number_after("triangles" "${RUN_OUTPUT}" tool_triangles)
  if(NOT tool_triangles EQUAL example_triangles)
    message(FATAL_ERROR "pcd_to_mesh: ${tool_triangles} triangles, "
                        "triangulate_pcd: ${example_triangles}")
  endif()
  check_loads_pcl_vts_from_prefix(${PREFIX}/bin/pcd_to_mesh)

  run(${examples}/triangulate_grid)
  check_loads_none(${examples}/triangulate_grid "[Vv][Tt][Kk]|gdal" "${adapters_library}")

  # COMPONENTS pcl_vts alone: the package finds PCL's common/search/kdtree for it
  # (consumer/CMakeLists.txt finds nothing itself, and checks that io is not found).
  set(adapters ${WORK}/adapters_only)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${adapters}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX} -DPCL_VTS_COMPONENT=pcl_vts
      -DPROGRAM=${SOURCE_DIR}/examples/triangulate_grid.cpp -DPCL_VTS_FORBID=pcl_io)
  run(${CMAKE_COMMAND} --build ${adapters})
  run(${adapters}/consumer)
  check_loads_pcl_vts_from_prefix(${adapters}/consumer)

  # COMPONENTS io alone: the readers (pcl_io and GDAL inside a shared library, so no
  # PCL searched) read the sample as PCL did for triangulate_pcd, the core meshes it.
  set(reader ${WORK}/io_only)
  set(forbid "pcl_common,pcl_io")
  set(with_c OFF)
  if(NOT PCL_VTS_SHARED)
    set(forbid "") # a static io links pcl_io into the program: the package finds it
    set(with_c ON)
  endif()
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${reader}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX} -DPCL_VTS_COMPONENT=io
      -DPROGRAM=${SOURCE_DIR}/tests/package/consumer/read_and_triangulate.cpp
      "-DPCL_VTS_FORBID=${forbid}" -DWITH_C=${with_c})
  run(${CMAKE_COMMAND} --build ${reader})
  run(${reader}/consumer ${SAMPLE})
  check_example_output("${RUN_OUTPUT}" reader_triangles)
  if(NOT reader_triangles EQUAL example_triangles)
    message(FATAL_ERROR "read_and_triangulate: ${reader_triangles} triangles, "
                        "triangulate_pcd: ${example_triangles}")
  endif()
  check_loads_pcl_vts_from_prefix(${reader}/consumer)

  # COMPONENTS core: no PCL searched, none loaded; the version file accepts this
  # minor version and refuses the next minor and major.
  string(REGEX MATCH "^([0-9]+)\\.([0-9]+)" major_minor ${VERSION})
  set(major ${CMAKE_MATCH_1})
  set(minor ${CMAKE_MATCH_2})
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${core}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${PREFIX}
      -DPCL_VTS_REQUEST=${major_minor})
  if(NOT RUN_OUTPUT MATCHES "pcl_vts_VERSION=${VERSION}\n")
    message(FATAL_ERROR "consumer did not find pcl_vts ${VERSION}:\n${RUN_OUTPUT}")
  endif()
  run(${CMAKE_COMMAND} --build ${core})
  run(${core}/consumer)
  check_loads_pcl_vts_from_prefix(${core}/consumer)
  check_loads_none(${core}/consumer "libpcl_(common|io|search|kdtree)|libpcl_vts\\.so"
                   "${core_library}")
  math(EXPR next_minor "${minor} + 1")
  math(EXPR next_major "${major} + 1")
  foreach(request ${major}.${next_minor} ${next_major}.0)
    file(REMOVE_RECURSE ${WORK}/refused)
    run_must_fail("compatible with requested version \"${request}\""
      ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK}/refused
      -DCMAKE_PREFIX_PATH=${PREFIX} -DPCL_VTS_REQUEST=${request})
  endforeach()
  file(REMOVE_RECURSE ${WORK}/refused)
  run_must_fail("pcl_vts has no component 'no_such_module'"
    ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK}/refused
    -DCMAKE_PREFIX_PATH=${PREFIX} -DPCL_VTS_COMPONENT=no_such_module)

  # pkg-config finds every installed .pc file (with what it requires: PCL's .pc files)
  # under the prefix, wherever it is; a core program builds from pcl_vts_core's flags.
  find_program(PKG_CONFIG pkg-config REQUIRED)
  file(GLOB_RECURSE pc_files ${PREFIX}/*.pc)
  set(pc_dirs "")
  set(pc_names "")
  foreach(pc_file IN LISTS pc_files)
    get_filename_component(dir ${pc_file} DIRECTORY)
    get_filename_component(name ${pc_file} NAME_WE)
    list(APPEND pc_dirs ${dir})
    list(APPEND pc_names ${name})
  endforeach()
  list(REMOVE_DUPLICATES pc_dirs)
  string(REPLACE ";" ":" pc_path "${pc_dirs}")
  set(ENV{PKG_CONFIG_PATH} "${pc_path}")
  foreach(name IN LISTS pc_names)
    run(${PKG_CONFIG} --print-errors --cflags --libs ${name})
  endforeach()
  run(${PKG_CONFIG} --variable=libdir pcl_vts_core)
  string(STRIP "${RUN_OUTPUT}" libdir)
  run(${PKG_CONFIG} --cflags --libs pcl_vts_core)
  string(STRIP "${RUN_OUTPUT}" flags)
  separate_arguments(flags UNIX_COMMAND "${flags}")
  run(c++ -std=c++17 ${SOURCE_DIR}/tests/package/consumer/core_only.cpp ${flags}
      -Wl,-rpath,${libdir} -o ${core}/core_only_pc)
  run(${core}/core_only_pc)
  check_loads_pcl_vts_from_prefix(${core}/core_only_pc)
  # ... and a PCL program from pcl_vts's, through PCL's own .pc files.
  run(${PKG_CONFIG} --cflags --libs pcl_vts)
  string(STRIP "${RUN_OUTPUT}" flags)
  separate_arguments(flags UNIX_COMMAND "${flags}")
  run(c++ -std=c++17 ${SOURCE_DIR}/examples/triangulate_grid.cpp ${flags}
      -Wl,-rpath,${libdir} -o ${core}/triangulate_grid_pc)
  run(${core}/triangulate_grid_pc)
  check_loads_pcl_vts_from_prefix(${core}/triangulate_grid_pc)

elseif(MODE STREQUAL "add_subdirectory")
  set(parent ${WORK}/parent)
  file(REMOVE_RECURSE ${parent})
  # No CMAKE_BUILD_TYPE: parent/CMakeLists.txt checks that it stays empty. GTest and
  # CGAL hidden: a parent must not need them.
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/parent -B ${parent}
      -DPCL_VTS_SOURCE_DIR=${SOURCE_DIR} -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON
      -DCMAKE_DISABLE_FIND_PACKAGE_CGAL=ON)
  run(${CMAKE_COMMAND} --build ${parent} -j ${JOBS} --target triangulate_pcd
      triangulate_grid)
  run(${parent}/examples/triangulate_pcd ${SAMPLE})
  check_example_output("${RUN_OUTPUT}" triangles)
  run(${parent}/examples/triangulate_grid)

else()
  message(FATAL_ERROR "package_test.cmake: unknown MODE '${MODE}'")
endif()
