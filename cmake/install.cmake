# cmake --install BUILD --prefix P: the libraries, their headers (the
# source layout kept: #include "libbead/profile/profile_processor.h"), the
# C header <bead/bead.h> and libbead.so, the bead tool, a CMake package
# (find_package(bead CONFIG REQUIRED): bead::core, bead::c, and bead::io,
# bead::model, ... when their dependencies are found) and bead.pc.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Core: Eigen and the standard library only (and libbead.so over it).
set(bead_core_targets bead_core bead_c)
# The rest: HDF5, yaml-cpp, Ceres, OpenCV.
set(bead_full_targets bead_io bead_flow bead_model bead_sim bead_occlusion_pool bead_occlusion bead_explain bead_archive bead_vision bead_control)
foreach(t ${bead_full_targets})
  string(REGEX REPLACE "^bead_" "" short ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${bead_core_targets} EXPORT beadCoreTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${bead_full_targets} EXPORT beadTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# Every header but the internals no installed header includes: the
# per-profile kernel's vector code (built once per instruction set), the
# identification's search, the stripe finder's estimators and the twin's
# YAML reader.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libbead/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libbead
  FILES_MATCHING PATTERN "*.h"
  PATTERN "vec8.h" EXCLUDE PATTERN "vec_sort.h" EXCLUDE PATTERN "kernel.h" EXCLUDE PATTERN "bead_heights.h" EXCLUDE PATTERN "sim_yaml_reader.h" EXCLUDE PATTERN "sim_timeline.h" EXCLUDE
  PATTERN "output_error.h" EXCLUDE PATTERN "stripe_steger.h" EXCLUDE PATTERN "stripe_line.h" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/include/bead/bead.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bead)
install(TARGETS bead bead-measure bead-flow bead-batch bead-calibrate bead-simulate bead-import bead-export bead-frames
  bead-identify bead-explain bead-report bead-tune bead-feedforward RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS bead-occlusion-fit LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/bead)
install(FILES ${PROJECT_SOURCE_DIR}/tools/report/bead_report.py DESTINATION ${CMAKE_INSTALL_DATADIR}/bead)

set(bead_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/bead)
install(EXPORT beadCoreTargets NAMESPACE bead:: DESTINATION ${bead_cmake_dir})
install(EXPORT beadTargets NAMESPACE bead:: DESTINATION ${bead_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/beadConfig.cmake.in
  ${PROJECT_BINARY_DIR}/beadConfig.cmake INSTALL_DESTINATION ${bead_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/beadConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/beadConfig.cmake ${PROJECT_BINARY_DIR}/beadConfigVersion.cmake
  DESTINATION ${bead_cmake_dir})
configure_file(${PROJECT_SOURCE_DIR}/cmake/bead.pc.in ${PROJECT_BINARY_DIR}/bead.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/bead.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
