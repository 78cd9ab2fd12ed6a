# Installing sdftrace: the public headers, the libraries (static and shared,
# the shared ones with a versioned soname), a relocatable CMake package with
# imported targets and components, and pkg-config files. The tools install
# themselves (CMakeLists.txt).
#
#   find_package(sdftrace CONFIG REQUIRED)                          sdftrace::sdftrace, sdftrace::sdftrace_static
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS vdb)           also sdftrace::vdb (shared)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS vdb_static)    also sdftrace::vdb_static (needs OpenVDB, C++)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS mesh)          also sdftrace::mesh (shared, sdftrace/mesh.h)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS mesh_static)   also sdftrace::mesh_static (needs OpenVDB, OpenMesh, TBB)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS gpu)           also sdftrace::gpu (shared, sdftrace/gpu.h, Vulkan)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS gpu_static)    also sdftrace::gpu_static (needs Vulkan's loader)
#   find_package(sdftrace CONFIG REQUIRED COMPONENTS scenes)        also sdftrace::scenes (static, the demo scenes)
#   pkg-config --cflags --libs sdftrace  (sdftrace_vdb; --static for the static libraries)

set(SDFT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sdftrace)

install(DIRECTORY include/sdftrace DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(FILES ${SDFT_GENERATED_INCLUDE}/sdftrace/config.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sdftrace)

set_target_properties(sdftrace PROPERTIES EXPORT_NAME sdftrace)
set_target_properties(sdftrace_static PROPERTIES EXPORT_NAME sdftrace_static)
install(TARGETS sdftrace sdftrace_static EXPORT sdftraceTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT sdftraceTargets NAMESPACE sdftrace:: DESTINATION ${SDFT_CMAKE_DIR})
# The demo scenes (sdftrace/scene.h), a static library on sdftrace_static.
set_target_properties(sdftrace_scenes PROPERTIES EXPORT_NAME scenes)
install(TARGETS sdftrace_scenes EXPORT sdftrace_scenesTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT sdftrace_scenesTargets NAMESPACE sdftrace:: DESTINATION ${SDFT_CMAKE_DIR})
# A component made by sdft_component (CMakeLists.txt) as two CMake
# components: `short`, the shared library, which needs nothing of its C++
# dependencies at build time (its headers are C), and `short_static`, which
# brings them to the link.
function(sdft_install_component name short)
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${short})
  set_target_properties(${name}_static PROPERTIES EXPORT_NAME ${short}_static)
  install(TARGETS ${name} EXPORT ${name}Targets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(TARGETS ${name}_static EXPORT ${name}_staticTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT ${name}Targets NAMESPACE sdftrace:: DESTINATION ${SDFT_CMAKE_DIR})
  install(EXPORT ${name}_staticTargets NAMESPACE sdftrace:: DESTINATION ${SDFT_CMAKE_DIR})
endfunction()
if(TARGET sdftrace_vdb)
  sdft_install_component(sdftrace_vdb vdb) # OpenVDB
endif()

if(TARGET sdftrace_mesh)
  sdft_install_component(sdftrace_mesh mesh) # OpenVDB, OpenMesh, TBB
endif()

if(TARGET sdftrace_gpu)
  sdft_install_component(sdftrace_gpu gpu) # Vulkan
endif()

configure_package_config_file(cmake/sdftraceConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/sdftraceConfig.cmake
                              INSTALL_DESTINATION ${SDFT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/sdftraceConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sdftraceConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/sdftraceConfigVersion.cmake
        DESTINATION ${SDFT_CMAKE_DIR})

# pkg-config: prefix found from the .pc file's own place, so the install
# tree can move.
file(RELATIVE_PATH SDFT_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" SDFT_PC_TO_PREFIX "${SDFT_PC_TO_PREFIX}")
string(JOIN " " SDFT_PC_OPENMP ${OpenMP_C_FLAGS})
configure_file(cmake/sdftrace.pc.in ${CMAKE_CURRENT_BINARY_DIR}/sdftrace.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sdftrace.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(TARGET sdftrace_vdb)
  configure_file(cmake/sdftrace_vdb.pc.in ${CMAKE_CURRENT_BINARY_DIR}/sdftrace_vdb.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sdftrace_vdb.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
if(TARGET sdftrace_mesh)
  configure_file(cmake/sdftrace_mesh.pc.in ${CMAKE_CURRENT_BINARY_DIR}/sdftrace_mesh.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sdftrace_mesh.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
