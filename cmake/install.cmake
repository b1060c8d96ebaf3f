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
set(bead_full_targets bead_io bead_flow bead_model bead_sim bead_occlusion_pool bead_occlusion bead_explain bead_archive bead_vision bead_control bead_part)
foreach(t ${bead_full_targets})
  string(REGEX REPLACE "^bead_" "" short ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${bead_core_targets} EXPORT beadCoreTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${bead_full_targets} EXPORT beadTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# Every header but the internals no installed header includes: the
# per-profile kernel's vector code and the part's (each built once per
# instruction set, and the part's grid path over it), the identification's
# search, the stripe finder's estimators and the twin's YAML reader.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libbead/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libbead
  FILES_MATCHING PATTERN "*.h"
  PATTERN "vec8.h" EXCLUDE PATTERN "vec_sort.h" EXCLUDE PATTERN "kernel.h" EXCLUDE PATTERN "part_kernel.h" EXCLUDE PATTERN "grid_costs.h" EXCLUDE PATTERN "bead_heights.h" EXCLUDE PATTERN "sim_yaml_reader.h" EXCLUDE PATTERN "sim_timeline.h" EXCLUDE
  PATTERN "output_error.h" EXCLUDE PATTERN "stripe_steger.h" EXCLUDE PATTERN "stripe_line.h" EXCLUDE
  PATTERN "float_bits.h" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/include/bead/bead.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bead)
install(TARGETS bead bead-measure bead-flow bead-batch bead-calibrate bead-simulate bead-import bead-export bead-frames
  bead-identify bead-explain bead-report bead-tune bead-feedforward RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS bead-occlusion-fit LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/bead)
install(FILES ${PROJECT_SOURCE_DIR}/tools/report/bead_report.py ${PROJECT_SOURCE_DIR}/tools/report/report_common.py
              ${PROJECT_SOURCE_DIR}/tools/report/part_report.py DESTINATION ${CMAKE_INSTALL_DATADIR}/bead)

set(bead_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/bead)
install(EXPORT beadCoreTargets NAMESPACE bead:: DESTINATION ${bead_cmake_dir})
install(EXPORT beadTargets NAMESPACE bead:: DESTINATION ${bead_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/beadConfig.cmake.in
  ${PROJECT_BINARY_DIR}/beadConfig.cmake INSTALL_DESTINATION ${bead_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/beadConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/beadConfig.cmake ${PROJECT_BINARY_DIR}/beadConfigVersion.cmake
  DESTINATION ${bead_cmake_dir})
# bead.pc twice: the installed one finds PREFIX from its own folder; the
# build tree's (PKG_CONFIG_PATH=BUILD) names the source's header and the
# build's library.
configure_file(${PROJECT_SOURCE_DIR}/cmake/bead.pc.in ${PROJECT_BINARY_DIR}/pkgconfig-install/bead.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/pkgconfig-install/bead.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
configure_file(${PROJECT_SOURCE_DIR}/cmake/bead-build.pc.in ${PROJECT_BINARY_DIR}/bead.pc @ONLY)

# What --help points at, installed: the documents (PREFIX/share/doc/bead),
# the example configs, the sample run and the README chains' data
# (PREFIX/share/bead/testdata: `bead flow` with no arguments finds the
# sample there), a man page per command made from its --help, and bash
# completion read from --help at completion time.
set(bead_doc_dir ${CMAKE_INSTALL_DATAROOTDIR}/doc/bead)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${bead_doc_dir})
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${bead_doc_dir})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/testdata/configs ${PROJECT_SOURCE_DIR}/testdata/sample
                  ${PROJECT_SOURCE_DIR}/testdata/step ${PROJECT_SOURCE_DIR}/testdata/plan
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bead/testdata)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples DESTINATION ${bead_doc_dir})
set(bead_man_dir ${PROJECT_BINARY_DIR}/man1)
add_custom_command(OUTPUT ${bead_man_dir}/bead.1
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/shell/man_pages.sh $<TARGET_FILE:bead> ${PROJECT_VERSION} ${bead_man_dir}
  DEPENDS bead bead-measure bead-flow bead-batch bead-calibrate bead-simulate bead-import bead-export bead-frames
          bead-identify bead-explain bead-report bead-tune bead-feedforward ${PROJECT_SOURCE_DIR}/tools/shell/man_pages.sh
  COMMENT "Man pages from each command's --help")
add_custom_target(bead_man_pages ALL DEPENDS ${bead_man_dir}/bead.1)
install(DIRECTORY ${bead_man_dir} DESTINATION ${CMAKE_INSTALL_MANDIR})
install(FILES ${PROJECT_SOURCE_DIR}/tools/shell/bead.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME bead)
