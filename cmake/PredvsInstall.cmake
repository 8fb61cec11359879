# Install rules and the predvs CMake package (find_package(predvs) -> predvs::predictors,
# predvs::tasks, predvs::servo; find_package(predvs COMPONENTS calibration) adds
# predvs::calibration, which also finds OpenCV and Ceres). Two install components, which the
# Debian packages of cmake/PredvsPackage.cmake follow: `runtime` (bin/predvs and bin/predvs-all, share/predvs/) and
# `dev` (headers, static libraries, the CMake package). Data is found at run time
# (servo/include/predvs/servo/data_dir.h): installed binaries look in <prefix>/bin/../share/predvs;
# the build tree mimics that layout with a link <build>/share/predvs -> <source>/data, so nothing
# of the source tree is compiled in.
include(CMakePackageConfigHelpers)

file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/share)
if(NOT EXISTS ${PROJECT_BINARY_DIR}/share/predvs)
  file(CREATE_LINK ${PROJECT_SOURCE_DIR}/data ${PROJECT_BINARY_DIR}/share/predvs SYMBOLIC)
endif()

set_target_properties(predvs_predictors PROPERTIES EXPORT_NAME predictors)
set_target_properties(predvs_tasks PROPERTIES EXPORT_NAME tasks)
set_target_properties(predvs_servo PROPERTIES EXPORT_NAME servo)
# predvs_visp links the visp_* targets that find_dependency(VISP) re-creates for the user.
set_target_properties(predvs_visp PROPERTIES EXPORT_NAME visp)

set_target_properties(predvs_calibration PROPERTIES EXPORT_NAME calibration)

install(TARGETS predvs predvs-all RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
install(TARGETS predvs_predictors predvs_tasks predvs_servo predvs_visp EXPORT predvsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
# Its own export set: loaded only for find_package(predvs COMPONENTS calibration).
install(TARGETS predvs_calibration EXPORT predvsCalibrationTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
foreach(layer predictors tasks servo calibration)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          COMPONENT dev)
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/scenarios ${PROJECT_SOURCE_DIR}/data/textures
                  ${PROJECT_SOURCE_DIR}/data/params
        DESTINATION ${CMAKE_INSTALL_DATADIR}/predvs COMPONENT runtime)

set(PREDVS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/predvs)
install(EXPORT predvsTargets NAMESPACE predvs:: DESTINATION ${PREDVS_CMAKE_DIR} COMPONENT dev)
install(EXPORT predvsCalibrationTargets NAMESPACE predvs:: DESTINATION ${PREDVS_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/predvsConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/predvsConfig.cmake
                              INSTALL_DESTINATION ${PREDVS_CMAKE_DIR} PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/predvsConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/predvsConfig.cmake ${PROJECT_BINARY_DIR}/predvsConfigVersion.cmake
        DESTINATION ${PREDVS_CMAKE_DIR} COMPONENT dev)
