#!/bin/bash
# Every public header of the predictors layer (Eigen only) compiles on its own: an installed header
# a user includes first must bring what it uses (recent_values.h relied on an earlier include for
# size_t). The layers on ViSP are left out: their headers take seconds each to parse.
#   headers_self_contained_test.sh CXX SOURCE_DIR EIGEN_INCLUDE_DIR
set -euo pipefail
cxx=$1
src=$2
eigen=$3
cd "$src/predictors/include"
ls predvs/predictors/*.h | xargs -P 2 -I{} bash -c \
  'echo "#include \"{}\"" | "$0" -std=c++17 -fsyntax-only -x c++ -I . -isystem "$1" - || { echo "FAIL: {} does not compile alone" >&2; exit 255; }' \
  "$cxx" "$eigen"
echo "headers_self_contained_test: OK ($(ls predvs/predictors/*.h | wc -l) headers)"
