# Debian packages of predvs (CPack DEB): `make deb`, or `cd build && cpack -G DEB`, writes
#   build/predvs_<version>_<arch>.deb      component `runtime`: /usr/bin/predvs, predvs-all and
#                                          /usr/share/predvs/ (scenarios/, textures/, params/)
#   build/predvs-dev_<version>_<arch>.deb  component `dev`: /usr/include/predvs/, the static
#                                          libraries (/usr/lib/) and the CMake package
#                                          (/usr/lib/cmake/predvs/)
#   build/python3-predvs_<version>_<arch>.deb  component `python` (when python/ is built): the
#                                          module under /usr/lib/python3/dist-packages/predvs
# Why two packages: the CLI needs only shared libraries (ViSP, OpenCV, yaml-cpp, those of the
# static Ceres: glog, SuiteSparse, LAPACK/BLAS, and Open MPI if found at build time), while
# find_package(predvs) needs ViSP's and Eigen's -dev packages and a compiler, much more to
# download (docs/PERFORMANCE.md, "The Debian package on a fresh Debian 12"). A user of the CLI
# installs predvs alone; predvs-dev depends on the predvs of the same version (the CMake package's
# PREDVS_DATA_DIR is /usr/share/predvs).
# Dependencies:
#   predvs      the shared libraries the binary links, computed by dpkg-shlibdeps at packaging time
#               (CPACK_DEBIAN_PACKAGE_SHLIBDEPS; needs dpkg-dev, which build-essential brings, and
#               `file`), plus gnuplot-nox, which the default `predvs servo` runs for its plots and
#               which no library link reveals (--no-plots runs without it).
#   predvs-dev  predvs (= same version), libeigen3-dev and libvisp-dev (find_dependency in
#               predvsConfig.cmake); libopencv-dev and libceres-dev are recommended, needed only for
#               find_package(predvs COMPONENTS calibration).
#   python3-predvs  predvs (= same version: parameter files and scenarios), the Python 3 minor
#               version the module was built for (its ABI tag is in the file name) and python3-numpy
#               (pybind11's numpy arrays), plus the module's shared libraries (shlibdeps).
# Install prefix /usr; the binary finds its data at <bin>/../share/predvs (servo/.../data_dir.h).
# The package is built from the already built tree: the build type of that tree is what ships
# (Release by default); binaries are stripped.

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME predvs)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "predvs developers")
set(CPACK_PACKAGE_CONTACT "predvs developers <dev@predvs.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "predictive visual servoing on ViSP")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL runtime dev)
if(TARGET predvs_python)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()

set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # <package>_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)  # predvs-dev: Depends predvs (= version)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME predvs)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "gnuplot-nox | gnuplot")
# Synopsis: CPACK_PACKAGE_DESCRIPTION_SUMMARY; these are the extended descriptions.
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "The predvs command line and its data (scenarios, textures, parameters).
Kalman-type predictors (CV/CA KF, CS-model AKF, fuzzy adaptive, self-tuning,
strong-tracking, IMM) ahead of ViSP visual-servoing loops with a delayed camera,
with scenarios, simulated robots, image trackers, calibration and campaigns.")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME predvs-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libeigen3-dev, libvisp-dev")
set(CPACK_DEBIAN_DEV_PACKAGE_RECOMMENDS "libopencv-dev, libceres-dev")
set(CPACK_COMPONENT_DEV_DESCRIPTION "Headers, static libraries and the CMake package of predvs.
find_package(predvs) gives predvs::predictors, predvs::tasks and predvs::servo;
find_package(predvs COMPONENTS calibration) adds predvs::calibration.")

if(TARGET predvs_python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-predvs)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
      "python3 (>= ${PREDVS_PYTHON_VERSION}), python3 (<< ${PREDVS_PYTHON_NEXT_VERSION}~), python3-numpy")
  set(CPACK_COMPONENT_PYTHON_DESCRIPTION "The predvs Python module: import predvs.
The predictor registry (make, update, predict on numpy arrays), noise fitting and
parameter files of predvs, from Python 3 (docs/PYTHON.md).")
endif()

include(CPack)
cpack_add_component(runtime DISPLAY_NAME "predvs command line and data")
cpack_add_component(dev DISPLAY_NAME "predvs development files" DEPENDS runtime)
if(TARGET predvs_python)
  cpack_add_component(python DISPLAY_NAME "predvs Python module" DEPENDS runtime)
endif()
